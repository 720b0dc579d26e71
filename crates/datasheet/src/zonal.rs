//! The zonal lumen summary and the CIE flux code (CIE 52:1982): how the
//! luminaire's flux divides between cones about the nadir.

use lucerna_photometry::figures::ZONES_DEG;
use lucerna_photometry::{CandelaTable, Figures};
use serde::Serialize;

/// One zone of the summary.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Zone {
    pub gamma_from_deg: f64,
    pub gamma_to_deg: f64,
    pub flux_lm: f64,
    /// Share of the luminaire's flux (%).
    pub percent_of_luminaire: f64,
    /// Share of the lamp flux (%), for relative photometry.
    pub percent_of_lamp: Option<f64>,
}

/// The zonal lumen summary at 0-30°, 0-40°, 0-60°, 0-90° and 90-180°.
/// The zonal lumen summary of the figures' zones (`ZONES_DEG`).
pub fn zonal_summary(figures: &Figures, lamp_flux_lm: Option<f64>) -> Vec<Zone> {
    let total = figures.flux_lm;
    ZONES_DEG
        .iter()
        .zip(figures.zonal_flux_lm)
        .map(|(&(g0, g1), flux)| Zone {
            gamma_from_deg: g0,
            gamma_to_deg: g1,
            flux_lm: flux,
            percent_of_luminaire: percent(flux, total),
            percent_of_lamp: lamp_flux_lm.map(|l| percent(flux, l)),
        })
        .collect()
}

fn percent(part: f64, whole: f64) -> f64 {
    if whole > 0.0 {
        100.0 * part / whole
    } else {
        0.0
    }
}

/// The cones of the CIE flux code: each adds π/2 sr to the last
/// (cos γ = 3/4, 1/2, 1/4, 0), so N1–N3 read as how concentrated the
/// downward light is.
pub const FLUX_CODE_CONES_DEG: [f64; 4] =
    [41.409_622_109_270_85, 60.0, 75.522_487_814_070_25, 90.0];

/// CIE flux code N1–N5 (CIE 52:1982, as DIALux and Relux print it):
/// N1, N2, N3 the flux in the 41.4°, 60° and 75.5° cones as per cent of
/// the downward flux; N4 the downward flux as per cent of the
/// luminaire's; N5 the luminaire's flux as per cent of the lamp flux
/// (the LOR; 100 for absolute photometry). Rounded to whole per cent.
pub fn cie_flux_code(table: &CandelaTable, lamp_flux_lm: Option<f64>) -> [u32; 5] {
    let total = table.flux_lm();
    let down = table.flux_between_lm(0.0, 90.0);
    let cone = |g: f64| percent(table.flux_between_lm(0.0, g), down);
    let lor = lamp_flux_lm.map_or(100.0, |l| percent(total, l));
    [
        cone(FLUX_CODE_CONES_DEG[0]),
        cone(FLUX_CODE_CONES_DEG[1]),
        cone(FLUX_CODE_CONES_DEG[2]),
        percent(down, total),
        lor,
    ]
    .map(|v| v.round().max(0.0) as u32)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A Lambertian downlight: the flux in a cone of half angle γ is
    /// π I₀ sin²γ, so N1..N3 are exactly 43.75, 75, 93.75 %.
    #[test]
    fn lambertian_flux_code_is_the_closed_form() {
        let table = CandelaTable::from_fn(0.0, 0.5, |_, g| {
            if g <= 90.0 {
                1000.0 * g.to_radians().cos()
            } else {
                0.0
            }
        });
        let total = std::f64::consts::PI * 1000.0;
        assert!((table.flux_lm() - total).abs() / total < 1e-4);
        let code = cie_flux_code(&table, Some(total / 0.8));
        assert_eq!(code, [44, 75, 94, 100, 80]);
        let zones = zonal_summary(&lucerna_photometry::figures(&table, None), None);
        // 0-30°: sin² 30° = 1/4 of the flux.
        assert!((zones[0].percent_of_luminaire - 25.0).abs() < 0.01);
        assert!((zones[2].percent_of_luminaire - 75.0).abs() < 0.01);
        assert!(zones[4].flux_lm.abs() < 1e-9);
    }

    #[test]
    fn cones_hold_equal_solid_angles() {
        for (k, g) in FLUX_CODE_CONES_DEG.iter().enumerate() {
            let cos = g.to_radians().cos();
            assert!((cos - (1.0 - 0.25 * (k as f64 + 1.0))).abs() < 1e-12);
        }
    }
}
