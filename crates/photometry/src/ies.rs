//! IES LM-63 (1986 to 2019) reading, and LM-63-2002 / LM-63-2019 writing,
//! photometric type C.

use crate::limits::{self, WritePhotometryError, check_printed_angles, check_written};
use crate::photometry::{
    Dimensions, Format, LampSet, Metadata, ParsePhotometryError, Photometry, WriteOptions,
    consistent_with, expand_planes, plausible_magnitude,
};
use crate::table::{CPlaneSymmetry, CandelaTable};
use crate::text::{format_number, normalise_line_ends};

const FORMAT: &str = "IES";
const FEET_TO_M: f64 = 0.3048;

fn error(line: usize, message: impl Into<String>) -> ParsePhotometryError {
    ParsePhotometryError::new(FORMAT, Some(line), message)
}

/// Numbers after the TILT line, split on blanks and commas, with the line
/// each came from.
struct Tokens<'a> {
    items: Vec<(usize, &'a str)>,
    next: usize,
    last_line: usize,
}

impl<'a> Tokens<'a> {
    fn new(lines: &[(usize, &'a str)]) -> Self {
        let items = lines
            .iter()
            .flat_map(|&(n, l)| {
                l.split(|c: char| c.is_whitespace() || c == ',')
                    .filter(|t| !t.is_empty())
                    .map(move |t| (n, t))
            })
            .collect();
        Tokens {
            items,
            next: 0,
            last_line: lines.last().map_or(1, |l| l.0),
        }
    }

    fn number(&mut self, what: &str) -> Result<f64, ParsePhotometryError> {
        let Some(&(line, token)) = self.items.get(self.next) else {
            return Err(error(
                self.last_line,
                format!("the file ends where {what} was expected"),
            ));
        };
        self.next += 1;
        let v: f64 = token
            .parse()
            .map_err(|_| error(line, format!("{what}: '{token}' is not a number")))?;
        if !v.is_finite() {
            return Err(error(
                line,
                format!("{what}: {token} is not a finite number"),
            ));
        }
        Ok(v)
    }

    fn line(&self) -> usize {
        self.items
            .get(self.next.saturating_sub(1))
            .map_or(self.last_line, |t| t.0)
    }

    fn count(&mut self, what: &str, max: usize) -> Result<usize, ParsePhotometryError> {
        let v = self.number(what)?;
        if v.fract() != 0.0 || v < 1.0 || v > max as f64 {
            return Err(error(
                self.line(),
                format!("{what} must be a whole number from 1 to {max}, got {v}"),
            ));
        }
        Ok(v as usize)
    }

    fn numbers(&mut self, n: usize, what: &str) -> Result<Vec<f64>, ParsePhotometryError> {
        (0..n).map(|_| self.number(what)).collect()
    }

    fn remaining(&self) -> usize {
        self.items.len() - self.next
    }
}

fn check_ascending(v: &[f64], what: &str, line: usize) -> Result<(), ParsePhotometryError> {
    let apart = |w: &&[f64]| limits::apart(w[0], w[1]);
    if let Some(w) = v.windows(2).find(|w| !apart(w)) {
        return Err(error(
            line,
            format!(
                "{what} must be strictly ascending, at least 0.0001° apart, but {} is followed by {}",
                format_number(w[0], 8),
                format_number(w[1], 8)
            ),
        ));
    }
    Ok(())
}

/// Reads IES LM-63 text (any version from 1986 to 2019).
pub fn parse_ies(text: &str) -> Result<Photometry, ParsePhotometryError> {
    let text = normalise_line_ends(text);
    let lines: Vec<(usize, &str)> = text.lines().enumerate().map(|(i, l)| (i + 1, l)).collect();
    if lines.is_empty() {
        return Err(ParsePhotometryError::new(FORMAT, None, "the file is empty"));
    }
    let first = lines[0].1.trim();
    let upper = first.to_ascii_uppercase();
    let (year, header_start) = if let Some(rest) = upper
        .strip_prefix("IESNA:LM-63-")
        .or_else(|| upper.strip_prefix("IES:LM-63-"))
    {
        let year = rest.trim().parse::<u16>().unwrap_or(2002);
        (year, 1)
    } else if upper.starts_with("IESNA91") {
        (1991, 1)
    } else {
        (1986, 0)
    };
    let mut meta = Metadata {
        ballast_factor: 1.0,
        ..Metadata::default()
    };
    let tilt_at = lines
        .iter()
        .position(|(_, l)| {
            let l = l.trim_start().to_ascii_uppercase();
            l.strip_prefix("TILT")
                .is_some_and(|r| r.trim_start().starts_with('='))
        })
        .ok_or_else(|| ParsePhotometryError::new(FORMAT, None, "no TILT= line: not an IES file"))?;
    let mut last_key: Option<usize> = None;
    for &(_, line) in &lines[header_start..tilt_at] {
        let line = line.trim();
        if let Some(rest) = line.strip_prefix('[')
            && let Some(close) = rest.find(']')
        {
            let key = rest[..close].trim().to_ascii_uppercase();
            let value = rest[close + 1..].trim().to_owned();
            if key == "MORE"
                && let Some(k) = last_key
            {
                let entry = &mut meta.keywords[k].1;
                entry.push(' ');
                entry.push_str(&value);
                continue;
            }
            meta.keywords.push((key, value));
            last_key = Some(meta.keywords.len() - 1);
        } else if !line.is_empty() {
            // 1986 files carry free text before TILT.
            meta.keywords.push((String::new(), line.to_owned()));
            last_key = None;
        }
    }
    let take = |meta: &mut Metadata, key: &str| -> String {
        match meta.keywords.iter().position(|(k, _)| k == key) {
            Some(i) => meta.keywords.remove(i).1,
            None => String::new(),
        }
    };
    meta.test_report = take(&mut meta, "TEST");
    meta.test_lab = take(&mut meta, "TESTLAB");
    meta.issue_date = take(&mut meta, "ISSUEDATE");
    meta.manufacturer = take(&mut meta, "MANUFAC");
    meta.catalog_number = take(&mut meta, "LUMCAT");
    meta.luminaire = take(&mut meta, "LUMINAIRE");
    meta.file_generation_info = take(&mut meta, "FILEGENINFO");
    let lamp_name = take(&mut meta, "LAMP");

    let (tilt_line_no, tilt_line) = lines[tilt_at];
    let tilt = tilt_line
        .trim()
        .split_once('=')
        .map(|(_, v)| v.trim().to_owned())
        .ok_or_else(|| error(tilt_line_no, "the TILT line has no '='"))?;
    let mut tokens = Tokens::new(&lines[tilt_at + 1..]);
    match tilt.to_ascii_uppercase().as_str() {
        "NONE" => {}
        "INCLUDE" => {
            tokens.number("lamp-to-luminaire geometry")?;
            let pairs = tokens.count("number of tilt angles", limits::IES_MAX_ANGLES)?;
            let angles = tokens.numbers(pairs, "tilt angle")?;
            let factors = tokens.numbers(pairs, "tilt multiplying factor")?;
            meta.tilt = Some((angles, factors));
        }
        other => meta.warnings.push(format!(
            "TILT={other} refers to a separate file, which is not read; the table is used as it is"
        )),
    }
    let lamp_count = tokens.number("number of lamps")?;
    plausible_magnitude(
        FORMAT,
        tokens.line(),
        "number of lamps",
        lamp_count,
        limits::MAX_LAMPS,
    )?;
    let lumens_per_lamp = tokens.number("lumens per lamp")?;
    plausible_magnitude(
        FORMAT,
        tokens.line(),
        "lumens per lamp",
        lumens_per_lamp,
        limits::MAX_FLUX_LM,
    )?;
    let multiplier = tokens.number("candela multiplier")?;
    if multiplier <= 0.0 {
        return Err(error(
            tokens.line(),
            format!("candela multiplier must be > 0, got {multiplier}"),
        ));
    }
    let n_vertical = tokens.count("number of vertical angles", limits::IES_MAX_ANGLES)?;
    let n_horizontal = tokens.count("number of horizontal angles", limits::IES_MAX_ANGLES)?;
    let photometric_type = tokens.number("photometric type")?;
    let type_line = tokens.line();
    match photometric_type as i64 {
        1 => {}
        2 | 3 => {
            return Err(error(
                type_line,
                format!(
                    "photometric type {} (type {}) is not supported: Lucerna reads type C (1)",
                    photometric_type,
                    if photometric_type == 2.0 { "B" } else { "A" }
                ),
            ));
        }
        _ => {
            return Err(error(
                type_line,
                format!("photometric type must be 1, 2 or 3, got {photometric_type}"),
            ));
        }
    }
    let units = tokens.number("units type")?;
    let to_m = match units as i64 {
        1 => FEET_TO_M,
        2 => 1.0,
        _ => {
            return Err(error(
                tokens.line(),
                format!("units type must be 1 (feet) or 2 (metres), got {units}"),
            ));
        }
    };
    let mut size = |what: &str| -> Result<f64, ParsePhotometryError> {
        let v = tokens.number(what)?;
        plausible_magnitude(
            FORMAT,
            tokens.line(),
            what,
            v * to_m,
            limits::MAX_DIMENSION_M,
        )?;
        Ok(v)
    };
    let width = size("luminous opening width")?;
    let length = size("luminous opening length")?;
    let height = size("luminous opening height")?;
    meta.luminous_area = if width < 0.0 || length < 0.0 {
        Dimensions {
            length_m: width.abs().max(length.abs()) * to_m,
            width_m: 0.0,
            height_m: height.abs() * to_m,
            circular: true,
        }
    } else {
        Dimensions {
            length_m: length * to_m,
            width_m: width * to_m,
            height_m: height * to_m,
            circular: false,
        }
    };
    meta.ballast_factor = tokens.number("ballast factor")?;
    // LM-63-2019: the file-generation type; before: the ballast-lamp
    // photometric factor (or "future use"), which must not scale candela.
    let second = tokens.number("file-generation type / ballast-lamp factor")?;
    if year >= 2019 {
        meta.file_generation_type = Some(second);
    }
    meta.input_watts = tokens.number("input watts")?;
    plausible_magnitude(
        FORMAT,
        tokens.line(),
        "input watts",
        meta.input_watts,
        limits::MAX_WATTS,
    )?;
    let vertical_line = tokens.line();
    let gammas = tokens.numbers(n_vertical, "vertical angle")?;
    check_ascending(&gammas, "vertical angles", vertical_line)?;
    if gammas.iter().any(|g| !(0.0..=180.0).contains(g)) {
        return Err(error(
            vertical_line,
            format!(
                "type C vertical angles must lie in 0..180°, got {} to {}",
                gammas[0],
                gammas[gammas.len() - 1]
            ),
        ));
    }
    let horizontal_line = tokens.line();
    let horizontal = tokens.numbers(n_horizontal, "horizontal angle")?;
    check_ascending(&horizontal, "horizontal angles", horizontal_line)?;
    let mut rows = Vec::with_capacity(n_horizontal);
    let mut clamped = 0usize;
    for h in &horizontal {
        let mut row =
            tokens.numbers(n_vertical, &format!("candela value (horizontal angle {h})"))?;
        for v in &mut row {
            if *v < 0.0 {
                clamped += 1;
                *v = 0.0;
            }
            *v *= multiplier;
        }
        rows.push(row);
    }
    if clamped > 0 {
        meta.warnings
            .push(format!("{clamped} negative candela value(s) set to 0"));
    }
    if tokens.remaining() > 0 {
        meta.warnings.push(format!(
            "{} value(s) after the candela table ignored",
            tokens.remaining()
        ));
    }
    let symmetry = horizontal_symmetry(&horizontal)
        .ok_or_else(|| error(horizontal_line, format!(
            "unsupported horizontal angle set {} to {}: type C files use 0; 0-90; 0-180; 0-360 (or up to 360 without it); 90-270",
            format_number(horizontal[0], 8), format_number(horizontal[horizontal.len() - 1], 8)
        )))?;
    let (c_planes, rows) = expand_planes(symmetry, &horizontal, &rows);
    let table = CandelaTable::new(c_planes, gammas.clone(), rows.concat())
        .map_err(|e| error(vertical_line, e.to_string()))?;
    let table = consistent_with(symmetry, table, &mut meta.warnings);
    let absolute = lumens_per_lamp < 0.0;
    meta.absolute = absolute;
    meta.lamps = vec![LampSet {
        count: lamp_count as i32,
        kind: lamp_name,
        flux_lm: if absolute {
            0.0
        } else {
            lumens_per_lamp * lamp_count
        },
        colour_temperature: String::new(),
        colour_rendering: String::new(),
        watts: meta.input_watts,
    }];
    Ok(Photometry {
        format: Format::Ies(year),
        symmetry,
        table,
        meta,
    })
}

/// The symmetry a type C horizontal-angle set implies, if it is a valid set.
fn horizontal_symmetry(h: &[f64]) -> Option<CPlaneSymmetry> {
    let (first, last) = (h[0], h[h.len() - 1]);
    if h.len() == 1 {
        return Some(CPlaneSymmetry::Rotational);
    }
    if first == 0.0 && last == 90.0 {
        Some(CPlaneSymmetry::Quadrant)
    } else if first == 0.0 && last == 180.0 {
        Some(CPlaneSymmetry::AboutC0C180)
    } else if first == 90.0 && last == 270.0 {
        Some(CPlaneSymmetry::AboutC90C270)
    } else if first == 0.0 && last > 180.0 && last <= 360.0 {
        Some(CPlaneSymmetry::None)
    } else {
        None
    }
}

/// User keyword stating relative or absolute photometry in the header.
pub const PHOTOMETRY_KEYWORD: &str = "_PHOTOMETRY";

/// The user keyword in which an IES written from a file of several lamp
/// sets (EULUMDAT's alternative equipments) states which set it
/// describes: the first, with the others named.
pub const LAMP_SET_KEYWORD: &str = "_LAMPSET";

/// "Lamp set 1 of 2 (1 x LED110, 9408 lm, 72 W); not described here: set
/// 2 (1 x LED120, 10080 lm, 79 W)".
fn lamp_set_statement(p: &Photometry) -> String {
    let describe = |l: &crate::photometry::LampSet| {
        let kind = if l.kind.trim().is_empty() {
            "lamp"
        } else {
            l.kind.trim()
        };
        format!(
            "{} x {kind}, {} lm, {} W",
            l.count.unsigned_abs(),
            format_number(l.flux_lm, 7),
            format_number(l.watts, 6)
        )
    };
    let lamps = &p.meta.lamps;
    let others: Vec<String> = lamps
        .iter()
        .enumerate()
        .skip(1)
        .map(|(i, l)| format!("set {} ({})", i + 1, describe(l)))
        .collect();
    format!(
        "lamp set 1 of {} ({}); the others are alternatives not described here: {}",
        lamps.len(),
        describe(&lamps[0]),
        others.join(", ")
    )
}

/// Which LM-63 edition to write.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum IesVersion {
    Lm63_2002,
    Lm63_2019,
}

/// LM-63-2019 file-generation type for computer simulations.
pub const FILE_GENERATION_SIMULATION: f64 = 1.00010;
/// LM-63-2019 file-generation type "undefined".
pub const FILE_GENERATION_UNDEFINED: f64 = 1.00001;

/// The horizontal angles a file with `symmetry` stores, taken from the
/// table's C-planes plus the range's end planes.
pub fn stored_c_planes(table: &CandelaTable, symmetry: CPlaneSymmetry) -> Vec<f64> {
    let (lo, hi) = match symmetry {
        CPlaneSymmetry::Rotational => return vec![0.0],
        CPlaneSymmetry::Quadrant => (0.0, 90.0),
        CPlaneSymmetry::AboutC0C180 => (0.0, 180.0),
        CPlaneSymmetry::AboutC90C270 => (90.0, 270.0),
        CPlaneSymmetry::None => (0.0, 360.0),
    };
    let mut planes: Vec<f64> = table
        .c_planes_deg
        .iter()
        .copied()
        .filter(|&c| c >= lo && c <= hi)
        .collect();
    for end in [lo, hi] {
        // A plane within 1e-9° of an end is that end, exactly: readers
        // check the range's ends by value.
        match planes.iter_mut().find(|c| (**c - end).abs() < 1e-9) {
            Some(c) => *c = end,
            None => planes.push(end),
        }
    }
    planes.sort_by(f64::total_cmp);
    planes
}

/// The longest line an IES file may hold: LM-63 says lines are under
/// 256 characters; the writer keeps to 80, as LM-63-2019 recommends.
pub const MAX_LINE_CHARS: usize = 255;
/// The longest keyword name written (LM-63 names are short; a file's own
/// may be any length).
const MAX_KEY_CHARS: usize = 32;

/// Wraps `[KEY] value` into lines of at most 80 characters with `[MORE]`;
/// a word longer than a line is cut across lines.
fn keyword_lines(key: &str, value: &str, out: &mut String) {
    let key: String = key.chars().take(MAX_KEY_CHARS).collect();
    let mut first = true;
    let mut current = String::new();
    let flush = |out: &mut String, current: &str, first: bool| {
        let k = if first { key.as_str() } else { "MORE" };
        out.push_str(format!("[{k}] {current}").trim_end());
        out.push_str("\r\n");
    };
    // "[KEY] " takes the key's length and 3; lines stay within 80.
    let room = |first: bool| {
        77usize
            .saturating_sub(if first { key.len() } else { 4 })
            .max(8)
    };
    for word in value.split_whitespace() {
        let mut word: Vec<char> = word.chars().collect();
        loop {
            let limit = room(first);
            let used = current.chars().count();
            let gap = usize::from(used > 0);
            if used + gap + word.len() <= limit {
                if gap == 1 {
                    current.push(' ');
                }
                current.extend(word.iter());
                break;
            }
            if used > 0 && (word.len() <= limit || used + gap >= limit) {
                flush(out, &current, first);
                first = false;
                current.clear();
                continue;
            }
            // A word longer than a whole line: fill this one with its head.
            let take = limit - used - gap;
            if gap == 1 {
                current.push(' ');
            }
            current.extend(word.drain(..take));
            flush(out, &current, first);
            first = false;
            current.clear();
        }
    }
    flush(out, &current, first);
}

/// Writes numbers, at most ten and 80 characters to a line.
fn number_lines(values: impl IntoIterator<Item = f64>, significant: usize, out: &mut String) {
    let mut line = String::new();
    let mut on_line = 0;
    for v in values {
        let n = format_number(v, significant);
        if on_line > 0 && (on_line == 10 || line.len() + 1 + n.len() > 80) {
            out.push_str(&line);
            out.push_str("\r\n");
            line.clear();
            on_line = 0;
        }
        if on_line > 0 {
            line.push(' ');
        }
        line.push_str(&n);
        on_line += 1;
    }
    if on_line > 0 {
        out.push_str(&line);
        out.push_str("\r\n");
    }
}

/// Writes an IES file as every reader accepts it
/// ([`WriteOptions::default`]).
pub fn write_ies(p: &Photometry, version: IesVersion) -> Result<String, WritePhotometryError> {
    write_ies_with(p, version, &WriteOptions::default())
}

/// Writes an IES file (CR LF line ends, lines under 80 characters). The
/// horizontal angles follow `p.symmetry`; relative photometry states the
/// lamp lumens, absolute photometry −1.
pub fn write_ies_with(
    p: &Photometry,
    version: IesVersion,
    options: &WriteOptions,
) -> Result<String, WritePhotometryError> {
    let m = &p.meta;
    let keyword_lines = |key: &str, value: &str, out: &mut String| {
        keyword_lines(key, &options.text(value), out);
    };
    let mut out = String::new();
    out.push_str(match version {
        IesVersion::Lm63_2002 => "IESNA:LM-63-2002\r\n",
        IesVersion::Lm63_2019 => "IES:LM-63-2019\r\n",
    });
    let or_unknown = |s: &str| {
        if s.trim().is_empty() {
            "Unknown".to_owned()
        } else {
            s.to_owned()
        }
    };
    keyword_lines("TEST", &or_unknown(&m.test_report), &mut out);
    keyword_lines("TESTLAB", &or_unknown(&m.test_lab), &mut out);
    keyword_lines("ISSUEDATE", &or_unknown(&m.issue_date), &mut out);
    keyword_lines("MANUFAC", &or_unknown(&m.manufacturer), &mut out);
    if !m.catalog_number.is_empty() {
        keyword_lines("LUMCAT", &m.catalog_number, &mut out);
    }
    if !m.luminaire.is_empty() {
        keyword_lines("LUMINAIRE", &m.luminaire, &mut out);
    }
    if let Some(lamp) = m.lamps.first().filter(|l| !l.kind.is_empty()) {
        keyword_lines("LAMP", &lamp.kind, &mut out);
    }
    if !m.file_generation_info.is_empty() && version == IesVersion::Lm63_2019 {
        keyword_lines("FILEGENINFO", &m.file_generation_info, &mut out);
    }
    for (k, v) in &m.keywords {
        // LM-63 keywords are letters, digits and underscores.
        let k: String = k
            .chars()
            .filter(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect::<String>()
            .to_ascii_uppercase();
        let key = if k.is_empty() { "OTHER" } else { k.as_str() };
        if key == "FILEGENINFO"
            || key == PHOTOMETRY_KEYWORD
            || key.starts_with("TILT")
            || (key == LAMP_SET_KEYWORD && m.lamps.len() > 1)
        {
            continue;
        }
        keyword_lines(key, v, &mut out);
    }
    if m.lamps.len() > 1 {
        keyword_lines(LAMP_SET_KEYWORD, &lamp_set_statement(p), &mut out);
    }
    keyword_lines(
        PHOTOMETRY_KEYWORD,
        if p.lamp_flux_lm().is_some() {
            "RELATIVE: candela for the rated lamp lumens stated below"
        } else {
            "ABSOLUTE: candela of the luminaire itself; lumens per lamp -1"
        },
        &mut out,
    );
    out.push_str("TILT=NONE\r\n");
    let symmetry = match p.symmetry {
        CPlaneSymmetry::AboutC90C270 if options.full_circle_for_c90_mirror => CPlaneSymmetry::None,
        s => s,
    };
    let horizontal = stored_c_planes(&p.table, symmetry);
    let gammas = &p.table.gammas_deg;
    // Refuse what the reader would refuse (its limits are the file's).
    for (what, got) in [
        ("vertical angles", gammas.len()),
        ("horizontal angles", horizontal.len()),
    ] {
        if got > limits::IES_MAX_ANGLES {
            return Err(WritePhotometryError::TooMany {
                format: FORMAT,
                what,
                max: limits::IES_MAX_ANGLES,
                got,
            });
        }
    }
    check_printed_angles("vertical angles", gammas)?;
    check_printed_angles("horizontal angles", &horizontal)?;
    // LM-63 describes one lamp set: an EULUMDAT's first (its later sets
    // are alternatives, named in the `_LAMPSET` keyword). Its "lumens per
    // lamp" × lamps is the set's total, which EULUMDAT states directly.
    let lamp_count = p.lamp_set().map_or(1, |l| l.count.unsigned_abs()).max(1);
    check_written(
        FORMAT,
        "number of lamps",
        f64::from(lamp_count),
        limits::MAX_LAMPS,
    )?;
    let lumens_per_lamp = match p.lamp_flux_lm() {
        Some(total) => total / f64::from(lamp_count),
        None => -1.0,
    };
    check_written(
        FORMAT,
        "lumens per lamp",
        lumens_per_lamp,
        limits::MAX_FLUX_LM,
    )?;
    check_written(FORMAT, "input watts", m.input_watts, limits::MAX_WATTS)?;
    let a = &m.luminous_area;
    for (what, v) in [
        ("luminous opening length", a.length_m),
        ("luminous opening width", a.width_m),
        ("luminous opening height", a.height_m),
    ] {
        check_written(FORMAT, what, v, limits::MAX_DIMENSION_M)?;
    }
    let (width, length) = if a.circular {
        (-a.length_m, -a.length_m)
    } else {
        (a.width_m, a.length_m)
    };
    out.push_str(&format!(
        "{} {} 1 {} {} 1 2 {} {} {}\r\n",
        lamp_count,
        format_number(lumens_per_lamp, 7),
        gammas.len(),
        horizontal.len(),
        format_number(width, 6),
        format_number(length, 6),
        format_number(a.height_m, 6),
    ));
    let second = match version {
        IesVersion::Lm63_2002 => "1".to_owned(),
        // LM-63-2019's codes are 1.00000-1.11100 (section 5.13); what a
        // file held beyond them (-1e308 printed 300 digits) is undefined.
        IesVersion::Lm63_2019 => format!(
            "{:.5}",
            m.file_generation_type
                .filter(|t| (1.0..2.0).contains(t))
                .unwrap_or(FILE_GENERATION_UNDEFINED)
        ),
    };
    out.push_str(&format!(
        "{} {} {}\r\n",
        format_number(
            if m.ballast_factor > 0.0 {
                m.ballast_factor
            } else {
                1.0
            },
            6
        ),
        second,
        format_number(m.input_watts, 6)
    ));
    // Angles keep 8 significant digits: fine grids (0.3125°) stay exact.
    number_lines(gammas.iter().copied(), 10, &mut out);
    number_lines(horizontal.iter().copied(), 10, &mut out);
    for &c in &horizontal {
        let row: Vec<f64> = gammas.iter().map(|&g| p.table.intensity(c, g)).collect();
        // As it will read back (6 significant digits): within what a
        // reader accepts, as the EULUMDAT writer checks too.
        if let Some(&v) = row.iter().find(|v| {
            !(v.is_finite() && **v >= 0.0 && limits::intensity_ok(limits::printed(**v, 6)))
        }) {
            return Err(WritePhotometryError::Value {
                format: FORMAT,
                what: format!(
                    "the intensity in C{c}° (at most {:e} cd)",
                    limits::MAX_CANDELA
                ),
                value: v,
            });
        }
        number_lines(row, 6, &mut out);
    }
    Ok(out)
}
