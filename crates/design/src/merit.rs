//! How far a candidate is from its target: for a distribution, the
//! relative L2 difference on the sphere; for a spec, each term's shortfall
//! in its own units of tolerance, squared and summed, plus what the spec
//! maximises.

use lucerna_datasheet::Opening;
use lucerna_datasheet::ugr::{REFLECTANCES, ROOMS, ugr_table};
use lucerna_photometry::{CandelaTable, Dimensions, figures};
use serde::Serialize;

use crate::target::{Maximise, Spec, Target};

/// The target, ready to compare candidates with. A distribution's
/// candidates are tabulated on its own grid (as a bake would tabulate
/// them for that file), so the two differ by the light, not by the grid.
#[derive(Debug, Clone)]
pub struct Aim {
    target: Target,
    /// A rotationally symmetric distribution's mean over C, on
    /// [`SMOOTH_STEP_DEG`] steps from γ 0° to 180°, for the smoothed merits
    /// of the early stages.
    axial: Option<Vec<f64>>,
}

/// The γ step of the axial profiles the smoothed merits compare.
pub const SMOOTH_STEP_DEG: f64 = 0.1;

/// A table's mean over C on [`SMOOTH_STEP_DEG`] steps.
pub fn axial(table: &CandelaTable) -> Vec<f64> {
    let n = (180.0 / SMOOTH_STEP_DEG).round() as usize;
    let planes = &table.c_planes_deg;
    (0..=n)
        .map(|k| {
            let g = k as f64 * SMOOTH_STEP_DEG;
            planes.iter().map(|&c| table.intensity(c, g)).sum::<f64>() / planes.len() as f64
        })
        .collect()
}

/// `profile` blurred by a Gaussian of `sigma_deg` in γ (mirrored at 0°
/// and 180°, where the sphere continues into the opposite plane).
pub fn blurred(profile: &[f64], sigma_deg: f64) -> Vec<f64> {
    if sigma_deg <= 0.0 {
        return profile.to_vec();
    }
    let s = sigma_deg / SMOOTH_STEP_DEG;
    let reach = (3.0 * s).ceil() as isize;
    let kernel: Vec<f64> = (-reach..=reach)
        .map(|k| (-0.5 * (k as f64 / s).powi(2)).exp())
        .collect();
    let n = profile.len() as isize;
    let at = |i: isize| -> f64 {
        let j = if i < 0 {
            -i
        } else if i >= n {
            2 * (n - 1) - i
        } else {
            i
        };
        profile[j.clamp(0, n - 1) as usize]
    };
    (0..n)
        .map(|i| {
            let (mut sum, mut weight) = (0.0, 0.0);
            for (k, w) in (-reach..=reach).zip(&kernel) {
                sum += w * at(i + k);
                weight += w;
            }
            sum / weight
        })
        .collect()
}

/// A spec term as a candidate holds it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TermStatus {
    /// "beam angle", "field angle", "cut-off above γ 60°", "LOR", "UGR".
    pub term: String,
    /// The candidate's value (degrees, %, UGR).
    pub value: f64,
    /// What the spec asks, in words ("24° ± 1°", "at most 40°").
    pub wanted: String,
    /// By how much it is missed (0 when met), in the term's units.
    pub missed_by: f64,
    /// Missed because the value is below what is wanted (a beam too
    /// narrow, a LOR too low); false when met or too high.
    #[serde(skip)]
    pub too_low: bool,
}

impl Aim {
    pub fn new(target: Target) -> Aim {
        let axial = match &target {
            Target::Distribution { table, .. } if target.rotationally_symmetric() => {
                Some(axial(table))
            }
            _ => None,
        };
        Aim { target, axial }
    }

    /// The merit of a stage whose comparison is blurred by `sigma_deg`
    /// in γ: early stages of a design see where the light goes before
    /// they see the fine shape of a narrow beam, which would otherwise
    /// pin them to the first local fit of its peak. Zero (or a target not
    /// the same in every C-plane, or a spec) is [`Aim::merit`].
    pub fn stage_merit(
        &self,
        table: &CandelaTable,
        lor: f64,
        lamp_flux_lm: f64,
        opening: &Dimensions,
        sigma_deg: f64,
    ) -> f64 {
        match (&self.target, &self.axial) {
            (Target::Distribution { absolute, .. }, Some(target)) if sigma_deg > 0.0 => {
                let goal = blurred(target, sigma_deg);
                let got = blurred(&axial(table), sigma_deg);
                let weight = |k: usize| (k as f64 * SMOOTH_STEP_DEG).to_radians().sin().max(1e-4);
                let flux = |v: &[f64]| {
                    v.iter()
                        .enumerate()
                        .map(|(k, x)| weight(k) * x)
                        .sum::<f64>()
                };
                let scale = if *absolute || !(flux(&got) > 0.0) {
                    1.0
                } else {
                    flux(&goal) / flux(&got)
                };
                let (mut diff, mut norm) = (0.0, 0.0);
                for (k, (g, t)) in got.iter().zip(&goal).enumerate() {
                    diff += weight(k) * (scale * g - t).powi(2);
                    norm += weight(k) * t * t;
                }
                if norm > 0.0 {
                    (diff / norm).sqrt()
                } else {
                    f64::INFINITY
                }
            }
            _ => self.merit(table, lor, lamp_flux_lm, opening),
        }
    }

    pub fn target(&self) -> &Target {
        &self.target
    }

    /// The grid candidates are tabulated on: the target file's, or the
    /// spec's merit grid.
    pub fn grid(&self) -> (Vec<f64>, Vec<f64>) {
        match &self.target {
            Target::Distribution { table, .. } => {
                (table.c_planes_deg.clone(), table.gammas_deg.clone())
            }
            Target::Spec(_) => crate::traced::evaluate::merit_grid(),
        }
    }

    /// The merit of a candidate (smaller is better) whose pooled table on
    /// [`Aim::grid`] is `table`, with light output ratio `lor` and
    /// luminous opening `opening`; `lamp_flux_lm` is the emitters' flux.
    pub fn merit(
        &self,
        table: &CandelaTable,
        lor: f64,
        lamp_flux_lm: f64,
        opening: &Dimensions,
    ) -> f64 {
        match &self.target {
            Target::Distribution { absolute, .. } => self.relative_l2(table, *absolute),
            Target::Spec(spec) => {
                let terms = spec_terms(spec, table, lor, lamp_flux_lm, opening);
                let shortfall: f64 = terms
                    .iter()
                    .map(|(t, unit)| (t.missed_by / unit).powi(2))
                    .sum();
                shortfall + objective(spec, table, lor, lamp_flux_lm)
            }
        }
    }

    /// The residuals whose sum of squares is the square of the
    /// distribution merit at blur `sigma_deg` (None for a spec): over the
    /// mean across C for a target the same in every C-plane, else over
    /// the table's cells, each weighted by its solid angle, the candidate
    /// scaled to the target's flux unless absolute.
    pub fn residuals(&self, table: &CandelaTable, sigma_deg: f64) -> Option<Vec<f64>> {
        // A negative blur asks for the cumulative flux against γ instead
        // (where the light goes, smooth in the geometry even where a
        // caustic makes the intensity jump).
        if sigma_deg < 0.0 {
            return self.cumulative_residuals(table);
        }
        let Target::Distribution {
            table: target,
            absolute,
            ..
        } = &self.target
        else {
            return None;
        };
        let (goal, got, weights): (Vec<f64>, Vec<f64>, Vec<f64>) = match &self.axial {
            Some(t) => (
                blurred(t, sigma_deg),
                blurred(&axial(table), sigma_deg),
                (0..t.len())
                    .map(|k| (k as f64 * SMOOTH_STEP_DEG).to_radians().sin().max(1e-4))
                    .collect(),
            ),
            None => {
                let g = &target.gammas_deg;
                let ng = g.len();
                let w: Vec<f64> = (0..target.candela.len())
                    .map(|k| {
                        let j = k % ng;
                        let lo = if j == 0 {
                            g[0]
                        } else {
                            0.5 * (g[j - 1] + g[j])
                        };
                        let hi = if j + 1 == ng {
                            g[ng - 1]
                        } else {
                            0.5 * (g[j] + g[j + 1])
                        };
                        (lo.to_radians().cos() - hi.to_radians().cos()).max(0.0)
                    })
                    .collect();
                (target.candela.clone(), table.candela.clone(), w)
            }
        };
        let flux = |v: &[f64]| v.iter().zip(&weights).map(|(x, w)| x * w).sum::<f64>();
        let scale = if *absolute || !(flux(&got) > 0.0) {
            1.0
        } else {
            flux(&goal) / flux(&got)
        };
        let norm: f64 = goal.iter().zip(&weights).map(|(t, w)| w * t * t).sum();
        if !(norm > 0.0) {
            return None;
        }
        let n = norm.sqrt();
        Some(
            got.iter()
                .zip(&goal)
                .zip(&weights)
                .map(|((g, t), w)| w.sqrt() * (scale * g - t) / n)
                .collect(),
        )
    }

    /// The differences of the cumulative flux from nadir against γ
    /// (shares of each distribution's own flux unless absolute), on the
    /// mean across C: the Cramér–von Mises distance's residuals.
    fn cumulative_residuals(&self, table: &CandelaTable) -> Option<Vec<f64>> {
        let (Target::Distribution { absolute, .. }, Some(goal)) = (&self.target, &self.axial)
        else {
            return None;
        };
        let got = axial(table);
        let cumulative = |v: &[f64]| -> Vec<f64> {
            let mut sum = 0.0;
            v.iter()
                .enumerate()
                .map(|(k, x)| {
                    sum += x * (k as f64 * SMOOTH_STEP_DEG).to_radians().sin();
                    sum
                })
                .collect()
        };
        let (cg, ct) = (cumulative(&got), cumulative(goal));
        let (tg, tt) = (cg[cg.len() - 1], ct[ct.len() - 1]);
        if !(tg > 0.0 && tt > 0.0) {
            return None;
        }
        let (sg, st) = if *absolute {
            (1.0 / tt, 1.0 / tt)
        } else {
            (1.0 / tg, 1.0 / tt)
        };
        let n = (cg.len() as f64).sqrt();
        Some(
            cg.iter()
                .zip(&ct)
                .map(|(a, b)| (a * sg - b * st) / n)
                .collect(),
        )
    }

    /// The relative L2 difference on the sphere between `table` (on the
    /// target's grid) and the target distribution: √(∫(I − T)² dΩ /
    /// ∫T² dΩ), both read as tables are (linear between angles), the
    /// candidate first scaled to the target's flux unless `absolute`.
    /// Infinite for a spec.
    pub fn relative_l2(&self, table: &CandelaTable, absolute: bool) -> f64 {
        let Target::Distribution { table: target, .. } = &self.target else {
            return f64::INFINITY;
        };
        let flux_c = table.flux_lm();
        let scale = if absolute || !(flux_c > 0.0) {
            1.0
        } else {
            target.flux_lm() / flux_c
        };
        let diff =
            sphere_integral_of_square(target, |k| scale * table.candela[k] - target.candela[k]);
        let norm = sphere_integral_of_square(target, |k| target.candela[k]);
        if norm > 0.0 {
            (diff / norm).sqrt()
        } else {
            f64::INFINITY
        }
    }

    /// How badly a candidate misses a spec's terms: each term's shortfall
    /// in its units of tolerance, squared and summed (0 when every term is
    /// met; the merit without its aim and what it maximises). For a
    /// distribution, the relative L2 difference.
    pub fn shortfall(
        &self,
        table: &CandelaTable,
        lor: f64,
        lamp_flux_lm: f64,
        opening: &Dimensions,
    ) -> f64 {
        match &self.target {
            Target::Distribution { absolute, .. } => self.relative_l2(table, *absolute),
            Target::Spec(spec) => spec_terms(spec, table, lor, lamp_flux_lm, opening)
                .iter()
                .filter(|(t, _)| !t.term.ends_with("(aim)"))
                .map(|(t, unit)| (t.missed_by / unit).powi(2))
                .sum(),
        }
    }

    /// Each spec term as `table` holds it (empty for a distribution).
    pub fn terms(
        &self,
        table: &CandelaTable,
        lor: f64,
        lamp_flux_lm: f64,
        opening: &Dimensions,
    ) -> Vec<TermStatus> {
        match &self.target {
            Target::Spec(spec) => spec_terms(spec, table, lor, lamp_flux_lm, opening)
                .into_iter()
                .map(|(t, _)| t)
                .collect(),
            Target::Distribution { .. } => Vec::new(),
        }
    }
}

/// Each term with the unit its shortfall is counted in.
fn spec_terms(
    spec: &Spec,
    table: &CandelaTable,
    lor: f64,
    lamp_flux_lm: f64,
    opening: &Dimensions,
) -> Vec<(TermStatus, f64)> {
    let f = figures(table, Some(lamp_flux_lm));
    let mut out = Vec::new();
    let worst = |a: [Option<f64>; 2], wide: bool| -> f64 {
        // A plane that never falls that low counts as 360°; one with no
        // light as 0°.
        let v = a.map(|x| x.unwrap_or(if f.peak_cd > 0.0 { 360.0 } else { 0.0 }));
        if wide { v[0].max(v[1]) } else { v[0].min(v[1]) }
    };
    if let Some(beam) = spec.beam_angle_deg {
        let tol = spec.beam_tolerance_deg;
        let (narrow, wide) = (
            worst(f.beam_angle_deg, false),
            worst(f.beam_angle_deg, true),
        );
        let off = (narrow - beam).abs().max((wide - beam).abs());
        let value = if (narrow - beam).abs() > (wide - beam).abs() {
            narrow
        } else {
            wide
        };
        // Aimed at the middle, met within the tolerance.
        out.push((
            TermStatus {
                term: "beam angle".to_owned(),
                value,
                wanted: format!("{beam}° ± {tol}°"),
                missed_by: (off - tol).max(0.0),
                too_low: off > tol && value < beam,
            },
            tol,
        ));
        out.push((
            TermStatus {
                term: "beam angle (aim)".to_owned(),
                value,
                wanted: format!("{beam}°"),
                missed_by: 0.5 * off,
                too_low: value < beam,
            },
            tol * 4.0,
        ));
    }
    if let Some(max) = spec.field_angle_max_deg {
        let field = worst(f.field_angle_deg, true);
        out.push((
            TermStatus {
                term: "field angle".to_owned(),
                value: field,
                wanted: format!("at most {max}°"),
                missed_by: (field - max).max(0.0),
                too_low: false,
            },
            1.0,
        ));
    }
    if let (Some(gamma), Some(fraction)) = (spec.cutoff_gamma_deg, spec.cutoff_max_fraction) {
        let n = table.gammas_deg.len();
        let above = table
            .gammas_deg
            .iter()
            .enumerate()
            .filter(|(_, g)| **g >= gamma)
            .flat_map(|(j, _)| (0..table.c_planes_deg.len()).map(move |i| i * n + j))
            .map(|k| table.candela[k])
            .fold(0.0, f64::max);
        let ratio = if f.peak_cd > 0.0 {
            above / f.peak_cd
        } else {
            0.0
        };
        out.push((
            TermStatus {
                term: format!("cut-off above γ {gamma}°"),
                value: 100.0 * ratio,
                wanted: format!("at most {} % of the peak", 100.0 * fraction),
                missed_by: 100.0 * (ratio - fraction).max(0.0),
                too_low: false,
            },
            100.0 * fraction,
        ));
    }
    if let Some(min) = spec.lor_min_percent {
        out.push((
            TermStatus {
                term: "LOR".to_owned(),
                value: 100.0 * lor,
                wanted: format!("at least {min} %"),
                missed_by: (min - 100.0 * lor).max(0.0),
                too_low: 100.0 * lor < min,
            },
            1.0,
        ));
    }
    if let Some(max) = spec.ugr_max {
        let value = ugr(spec, table, lamp_flux_lm, opening).unwrap_or(f64::INFINITY);
        out.push((
            TermStatus {
                term: format!(
                    "UGR ({}H × {}H, {}/{}/{})",
                    spec.ugr_room[0],
                    spec.ugr_room[1],
                    100.0 * spec.ugr_reflectances[0],
                    100.0 * spec.ugr_reflectances[1],
                    100.0 * spec.ugr_reflectances[2]
                ),
                value,
                wanted: format!("at most {max}"),
                missed_by: (value - max).clamp(0.0, 100.0),
                too_low: false,
            },
            0.5,
        ));
    }
    out
}

/// What the spec maximises, as a cost: one minus the share.
fn objective(spec: &Spec, table: &CandelaTable, lor: f64, lamp_flux_lm: f64) -> f64 {
    match spec.maximise {
        None => 0.0,
        Some(Maximise::Lor) => 1.0 - lor,
        Some(Maximise::ConeFlux) => {
            let g = spec.cone_half_angle_deg.unwrap_or(0.0);
            1.0 - table.flux_between_lm(0.0, g) / lamp_flux_lm.max(1e-30)
        }
    }
}

/// The corrected UGR of the spec's room and reflectances, the larger of
/// crosswise and endwise (CIE 190's table, as the datasheet prints it,
/// plus 8·log10(Φ/1000)).
fn ugr(spec: &Spec, table: &CandelaTable, lamp_flux_lm: f64, opening: &Dimensions) -> Option<f64> {
    let opening = Opening::from_dimensions(opening).ok()?;
    let klm = table.scaled(1000.0 / lamp_flux_lm);
    let t = ugr_table(&klm, &opening, 0.25, lamp_flux_lm).ok()?;
    let row = ROOMS.iter().position(|&(x, y)| [x, y] == spec.ugr_room)?;
    let col = REFLECTANCES
        .iter()
        .position(|r| *r == spec.ugr_reflectances)?;
    let cross = t.crosswise[row][col];
    let end = t.endwise[row][col];
    let worst = [cross, end]
        .into_iter()
        .flatten()
        .fold(f64::NEG_INFINITY, f64::max);
    worst.is_finite().then_some(worst + t.correction)
}

/// ∫ f² dΩ over the sphere of the piecewise-linear function whose values
/// at `grid`'s nodes are `value(k)` (k = plane × angles + angle): Simpson
/// on each γ segment, trapezoidal weights in C, as `CandelaTable` reads a
/// table.
fn sphere_integral_of_square(grid: &CandelaTable, value: impl Fn(usize) -> f64) -> f64 {
    let g = &grid.gammas_deg;
    let ng = g.len();
    let weights = grid.c_weights();
    let mut total = 0.0;
    for (i, w) in weights.iter().enumerate() {
        let mut plane = 0.0;
        for j in 0..ng - 1 {
            let (a, b) = (g[j].to_radians(), g[j + 1].to_radians());
            let (fa, fb) = (value(i * ng + j), value(i * ng + j + 1));
            let fm = 0.5 * (fa + fb);
            let m = 0.5 * (a + b);
            plane +=
                (b - a) / 6.0 * (fa * fa * a.sin() + 4.0 * fm * fm * m.sin() + fb * fb * b.sin());
        }
        total += w * plane;
    }
    total
}

/// A rotationally symmetric target as the refinement compares with it:
/// its mean over C at each of its γ nodes, each node weighted by the
/// solid angle of its cell ([`crate::model::reach::node_solid_angles`]).
/// Residuals on these nodes have a sum of squares close to the square of
/// [`Aim::relative_l2`] (which integrates the same interpolant exactly).
#[derive(Debug, Clone, PartialEq)]
pub struct AxialTarget {
    pub gammas_deg: Vec<f64>,
    /// Target candela at each node (the mean over C).
    pub intensity: Vec<f64>,
    pub solid_angle_sr: Vec<f64>,
    pub absolute: bool,
    norm: f64,
}

impl AxialTarget {
    /// The target's axial light, or None for a spec or a table with no
    /// light.
    pub fn of(target: &Target) -> Option<AxialTarget> {
        let Target::Distribution {
            table, absolute, ..
        } = target
        else {
            return None;
        };
        let intensity = crate::target::axial_nodes(table);
        let solid_angle_sr = crate::model::reach::node_solid_angles(&table.gammas_deg);
        let norm = intensity
            .iter()
            .zip(&solid_angle_sr)
            .map(|(t, w)| w * t * t)
            .sum::<f64>()
            .sqrt();
        (norm > 0.0).then(|| AxialTarget {
            gammas_deg: table.gammas_deg.clone(),
            intensity,
            solid_angle_sr,
            absolute: *absolute,
            norm,
        })
    }

    /// The same nodes aiming at other light (the corrected target of a
    /// feedback).
    pub fn aiming_at(&self, intensity: Vec<f64>) -> AxialTarget {
        let norm = intensity
            .iter()
            .zip(&self.solid_angle_sr)
            .map(|(t, w)| w * t * t)
            .sum::<f64>()
            .sqrt();
        AxialTarget {
            intensity,
            norm,
            ..self.clone()
        }
    }

    /// Flux of light on these nodes.
    pub fn flux(&self, light: &[f64]) -> f64 {
        light
            .iter()
            .zip(&self.solid_angle_sr)
            .map(|(i, w)| i * w)
            .sum()
    }

    /// The scale that brings `light` to the target's flux (1 when
    /// absolute).
    pub fn scale_of(&self, light: &[f64]) -> f64 {
        let f = self.flux(light);
        if self.absolute || !(f > 0.0) {
            1.0
        } else {
            self.flux(&self.intensity) / f
        }
    }

    /// √w (s·light − target) / ‖target‖ at each node.
    pub fn residuals(&self, light: &[f64]) -> Vec<f64> {
        let s = self.scale_of(light);
        light
            .iter()
            .zip(&self.intensity)
            .zip(&self.solid_angle_sr)
            .map(|((l, t), w)| w.sqrt() * (s * l - t) / self.norm)
            .collect()
    }
}

impl AxialTarget {
    /// The relative L2 difference of `light` from `reference` on these
    /// nodes (scaled to its flux unless absolute).
    pub fn relative_l2_between(&self, light: &[f64], reference: &[f64]) -> f64 {
        let f = self.flux(light);
        let s = if self.absolute || !(f > 0.0) {
            1.0
        } else {
            self.flux(reference) / f
        };
        let (mut diff, mut norm) = (0.0, 0.0);
        for ((l, r), w) in light.iter().zip(reference).zip(&self.solid_angle_sr) {
            diff += w * (s * l - r).powi(2);
            norm += w * r * r;
        }
        if norm > 0.0 {
            (diff / norm).sqrt()
        } else {
            f64::INFINITY
        }
    }
}

/// Quantiles of the γ distribution of flux the 2-Wasserstein residuals
/// compare, and the γ step they are read on (degrees).
const QUANTILES: usize = 200;
const QUANTILE_STEP_DEG: f64 = 0.05;

impl AxialTarget {
    /// The residuals whose sum of squares is the square of the
    /// 2-Wasserstein distance (radians) between the γ distributions of
    /// flux of `light` and of the target: where the light goes, smooth in
    /// the geometry even where the intensity's L2 is a needle.
    pub fn quantile_residuals(&self, light: &[f64]) -> Option<Vec<f64>> {
        let a = self.quantiles(light)?;
        let b = self.quantiles(&self.intensity)?;
        let n = (QUANTILES as f64).sqrt();
        Some(
            a.iter()
                .zip(&b)
                .map(|(a, b)| (a - b).to_radians() / n)
                .collect(),
        )
    }

    /// γ (degrees) at each quantile of `light`'s flux.
    fn quantiles(&self, light: &[f64]) -> Option<Vec<f64>> {
        use crate::model::direct::linear_at;
        let steps = (180.0 / QUANTILE_STEP_DEG).round() as usize;
        let h = QUANTILE_STEP_DEG.to_radians();
        let density = |k: usize| {
            let g = k as f64 * QUANTILE_STEP_DEG;
            linear_at(&self.gammas_deg, light, g) * g.to_radians().sin()
        };
        let mut c = vec![0.0; steps + 1];
        let mut previous = density(0);
        for k in 1..=steps {
            let d = density(k);
            c[k] = c[k - 1] + 0.5 * (previous + d) * h;
            previous = d;
        }
        let total = c[steps];
        if !(total > 0.0) {
            return None;
        }
        Some(
            (0..QUANTILES)
                .map(|i| {
                    let goal = (i as f64 + 0.5) / QUANTILES as f64 * total;
                    let j = c.partition_point(|&x| x < goal).clamp(1, steps);
                    let (c0, c1) = (c[j - 1], c[j]);
                    let t = if c1 > c0 {
                        (goal - c0) / (c1 - c0)
                    } else {
                        0.0
                    };
                    (j as f64 - 1.0 + t) * QUANTILE_STEP_DEG
                })
                .collect(),
        )
    }
}
