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
}

impl std::fmt::Display for Format {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Format::Ies(year) => write!(f, "IES LM-63-{year}"),
            Format::Eulumdat => write!(f, "EULUMDAT"),
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

/// What a photometric file may hold before it is taken for corrupt (the
/// readers refuse beyond, naming the field; the writers never get there).
pub mod plausible {
    /// Lengths of luminaires and openings (m).
    pub const MAX_DIMENSION_M: f64 = 1000.0;
    /// Lamps in a luminaire or a lamp set.
    pub const MAX_LAMPS: f64 = 1e6;
    /// Flux of a lamp set or a lamp (lm).
    pub const MAX_FLUX_LM: f64 = 1e10;
    /// Input power (W).
    pub const MAX_WATTS: f64 = 1e9;
    /// Closest γ or C angles (degrees): printed with 8 significant digits,
    /// angles this far apart stay apart, and in radians they differ.
    pub const MIN_ANGLE_STEP_DEG: f64 = 1e-4;
}

/// A value read from a file, refused unless its magnitude is at most
/// `max`: `what` names the field.
pub(crate) fn plausible_magnitude(
    format: &'static str,
    line: usize,
    what: &str,
    value: f64,
    max: f64,
) -> Result<f64, ParsePhotometryError> {
    if value.is_finite() && value.abs() <= max {
        Ok(value)
    } else {
        Err(ParsePhotometryError::new(
            format,
            Some(line),
            format!("{what} {value} is beyond any real luminaire (at most {max:e})"),
        ))
    }
}

/// Line ends as `\n`: files from old Macs end lines with a lone CR, which
/// `str::lines` would not split.
pub(crate) fn normalise_line_ends(text: &str) -> std::borrow::Cow<'_, str> {
    if text.contains('\r') {
        std::borrow::Cow::Owned(text.replace("\r\n", "\n").replace('\r', "\n"))
    } else {
        std::borrow::Cow::Borrowed(text)
    }
}

/// Why a file was not written: it would hold what its own reader refuses.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum WritePhotometryError {
    #[error("{format} holds at most {max} {what}; this table has {got}")]
    TooMany {
        format: &'static str,
        what: &'static str,
        max: usize,
        got: usize,
    },
    #[error("{what} is {value}, which {format} files cannot hold")]
    Value {
        format: &'static str,
        what: String,
        value: f64,
    },
    #[error(
        "{what} {a}° and {b}° are too close to be told apart in a file (at least 0.0001° apart)"
    )]
    Angles { what: &'static str, a: f64, b: f64 },
}

/// Checks the angles a writer is about to print with `significant`
/// digits: they must read back distinct and ascending, at least
/// [`plausible::MIN_ANGLE_STEP_DEG`] apart.
pub(crate) fn check_printed_angles(
    what: &'static str,
    angles: &[f64],
    significant: usize,
) -> Result<(), WritePhotometryError> {
    let printed: Vec<f64> = angles
        .iter()
        .map(|&a| format_number(a, significant).parse().unwrap_or(f64::NAN))
        .collect();
    for (i, w) in printed.windows(2).enumerate() {
        let apart = w[1] - w[0] >= plausible::MIN_ANGLE_STEP_DEG;
        if !apart {
            return Err(WritePhotometryError::Angles {
                what,
                a: angles[i],
                b: angles[i + 1],
            });
        }
    }
    Ok(())
}

/// Refuses a non-finite or implausibly large value a writer would print.
pub(crate) fn check_written(
    format: &'static str,
    what: &str,
    value: f64,
    max: f64,
) -> Result<(), WritePhotometryError> {
    if value.is_finite() && value.abs() <= max {
        Ok(())
    } else {
        Err(WritePhotometryError::Value {
            format,
            what: what.to_owned(),
            value,
        })
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

impl Photometry {
    /// Total rated lamp flux (lm) for relative photometry.
    pub fn lamp_flux_lm(&self) -> Option<f64> {
        if self.meta.absolute {
            return None;
        }
        let total: f64 = self.meta.lamps.iter().map(|l| l.flux_lm).sum();
        (total > 0.0).then_some(total)
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
    // thousands of planes.
    let mut planes: Vec<(f64, usize)> = Vec::new();
    for (i, &c) in stored_c_deg.iter().enumerate() {
        for image in symmetry.images(c) {
            let image = if (image - 360.0).abs() < 1e-9 {
                0.0
            } else {
                image
            };
            planes.push((image, i));
        }
    }
    planes.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)));
    planes.dedup_by(|later, kept| (later.0 - kept.0).abs() < 1e-9);
    (
        planes.iter().map(|p| p.0).collect(),
        planes.iter().map(|p| rows[p.1].clone()).collect(),
    )
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

/// Decodes file bytes: UTF-8 where valid, else Latin-1 (old EULUMDAT and
/// IES files from European tools), which maps every byte to a character.
pub fn decode_text(bytes: &[u8]) -> String {
    match std::str::from_utf8(bytes) {
        Ok(s) => s.trim_start_matches('\u{feff}').to_owned(),
        Err(_) => bytes.iter().map(|&b| char::from(b)).collect(),
    }
}

/// Tells IES from EULUMDAT by content: IES files open with `IESNA`/`IES:`
/// (LM-63-1991 and later) or, in 1986 files, have a `TILT=` line before
/// their data; EULUMDAT has numbers on lines 2–7 and at least 42 lines.
/// EULUMDAT is recognised first, since its free-text lines may contain
/// anything, `TILT=` included.
pub fn sniff(text: &str) -> Option<Format> {
    let text = normalise_line_ends(text);
    let lines: Vec<&str> = text.lines().take(64).collect();
    // EULUMDAT first: numbers on lines 2-7 (an IES file has keywords or
    // its TILT line there), whatever its company line says: "IESNA
    // Lighting" is a fine company name.
    let numeric = lines
        .iter()
        .skip(1)
        .take(6)
        .filter(|l| {
            l.trim()
                .replace(',', ".")
                .parse::<f64>()
                .is_ok_and(|v| v.is_finite())
        })
        .count();
    if numeric == 6 && text.lines().count() >= 42 {
        return Some(Format::Eulumdat);
    }
    let first = lines.first().unwrap_or(&"").trim().to_ascii_uppercase();
    if first.starts_with("IESNA") || first.starts_with("IES:") {
        return Some(Format::Ies(0));
    }
    let is_tilt = |l: &str| {
        let l = l.trim_start().to_ascii_uppercase();
        l.strip_prefix("TILT")
            .is_some_and(|r| r.trim_start().starts_with('='))
    };
    text.lines()
        .take(2000)
        .any(is_tilt)
        .then_some(Format::Ies(0))
}

/// Reads an IES or EULUMDAT file from its bytes, whatever its extension.
pub fn read_photometry(bytes: &[u8]) -> Result<Photometry, ParsePhotometryError> {
    if bytes.is_empty() {
        return Err(ParsePhotometryError::new(
            "photometric file",
            None,
            "the file is empty",
        ));
    }
    if bytes.iter().take(4096).filter(|&&b| b == 0).count() > 0 {
        return Err(ParsePhotometryError::new(
            "photometric file",
            None,
            "binary data (NUL bytes): not an IES or EULUMDAT text file",
        ));
    }
    let text = decode_text(bytes);
    match sniff(&text) {
        Some(Format::Ies(_)) => crate::ies::parse_ies(&text),
        Some(Format::Eulumdat) => crate::ldt::parse_ldt(&text),
        None => Err(ParsePhotometryError::new(
            "photometric file",
            None,
            "neither IES LM-63 (no TILT= line) nor EULUMDAT (lines 2-7 are not numbers)",
        )),
    }
}

/// Formats a number with at most `significant` significant digits and no
/// trailing zeros (files stay short and are read back exactly as printed).
pub fn format_number(v: f64, significant: usize) -> String {
    if v == 0.0 || !v.is_finite() {
        // Writers refuse non-finite values before they get here.
        return "0".to_owned();
    }
    let magnitude = v.abs().log10().floor() as i32;
    if !(-6..12).contains(&magnitude) {
        // Far from 1, positional notation would print zero or hundreds of
        // digits: scientific notation, which every reader's strtod takes.
        let s = format!("{v:.*e}", significant.saturating_sub(1));
        let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
        let mantissa = if mantissa.contains('.') {
            mantissa.trim_end_matches('0').trim_end_matches('.')
        } else {
            mantissa
        };
        return format!("{mantissa}e{exponent}");
    }
    let decimals = (significant as i32 - 1 - magnitude).clamp(0, 12) as usize;
    let s = format!("{v:.decimals$}");
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_owned()
    } else {
        s
    };
    if s == "-0" { "0".to_owned() } else { s }
}
