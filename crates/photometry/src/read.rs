//! Reading a photometric file whose format is not known: IES or
//! EULUMDAT told apart by content, then parsed by its own reader.

use crate::photometry::{Format, ParsePhotometryError, Photometry};
use crate::text::{decode_text, normalise_line_ends};

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
        // Text is never a ray file (those are binary, read by `tm25`).
        Some(Format::Tm25RayFile) | None => Err(ParsePhotometryError::new(
            "photometric file",
            None,
            "neither IES LM-63 (no TILT= line) nor EULUMDAT (lines 2-7 are not numbers)",
        )),
    }
}
