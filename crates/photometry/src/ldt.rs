//! EULUMDAT (.ldt) reading and writing: one field a line, intensities in
//! cd/klm of lamp set 1, symmetry indicators 0–4.

use crate::limits::{self, WritePhotometryError, check_printed_angles, check_written};
use crate::photometry::{
    Dimensions, Format, LampSet, Metadata, ParsePhotometryError, Photometry, WriteOptions,
    consistent_with, expand_planes, plausible_magnitude,
};
use crate::table::{CPlaneSymmetry, CandelaTable};
use crate::text::{format_number, normalise_line_ends};

const FORMAT: &str = "EULUMDAT";

/// The widths (characters) of EULUMDAT's free-text fields, by the
/// format's description (Stockmar, "EULUMDAT — ein Leuchtendaten-Format",
/// 1990; the same in every later summary of it): company, measurement
/// report, luminaire name, luminaire number and date/user 78; file name
/// 8; lamp type 24; colour appearance 16; colour rendering 6. The writer
/// cuts to them, the fuzzer checks them.
pub mod field_width {
    pub const COMPANY: usize = 78;
    pub const REPORT: usize = 78;
    pub const LUMINAIRE_NAME: usize = 78;
    pub const LUMINAIRE_NUMBER: usize = 78;
    pub const FILE_NAME: usize = 8;
    pub const DATE_USER: usize = 78;
    pub const LAMP_TYPE: usize = 24;
    pub const COLOUR_APPEARANCE: usize = 16;
    pub const COLOUR_RENDERING: usize = 6;
}

fn error(line: usize, message: impl Into<String>) -> ParsePhotometryError {
    ParsePhotometryError::new(FORMAT, Some(line), message)
}

struct Lines<'a> {
    lines: Vec<&'a str>,
    next: usize,
}

impl<'a> Lines<'a> {
    /// 1-based number of the line last read.
    fn line(&self) -> usize {
        self.next
    }

    fn text(&mut self, what: &str) -> Result<&'a str, ParsePhotometryError> {
        let l = self.lines.get(self.next).ok_or_else(|| {
            error(
                self.next + 1,
                format!("the file ends where {what} was expected"),
            )
        })?;
        self.next += 1;
        Ok(l.trim())
    }

    /// A number; decimal commas are accepted (one field per line, so a comma
    /// cannot be a separator).
    fn number(&mut self, what: &str) -> Result<f64, ParsePhotometryError> {
        let t = self.text(what)?;
        let v: f64 = t
            .replace(',', ".")
            .parse()
            .map_err(|_| error(self.line(), format!("{what}: '{t}' is not a number")))?;
        if !v.is_finite() {
            return Err(error(
                self.line(),
                format!("{what}: {t} is not a finite number"),
            ));
        }
        Ok(v)
    }

    /// A number where old files sometimes leave the line blank.
    fn number_or_zero(&mut self, what: &str) -> Result<f64, ParsePhotometryError> {
        let t = self.lines.get(self.next).map(|l| l.trim());
        if t == Some("") {
            self.next += 1;
            return Ok(0.0);
        }
        self.number(what)
    }

    fn integer(&mut self, what: &str, min: i64, max: i64) -> Result<i64, ParsePhotometryError> {
        let v = self.number(what)?;
        if v.fract() != 0.0 || v < min as f64 || v > max as f64 {
            return Err(error(
                self.line(),
                format!("{what} must be a whole number from {min} to {max}, got {v}"),
            ));
        }
        Ok(v as i64)
    }
}

fn symmetry_of(isym: i64) -> CPlaneSymmetry {
    match isym {
        1 => CPlaneSymmetry::Rotational,
        2 => CPlaneSymmetry::AboutC0C180,
        3 => CPlaneSymmetry::AboutC90C270,
        4 => CPlaneSymmetry::Quadrant,
        _ => CPlaneSymmetry::None,
    }
}

/// The Isym an EULUMDAT of `table` with `symmetry` is written with.
/// EULUMDAT finds the stored planes by index (Mc1..Mc2): on a listed set
/// where those indices are not the symmetry's half, a reader would mirror
/// the wrong planes (seen: +2.6 % and −14 % of the flux on non-uniform
/// planes mirrored about C90-C270). Such a table is written whole
/// (Isym 0), its symmetry unsaid.
fn written_isym(symmetry: CPlaneSymmetry, c_list: &[f64]) -> i64 {
    let isym = isym_of(symmetry, c_list.len());
    if isym > 1 && !stored_half_expands_to(isym, c_list) {
        0
    } else {
        isym
    }
}

/// Whether EULUMDAT can state `symmetry` for `table` (else it is written
/// whole, without it).
pub fn states_symmetry(symmetry: CPlaneSymmetry, table: &CandelaTable) -> bool {
    symmetry == CPlaneSymmetry::None || written_isym(symmetry, &listed_c_planes(table)) != 0
}

/// Whether the planes a reader takes as stored for `isym` (by index),
/// mirrored by its symmetry, give back exactly the listed planes.
fn stored_half_expands_to(isym: i64, c_list: &[f64]) -> bool {
    // As the reader sees them: the angles as printed, expanded as it
    // expands them.
    let c_list: Vec<f64> = c_list
        .iter()
        .map(|&c| limits::printed(c, limits::ANGLE_DIGITS))
        .collect();
    let mc = c_list.len();
    let (mc1, mc2) = stored_range(isym, mc);
    let stored: Vec<f64> = (mc1..=mc2)
        .map(|k| {
            let c = c_list[(k - 1) % mc];
            if k > mc { c + 360.0 } else { c }.rem_euclid(360.0)
        })
        .collect();
    let rows = vec![Vec::new(); stored.len()];
    let (expanded, _) = expand_planes(symmetry_of(isym), &stored, &rows);
    expanded.len() == mc
        && expanded.windows(2).all(|w| limits::apart(w[0], w[1]))
        && expanded
            .iter()
            .zip(&c_list)
            .all(|(a, b)| (a - b).abs() < limits::MIN_ANGLE_STEP_DEG / 2.0)
}

/// 1-based first and last stored C-plane index (Mc1, Mc2) per EULUMDAT.
fn stored_range(isym: i64, mc: usize) -> (usize, usize) {
    match isym {
        1 => (1, 1),
        2 => (1, mc / 2 + 1),
        3 => {
            let mc1 = 3 * mc / 4 + 1;
            (mc1, mc1 + mc / 2)
        }
        4 => (1, mc / 4 + 1),
        _ => (1, mc),
    }
}

/// EULUMDAT's length (along C90-C270, or the diameter) and width (along
/// C0-C180; 0 for round) in mm as [`Dimensions`], whose length is along
/// C0-C180 (EN 13032-1 and the GLDF schema: "width of the product
/// C0/C180", "length of the product C90/C270").
fn from_ldt_axes(length_mm: f64, width_mm: f64, height_mm: f64) -> Dimensions {
    let mm = 0.001;
    let circular = width_mm == 0.0;
    Dimensions {
        length_m: if circular { length_mm } else { width_mm } * mm,
        width_m: if circular { 0.0 } else { length_mm * mm },
        height_m: height_mm * mm,
        circular,
    }
}

/// The EULUMDAT length and width (m) of [`Dimensions`]: the inverse of
/// [`from_ldt_axes`].
fn ldt_axes(d: &Dimensions) -> (f64, f64) {
    if d.circular || d.width_m == 0.0 {
        (d.length_m, 0.0)
    } else {
        (d.width_m, d.length_m)
    }
}

/// Reads EULUMDAT text.
pub fn parse_ldt(text: &str) -> Result<Photometry, ParsePhotometryError> {
    let text = normalise_line_ends(text);
    let mut l = Lines {
        lines: text.lines().collect(),
        next: 0,
    };
    let mut meta = Metadata {
        ballast_factor: 1.0,
        ..Metadata::default()
    };
    meta.manufacturer = l.text("company identification")?.to_owned();
    let ityp = l.integer("type indicator Ityp", 0, 3)?;
    meta.ldt_type = Some(ityp as u8);
    let isym = l.integer("symmetry indicator Isym", 0, 4)?;
    let mc = l.integer("number of C-planes Mc", 1, limits::LDT_MAX_ANGLES as i64)? as usize;
    let mc_line = l.line();
    let dc = l.number("C-plane spacing Dc")?;
    let ng = l.integer("number of γ angles Ng", 2, limits::LDT_MAX_ANGLES as i64)? as usize;
    let dg = l.number("γ spacing Dg")?;
    if (isym == 2 || isym == 3) && !mc.is_multiple_of(2) || isym == 4 && !mc.is_multiple_of(4) {
        return Err(error(
            mc_line,
            format!("Mc = {mc} C-planes cannot hold symmetry Isym {isym}"),
        ));
    }
    meta.test_report = l.text("measurement report number")?.to_owned();
    meta.luminaire = l.text("luminaire name")?.to_owned();
    meta.catalog_number = l.text("luminaire number")?.to_owned();
    let file_name = l.text("file name")?.to_owned();
    if !file_name.is_empty() {
        meta.keywords.push(("_LDT_FILE_NAME".to_owned(), file_name));
    }
    meta.issue_date = l.text("date/user")?.to_owned();
    let mut size = |what: &str| -> Result<f64, ParsePhotometryError> {
        let v = l.number_or_zero(what)?;
        plausible_magnitude(FORMAT, l.line(), what, v * 0.001, limits::MAX_DIMENSION_M)?;
        Ok(v)
    };
    let body_length = size("luminaire length/diameter")?;
    let body_width = size("luminaire width")?;
    let body_height = size("luminaire height")?;
    meta.luminaire_dimensions = from_ldt_axes(body_length, body_width, body_height);
    let area_length = size("luminous area length/diameter")?;
    let area_width = size("luminous area width")?;
    let mut heights = [0.0; 4];
    for (i, h) in heights.iter_mut().enumerate() {
        *h = size(&format!("luminous area height C{}", 90 * i))?;
    }
    meta.luminous_area = from_ldt_axes(area_length, area_width, heights[0]);
    let dff = l.number_or_zero("downward flux fraction DFF")?;
    let lorl = l.number_or_zero("light output ratio LORL")?;
    // Stated for comparison only: 0 (or a blank line) means "not given".
    meta.declared_downward_percent = (dff > 0.0 && dff <= 100.0).then_some(dff);
    meta.declared_lor_percent = (lorl > 0.0 && lorl <= 1000.0).then_some(lorl);
    let mut cfli = l.number_or_zero("intensity conversion factor CFLI")?;
    if cfli <= 0.0 {
        cfli = 1.0;
    }
    l.number_or_zero("tilt during measurement")?;
    let sets = l.integer("number of lamp sets", 1, limits::LDT_MAX_LAMP_SETS as i64)? as usize;
    let mut flux_line = 0;
    for set in 0..sets {
        let count = l.number("number of lamps")?;
        plausible_magnitude(
            FORMAT,
            l.line(),
            "number of lamps",
            count,
            limits::MAX_LAMPS,
        )?;
        let kind = l.text("lamp type")?.to_owned();
        let flux_lm = l.number("lamp set luminous flux")?;
        plausible_magnitude(
            FORMAT,
            l.line(),
            "lamp set luminous flux",
            flux_lm,
            limits::MAX_FLUX_LM,
        )?;
        if set == 0 {
            flux_line = l.line();
        }
        let colour_temperature = l.text("colour temperature")?.to_owned();
        let colour_rendering = l.text("colour rendering")?.to_owned();
        let watts = l.number_or_zero("lamp set wattage")?;
        plausible_magnitude(
            FORMAT,
            l.line(),
            "lamp set wattage",
            watts,
            limits::MAX_WATTS,
        )?;
        meta.lamps.push(LampSet {
            count: count as i32,
            kind,
            flux_lm,
            colour_temperature,
            colour_rendering,
            watts,
        });
    }
    // The sets are alternatives (EN 13032-1's "standard sets of lamps"):
    // the luminaire's power is the first set's.
    meta.input_watts = meta.lamps[0].watts;
    meta.absolute = meta.lamps[0].count < 0;
    for k in 0..10 {
        l.number_or_zero(&format!("direct ratio {}", k + 1))?;
    }
    let c_line = l.line() + 1;
    let c_angles: Vec<f64> = (0..mc)
        .map(|_| l.number("C angle"))
        .collect::<Result<_, _>>()?;
    let g_line = l.line() + 1;
    let gammas: Vec<f64> = (0..ng)
        .map(|_| l.number("γ angle"))
        .collect::<Result<_, _>>()?;
    let apart = |w: &[f64]| limits::apart(w[0], w[1]);
    if c_angles.iter().any(|c| !(0.0..=360.0).contains(c)) || !c_angles.windows(2).all(apart) {
        return Err(error(
            c_line,
            "C angles must be ascending within 0..360°, at least 0.0001° apart",
        ));
    }
    if gammas.iter().any(|g| !(0.0..=180.0).contains(g)) || !gammas.windows(2).all(apart) {
        return Err(error(
            g_line,
            "γ angles must be ascending within 0..180°, at least 0.0001° apart",
        ));
    }
    let _ = (dc, dg); // the angle lists are authoritative
    let (mc1, mc2) = stored_range(isym, mc);
    let flux_set1 = meta.lamps[0].flux_lm;
    if flux_set1 <= 0.0 {
        return Err(error(
            flux_line,
            "lamp set 1 has no luminous flux: cd/klm cannot be converted to cd",
        ));
    }
    let to_cd = flux_set1 / 1000.0 * cfli;
    let mut stored_c = Vec::new();
    let mut rows = Vec::new();
    let mut clamped = 0usize;
    for k in mc1..=mc2 {
        // Isym 3 runs from C270 through C0 to C90: indices past Mc wrap.
        let c = if k > mc {
            c_angles[k - 1 - mc] + 360.0
        } else {
            c_angles[k - 1]
        };
        stored_c.push(c.rem_euclid(360.0));
        let mut row = Vec::with_capacity(ng);
        for _ in 0..ng {
            let mut v = l.number(&format!("intensity in C-plane {c}°"))?;
            if v < 0.0 {
                clamped += 1;
                v = 0.0;
            }
            row.push(v * to_cd);
        }
        rows.push(row);
    }
    if clamped > 0 {
        meta.warnings
            .push(format!("{clamped} negative intensity value(s) set to 0"));
    }
    let symmetry = symmetry_of(isym);
    let (c_planes, rows) = expand_planes(symmetry, &stored_c, &rows);
    let table = CandelaTable::new(c_planes, gammas, rows.concat())
        .map_err(|e| error(c_line, e.to_string()))?;
    let table = consistent_with(symmetry, table, &mut meta.warnings);
    Ok(Photometry {
        format: Format::Eulumdat,
        symmetry,
        table,
        meta,
    })
}

/// The C-planes around the full circle that the file lists: the table's
/// own when it has several, else 24 planes (a rotational file stores one).
fn listed_c_planes(table: &CandelaTable) -> Vec<f64> {
    if table.c_planes_deg.len() > 1 {
        table.c_planes_deg.clone()
    } else {
        crate::table::uniform_c_planes(15.0)
    }
}

fn isym_of(symmetry: CPlaneSymmetry, mc: usize) -> i64 {
    match symmetry {
        CPlaneSymmetry::Rotational => 1,
        CPlaneSymmetry::AboutC0C180 if mc.is_multiple_of(2) => 2,
        CPlaneSymmetry::AboutC90C270 if mc.is_multiple_of(2) => 3,
        CPlaneSymmetry::Quadrant if mc.is_multiple_of(4) => 4,
        _ => 0,
    }
}

/// Writes EULUMDAT (CR LF) as every reader accepts it
/// ([`WriteOptions::default`]).
pub fn write_ldt(p: &Photometry) -> Result<String, WritePhotometryError> {
    write_ldt_with(p, &WriteOptions::default())
}

/// Writes EULUMDAT (CR LF). Intensities are cd/klm of lamp set 1; absolute
/// photometry is written with a negative lamp count and the luminaire's
/// own flux as the set's flux, so cd = cd/klm × flux / 1000 still holds.
pub fn write_ldt_with(
    p: &Photometry,
    options: &WriteOptions,
) -> Result<String, WritePhotometryError> {
    let m = &p.meta;
    let table = &p.table;
    let figures = p.figures();
    let c_list = listed_c_planes(table);
    let mc = c_list.len();
    let isym = written_isym(p.symmetry, &c_list);
    let step = 360.0 / mc as f64;
    let uniform_c = c_list
        .iter()
        .enumerate()
        .all(|(i, &c)| (c - i as f64 * step).abs() < 1e-6);
    let g = &table.gammas_deg;
    for (what, got) in [("C-planes", mc), ("γ angles", g.len())] {
        if got > limits::LDT_MAX_ANGLES {
            return Err(WritePhotometryError::TooMany {
                format: FORMAT,
                what,
                max: limits::LDT_MAX_ANGLES,
                got,
            });
        }
    }
    check_printed_angles("C-plane angles", &c_list)?;
    check_printed_angles("γ angles", g)?;
    // EULUMDAT's Dg means angles 0, Dg, 2·Dg, …: equal steps from 0.
    let g_step = table.uniform_gamma_step().filter(|_| g[0] == 0.0);
    let mut lamps = m.lamps.clone();
    if lamps.is_empty() || lamps[0].flux_lm <= 0.0 || m.absolute {
        let first = lamps.first().cloned();
        lamps = vec![LampSet {
            count: if m.absolute { -1 } else { 1 },
            kind: first.as_ref().map(|l| l.kind.clone()).unwrap_or_default(),
            flux_lm: figures.flux_lm,
            colour_temperature: first
                .as_ref()
                .map(|l| l.colour_temperature.clone())
                .unwrap_or_default(),
            colour_rendering: first
                .as_ref()
                .map(|l| l.colour_rendering.clone())
                .unwrap_or_default(),
            watts: m.input_watts,
        }];
    }
    let has_flux = lamps[0].flux_lm > 0.0;
    if !has_flux {
        return Err(WritePhotometryError::Value {
            format: FORMAT,
            what: "the flux that cd/klm refers to (an all-dark table)".to_owned(),
            value: lamps[0].flux_lm,
        });
    }
    for s in &lamps {
        check_written(FORMAT, "a lamp set's flux", s.flux_lm, limits::MAX_FLUX_LM)?;
        check_written(FORMAT, "a lamp set's wattage", s.watts, limits::MAX_WATTS)?;
    }
    for (what, v) in [
        ("the luminaire's length", m.luminaire_dimensions.length_m),
        ("the luminaire's width", m.luminaire_dimensions.width_m),
        ("the luminaire's height", m.luminaire_dimensions.height_m),
        ("the luminous area's length", m.luminous_area.length_m),
        ("the luminous area's width", m.luminous_area.width_m),
        ("the luminous area's height", m.luminous_area.height_m),
    ] {
        check_written(FORMAT, what, v, limits::MAX_DIMENSION_M)?;
    }
    let per_klm = 1000.0 / lamps[0].flux_lm;
    // cd/klm → cd as the reader converts: by the set flux as printed.
    let to_cd = limits::printed(lamps[0].flux_lm, limits::FLUX_DIGITS) / 1000.0;
    // LORL is of lamp set 1, which the cd/klm are per; later sets are
    // alternatives, not lamps added.
    let lor_percent = figures.flux_lm / lamps[0].flux_lm * 100.0;
    let mm = |m: f64| format_number(m * 1000.0, 6);
    let area = &m.luminous_area;
    let body = &m.luminaire_dimensions;
    let text = |s: &str, width: usize| options.text_within(s, width);
    let (area_length, area_width) = ldt_axes(area);
    let (body_length, body_width) = ldt_axes(body);
    let file_name = m
        .keywords
        .iter()
        .find(|(k, _)| k == "_LDT_FILE_NAME")
        .map(|(_, v)| v.clone())
        .unwrap_or_default();
    use field_width as w;
    let mut lines: Vec<String> = vec![
        text(&m.manufacturer, w::COMPANY),
        m.ldt_type
            .unwrap_or(if isym == 1 { 1 } else { 3 })
            .to_string(),
        isym.to_string(),
        mc.to_string(),
        format_number(if uniform_c { step } else { 0.0 }, 10),
        g.len().to_string(),
        format_number(g_step.unwrap_or(0.0), 10),
        text(&m.test_report, w::REPORT),
        text(&m.luminaire, w::LUMINAIRE_NAME),
        text(&m.catalog_number, w::LUMINAIRE_NUMBER),
        text(&file_name, w::FILE_NAME),
        text(&m.issue_date, w::DATE_USER),
        mm(body_length),
        mm(body_width),
        mm(body.height_m),
        mm(area_length),
        mm(area_width),
        mm(area.height_m),
        mm(area.height_m),
        mm(area.height_m),
        mm(area.height_m),
        format_number(figures.downward_fraction * 100.0, 5),
        format_number(lor_percent, 5),
        "1".to_owned(),
        "0".to_owned(),
        lamps.len().to_string(),
    ];
    for s in &lamps {
        lines.push(s.count.to_string());
        lines.push(text(&s.kind, w::LAMP_TYPE));
        lines.push(format_number(s.flux_lm, limits::FLUX_DIGITS));
        lines.push(text(&s.colour_temperature, w::COLOUR_APPEARANCE));
        lines.push(text(&s.colour_rendering, w::COLOUR_RENDERING));
        lines.push(format_number(s.watts, 6));
    }
    // Direct ratios for room indices 0.6–5 are a utilisation-factor
    // computation not done here; 0 marks them as not given.
    lines.extend(std::iter::repeat_n("0".to_owned(), 10));
    lines.extend(
        c_list
            .iter()
            .map(|&c| format_number(c, limits::ANGLE_DIGITS)),
    );
    lines.extend(g.iter().map(|&x| format_number(x, limits::ANGLE_DIGITS)));
    let (mc1, mc2) = stored_range(isym, mc);
    for k in mc1..=mc2 {
        let c = c_list[(k - 1) % mc];
        for &gamma in g {
            let v = table.intensity(c, gamma) * per_klm;
            if !(v.is_finite() && v >= 0.0) {
                return Err(WritePhotometryError::Value {
                    format: FORMAT,
                    what: format!("the intensity at C{c}° γ{gamma}° (cd/klm)"),
                    value: v,
                });
            }
            // What the reader will make of the printed value (times the
            // printed set flux / 1000) must be a table it accepts: where
            // rounding would cross the limit, it rounds down.
            let printed = limits::printed_within(
                v,
                limits::INTENSITY_DIGITS,
                |cd_per_klm| cd_per_klm * to_cd,
                limits::intensity_ok,
            )
            .ok_or_else(|| WritePhotometryError::Value {
                format: FORMAT,
                what: format!("the intensity at C{c}° γ{gamma}° (cd)"),
                value: v / per_klm,
            })?;
            lines.push(printed);
        }
    }
    let mut out = lines.join("\r\n");
    out.push_str("\r\n");
    Ok(out)
}

/// EULUMDAT text as Latin-1 bytes (what older tools expect); characters
/// outside Latin-1 become '?'.
pub fn to_latin1(text: &str) -> Vec<u8> {
    text.chars()
        .map(|c| u8::try_from(u32::from(c)).unwrap_or(b'?'))
        .collect()
}
