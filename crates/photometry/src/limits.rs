//! What a photometric file may hold: the one set of limits every reader
//! checks (refusing beyond, naming the field) and every writer applies to
//! the values as they will read back, before it writes (rounding in the
//! safe direction, or refusing with a [`WritePhotometryError`] that says
//! why). A file Lucerna writes is never one its readers refuse.

use crate::text::format_number;

/// Lengths of luminaires and openings (m).
pub const MAX_DIMENSION_M: f64 = 1000.0;
/// Lamps in a luminaire or a lamp set.
pub const MAX_LAMPS: f64 = 1e6;
/// Flux of a lamp set or a lamp (lm).
pub const MAX_FLUX_LM: f64 = 1e10;
/// Input power (W).
pub const MAX_WATTS: f64 = 1e9;
/// Closest γ or C angles (degrees): printed with 10 significant digits,
/// angles this far apart stay apart, and in radians they differ.
pub const MIN_ANGLE_STEP_DEG: f64 = 1e-4;
/// Largest plausible intensity (cd): the brightest searchlights reach
/// about 10⁹ cd; anything far beyond is a corrupt file.
pub const MAX_CANDELA: f64 = 1e12;
/// C-planes and γ angles an EULUMDAT file may list (Mc, Ng).
pub const LDT_MAX_ANGLES: usize = 3600;
/// Lamp sets an EULUMDAT file may list.
pub const LDT_MAX_LAMP_SETS: usize = 20;
/// Vertical or horizontal angles (and tilt pairs) an LM-63 file may list.
pub const IES_MAX_ANGLES: usize = 10_000;
/// The longest line LM-63 allows (lines under 256 characters).
pub const IES_MAX_LINE_CHARS: usize = 255;
/// Significant digits the writers print angles with.
pub const ANGLE_DIGITS: usize = 10;
/// Significant digits the writers print intensities with.
pub const INTENSITY_DIGITS: usize = 6;
/// Significant digits the writers print lamp fluxes with.
pub const FLUX_DIGITS: usize = 7;

/// Slack a reader allows below [`MIN_ANGLE_STEP_DEG`]: the images of
/// printed angles under a symmetry (180° − C, 360° − C) are computed in
/// floating point, which moves a spacing of exactly 0.0001° by up to
/// 10⁻¹³°. The writers give no slack ([`printed_apart`]).
const ANGLE_SLACK_DEG: f64 = 1e-9;

/// Whether two ascending angles are far enough apart for a reader (and a
/// table).
pub fn apart(a: f64, b: f64) -> bool {
    b - a >= MIN_ANGLE_STEP_DEG - ANGLE_SLACK_DEG
}

/// Whether two ascending angles, as printed, are far enough apart for a
/// writer: the full [`MIN_ANGLE_STEP_DEG`], so that their images under
/// any symmetry stay apart for the reader.
pub fn printed_apart(a: f64, b: f64) -> bool {
    b - a >= MIN_ANGLE_STEP_DEG
}

/// Whether a value's magnitude is within `max` (and finite).
pub fn within(value: f64, max: f64) -> bool {
    value.is_finite() && value.abs() <= max
}

/// Whether an intensity (cd) is one a table holds.
pub fn intensity_ok(cd: f64) -> bool {
    cd.is_finite() && (0.0..=MAX_CANDELA).contains(&cd)
}

/// What a reader makes of `v` printed with `significant` digits.
pub fn printed(v: f64, significant: usize) -> f64 {
    format_number(v, significant)
        .parse()
        .unwrap_or(f64::INFINITY)
}

/// `v` printed with `significant` digits such that `read_back` of what
/// is printed stays within `ok`: where rounding to nearest would cross a
/// limit, the value is rounded towards zero, one unit of its last digit
/// at a time (a change of at most 10^(1−significant), below every
/// round-trip tolerance). None where even that cannot hold.
pub fn printed_within(
    v: f64,
    significant: usize,
    read_back: impl Fn(f64) -> f64,
    ok: impl Fn(f64) -> bool,
) -> Option<String> {
    let mut text = format_number(v, significant);
    for _ in 0..4 {
        let value: f64 = text.parse().ok()?;
        if ok(read_back(value)) {
            return Some(text);
        }
        if value == 0.0 {
            return None;
        }
        // One unit of the last printed digit towards zero.
        let magnitude = value.abs().log10().floor() as i32;
        let unit = 10f64.powi(magnitude + 1 - significant as i32);
        let smaller = value - unit.copysign(value);
        text = format_number(smaller, significant);
    }
    None
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

/// Checks the angles a writer is about to print with [`ANGLE_DIGITS`]:
/// they must read back distinct and ascending, at least
/// [`MIN_ANGLE_STEP_DEG`] apart.
pub(crate) fn check_printed_angles(
    what: &'static str,
    angles: &[f64],
) -> Result<(), WritePhotometryError> {
    let read: Vec<f64> = angles.iter().map(|&a| printed(a, ANGLE_DIGITS)).collect();
    for (i, w) in read.windows(2).enumerate() {
        if !printed_apart(w[0], w[1]) {
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
    if within(value, max) {
        Ok(())
    } else {
        Err(WritePhotometryError::Value {
            format,
            what: what.to_owned(),
            value,
        })
    }
}
