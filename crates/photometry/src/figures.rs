//! Derived figures a datasheet shows: flux, LOR, downward/upward fractions,
//! peak intensity, beam and field angles, zonal lumens.

use serde::Serialize;

use crate::table::CandelaTable;

/// Figures derived from a candela table.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Figures {
    /// Luminous flux integrated from the table (lm).
    pub flux_lm: f64,
    /// Flux below the horizontal plane, γ < 90° (lm).
    pub downward_flux_lm: f64,
    /// Flux above the horizontal plane (lm).
    pub upward_flux_lm: f64,
    /// Downward flux fraction (0–1).
    pub downward_fraction: f64,
    /// Light output ratio: table flux over lamp flux, where the lamp flux is
    /// known (relative photometry).
    pub light_output_ratio: Option<f64>,
    pub peak_cd: f64,
    pub peak_c_deg: f64,
    pub peak_gamma_deg: f64,
    /// Full beam angle (50 % of the plane's maximum) in the C0-C180 and
    /// C90-C270 planes (degrees); `None` where the intensity never falls
    /// that low.
    pub beam_angle_deg: [Option<f64>; 2],
    /// Full field angle (10 %) in the same planes.
    pub field_angle_deg: [Option<f64>; 2],
    /// Flux in the zones of [`ZONES_DEG`] (lm): the zonal lumen summary of
    /// a datasheet.
    pub zonal_flux_lm: [f64; 5],
}

/// The zonal lumen summary's γ zones (degrees): 0-30°, 0-40°, 0-60°,
/// 0-90°, 90-180°.
pub const ZONES_DEG: [(f64, f64); 5] = [
    (0.0, 30.0),
    (0.0, 40.0),
    (0.0, 60.0),
    (0.0, 90.0),
    (90.0, 180.0),
];

/// Intensity along a full vertical plane through C and C + 180°, as a
/// function of the signed angle θ ∈ [−180°, 180°]: θ ≥ 0 is γ = θ in plane
/// C, θ < 0 is γ = −θ in plane C + 180°.
fn plane_profile(table: &CandelaTable, c_deg: f64, theta_deg: f64) -> f64 {
    if theta_deg >= 0.0 {
        table.intensity(c_deg, theta_deg)
    } else {
        table.intensity(c_deg + 180.0, -theta_deg)
    }
}

/// Full angle between the points on either side of the plane's maximum
/// where the intensity first falls to `fraction` of it (linear
/// interpolation on a 0.05° walk).
pub fn spread_angle(table: &CandelaTable, c_deg: f64, fraction: f64) -> Option<f64> {
    const STEP: f64 = 0.05;
    let steps = (360.0 / STEP) as i64;
    let values: Vec<f64> = (0..=steps)
        .map(|k| plane_profile(table, c_deg, -180.0 + k as f64 * STEP))
        .collect();
    crossing_width(&values, STEP, fraction)
}

/// Width (in units of `step`) between the crossings of `fraction` of the
/// maximum of equally spaced samples either side of it, interpolated
/// linearly between samples; `None` where no sample falls that low. The
/// samples go once round a full vertical plane (θ from −180° to 180°, the
/// last the first's direction again, the zenith), so a walk that reaches
/// an end goes on from the other: a beam about the zenith (an LED file
/// emitting toward +z) has its angles as one about the nadir does.
pub(crate) fn crossing_width(values: &[f64], step: f64, fraction: f64) -> Option<f64> {
    // The samples without the repeated last direction.
    let n = values.len().checked_sub(1).filter(|&n| n > 0)?;
    let values = &values[..n];
    let (k_max, i_max) =
        values
            .iter()
            .enumerate()
            .fold((0, f64::NEG_INFINITY), |(bk, bv), (k, &v)| {
                if v > bv { (k, v) } else { (bk, bv) }
            });
    if !(i_max > 0.0) {
        return None;
    }
    let level = fraction * i_max;
    let at = |k: isize| values[k.rem_euclid(n as isize) as usize];
    let crossing = |dir: isize| -> Option<f64> {
        let mut k = k_max as isize;
        for walked in 0..n {
            let next = k + dir;
            let v = at(next);
            if v <= level {
                let prev = at(k);
                let t = (prev - level) / (prev - v);
                return Some((walked as f64 + t) * step);
            }
            k = next;
        }
        None
    };
    Some(crossing(1)? + crossing(-1)?)
}

/// All figures of a table; `lamp_flux_lm` is the total rated lamp flux for
/// relative photometry (None for absolute photometry).
pub fn figures(table: &CandelaTable, lamp_flux_lm: Option<f64>) -> Figures {
    let flux_lm = table.flux_lm();
    let downward_flux_lm = table.flux_between_lm(0.0, 90.0);
    let (peak_cd, peak_c_deg, peak_gamma_deg) = table.peak();
    Figures {
        flux_lm,
        downward_flux_lm,
        upward_flux_lm: flux_lm - downward_flux_lm,
        downward_fraction: if flux_lm > 0.0 {
            downward_flux_lm / flux_lm
        } else {
            0.0
        },
        light_output_ratio: lamp_flux_lm
            .filter(|f| *f > 0.0)
            .map(|f| flux_lm / f)
            .filter(|r| r.is_finite()),
        peak_cd,
        peak_c_deg,
        peak_gamma_deg,
        beam_angle_deg: [
            spread_angle(table, 0.0, 0.5),
            spread_angle(table, 90.0, 0.5),
        ],
        field_angle_deg: [
            spread_angle(table, 0.0, 0.1),
            spread_angle(table, 90.0, 0.1),
        ],
        zonal_flux_lm: ZONES_DEG.map(|(g0, g1)| table.flux_between_lm(g0, g1)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A Lambertian-like beam cos^m about nadir, or the same turned to
    /// the zenith (an LED file emitting toward +z).
    fn beam(up: bool) -> CandelaTable {
        CandelaTable::from_fn(15.0, 0.5, |_, g| {
            let from_axis = if up { 180.0 - g } else { g };
            let c = from_axis.to_radians().cos();
            if c > 0.0 { 100.0 * c.powi(3) } else { 0.0 }
        })
    }

    #[test]
    fn a_beam_about_the_zenith_has_the_angles_of_the_same_beam_about_the_nadir() {
        let (down, up) = (figures(&beam(false), None), figures(&beam(true), None));
        // cos³ falls to half at acos(0.5^(1/3)) = 37.47°, to a tenth at 62.36°.
        let half = 2.0 * 0.5f64.powf(1.0 / 3.0).acos().to_degrees();
        let tenth = 2.0 * 0.1f64.powf(1.0 / 3.0).acos().to_degrees();
        for f in [&down, &up] {
            for k in 0..2 {
                let b = f.beam_angle_deg[k].expect("a beam angle");
                let w = f.field_angle_deg[k].expect("a field angle");
                assert!((b - half).abs() < 0.1, "{b} against {half}");
                assert!((w - tenth).abs() < 0.1, "{w} against {tenth}");
            }
        }
        assert_eq!(up.peak_gamma_deg, 180.0);
    }

    #[test]
    fn light_that_never_falls_to_the_level_has_no_angle() {
        let even = CandelaTable::from_fn(15.0, 1.0, |_, _| 10.0);
        assert_eq!(figures(&even, None).beam_angle_deg, [None, None]);
    }
}
