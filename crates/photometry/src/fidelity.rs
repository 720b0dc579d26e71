//! How faithfully a candela table carries the photometry of the cube map
//! it was resampled from: the map's own figures (flux, cone fluxes, beam
//! and field angles, peak), the table's as a reader that interpolates
//! linearly sees them, and the gaps between the two.
//!
//! A table on too coarse a γ grid loses a narrow beam: its cone fluxes,
//! angles and peak drift while its total flux may still look right, so an
//! automatic grid is chosen on all of these figures, and a grid the user
//! fixed is checked against them and warned about with the numbers.

use serde::Serialize;

use crate::cubemap::{CubeMapLayout, face_coordinates};
use crate::figures::{crossing_width, spread_angle};
use crate::photometry::format_number;
use crate::table::{CandelaTable, direction};

/// Half-angles of the cones whose flux a table must keep (degrees).
pub const CONE_HALF_ANGLES_DEG: [f64; 4] = [2.0, 5.0, 10.0, 30.0];

/// What a table must hold of its map's figures.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct FidelityTargets {
    /// Total flux, relative.
    pub flux: f64,
    /// Flux in each cone of [`CONE_HALF_ANGLES_DEG`], relative to the
    /// cone's own flux on the map (or to 1 % of the total flux where the
    /// cone holds less: a broad or upward distribution's few lumens in a 2°
    /// cone do not decide its grid).
    pub cone_flux: f64,
    /// Beam (50 %) and field (10 %) angles per main plane (degrees).
    pub angle_deg: f64,
    /// Peak intensity, relative.
    pub peak: f64,
    /// The angle and peak targets apply where the map's beam angle (the
    /// narrower main plane) spans fewer γ steps than this. A grid's error
    /// on them falls with the square of step over beam, and over a broad
    /// distribution what remains is the photon noise of single texels (the
    /// map's brightest texel, a crossing in a noisy flank), which no grid
    /// should chase; the flux and cone targets always apply.
    pub resolved_beam_steps: f64,
}

impl Default for FidelityTargets {
    fn default() -> Self {
        FidelityTargets {
            flux: 0.0005,
            cone_flux: 0.003,
            angle_deg: 0.05,
            peak: 0.005,
            resolved_beam_steps: 20.0,
        }
    }
}

/// The figures a table is checked on, of a map or of a table.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BeamFigures {
    pub flux_lm: f64,
    /// Flux inside each cone of [`CONE_HALF_ANGLES_DEG`] around nadir (lm).
    pub cone_flux_lm: [f64; 4],
    /// Full beam angle (50 %) in C0-C180 and C90-C270 (degrees).
    pub beam_angle_deg: [Option<f64>; 2],
    /// Full field angle (10 %) in the same planes.
    pub field_angle_deg: [Option<f64>; 2],
    pub peak_cd: f64,
}

impl BeamFigures {
    /// The figures of a table, read as LM-63 and EULUMDAT readers read it:
    /// linear between angles.
    pub fn of_table(table: &CandelaTable) -> BeamFigures {
        BeamFigures {
            flux_lm: table.flux_lm(),
            cone_flux_lm: CONE_HALF_ANGLES_DEG.map(|g| table.flux_between_lm(0.0, g)),
            beam_angle_deg: [0.0, 90.0].map(|c| spread_angle(table, c, 0.5)),
            field_angle_deg: [0.0, 90.0].map(|c| spread_angle(table, c, 0.1)),
            peak_cd: table.peak().0,
        }
    }

    /// The figures of a cube map (cd per texel), computed on the map
    /// itself: flux and cone fluxes from the texels' solid angles (texels
    /// cut by a cone's edge counted by the part inside); angles along the
    /// plane, and the peak, from the map interpolated bilinearly between
    /// texel centres such that each texel keeps its mean
    /// ([`crate::resample::histopolated`]).
    pub fn of_map(layout: CubeMapLayout, candela_per_texel: &[f64]) -> BeamFigures {
        let reconstructed = crate::resample::histopolated(layout, candela_per_texel);
        let omega = layout.shared_solid_angles();
        let flux_lm = candela_per_texel
            .iter()
            .zip(omega.iter())
            .map(|(i, o)| i * o)
            .sum();
        BeamFigures {
            flux_lm,
            cone_flux_lm: crate::resample::cone_flux_lm(
                layout,
                candela_per_texel,
                CONE_HALF_ANGLES_DEG,
            ),
            beam_angle_deg: [0.0, 90.0].map(|c| map_spread_angle(layout, &reconstructed, c, 0.5)),
            field_angle_deg: [0.0, 90.0].map(|c| map_spread_angle(layout, &reconstructed, c, 0.1)),
            peak_cd: reconstructed.iter().copied().fold(0.0, f64::max),
        }
    }
}

/// The map's intensity at a direction, bilinear between the centres of
/// the texels of its face (clamped to the face's outer texel centres, half
/// a texel from its edge).
pub fn map_intensity_bilinear(
    layout: CubeMapLayout,
    candela_per_texel: &[f64],
    d: [f64; 3],
) -> f64 {
    let (face, a, b) = face_coordinates(d);
    let n = layout.resolution;
    let last = f64::from(n) - 1.0;
    let texel_coordinate = |t: f64| ((t + 1.0) * 0.5 * f64::from(n) - 0.5).clamp(0.0, last);
    let (u, v) = (texel_coordinate(a), texel_coordinate(b));
    let (i0, j0) = (u.floor() as u32, v.floor() as u32);
    let (i1, j1) = ((i0 + 1).min(n - 1), (j0 + 1).min(n - 1));
    let (tu, tv) = (u - f64::from(i0), v - f64::from(j0));
    let at = |i: u32, j: u32| candela_per_texel[layout.texel_index(face, i, j)];
    (at(i0, j0) * (1.0 - tu) + at(i1, j0) * tu) * (1.0 - tv)
        + (at(i0, j1) * (1.0 - tu) + at(i1, j1) * tu) * tv
}

/// Full angle between the points either side of the plane's maximum where
/// the map's bilinear intensity first falls to `fraction` of it, along the
/// plane through C and C + 180° (a walk of a tenth of a texel).
pub fn map_spread_angle(
    layout: CubeMapLayout,
    candela_per_texel: &[f64],
    c_deg: f64,
    fraction: f64,
) -> Option<f64> {
    let step_deg = 9.0 / f64::from(layout.resolution);
    let steps = (360.0 / step_deg).round() as i64;
    let step_deg = 360.0 / steps as f64;
    let theta = |k: i64| -180.0 + k as f64 * step_deg;
    let profile = |k: i64| {
        let t = theta(k);
        let (c, g) = if t >= 0.0 {
            (c_deg, t)
        } else {
            (c_deg + 180.0, -t)
        };
        map_intensity_bilinear(
            layout,
            candela_per_texel,
            direction(c.to_radians(), g.to_radians()),
        )
    };
    let values: Vec<f64> = (0..=steps).map(profile).collect();
    crossing_width(&values, step_deg, fraction)
}

/// A table's figures beside its map's, and whether it holds them.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TableFidelity {
    /// The table's γ step (degrees).
    pub gamma_step_deg: f64,
    /// Whether the step was chosen automatically (the coarsest that holds
    /// every target) or fixed by the user.
    pub automatic: bool,
    pub map: BeamFigures,
    pub table: BeamFigures,
    pub targets: FidelityTargets,
}

impl TableFidelity {
    pub fn new(
        gamma_step_deg: f64,
        automatic: bool,
        map: BeamFigures,
        table: &CandelaTable,
        targets: FidelityTargets,
    ) -> Self {
        TableFidelity {
            gamma_step_deg,
            automatic,
            map,
            table: BeamFigures::of_table(table),
            targets,
        }
    }

    /// Every figure the table misses by more than its target, in words
    /// with the numbers ("the 5° γ grid carries 12.0 % less flux inside
    /// 5° than the map").
    pub fn shortfalls(&self) -> Vec<String> {
        let (m, t, k) = (&self.map, &self.table, &self.targets);
        let grid = format!("the {}° γ grid", trim(self.gamma_step_deg));
        let mut out = Vec::new();
        let relative = |table: f64, map: f64| (table - map) / map;
        if m.flux_lm > 0.0 {
            let r = relative(t.flux_lm, m.flux_lm);
            if !(r.abs() <= k.flux) {
                out.push(format!(
                    "{grid} carries {:.2} % {} flux than the map ({:.1} lm against {:.1} lm)",
                    100.0 * r.abs(),
                    more_or_less(r),
                    t.flux_lm,
                    m.flux_lm
                ));
            }
        }
        for (g, (&tc, &mc)) in CONE_HALF_ANGLES_DEG
            .iter()
            .zip(t.cone_flux_lm.iter().zip(&m.cone_flux_lm))
        {
            let reference = mc.max(0.01 * m.flux_lm);
            if reference <= 0.0 {
                continue;
            }
            let r = (tc - mc) / reference;
            if !(r.abs() <= k.cone_flux) {
                out.push(format!(
                    "{grid} carries {:.1} % {} flux inside {}° than the map ({:.1} lm against {:.1} lm)",
                    100.0 * r.abs(),
                    more_or_less(r),
                    trim(*g),
                    tc,
                    mc
                ));
            }
        }
        if !self.checks_angles_and_peak() {
            return out;
        }
        let angles = [
            ("beam", t.beam_angle_deg, m.beam_angle_deg),
            ("field", t.field_angle_deg, m.field_angle_deg),
        ];
        for (what, table, map) in angles {
            for (plane, (ta, ma)) in ["C0-C180", "C90-C270"].iter().zip(table.iter().zip(&map)) {
                match (ta, ma) {
                    (Some(ta), Some(ma)) if (ta - ma).abs() <= k.angle_deg => {}
                    (None, None) => {}
                    (Some(ta), Some(ma)) => out.push(format!(
                        "{grid} gives a {what} angle of {ta:.2}° in {plane} where the map has {ma:.2}°"
                    )),
                    (ta, ma) => out.push(format!(
                        "{grid} gives a {what} angle of {} in {plane} where the map has {}",
                        describe_angle(*ta),
                        describe_angle(*ma)
                    )),
                }
            }
        }
        if m.peak_cd > 0.0 {
            let r = relative(t.peak_cd, m.peak_cd);
            if !(r.abs() <= k.peak) {
                out.push(format!(
                    "{grid} has a peak {:.1} % {} than the map's ({:.0} cd against {:.0} cd)",
                    100.0 * r.abs(),
                    if r < 0.0 { "lower" } else { "higher" },
                    t.peak_cd,
                    m.peak_cd
                ));
            }
        }
        out
    }

    /// The map's beam angle in the narrower main plane (degrees).
    fn narrowest_beam_deg(&self) -> f64 {
        self.map
            .beam_angle_deg
            .iter()
            .flatten()
            .copied()
            .fold(f64::INFINITY, f64::min)
    }

    /// Whether the beam is narrow enough on this grid for the angle and
    /// peak targets to apply ([`FidelityTargets::resolved_beam_steps`]).
    pub fn checks_angles_and_peak(&self) -> bool {
        self.narrowest_beam_deg() < self.targets.resolved_beam_steps * self.gamma_step_deg
    }

    /// Whether the table holds every target.
    pub fn holds(&self) -> bool {
        self.shortfalls().is_empty()
    }

    /// One line for a bake's log or a status bar.
    pub fn summary(&self) -> String {
        let (m, t) = (&self.map, &self.table);
        let percent = |a: f64, b: f64| {
            if b > 0.0 {
                format!("{:+.3} %", 100.0 * (a - b) / b)
            } else {
                "n/a".to_owned()
            }
        };
        let worst_angle = t
            .beam_angle_deg
            .iter()
            .chain(&t.field_angle_deg)
            .zip(m.beam_angle_deg.iter().chain(&m.field_angle_deg))
            .filter_map(|(a, b)| Some((a.as_ref()? - b.as_ref()?).abs()))
            .fold(0.0, f64::max);
        let worst_cone = t
            .cone_flux_lm
            .iter()
            .zip(&m.cone_flux_lm)
            .map(|(t, m)| (t - m) / m.max(0.01 * self.map.flux_lm))
            .fold(0.0f64, |w, r| if r.abs() > w.abs() { r } else { w });
        let mut beam = format!(
            "peak {}, beam and field angles within {:.3}° of the map",
            percent(t.peak_cd, m.peak_cd),
            worst_angle
        );
        if !self.checks_angles_and_peak() {
            beam += &format!(
                " (not criteria: the {:.1}° beam spans {:.0} steps, where what differs is single texels' photon noise)",
                self.narrowest_beam_deg(),
                self.narrowest_beam_deg() / self.gamma_step_deg
            );
        }
        format!(
            "γ grid {}° ({}): flux {} of the map's, cones at 2/5/10/30° within {:.3} %, {beam}",
            trim(self.gamma_step_deg),
            if self.automatic { "automatic" } else { "fixed" },
            percent(t.flux_lm, m.flux_lm),
            100.0 * worst_cone.abs(),
        )
    }
}

fn more_or_less(r: f64) -> &'static str {
    if r < 0.0 { "less" } else { "more" }
}

fn describe_angle(a: Option<f64>) -> String {
    a.map_or_else(
        || "none (never that low)".to_owned(),
        |a| format!("{a:.2}°"),
    )
}

fn trim(v: f64) -> String {
    format_number(v, 8)
}
