//! Text at the file boundary: numbers printed as the writers print them
//! (and the readers read them back), line ends and encodings.

/// Line ends as `\n`: files from old Macs end lines with a lone CR, which
/// `str::lines` would not split.
pub(crate) fn normalise_line_ends(text: &str) -> std::borrow::Cow<'_, str> {
    if text.contains('\r') {
        std::borrow::Cow::Owned(text.replace("\r\n", "\n").replace('\r', "\n"))
    } else {
        std::borrow::Cow::Borrowed(text)
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
