//! The luminaire data block of a datasheet: what the file says about the
//! product, its lamps and its flux, in the terms catalogues print.

use lucerna_photometry::{Dimensions, Photometry};
use serde::Serialize;

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LuminaireData {
    pub name: String,
    pub manufacturer: String,
    pub catalogue_number: String,
    pub test_report: String,
    pub issue_date: String,
    pub file_format: String,
    /// "absolute" (LED, the luminaire measured as a whole) or "relative"
    /// (per rated lamp flux).
    pub photometry: &'static str,
    pub luminaire_dimensions: Dimensions,
    pub luminous_opening: Dimensions,
    pub lamps: Vec<LampLine>,
    /// Rated lamp flux (lm), relative photometry only.
    pub lamp_flux_lm: Option<f64>,
    /// The luminaire's flux (lm) as the table integrates it.
    pub luminaire_flux_lm: f64,
    /// Light output ratio (%), relative photometry only.
    pub light_output_ratio_percent: Option<f64>,
    /// Input power (W), where the file gives it.
    pub power_w: Option<f64>,
    /// Luminaire flux per watt (lm/W), where the power is known.
    pub efficacy_lm_per_w: Option<f64>,
    /// The file's alternative lamp sets (EULUMDAT's second and later
    /// sets), each with the luminaire flux and efficacy it gives; every
    /// other figure is of the first set.
    pub variants: Vec<lucerna_photometry::LampVariant>,
    /// The light output ratio the file declares (%), where it does.
    pub declared_lor_percent: Option<f64>,
    /// Correlated colour temperature and colour rendering, from the lamp
    /// data or the file's keywords.
    pub cct: String,
    pub cri: String,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LampLine {
    pub count: i32,
    pub kind: String,
    pub flux_lm: f64,
    pub watts: f64,
}

/// The value of the first keyword (case-insensitive, brackets and a
/// leading underscore ignored) among `names`.
fn keyword(p: &Photometry, names: &[&str]) -> Option<String> {
    p.meta.keywords.iter().find_map(|(k, v)| {
        let key = k
            .trim_matches(|c| c == '[' || c == ']')
            .trim_start_matches('_')
            .to_ascii_uppercase();
        (names.contains(&key.as_str()) && !v.trim().is_empty()).then(|| v.trim().to_owned())
    })
}

/// A label without the quotes some files put round it, trimmed.
fn label(s: &str) -> String {
    let t = s.trim();
    let unquoted = t
        .strip_prefix('"')
        .and_then(|r| r.strip_suffix('"'))
        .unwrap_or(t);
    unquoted.trim().to_owned()
}

pub fn luminaire_data(p: &Photometry) -> LuminaireData {
    let lamp_flux_lm = p.lamp_flux_lm();
    let luminaire_flux_lm = p.table.flux_lm();
    let power_w = p.power_w();
    let first_lamp = |f: fn(&lucerna_photometry::LampSet) -> &String| {
        p.meta
            .lamps
            .iter()
            .map(f)
            .find(|s| !s.trim().is_empty())
            .map(|s| s.trim().to_owned())
    };
    let name = [&p.meta.luminaire, &p.meta.catalog_number]
        .into_iter()
        .find(|s| !s.trim().is_empty())
        .map_or("Luminaire".to_owned(), |s| label(s));
    LuminaireData {
        name,
        manufacturer: label(&p.meta.manufacturer),
        catalogue_number: label(&p.meta.catalog_number),
        test_report: label(&p.meta.test_report),
        issue_date: label(&p.meta.issue_date),
        file_format: p.format.to_string(),
        photometry: if p.meta.absolute {
            "absolute"
        } else {
            "relative"
        },
        luminaire_dimensions: p.meta.luminaire_dimensions,
        luminous_opening: p.meta.luminous_area,
        lamps: p
            .lamp_set()
            .into_iter()
            .map(|l| LampLine {
                count: l.count,
                kind: l.kind.trim().to_owned(),
                flux_lm: l.flux_lm,
                watts: l.watts,
            })
            .collect(),
        lamp_flux_lm,
        luminaire_flux_lm,
        light_output_ratio_percent: lamp_flux_lm.map(|l| 100.0 * luminaire_flux_lm / l),
        power_w,
        efficacy_lm_per_w: power_w.map(|w| luminaire_flux_lm / w),
        variants: p.variants(),
        declared_lor_percent: p.meta.declared_lor_percent,
        cct: first_lamp(|l| &l.colour_temperature)
            .or_else(|| {
                keyword(
                    p,
                    &["CCT", "COLORTEMP", "COLOURTEMP", "COLOR_TEMP", "LAMPCOLOR"],
                )
            })
            .unwrap_or_default(),
        cri: first_lamp(|l| &l.colour_rendering)
            .or_else(|| keyword(p, &["CRI", "RA", "COLORRENDERING", "COLOUR_RENDERING"]))
            .unwrap_or_default(),
    }
}

/// "600 × 300 × 40 mm", "Ø 120 × 40 mm", or "—" where the file gives none.
pub fn describe_dimensions(d: &Dimensions) -> String {
    let mm = |m: f64| {
        let v = m.abs() * 1000.0;
        if v >= 100.0 {
            format!("{v:.0}")
        } else {
            format!("{v:.1}")
        }
    };
    if d.length_m == 0.0 && d.width_m == 0.0 && d.height_m == 0.0 {
        return "—".to_owned();
    }
    let base = if d.circular {
        format!("Ø {}", mm(d.length_m))
    } else {
        format!("{} × {}", mm(d.length_m), mm(d.width_m))
    };
    if d.height_m != 0.0 {
        format!("{base} × {} mm", mm(d.height_m))
    } else {
        format!("{base} mm")
    }
}
