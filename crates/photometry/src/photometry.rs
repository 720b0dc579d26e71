//! A photometric data set as the file formats carry it: a candela table and
//! the metadata both IES and EULUMDAT can hold.

use serde::Serialize;

use crate::table::{CPlaneSymmetry, CandelaTable};

/// The file format a data set came from (or goes to).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum Format {
    /// IES LM-63 with its version year (1986, 1991, 1995, 2002, 2019).
    Ies(u16),
    /// EULUMDAT (.ldt).
    Eulumdat,
    /// The far field of an IES TM-25 ray file's rays.
    Tm25RayFile,
}

impl std::fmt::Display for Format {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Format::Ies(year) => write!(f, "IES LM-63-{year}"),
            Format::Eulumdat => write!(f, "EULUMDAT"),
            Format::Tm25RayFile => write!(f, "IES TM-25 ray file, its rays' far field"),
        }
    }
}

/// A set of identical lamps (EULUMDAT lamp set; IES has one).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LampSet {
    /// Number of lamps (negative in EULUMDAT marks absolute photometry).
    pub count: i32,
    pub kind: String,
    /// Total rated flux of the set (lm).
    pub flux_lm: f64,
    pub colour_temperature: String,
    pub colour_rendering: String,
    /// Power including ballast (W).
    pub watts: f64,
}

/// Dimensions of a luminaire or its luminous area (m), in IES LM-63's
/// terms, which this type keeps whatever file it came from: length is
/// along the C0-C180 axis (x), width along C90-C270 (y); a circular shape
/// has `width_m = 0` and its diameter in `length_m`. EULUMDAT names them
/// the other way round (its length lies along C90-C270): its reader and
/// writer swap them (ARCHITECTURE.md, "photometric files").
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct Dimensions {
    pub length_m: f64,
    pub width_m: f64,
    pub height_m: f64,
    pub circular: bool,
}

/// A value read from a file, refused unless its magnitude is at most
/// `max` (one of [`crate::limits`]): `what` names the field.
pub(crate) fn plausible_magnitude(
    format: &'static str,
    line: usize,
    what: &str,
    value: f64,
    max: f64,
) -> Result<f64, ParsePhotometryError> {
    if crate::limits::within(value, max) {
        Ok(value)
    } else {
        Err(ParsePhotometryError::new(
            format,
            Some(line),
            format!("{what} {value} is beyond any real luminaire (at most {max:e})"),
        ))
    }
}

/// How a file is written. The defaults are what every reader accepts
/// (independent readers refused legal files over these two points).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct WriteOptions {
    /// Free text transliterated to ASCII ("25 °C" → "25 degC", "é" → "e").
    pub ascii_text: bool,
    /// A table mirrored about the C90-C270 plane written over the whole
    /// circle (0°-360°) instead of LM-63's legal 90°-270° range.
    pub full_circle_for_c90_mirror: bool,
}

impl Default for WriteOptions {
    fn default() -> Self {
        WriteOptions {
            ascii_text: true,
            full_circle_for_c90_mirror: true,
        }
    }
}

/// Whether `c` ends a line to some reader or editor: the ASCII and C1
/// controls (NUL makes a file "binary", CR and LF break it), and Unicode's
/// line and paragraph separators (U+2028, U+2029), which word processors
/// paste and transliteration turns into line breaks.
fn breaks_a_line(c: char) -> bool {
    c.is_control() || c == '\u{2028}' || c == '\u{2029}'
}

impl WriteOptions {
    /// A free-text field on one line, in ASCII where asked: the one
    /// sanitiser of free text both writers use. Line breaks and control
    /// characters become spaces, before and after transliteration (which
    /// may itself yield a control character).
    pub fn text(&self, s: &str) -> String {
        let one_line = |t: &str| -> String {
            t.chars()
                .map(|c| if breaks_a_line(c) { ' ' } else { c })
                .collect()
        };
        let line = one_line(s);
        if self.ascii_text && !line.is_ascii() {
            one_line(&deunicode::deunicode_with_tofu(&line, "?"))
        } else {
            line
        }
    }

    /// [`WriteOptions::text`] cut to at most `width` characters (a
    /// fixed-width field of EULUMDAT).
    pub fn text_within(&self, s: &str, width: usize) -> String {
        let t = self.text(s);
        if t.chars().count() <= width {
            t
        } else {
            t.chars()
                .take(width)
                .collect::<String>()
                .trim_end()
                .to_owned()
        }
    }
}

/// Everything but the intensities.
#[derive(Debug, Clone, PartialEq, Default, Serialize)]
pub struct Metadata {
    pub manufacturer: String,
    pub luminaire: String,
    /// IES `[LUMCAT]`, EULUMDAT luminaire number.
    pub catalog_number: String,
    /// IES `[TEST]`, EULUMDAT measurement report number.
    pub test_report: String,
    pub test_lab: String,
    pub issue_date: String,
    /// IES 2019 `[FILEGENINFO]`.
    pub file_generation_info: String,
    /// IES 2019 file-generation type (1.00010 = computer simulation), where
    /// the file says.
    pub file_generation_type: Option<f64>,
    /// Other IES keywords in file order (`[MORE]` lines folded in), and the
    /// EULUMDAT file-name field as `_LDT_FILE_NAME`.
    pub keywords: Vec<(String, String)>,
    pub lamps: Vec<LampSet>,
    /// Absolute photometry: intensities are the luminaire's own, no rated
    /// lamp flux (IES −1 lumens, EULUMDAT negative lamp count).
    pub absolute: bool,
    pub ballast_factor: f64,
    pub input_watts: f64,
    pub luminous_area: Dimensions,
    /// EULUMDAT only: the luminaire body.
    pub luminaire_dimensions: Dimensions,
    /// EULUMDAT type indicator (1 point source rotational, 2 linear, 3 other).
    pub ldt_type: Option<u8>,
    /// EULUMDAT's declared light output ratio LORL (%), as the file states
    /// it (the figures integrate their own from the table; a file whose
    /// two disagree has misread lamp data, see
    /// [`Photometry::consistency_warnings`]).
    pub declared_lor_percent: Option<f64>,
    /// EULUMDAT's declared downward flux fraction DFF (%).
    pub declared_downward_percent: Option<f64>,
    /// IES TILT=INCLUDE data (angles, factors), kept for information: the
    /// table is at the luminaire's nominal tilt.
    pub tilt: Option<(Vec<f64>, Vec<f64>)>,
    /// Things the reader tolerated (clamped negative values, extra data).
    pub warnings: Vec<String>,
}

/// A photometric data set: absolute candela on a full C-γ grid plus
/// metadata.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Photometry {
    pub format: Format,
    /// The symmetry the file declared (or, for a bake, was detected).
    pub symmetry: CPlaneSymmetry,
    pub table: CandelaTable,
    pub meta: Metadata,
}

/// Declared and integrated light output ratios further apart than this
/// (percentage points) are reported: a misread lamp field shows so.
pub const LOR_MISMATCH_POINTS: f64 = 2.0;

/// An alternative lamp set of a luminaire (EULUMDAT's second and later
/// "standard sets of lamps"): the same relative table serves it, scaled
/// to its flux.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LampVariant {
    /// 1-based number of the set in the file.
    pub set: usize,
    pub lamps: LampSet,
    /// The luminaire's flux with this set (lm): the table's flux scaled
    /// by the set's rated flux over the first set's.
    pub luminaire_flux_lm: f64,
    /// Luminaire flux per watt with this set (lm/W), where it gives watts.
    pub efficacy_lm_per_w: Option<f64>,
}

impl Photometry {
    /// The lamp set the table describes: the first. EULUMDAT's further
    /// sets are alternative equipments of the same luminaire, not lamps
    /// added to it ([`Photometry::variants`]); LM-63 has one set.
    pub fn lamp_set(&self) -> Option<&LampSet> {
        self.meta.lamps.first()
    }

    /// Rated lamp flux (lm) of the first lamp set, for relative
    /// photometry: what the candela table is per, what the LOR and a
    /// datasheet's UGR correction divide by.
    pub fn lamp_flux_lm(&self) -> Option<f64> {
        if self.meta.absolute {
            return None;
        }
        self.lamp_set()
            .map(|l| l.flux_lm)
            .filter(|f| f.is_finite() && *f > 0.0)
    }

    /// The luminaire's input power (W): the first lamp set's where it
    /// gives one (EULUMDAT's watts are per set, with ballast), else the
    /// file's input watts (LM-63).
    pub fn power_w(&self) -> Option<f64> {
        let set = self.lamp_set().map(|l| l.watts);
        [set, Some(self.meta.input_watts)]
            .into_iter()
            .flatten()
            .find(|w| w.is_finite() && *w > 0.0)
    }

    /// The lamp sets after the first, each with the luminaire flux and
    /// efficacy it gives (the relative table scaled to its flux).
    pub fn variants(&self) -> Vec<LampVariant> {
        let Some(first) = self.lamp_flux_lm() else {
            return Vec::new();
        };
        let flux = self.table.flux_lm();
        self.meta
            .lamps
            .iter()
            .enumerate()
            .skip(1)
            .map(|(i, l)| {
                let luminaire_flux_lm = flux * l.flux_lm / first;
                LampVariant {
                    set: i + 1,
                    lamps: l.clone(),
                    luminaire_flux_lm,
                    efficacy_lm_per_w: (l.watts.is_finite() && l.watts > 0.0)
                        .then(|| luminaire_flux_lm / l.watts),
                }
            })
            .collect()
    }

    /// What the file states that its own table contradicts, in words with
    /// both numbers: a declared LOR more than [`LOR_MISMATCH_POINTS`] from
    /// the one integrated from the table over the first lamp set's flux.
    pub fn consistency_warnings(&self) -> Vec<String> {
        let mut out = Vec::new();
        if let (Some(declared), Some(lamp)) = (self.meta.declared_lor_percent, self.lamp_flux_lm())
        {
            let computed = 100.0 * self.table.flux_lm() / lamp;
            if declared > 0.0
                && computed.is_finite()
                && (declared - computed).abs() > LOR_MISMATCH_POINTS
            {
                out.push(format!(
                    "the file declares LOR {declared:.1} % but its table gives {computed:.1} % of lamp set 1's {lamp:.0} lm: its lamp data may be misread or inconsistent"
                ));
            }
        }
        out
    }

    /// The derived datasheet figures.
    pub fn figures(&self) -> crate::figures::Figures {
        crate::figures::figures(&self.table, self.lamp_flux_lm())
    }
}

/// Expands the C-planes a symmetric file stores to the whole circle:
/// every stored plane is copied to its images under `symmetry`; planes
/// that coincide (C360 = C0) keep the first stored.
pub fn expand_planes(
    symmetry: CPlaneSymmetry,
    stored_c_deg: &[f64],
    rows: &[Vec<f64>],
) -> (Vec<f64>, Vec<Vec<f64>>) {
    if symmetry == CPlaneSymmetry::Rotational {
        return (vec![0.0], vec![rows[0].clone()]);
    }
    // Every image of every stored plane, sorted, the first of equal angles
    // kept (a stored plane before a mirrored one): n log n for files of
    // thousands of planes. Images closer than half the closest spacing a
    // file may have are one plane: printed with 10 digits, 180° − C of a
    // stored plane lands 10⁻⁸° from the plane stored for it.
    let same = crate::limits::MIN_ANGLE_STEP_DEG / 2.0;
    // (angle, 0 for the stored plane itself and 1 for an image, index).
    let mut images: Vec<(f64, u8, usize)> = Vec::new();
    for (i, &c) in stored_c_deg.iter().enumerate() {
        for (k, image) in symmetry.images(c).into_iter().enumerate() {
            let image = if (image - 360.0).abs() < same {
                0.0
            } else {
                image
            };
            images.push((image, u8::from(k != 0), i));
        }
    }
    images.sort_by(|a, b| a.0.total_cmp(&b.0));
    // Runs of angles closer than `same` are one plane: the stored plane
    // itself where the run has one (the first stored), else the image of
    // the first stored plane.
    let mut planes: Vec<(f64, usize)> = Vec::new();
    let mut k = 0;
    while k < images.len() {
        let mut end = k + 1;
        while end < images.len() && images[end].0 - images[end - 1].0 < same {
            end += 1;
        }
        let chosen = images[k..end]
            .iter()
            .min_by_key(|x| (x.1, x.2))
            .unwrap_or(&images[k]);
        planes.push((chosen.0, chosen.2));
        k = end;
    }
    (
        planes.iter().map(|p| p.0).collect(),
        planes.iter().map(|p| rows[p.1].clone()).collect(),
    )
}

/// A table read with `symmetry` that does not have it (a file whose
/// stored planes include two images of one another with other values):
/// averaged over the symmetry, with a warning, so that what the file
/// declares and what the table holds agree, as every writer assumes.
pub(crate) fn consistent_with(
    symmetry: CPlaneSymmetry,
    table: CandelaTable,
    warnings: &mut Vec<String>,
) -> CandelaTable {
    if symmetry == CPlaneSymmetry::None || table.c_planes_deg.len() == 1 {
        return table;
    }
    let asymmetry = table.asymmetry(symmetry);
    if asymmetry <= 1e-9 {
        return table;
    }
    warnings.push(format!(
        "the stored C-planes disagree with the declared symmetry ({}) by up to {:.1} % of the peak: averaged over it",
        symmetry.describe(),
        100.0 * asymmetry
    ));
    table.symmetrised(symmetry)
}

/// Reading failed: which format, where, and what was wrong.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{format}{}: {message}", line.map(|l| format!(" line {l}")).unwrap_or_default())]
pub struct ParsePhotometryError {
    /// "IES", "EULUMDAT" or "photometric file".
    pub format: &'static str,
    pub line: Option<usize>,
    pub message: String,
}

impl ParsePhotometryError {
    pub(crate) fn new(
        format: &'static str,
        line: Option<usize>,
        message: impl Into<String>,
    ) -> Self {
        ParsePhotometryError {
            format,
            line,
            message: message.into(),
        }
    }
}
