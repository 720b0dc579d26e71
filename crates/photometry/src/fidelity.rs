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
use crate::table::{CandelaTable, direction};
use crate::text::format_number;

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

/// The shape of a table's γ grid, as a report names it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct GammaGridShape {
    /// Number of γ angles.
    pub angles: usize,
    /// Smallest and largest step between neighbouring angles (degrees);
    /// equal on a uniform grid.
    pub finest_step_deg: f64,
    pub coarsest_step_deg: f64,
    /// The largest step within the map's beam (from nadir to half the
    /// narrower main plane's beam angle): the step the angle and peak
    /// criteria judge a beam's breadth by
    /// ([`FidelityTargets::resolved_beam_steps`]).
    pub beam_step_deg: f64,
}

impl GammaGridShape {
    /// The shape of `gammas_deg` around a beam of full angle `beam_deg`.
    pub fn of(gammas_deg: &[f64], beam_deg: f64) -> GammaGridShape {
        let steps = gammas_deg.windows(2).map(|w| w[1] - w[0]);
        let coarsest_step_deg = steps.clone().fold(0.0, f64::max);
        let beam_step_deg = gammas_deg
            .windows(2)
            .filter(|w| w[0] < 0.5 * beam_deg)
            .map(|w| w[1] - w[0])
            .fold(0.0, f64::max);
        GammaGridShape {
            angles: gammas_deg.len(),
            finest_step_deg: steps.fold(f64::INFINITY, f64::min),
            coarsest_step_deg,
            beam_step_deg: if beam_step_deg > 0.0 {
                beam_step_deg
            } else {
                coarsest_step_deg
            },
        }
    }

    /// Whether every step is the same (within 1e-9°).
    pub fn uniform(&self) -> bool {
        self.coarsest_step_deg - self.finest_step_deg < 1e-9
    }

    /// "the 2.5° γ grid", "the 97-angle γ grid (0.078125°–5°)".
    pub fn describe(&self) -> String {
        if self.uniform() {
            format!("the {}° γ grid", trim(self.finest_step_deg))
        } else {
            format!(
                "the {}-angle γ grid ({}°–{}°)",
                self.angles,
                trim(self.finest_step_deg),
                trim(self.coarsest_step_deg)
            )
        }
    }
}

/// A figure a table misses by more than its target.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Miss {
    /// Total flux, table against map, relative.
    Flux { relative: f64 },
    /// Flux inside a cone, relative to the cone's (or 1 % of the total).
    Cone { half_angle_deg: f64, relative: f64 },
    /// Beam (or field) angle in plane 0 (C0-C180) or 1 (C90-C270).
    Angle {
        field: bool,
        plane: usize,
        table_deg: Option<f64>,
        map_deg: Option<f64>,
    },
    /// Peak intensity, relative.
    Peak { relative: f64 },
}

/// How far the map's beam and field angles move per main plane when its
/// peak moves by two standard deviations of its photon noise (degrees).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct AngleNoise {
    pub beam: [f64; 2],
    pub field: [f64; 2],
}

/// Standard deviations of photon noise a map's maximum may stand above
/// the intensity beneath it: the largest of many noisy texels on a
/// plateau is biased upwards by up to about three of theirs.
pub const MAXIMUM_NOISE_Z: f64 = 3.0;

impl AngleNoise {
    /// Of a map (cd per texel) with the photon statistics `noise`.
    pub fn of_map(
        layout: CubeMapLayout,
        candela_per_texel: &[f64],
        noise: Option<crate::noise::PhotonNoise>,
    ) -> AngleNoise {
        let Some(noise) = noise else {
            return AngleNoise::default();
        };
        let reconstructed = crate::resample::histopolated(layout, candela_per_texel);
        let omega = layout.shared_solid_angles();
        let moved = |c: f64, fraction: f64| {
            // The plane's maximum and its texel's noise, relative.
            let (_, top) = map_plane_maximum(layout, &reconstructed, c);
            let Some((cd, t)) = top else { return 0.0 };
            let relative = MAXIMUM_NOISE_Z * noise.sigma_cd(cd * omega[t], omega[t]) / cd;
            let at = |f: f64| map_spread_angle(layout, &reconstructed, c, f);
            let base = at(fraction);
            [fraction * (1.0 - relative), fraction * (1.0 + relative)]
                .into_iter()
                .filter_map(|f| Some((at(f)? - base?).abs()))
                .fold(0.0, f64::max)
        };
        AngleNoise {
            beam: [moved(0.0, 0.5), moved(90.0, 0.5)],
            field: [moved(0.0, 0.1), moved(90.0, 0.1)],
        }
    }
}

/// The largest intensity along the plane through C and C + 180° (the walk
/// of [`map_spread_angle`]) and the texel it lies in.
fn map_plane_maximum(
    layout: CubeMapLayout,
    candela_per_texel: &[f64],
    c_deg: f64,
) -> (f64, Option<(f64, usize)>) {
    let step_deg = 9.0 / f64::from(layout.resolution);
    let steps = (360.0 / step_deg).round() as i64;
    let step_deg = 360.0 / steps as f64;
    let mut best: Option<(f64, usize)> = None;
    for k in 0..=steps {
        let t = -180.0 + k as f64 * step_deg;
        let (c, g) = if t >= 0.0 {
            (c_deg, t)
        } else {
            (c_deg + 180.0, -t)
        };
        let d = direction(c.to_radians(), g.to_radians());
        let v = map_intensity_bilinear(layout, candela_per_texel, d);
        if best.is_none_or(|(b, _)| v > b) {
            best = Some((v, layout.texel_of_direction(d)));
        }
    }
    (best.map_or(0.0, |b| b.0), best.filter(|b| b.0 > 0.0))
}

/// A table's figures beside its map's, and whether it holds them.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TableFidelity {
    /// The table's γ grid.
    pub gamma_grid: GammaGridShape,
    /// Whether the grid was chosen automatically (the coarsest that holds
    /// every target) or fixed by the user.
    pub automatic: bool,
    pub map: BeamFigures,
    pub table: BeamFigures,
    pub targets: FidelityTargets,
    /// The relative photon noise (one standard deviation) of the map's
    /// brightest texel, 0 where unknown. A peak within
    /// [`MAXIMUM_NOISE_Z`] of them of the map's is held whatever the peak
    /// target: the map's peak is one texel's estimate, the largest of
    /// many, and no grid should chase its noise.
    pub peak_noise: f64,
    /// How far the map's angles move with its peak's noise; an angle
    /// within that of the map's is held whatever the angle target.
    pub angle_noise_deg: AngleNoise,
    /// The figures of the table on the finest γ grid (automatic grids):
    /// what the finest grid misses of the map is not the γ grid's doing
    /// (its C-planes average across their cells, a line through the map
    /// does not), so an angle or peak as close to these as the targets
    /// say is held.
    pub finest: Option<BeamFigures>,
}

impl TableFidelity {
    pub fn new(
        automatic: bool,
        map: BeamFigures,
        table: &CandelaTable,
        targets: FidelityTargets,
        peak_noise: f64,
        angle_noise_deg: AngleNoise,
    ) -> Self {
        let narrowest_beam_deg = map
            .beam_angle_deg
            .iter()
            .flatten()
            .copied()
            .fold(f64::INFINITY, f64::min);
        TableFidelity {
            gamma_grid: GammaGridShape::of(&table.gammas_deg, narrowest_beam_deg),
            automatic,
            map,
            table: BeamFigures::of_table(table),
            targets,
            peak_noise,
            angle_noise_deg,
            finest: None,
        }
    }

    /// The same, also held to what the finest γ grid achieves (`finest`,
    /// that grid's figures).
    pub fn with_finest(mut self, finest: BeamFigures) -> Self {
        self.finest = Some(finest);
        self
    }

    /// The relative difference of peaks the table may have from its map:
    /// the target, or [`MAXIMUM_NOISE_Z`] standard deviations of the
    /// map's peak texel.
    pub fn peak_allowance(&self) -> f64 {
        self.targets.peak.max(MAXIMUM_NOISE_Z * self.peak_noise)
    }

    /// The angle difference (degrees) the table may have from its map in
    /// each main plane, beam and field: the target, or how far the map's
    /// own angle moves when its plane's maximum moves by its noise (the
    /// angles are crossings of a fraction of the maximum, so a noisy
    /// maximum makes them as uncertain).
    pub fn angle_allowance_deg(&self, field: bool, plane: usize) -> f64 {
        let noise = if field {
            self.angle_noise_deg.field[plane]
        } else {
            self.angle_noise_deg.beam[plane]
        };
        self.targets.angle_deg.max(noise)
    }

    /// Whether the table's angle `table` holds the map's `map` (or the
    /// finest grid's `finest`, where known).
    fn angle_held(
        &self,
        field: bool,
        plane: usize,
        table: Option<f64>,
        map: Option<f64>,
        finest: Option<Option<f64>>,
    ) -> bool {
        let close = |a: Option<f64>, b: Option<f64>, within: f64| match (a, b) {
            (Some(a), Some(b)) => (a - b).abs() <= within,
            (None, None) => true,
            _ => false,
        };
        close(table, map, self.angle_allowance_deg(field, plane))
            || finest.is_some_and(|f| {
                !close(f, map, self.angle_allowance_deg(field, plane))
                    && close(table, f, self.targets.angle_deg)
            })
    }

    /// Every figure the table misses by more than its target.
    pub fn misses(&self) -> Vec<Miss> {
        let (m, t, k) = (&self.map, &self.table, &self.targets);
        let mut out = Vec::new();
        let relative = |table: f64, map: f64| (table - map) / map;
        // What the finest grid misses too is no coarser grid's to chase:
        // a figure as close to the finest grid's as the target says holds.
        let finest = self.finest.as_ref();
        if m.flux_lm > 0.0 {
            let r = relative(t.flux_lm, m.flux_lm);
            let as_finest = finest.is_some_and(|f| {
                (f.flux_lm - m.flux_lm).abs() > k.flux * m.flux_lm
                    && (t.flux_lm - f.flux_lm).abs() <= k.flux * m.flux_lm
            });
            if !(r.abs() <= k.flux || as_finest) {
                out.push(Miss::Flux { relative: r });
            }
        }
        for (i, (&tc, &mc)) in t.cone_flux_lm.iter().zip(&m.cone_flux_lm).enumerate() {
            let reference = mc.max(0.01 * m.flux_lm);
            if reference <= 0.0 {
                continue;
            }
            let r = (tc - mc) / reference;
            let as_finest = finest.is_some_and(|f| {
                let fc = f.cone_flux_lm[i];
                (fc - mc).abs() > k.cone_flux * reference
                    && (tc - fc).abs() <= k.cone_flux * reference
            });
            if !(r.abs() <= k.cone_flux || as_finest) {
                out.push(Miss::Cone {
                    half_angle_deg: CONE_HALF_ANGLES_DEG[i],
                    relative: r,
                });
            }
        }
        if !self.checks_angles_and_peak() {
            return out;
        }
        let angles = [
            (false, t.beam_angle_deg, m.beam_angle_deg),
            (true, t.field_angle_deg, m.field_angle_deg),
        ];
        for (field, table, map) in angles {
            for plane in 0..2 {
                let (ta, ma) = (table[plane], map[plane]);
                let finest = self.finest.map(|f| {
                    if field {
                        f.field_angle_deg[plane]
                    } else {
                        f.beam_angle_deg[plane]
                    }
                });
                if !self.angle_held(field, plane, ta, ma, finest) {
                    out.push(Miss::Angle {
                        field,
                        plane,
                        table_deg: ta,
                        map_deg: ma,
                    });
                }
            }
        }
        if m.peak_cd > 0.0 {
            let r = relative(t.peak_cd, m.peak_cd);
            let as_finest = self.finest.is_some_and(|f| {
                f.peak_cd > 0.0
                    && (f.peak_cd / m.peak_cd - 1.0).abs() > self.peak_allowance()
                    && (t.peak_cd / f.peak_cd - 1.0).abs() <= k.peak
            });
            if !(r.abs() <= self.peak_allowance() || as_finest) {
                out.push(Miss::Peak { relative: r });
            }
        }
        out
    }

    /// Every figure the table misses by more than its target, in words
    /// with the numbers ("the 5° γ grid carries 12.0 % less flux inside
    /// 5° than the map").
    pub fn shortfalls(&self) -> Vec<String> {
        let (m, t) = (&self.map, &self.table);
        let grid = self.gamma_grid.describe();
        self.misses()
            .into_iter()
            .map(|miss| match miss {
                Miss::Flux { relative: r } => format!(
                    "{grid} carries {:.2} % {} flux than the map ({:.1} lm against {:.1} lm)",
                    100.0 * r.abs(),
                    more_or_less(r),
                    t.flux_lm,
                    m.flux_lm
                ),
                Miss::Cone {
                    half_angle_deg: g,
                    relative: r,
                } => {
                    let i = CONE_HALF_ANGLES_DEG.iter().position(|&x| x == g).unwrap_or(0);
                    format!(
                        "{grid} carries {:.1} % {} flux inside {}° than the map ({:.1} lm against {:.1} lm)",
                        100.0 * r.abs(),
                        more_or_less(r),
                        trim(g),
                        t.cone_flux_lm[i],
                        m.cone_flux_lm[i]
                    )
                }
                Miss::Angle {
                    field,
                    plane,
                    table_deg,
                    map_deg,
                } => {
                    let what = if field { "field" } else { "beam" };
                    let plane = ["C0-C180", "C90-C270"][plane];
                    match (table_deg, map_deg) {
                        (Some(ta), Some(ma)) => format!(
                            "{grid} gives a {what} angle of {ta:.2}° in {plane} where the map has {ma:.2}°"
                        ),
                        (ta, ma) => format!(
                            "{grid} gives a {what} angle of {} in {plane} where the map has {}",
                            describe_angle(ta),
                            describe_angle(ma)
                        ),
                    }
                }
                Miss::Peak { relative: r } => format!(
                    "{grid} has a peak {:.1} % {} than the map's ({:.0} cd against {:.0} cd)",
                    100.0 * r.abs(),
                    if r < 0.0 { "lower" } else { "higher" },
                    t.peak_cd,
                    m.peak_cd
                ),
            })
            .collect()
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
        self.narrowest_beam_deg() < self.targets.resolved_beam_steps * self.reference_step_deg()
    }

    /// The step a beam's breadth is judged at: the grid's largest within
    /// the beam (a uniform grid's own step).
    fn reference_step_deg(&self) -> f64 {
        self.gamma_grid.beam_step_deg
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
                " (not criteria: the {:.1}° beam spans {:.0} steps of {}°, where what differs is single texels' photon noise)",
                self.narrowest_beam_deg(),
                self.narrowest_beam_deg() / self.reference_step_deg(),
                trim(self.reference_step_deg())
            );
        }
        if let Some(f) = self.finest.filter(|_| self.checks_angles_and_peak()) {
            let angle = f
                .beam_angle_deg
                .iter()
                .chain(&f.field_angle_deg)
                .zip(m.beam_angle_deg.iter().chain(&m.field_angle_deg))
                .filter_map(|(a, b)| Some((a.as_ref()? - b.as_ref()?).abs()))
                .fold(0.0, f64::max);
            if angle > self.targets.angle_deg {
                beam += &format!(
                    " (the finest γ grid is itself {angle:.3}° and {} in peak from the map: its C-planes average across their cells)",
                    percent(f.peak_cd, m.peak_cd)
                );
            }
        }
        if self.checks_angles_and_peak() && MAXIMUM_NOISE_Z * self.peak_noise > self.targets.peak {
            let n = &self.angle_noise_deg;
            let angle_noise = n.beam.iter().chain(&n.field).copied().fold(0.0, f64::max);
            beam += &format!(
                " (the map's maximum is uncertain by ±{:.2} % (3σ of its photons), which moves its angles by up to {:.3}°: differences within these are its noise)",
                100.0 * MAXIMUM_NOISE_Z * self.peak_noise,
                angle_noise
            );
        }
        let g = &self.gamma_grid;
        let grid = if g.uniform() {
            format!("{}°", trim(g.finest_step_deg))
        } else {
            format!(
                "{} angles, {}°–{}°",
                g.angles,
                trim(g.finest_step_deg),
                trim(g.coarsest_step_deg)
            )
        };
        format!(
            "γ grid {grid} ({}): flux {} of the map's, cones at 2/5/10/30° within {:.3} %, {beam}",
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
