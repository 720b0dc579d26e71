//! IES TM-25 ray files (TM-25-13, revised as ANSI/IES TM-25-20): an LED
//! maker's measured near field as rays, and a luminaire's as Lucerna
//! writes it.
//!
//! Layout, little-endian throughout: a 256-byte file header (magic
//! `TM25`, version 2013, creation method, luminous and radiant flux, ray
//! count, date, start position, spectrum type and wavelengths, counts of
//! spectral tables, additional columns and additional text), eight i32
//! known-data flags, nine text fields of 1000 UTF-32 characters, the
//! spectral tables (padded to 32 bytes), 512-byte names of additional
//! columns, the additional text, then one f32 record per ray: x, y, z
//! (mm), kx, ky, kz, and the columns the flags announce in the standard's
//! order (radiant flux, wavelength, luminous flux, Stokes S1-S3,
//! tristimulus X and Z, spectrum index, additional columns).
//!
//! Written from the standard's layout and the Unlicense reference reader
//! (JuliusMuschaweck/TM25RaySetTools), not from the AGPL `tm25ray` crate.

mod far_field;
mod luminous;
mod read;
mod write;

pub use far_field::far_field_resolution;
pub use luminous::{luminous_efficacy_lm_per_w, photopic_v};
pub use read::{
    MAX_RAY_FILE_BYTES, ReadRayFileError, parse_ray_file, ray_file_luminous_flux, read_ray_file,
};
pub use write::write_ray_file;

/// The file type's four bytes.
pub const MAGIC: [u8; 4] = *b"TM25";
/// The only version TM-25 defines.
pub const VERSION: i32 = 2013;
/// Bytes of the file header block (4.7.1).
pub const FILE_HEADER_BYTES: usize = 256;
/// Bytes of the known-data flags block (4.7.2).
pub const FLAGS_BYTES: usize = 32;
/// UTF-32 characters of one description field (4.7.3).
pub const TEXT_FIELD_CHARS: usize = 1000;
/// Bytes of one additional column's name (4.7.5).
pub const COLUMN_NAME_BYTES: usize = 512;
/// Bytes of the header up to the spectral tables.
pub const FIXED_HEADER_BYTES: usize = FILE_HEADER_BYTES + FLAGS_BYTES + 9 * 4 * TEXT_FIELD_CHARS;

/// How the rays were obtained (4.7.1.3).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CreationMethod {
    Simulation,
    Measurement,
    /// A value the standard does not define, kept as read.
    Other(i32),
}

impl CreationMethod {
    pub fn code(self) -> i32 {
        match self {
            CreationMethod::Simulation => 0,
            CreationMethod::Measurement => 1,
            CreationMethod::Other(c) => c,
        }
    }

    pub fn from_code(code: i32) -> Self {
        match code {
            0 => CreationMethod::Simulation,
            1 => CreationMethod::Measurement,
            c => CreationMethod::Other(c),
        }
    }
}

/// What the file says of the rays' spectrum (4.7.1.9).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpectrumType {
    /// No spectral information.
    None,
    /// Every ray at the header's single wavelength.
    SingleWavelength,
    /// A wavelength column.
    PerRayWavelength,
    /// One spectral table for all rays.
    Table,
    /// A spectrum-index column into the tables.
    PerRayTable,
}

impl SpectrumType {
    pub fn code(self) -> i32 {
        match self {
            SpectrumType::None => 0,
            SpectrumType::SingleWavelength => 1,
            SpectrumType::PerRayWavelength => 2,
            SpectrumType::Table => 3,
            SpectrumType::PerRayTable => 4,
        }
    }

    pub fn from_code(code: i32) -> Option<Self> {
        Some(match code {
            0 => SpectrumType::None,
            1 => SpectrumType::SingleWavelength,
            2 => SpectrumType::PerRayWavelength,
            3 => SpectrumType::Table,
            4 => SpectrumType::PerRayTable,
            _ => return None,
        })
    }
}

/// Which optional columns each ray carries (4.7.2).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct KnownData {
    pub radiant_flux: bool,
    pub wavelength: bool,
    pub luminous_flux: bool,
    pub stokes: bool,
    pub tristimulus: bool,
    pub spectrum_index: bool,
}

/// The description block (4.7.3): nine free texts.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct Description {
    pub name: String,
    pub manufacturer: String,
    pub model_creator: String,
    pub ray_file_creator: String,
    pub equipment: String,
    pub camera: String,
    pub operation: String,
    pub additional_info: String,
    pub data_reference: String,
}

impl Description {
    pub fn fields(&self) -> [&str; 9] {
        [
            &self.name,
            &self.manufacturer,
            &self.model_creator,
            &self.ray_file_creator,
            &self.equipment,
            &self.camera,
            &self.operation,
            &self.additional_info,
            &self.data_reference,
        ]
    }

    /// The field names, as `lucerna info` and errors print them.
    pub const FIELD_NAMES: [&'static str; 9] = [
        "name",
        "manufacturer",
        "model creator",
        "ray file creator",
        "equipment",
        "camera",
        "light source operation",
        "additional information",
        "data reference",
    ];
}

/// One spectral table (4.7.4): wavelengths (nm) and their relative
/// weights.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SpectralTable {
    pub wavelengths_nm: Vec<f32>,
    pub weights: Vec<f32>,
}

/// Everything before the rays.
#[derive(Debug, Clone, PartialEq)]
pub struct RayFileHeader {
    pub creation_method: CreationMethod,
    /// Total luminous flux (lm); `None` where the file writes NaN
    /// (unknown).
    pub luminous_flux_lm: Option<f32>,
    /// Total radiant flux (W); `None` where unknown.
    pub radiant_flux_w: Option<f32>,
    pub ray_count: u64,
    /// ISO 8601 date and time, as written (28 bytes at most).
    pub date_time: String,
    /// Where the rays start (4.7.1.8: 0 unknown, 1-7 surfaces).
    pub start_position: i32,
    pub spectrum: SpectrumType,
    /// The single wavelength (nm), for [`SpectrumType::SingleWavelength`].
    pub wavelength_nm: Option<f32>,
    pub min_wavelength_nm: Option<f32>,
    pub max_wavelength_nm: Option<f32>,
    pub known: KnownData,
    pub description: Description,
    pub spectral_tables: Vec<SpectralTable>,
    /// Names of the columns after the standard ones.
    pub additional_columns: Vec<String>,
    pub additional_text: String,
}

impl RayFileHeader {
    /// A header for `ray_count` rays with luminous flux per ray and no
    /// spectrum: what Lucerna writes.
    pub fn luminous(ray_count: u64, luminous_flux_lm: f32) -> Self {
        RayFileHeader {
            creation_method: CreationMethod::Simulation,
            luminous_flux_lm: Some(luminous_flux_lm),
            radiant_flux_w: None,
            ray_count,
            date_time: String::new(),
            start_position: 0,
            spectrum: SpectrumType::None,
            wavelength_nm: None,
            min_wavelength_nm: None,
            max_wavelength_nm: None,
            known: KnownData {
                luminous_flux: true,
                ..KnownData::default()
            },
            description: Description::default(),
            spectral_tables: Vec::new(),
            additional_columns: Vec::new(),
            additional_text: String::new(),
        }
    }

    /// What a reader should know of fields the file fills beyond what
    /// TM-25 defines, read as given.
    pub fn notes(&self) -> Vec<String> {
        let mut out = Vec::new();
        if let CreationMethod::Other(c) = self.creation_method {
            out.push(format!(
                "creation method {c} is not one TM-25 defines (0 simulation, 1 measurement): read as given"
            ));
        }
        out
    }

    /// The columns of each ray, in the file's order.
    pub fn columns(&self) -> Columns {
        Columns::of(&self.known, self.additional_columns.len())
    }
}

/// Where each quantity sits in a ray's record.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Columns {
    /// f32 values per ray.
    pub count: usize,
    pub radiant_flux: Option<usize>,
    pub wavelength: Option<usize>,
    pub luminous_flux: Option<usize>,
    /// The three Stokes values and the two tristimulus values, where
    /// flagged: read only to refuse what is not finite.
    pub stokes: Option<usize>,
    pub tristimulus: Option<usize>,
    pub spectrum_index: Option<usize>,
}

impl Columns {
    /// Position and direction first, then the flagged columns in the
    /// standard's order, then the additional ones.
    pub fn of(known: &KnownData, additional: usize) -> Self {
        let mut next = 6;
        let mut take = |present: bool, width: usize| {
            present.then(|| {
                next += width;
                next - width
            })
        };
        let radiant_flux = take(known.radiant_flux, 1);
        let wavelength = take(known.wavelength, 1);
        let luminous_flux = take(known.luminous_flux, 1);
        let stokes = take(known.stokes, 3);
        let tristimulus = take(known.tristimulus, 2);
        let spectrum_index = take(known.spectrum_index, 1);
        Columns {
            count: next + additional,
            radiant_flux,
            wavelength,
            luminous_flux,
            stokes,
            tristimulus,
            spectrum_index,
        }
    }
}

/// How closely a header's stated flux and its rays' sum must agree before
/// a warning (a share).
pub const FLUX_AGREEMENT: f64 = 0.01;

/// A ray file in memory: its header and the rays' records, row by row,
/// held once.
#[derive(Debug, Clone, PartialEq)]
pub struct RaySet {
    pub header: RayFileHeader,
    /// `ray_count × columns().count` values.
    pub records: Vec<f32>,
    /// Each ray's luminous flux (lm), by the rule of [`luminous`]: what
    /// photons are sampled by.
    pub luminous_flux_lm: Vec<f32>,
}

impl RaySet {
    pub fn len(&self) -> usize {
        self.luminous_flux_lm.len()
    }

    pub fn is_empty(&self) -> bool {
        self.luminous_flux_lm.is_empty()
    }

    fn record(&self, i: usize) -> &[f32] {
        let n = self.header.columns().count;
        &self.records[i * n..(i + 1) * n]
    }

    /// Ray `i`'s start (mm, the file's frame).
    pub fn position_mm(&self, i: usize) -> [f32; 3] {
        let r = self.record(i);
        [r[0], r[1], r[2]]
    }

    /// Ray `i`'s direction as written (not necessarily unit length).
    pub fn direction(&self, i: usize) -> [f32; 3] {
        let r = self.record(i);
        [r[3], r[4], r[5]]
    }

    /// The rays' total luminous flux (lm), summed in f64.
    pub fn total_luminous_flux_lm(&self) -> f64 {
        self.luminous_flux_lm.iter().map(|&f| f64::from(f)).sum()
    }

    /// The rays' total radiant flux (W), where they have a radiant column.
    pub fn total_radiant_flux_w(&self) -> Option<f64> {
        let c = self.header.columns().radiant_flux?;
        let n = self.header.columns().count;
        Some(self.records.chunks_exact(n).map(|r| f64::from(r[c])).sum())
    }

    /// Where the header's stated totals and the rays' sums disagree by
    /// more than [`FLUX_AGREEMENT`], what a user should be told: which is
    /// which, and that the rays are what a bake samples (the emitter's
    /// `flux_lm`, or the rays' own luminous flux where it has none, sets
    /// the total).
    pub fn flux_warnings(&self) -> Vec<String> {
        let mut out = Vec::new();
        let mut check = |stated: Option<f32>, summed: Option<f64>, unit: &str| {
            let (Some(stated), Some(summed)) = (stated, summed) else {
                return;
            };
            let stated = f64::from(stated);
            if !(stated > 0.0 && summed > 0.0) {
                return;
            }
            let ratio = summed / stated;
            if (ratio - 1.0).abs() > FLUX_AGREEMENT {
                out.push(format!(
                    "the header states {stated} {unit}, the rays sum to {summed:.6} {unit} ({:+.2} %): the rays are what a bake samples; their shares, scaled to the emitter's flux, give the light",
                    100.0 * (ratio - 1.0)
                ));
            }
        };
        check(
            self.header.luminous_flux_lm,
            self.header
                .columns()
                .luminous_flux
                .map(|_| self.total_luminous_flux_lm()),
            "lm",
        );
        check(self.header.radiant_flux_w, self.total_radiant_flux_w(), "W");
        out
    }

    /// The smallest box holding every ray's start (mm).
    pub fn extent_mm(&self) -> Option<([f32; 3], [f32; 3])> {
        (0..self.len())
            .map(|i| self.position_mm(i))
            .fold(None, |acc, p| {
                let (lo, hi) = acc.unwrap_or((p, p));
                Some((
                    [lo[0].min(p[0]), lo[1].min(p[1]), lo[2].min(p[2])],
                    [hi[0].max(p[0]), hi[1].max(p[1]), hi[2].max(p[2])],
                ))
            })
    }
}

#[cfg(test)]
mod tests;
