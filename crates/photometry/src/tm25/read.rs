//! Reading a TM-25 file: every field checked, every size checked against
//! the file's own length before anything is allocated, the rays read
//! straight into their one buffer.

use std::io::Read;
use std::path::Path;

use super::luminous::LuminousRule;
use super::{
    COLUMN_NAME_BYTES, CreationMethod, Description, FILE_HEADER_BYTES, KnownData, MAGIC,
    RayFileHeader, RaySet, SpectralTable, SpectrumType, TEXT_FIELD_CHARS, VERSION,
};

/// Largest ray file read: 20 M rays of 12 columns, with room to spare.
/// The rays are held once, so this bounds the memory a file can take.
pub const MAX_RAY_FILE_BYTES: u64 = 1 << 30;
/// Most spectral tables, and wavelengths in one, additional columns:
/// far beyond any real file, small enough to refuse absurd counts early.
const MAX_SPECTRAL_TABLES: i32 = 100_000;
const MAX_TABLE_ENTRIES: i32 = 1_000_000;
const MAX_ADDITIONAL_COLUMNS: i32 = 1_000;
/// Bytes read at a time into the ray buffer.
const BLOCK_BYTES: usize = 1 << 22;

#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReadRayFileError {
    #[error("cannot read ray file {file}")]
    Io {
        file: String,
        #[source]
        source: std::io::Error,
    },
    #[error(
        "ray file {file} is {bytes} bytes, more than the {max} bytes (1 GiB) Lucerna reads; a ray file's rays are held in memory"
    )]
    TooLarge { file: String, bytes: u64, max: u64 },
    #[error("ray file {file}: {field}: {message}")]
    Format {
        file: String,
        field: &'static str,
        message: String,
    },
}

/// Reads and checks a TM-25 file.
pub fn read_ray_file(path: &Path) -> Result<RaySet, ReadRayFileError> {
    let file = path.display().to_string();
    let io = |source| ReadRayFileError::Io {
        file: file.clone(),
        source,
    };
    let handle = std::fs::File::open(path).map_err(io)?;
    let bytes = handle.metadata().map_err(io)?.len();
    parse(std::io::BufReader::new(handle), bytes, &file)
}

/// The luminous flux a ray file gives its emitter where a scene states
/// none (lm): its header's where it states one (the maker's figure), else
/// the rays' sum (a radiometric file weighed by V(λ)); the header alone
/// is read where it suffices, so a scene naming a 500 MB file loads at
/// once.
pub fn ray_file_luminous_flux(path: &Path) -> Result<f64, ReadRayFileError> {
    let file = path.display().to_string();
    let io = |source| ReadRayFileError::Io {
        file: file.clone(),
        source,
    };
    let mut handle = std::fs::File::open(path).map_err(io)?;
    let mut head = [0u8; 16];
    if handle.read_exact(&mut head).is_ok() && head[..4] == MAGIC {
        let stated = f32::from_le_bytes([head[12], head[13], head[14], head[15]]);
        if stated.is_finite() && stated > 0.0 {
            return Ok(f64::from(stated));
        }
    }
    Ok(read_ray_file(path)?.total_luminous_flux_lm())
}

/// Parses a TM-25 file held in memory (`name` for messages).
pub fn parse_ray_file(bytes: &[u8], name: &str) -> Result<RaySet, ReadRayFileError> {
    parse(bytes, bytes.len() as u64, name)
}

/// A reader that knows how much is left and names what it reads.
struct Fields<'a, R> {
    reader: R,
    left: u64,
    file: &'a str,
}

impl<R: Read> Fields<'_, R> {
    fn error(&self, field: &'static str, message: impl Into<String>) -> ReadRayFileError {
        ReadRayFileError::Format {
            file: self.file.to_owned(),
            field,
            message: message.into(),
        }
    }

    fn bytes(&mut self, field: &'static str, n: usize) -> Result<Vec<u8>, ReadRayFileError> {
        if (n as u64) > self.left {
            return Err(self.error(
                field,
                format!(
                    "the file ends here: {n} bytes wanted, {} left (truncated?)",
                    self.left
                ),
            ));
        }
        let mut buf = vec![0; n];
        self.reader
            .read_exact(&mut buf)
            .map_err(|e| self.error(field, format!("cannot read: {e}")))?;
        self.left -= n as u64;
        Ok(buf)
    }

    fn array<const N: usize>(&mut self, field: &'static str) -> Result<[u8; N], ReadRayFileError> {
        let v = self.bytes(field, N)?;
        let mut a = [0; N];
        a.copy_from_slice(&v);
        Ok(a)
    }

    fn i32(&mut self, field: &'static str) -> Result<i32, ReadRayFileError> {
        Ok(i32::from_le_bytes(self.array(field)?))
    }

    fn u64(&mut self, field: &'static str) -> Result<u64, ReadRayFileError> {
        Ok(u64::from_le_bytes(self.array(field)?))
    }

    fn f32(&mut self, field: &'static str) -> Result<f32, ReadRayFileError> {
        Ok(f32::from_le_bytes(self.array(field)?))
    }

    /// A flux or wavelength: NaN is "unknown", anything else must be
    /// finite and not negative (0 is read as unknown too, as some makers
    /// write it).
    fn optional_positive(&mut self, field: &'static str) -> Result<Option<f32>, ReadRayFileError> {
        let v = self.f32(field)?;
        if v.is_nan() || v == 0.0 {
            Ok(None)
        } else if v.is_finite() && v > 0.0 {
            Ok(Some(v))
        } else {
            Err(self.error(field, format!("must be positive or NaN (unknown), got {v}")))
        }
    }

    fn flag(&mut self, field: &'static str) -> Result<bool, ReadRayFileError> {
        match self.i32(field)? {
            0 => Ok(false),
            1 => Ok(true),
            v => Err(self.error(field, format!("must be 0 or 1, got {v}"))),
        }
    }

    /// UTF-32 text of `chars` characters, up to its first NUL.
    fn text(&mut self, field: &'static str, chars: usize) -> Result<String, ReadRayFileError> {
        let raw = self.bytes(field, 4 * chars)?;
        Ok(raw
            .chunks_exact(4)
            .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
            .take_while(|&c| c != 0)
            .map(|c| char::from_u32(c).unwrap_or(char::REPLACEMENT_CHARACTER))
            .collect())
    }
}

fn parse(reader: impl Read + Send, file_len: u64, file: &str) -> Result<RaySet, ReadRayFileError> {
    if file_len > MAX_RAY_FILE_BYTES {
        return Err(ReadRayFileError::TooLarge {
            file: file.to_owned(),
            bytes: file_len,
            max: MAX_RAY_FILE_BYTES,
        });
    }
    let mut f = Fields {
        reader,
        left: file_len,
        file,
    };
    // 4.7.1 file header block.
    let magic: [u8; 4] = f.array("file type (4.7.1.1)")?;
    if magic != MAGIC {
        return Err(f.error(
            "file type (4.7.1.1)",
            format!(
                "not a TM-25 ray file: it starts with {:?}, not \"TM25\"",
                String::from_utf8_lossy(&magic)
            ),
        ));
    }
    let version = f.i32("file version (4.7.1.2)")?;
    if version != VERSION {
        return Err(f.error(
            "file version (4.7.1.2)",
            format!("must be {VERSION}, got {version}"),
        ));
    }
    let creation_method = CreationMethod::from_code(f.i32("creation method (4.7.1.3)")?);
    let luminous_flux_lm = f.optional_positive("luminous flux (4.7.1.4)")?;
    let radiant_flux_w = f.optional_positive("radiant flux (4.7.1.5)")?;
    let ray_count = f.u64("number of rays (4.7.1.6)")?;
    let date: [u8; 28] = f.array("date and time (4.7.1.7)")?;
    let date_time = String::from_utf8_lossy(&date)
        .trim_end_matches('\0')
        .to_owned();
    let start_position = f.i32("ray start position (4.7.1.8)")?;
    let spectrum_code = f.i32("spectral data identifier (4.7.1.9)")?;
    let spectrum = SpectrumType::from_code(spectrum_code).ok_or_else(|| {
        f.error(
            "spectral data identifier (4.7.1.9)",
            format!("must be 0 to 4, got {spectrum_code}"),
        )
    })?;
    let wavelength_nm = f.optional_positive("single wavelength (4.7.1.10)")?;
    let min_wavelength_nm = f.optional_positive("minimum wavelength (4.7.1.11)")?;
    let max_wavelength_nm = f.optional_positive("maximum wavelength (4.7.1.12)")?;
    let table_count = f.i32("number of spectral tables (4.7.1.13)")?;
    let column_count = f.i32("number of additional ray data items (4.7.1.14)")?;
    let text_bytes = f.i32("size of the additional text block (4.7.1.15)")?;
    f.bytes("reserved (4.7.1.16)", FILE_HEADER_BYTES - 88)?;
    if !(0..=MAX_SPECTRAL_TABLES).contains(&table_count) {
        return Err(f.error(
            "number of spectral tables (4.7.1.13)",
            format!("must be 0 to {MAX_SPECTRAL_TABLES}, got {table_count}"),
        ));
    }
    if !(0..=MAX_ADDITIONAL_COLUMNS).contains(&column_count) {
        return Err(f.error(
            "number of additional ray data items (4.7.1.14)",
            format!("must be 0 to {MAX_ADDITIONAL_COLUMNS}, got {column_count}"),
        ));
    }
    if text_bytes < 0 || text_bytes % 4 != 0 || i64::from(text_bytes) > f.left as i64 {
        return Err(f.error(
            "size of the additional text block (4.7.1.15)",
            format!(
                "must be a multiple of 4 that the file holds, got {text_bytes} with {} bytes left",
                f.left
            ),
        ));
    }
    if spectrum == SpectrumType::SingleWavelength && wavelength_nm.is_none() {
        return Err(f.error(
            "single wavelength (4.7.1.10)",
            "a single-wavelength file (spectral identifier 1) must give the wavelength",
        ));
    }
    if matches!(spectrum, SpectrumType::Table | SpectrumType::PerRayTable) && table_count == 0 {
        return Err(f.error(
            "number of spectral tables (4.7.1.13)",
            format!("spectral identifier {spectrum_code} needs spectral tables, the file has none"),
        ));
    }
    // 4.7.2 known data flags.
    for field in ["position flag (4.7.2.1)", "direction flag (4.7.2.2)"] {
        let v = f.i32(field)?;
        if v != 1 {
            return Err(f.error(field, format!("must be 1 (every ray has one), got {v}")));
        }
    }
    let known = KnownData {
        radiant_flux: f.flag("radiant flux flag (4.7.2.3)")?,
        wavelength: f.flag("wavelength flag (4.7.2.4)")?,
        luminous_flux: f.flag("luminous flux flag (4.7.2.5)")?,
        stokes: f.flag("Stokes flag (4.7.2.6)")?,
        tristimulus: f.flag("tristimulus flag (4.7.2.7)")?,
        spectrum_index: f.flag("spectrum index flag (4.7.2.8)")?,
    };
    if !(known.radiant_flux || known.luminous_flux) {
        return Err(f.error(
            "flux flags (4.7.2.3, 4.7.2.5)",
            "the rays carry neither radiant nor luminous flux",
        ));
    }
    if spectrum == SpectrumType::PerRayWavelength && !known.wavelength {
        return Err(f.error(
            "wavelength flag (4.7.2.4)",
            "spectral identifier 2 (a wavelength per ray) needs the wavelength column",
        ));
    }
    if known.spectrum_index != (spectrum == SpectrumType::PerRayTable) {
        return Err(f.error(
            "spectrum index flag (4.7.2.8)",
            format!(
                "is {} but the spectral identifier is {spectrum_code}: the index column goes with identifier 4 only",
                u8::from(known.spectrum_index)
            ),
        ));
    }
    // 4.7.3 description.
    let mut texts = Vec::with_capacity(9);
    for name in [
        "name (4.7.3.1)",
        "manufacturer (4.7.3.2)",
        "model creator (4.7.3.3)",
        "ray file creator (4.7.3.4)",
        "equipment (4.7.3.5)",
        "camera (4.7.3.6)",
        "light source operation (4.7.3.7)",
        "additional information (4.7.3.8)",
        "data reference (4.7.3.9)",
    ] {
        texts.push(f.text(name, TEXT_FIELD_CHARS)?);
    }
    let mut texts = texts.into_iter();
    let mut next = || texts.next().unwrap_or_default();
    let description = Description {
        name: next(),
        manufacturer: next(),
        model_creator: next(),
        ray_file_creator: next(),
        equipment: next(),
        camera: next(),
        operation: next(),
        additional_info: next(),
        data_reference: next(),
    };
    // 4.7.4 spectral tables, padded to 32 bytes.
    let mut spectral_tables = Vec::with_capacity(table_count as usize);
    let mut table_bytes = 0u64;
    for _ in 0..table_count {
        let entries = f.i32("spectral table size (4.7.4)")?;
        if !(1..=MAX_TABLE_ENTRIES).contains(&entries) {
            return Err(f.error(
                "spectral table size (4.7.4)",
                format!("must be 1 to {MAX_TABLE_ENTRIES} pairs, got {entries}"),
            ));
        }
        if (entries as u64) * 8 > f.left {
            return Err(f.error(
                "spectral table size (4.7.4)",
                format!(
                    "{entries} pairs need {} bytes, the file holds {} (truncated inside the spectral table)",
                    entries as u64 * 8,
                    f.left
                ),
            ));
        }
        let mut table = SpectralTable::default();
        for _ in 0..entries {
            let wavelength = f.f32("spectral table wavelength (4.7.4)")?;
            let weight = f.f32("spectral table weight (4.7.4)")?;
            if !(wavelength.is_finite() && wavelength > 0.0 && weight.is_finite() && weight >= 0.0)
            {
                return Err(f.error(
                    "spectral table (4.7.4)",
                    format!("wavelength {wavelength} nm, weight {weight}: wavelengths must be positive, weights not negative"),
                ));
            }
            table.wavelengths_nm.push(wavelength);
            table.weights.push(weight);
        }
        table_bytes += 4 + 8 * entries as u64;
        spectral_tables.push(table);
    }
    if !table_bytes.is_multiple_of(32) {
        f.bytes(
            "spectral table padding (4.7.4)",
            (32 - table_bytes % 32) as usize,
        )?;
    }
    // The rays' columns, and where the rest of the file must end.
    let ray_bytes_for = |columns: usize| {
        ray_count
            .checked_mul(columns as u64)
            .and_then(|v| v.checked_mul(4))
    };
    let standard = super::Columns::of(&known, 0).count;
    let total_columns = standard + column_count as usize;
    let names_bytes = column_count as u64 * COLUMN_NAME_BYTES as u64;
    let after_names = f.left.saturating_sub(names_bytes + text_bytes as u64);
    // Makers differ on the column-name block: read it when the file
    // holds it, else name the columns by number.
    let names_written = ray_bytes_for(total_columns) == Some(after_names);
    let names_missing = column_count > 0
        && ray_bytes_for(total_columns) == Some(f.left.saturating_sub(text_bytes as u64));
    let additional_columns: Vec<String> = if names_written {
        let mut names = Vec::with_capacity(column_count as usize);
        for _ in 0..column_count {
            names.push(f.text("additional column name (4.7.5)", COLUMN_NAME_BYTES / 4)?);
        }
        names
    } else if names_missing {
        (1..=column_count).map(|k| format!("column {k}")).collect()
    } else {
        let rays_left = f.left.saturating_sub(names_bytes + text_bytes as u64);
        // 4 bytes a value: a count of 2⁶² rays or more has no size.
        let bytes_per_column = ray_count.checked_mul(4).filter(|&b| b > 0);
        let whole = bytes_per_column.filter(|&b| rays_left > 0 && rays_left.is_multiple_of(b));
        let message = match ray_bytes_for(total_columns) {
            None => format!("{ray_count} rays cannot be held in any file"),
            Some(_) if whole.is_some() => format!(
                "the flags announce {total_columns} values per ray, but the file holds {} per ray for {ray_count} rays",
                rays_left / whole.unwrap_or(1)
            ),
            Some(need) if need > rays_left => format!(
                "{ray_count} rays of {total_columns} values need {need} bytes, the file holds {rays_left} (truncated, or a wrong ray count)"
            ),
            Some(need) => format!(
                "{ray_count} rays of {total_columns} values need {need} bytes, the file holds {rays_left}: bytes left over"
            ),
        };
        return Err(f.error("ray data (4.7.7)", message));
    };
    let additional_text = if text_bytes > 0 {
        f.text("additional text (4.7.6)", text_bytes as usize / 4)?
    } else {
        String::new()
    };
    if ray_count == 0 {
        return Err(f.error("number of rays (4.7.1.6)", "the file has no rays"));
    }
    let header = RayFileHeader {
        creation_method,
        luminous_flux_lm,
        radiant_flux_w,
        ray_count,
        date_time,
        start_position,
        spectrum,
        wavelength_nm,
        min_wavelength_nm,
        max_wavelength_nm,
        known,
        description,
        spectral_tables,
        additional_columns,
        additional_text,
    };
    let columns = header.columns();
    let spectral_count = header.spectral_tables.len();
    let rule = LuminousRule::of(&header, &columns).ok_or_else(|| {
        f.error(
            "flux columns (4.7.2)",
            "the spectrum type needs a column the flags do not announce",
        )
    })?;
    // The rays, straight into their buffer: the file's little-endian
    // floats are read as the buffer's bytes (bytemuck's safe view), in
    // blocks of whole rays, and turned round only on a big-endian
    // machine. While a block is read the one before is checked on the
    // other core (a 20 M-ray file is 20 M checks): a ray that fails
    // reads as NaN there, and the first of them is checked again below
    // for its message, so the error names the same ray however the
    // threads ran.
    let values = ray_count as usize * columns.count;
    let mut records: Vec<f32> = vec![0.0; values];
    let mut luminous_flux_lm: Vec<f32> = vec![0.0; ray_count as usize];
    let block_values = (BLOCK_BYTES / (4 * columns.count)).max(1) * columns.count;
    let check = |block: &[f32], fluxes: &mut [f32]| {
        for (record, flux) in block.chunks_exact(columns.count).zip(fluxes) {
            *flux = ray_flux(&columns, spectral_count, &rule, record).unwrap_or(f32::NAN);
        }
    };
    let mut pending: Option<(&mut [f32], &mut [f32])> = None;
    for (block, fluxes) in records
        .chunks_mut(block_values)
        .zip(luminous_flux_lm.chunks_mut(block_values / columns.count))
    {
        let reader = &mut f.reader;
        let mut read = |block: &mut [f32]| {
            reader.read_exact(bytemuck::cast_slice_mut::<f32, u8>(block))?;
            if cfg!(target_endian = "big") {
                block
                    .iter_mut()
                    .for_each(|v| *v = f32::from_bits(v.to_bits().swap_bytes()));
            }
            Ok::<(), std::io::Error>(())
        };
        let got = match pending.take() {
            Some((before, its_fluxes)) => {
                rayon::join(|| read(block), || check(before, its_fluxes)).0
            }
            None => read(block),
        };
        got.map_err(|e| ReadRayFileError::Format {
            file: file.to_owned(),
            field: "ray data (4.7.7)",
            message: format!("cannot read: {e}"),
        })?;
        pending = Some((block, fluxes));
    }
    if let Some((block, fluxes)) = pending {
        check(block, fluxes);
    }
    if let Some(i) = luminous_flux_lm.iter().position(|f| f.is_nan()) {
        let record = &records[i * columns.count..(i + 1) * columns.count];
        let what = ray_flux(&columns, spectral_count, &rule, record)
            .err()
            .unwrap_or_else(|| "its luminous flux is not a number".to_owned());
        return Err(ReadRayFileError::Format {
            file: file.to_owned(),
            field: "ray data (4.7.7)",
            message: format!("ray {i}: {what}"),
        });
    }
    let set = RaySet {
        header,
        records,
        luminous_flux_lm,
    };
    if !(set.total_luminous_flux_lm() > 0.0) {
        return Err(ReadRayFileError::Format {
            file: file.to_owned(),
            field: "ray data (4.7.7)",
            message: "the rays carry no flux (every ray's flux is 0)".to_owned(),
        });
    }
    Ok(set)
}

/// A ray's luminous flux (lm), or what is wrong with it.
fn ray_flux(
    columns: &super::Columns,
    tables: usize,
    rule: &LuminousRule,
    record: &[f32],
) -> Result<f32, String> {
    if !record[..6].iter().all(|v| v.is_finite()) {
        return Err(format!(
            "position or direction is not finite: {:?}",
            &record[..6]
        ));
    }
    if record[3] == 0.0 && record[4] == 0.0 && record[5] == 0.0 {
        return Err("its direction is the zero vector".to_owned());
    }
    if let Some(problem) = column_problem(columns, tables, record) {
        return Err(problem);
    }
    let flux = rule
        .flux(record)
        .ok_or_else(|| "its spectrum index names no spectral table".to_owned())?;
    let flux32 = flux as f32;
    if !(flux.is_finite() && flux >= 0.0 && flux32.is_finite()) {
        return Err(format!(
            "its luminous flux must be finite and not negative, got {flux} lm"
        ));
    }
    Ok(flux32)
}

/// What is wrong with a ray's flagged columns, if anything: every flux
/// finite and not negative, a wavelength finite and positive, Stokes and
/// tristimulus values finite, a spectrum index a whole number naming one
/// of the file's tables (from 1) (the column a file's flux is read from and the
/// others alike: a file is refused, not half read).
fn column_problem(columns: &super::Columns, tables: usize, record: &[f32]) -> Option<String> {
    let value = |k: Option<usize>| k.map(|k| record[k]);
    if let Some(w) = value(columns.radiant_flux)
        && !(w.is_finite() && w >= 0.0)
    {
        return Some(format!(
            "radiant flux must be finite and not negative, got {w} W"
        ));
    }
    if let Some(l) = value(columns.luminous_flux)
        && !(l.is_finite() && l >= 0.0)
    {
        return Some(format!(
            "luminous flux must be finite and not negative, got {l} lm"
        ));
    }
    if let Some(nm) = value(columns.wavelength)
        && !(nm.is_finite() && nm > 0.0)
    {
        return Some(format!(
            "wavelength must be finite and positive, got {nm} nm"
        ));
    }
    for (name, at, n) in [
        ("Stokes", columns.stokes, 3),
        ("tristimulus", columns.tristimulus, 2),
    ] {
        if let Some(k) = at
            && let Some(v) = record[k..k + n].iter().find(|v| !v.is_finite())
        {
            return Some(format!("its {name} values must be finite, got {v}"));
        }
    }
    if let Some(i) = value(columns.spectrum_index)
        && !(i.is_finite() && i.fract() == 0.0 && i >= 1.0 && (i as usize) <= tables)
    {
        return Some(format!(
            "its spectrum index {i} names none of the file's {tables} spectral tables"
        ));
    }
    None
}
