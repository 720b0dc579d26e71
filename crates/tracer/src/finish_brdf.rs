//! A finished surface's reflection: the microfacet
//! distribution is the finish's own tabulated slope distribution
//! ([`lucerna_scene::finish::SlopeStatistics`]) with its flat land as a
//! mirror-like share, not a Gaussian of the same variance.
//!
//! In the local frame (z the macro normal), a facet of slope s = (s_u,
//! s_v) has the normal m = (−s_u, −s_v, 1)/√(1 + |s|²); seen from `wo` it
//! shows the projected area (wo·m)/m_z = wo_z − wo_x s_u − wo_y s_v per unit
//! of surface. A visible facet is drawn with probability ∝ P22(s)·that
//! area (rejection against its largest value over the table), and `wo`
//! is reflected about it. A reflection that points into the surface would
//! meet another facet (multiple scattering, not modelled): it is lost, as
//! single-scattering microfacet models lose it.

use lucerna_scene::finish::SlopeStatistics;

/// A finish's slope distribution, ready to sample.
#[derive(Debug, Clone)]
pub struct FinishBrdf {
    range: f64,
    bins: usize,
    /// The flat land's share.
    flat: f64,
    /// Each table cell's probability (u fastest), and its cumulative sum.
    probability: Vec<f64>,
    cumulative: Vec<f64>,
    /// The cells by Walker's alias method (keep probability, alias): a
    /// cell in constant time per photon (a search of the 16 384 cells'
    /// sums cost a third of the smooth part's speed).
    alias: Vec<(f32, u32)>,
    /// The steepest slope the table holds (the farthest corner of its
    /// farthest cell with any probability, the flat land's 0 included):
    /// the rejection's bound, tighter than the table's square.
    steepest: f64,
}

/// Tries of the rejection before the photon is given up (at grazing
/// incidence on steep finishes the acceptance falls; the bound keeps a
/// photon's cost finite).
const MAX_TRIES: usize = 256;

impl FinishBrdf {
    pub fn new(stats: &SlopeStatistics) -> FinishBrdf {
        let t = &stats.table;
        let mut cumulative = Vec::with_capacity(t.probability.len());
        let mut sum = 0.0;
        for p in &t.probability {
            sum += p;
            cumulative.push(sum);
        }
        // Vose's construction over the table's cells and, last, the flat
        // land (one draw picks either).
        let alias = crate::sampling::alias_table(
            t.probability
                .iter()
                .map(|p| p / sum.max(1e-300) * (1.0 - stats.flat_share))
                .chain(std::iter::once(stats.flat_share)),
        );
        let w = 2.0 * t.range / t.bins as f64;
        let steepest = t
            .probability
            .iter()
            .enumerate()
            .filter(|(_, p)| **p > 0.0)
            .map(|(k, _)| {
                let (i, j) = ((k % t.bins) as f64, (k / t.bins) as f64);
                let far = |c: f64| {
                    (-t.range + c * w)
                        .abs()
                        .max((-t.range + (c + 1.0) * w).abs())
                };
                far(i).hypot(far(j))
            })
            .fold(0.0, f64::max);
        FinishBrdf {
            range: t.range,
            bins: t.bins,
            flat: stats.flat_share,
            probability: t.probability.clone(),
            cumulative,
            alias,
            steepest,
        }
    }

    /// The flat land's share.
    pub fn flat_share(&self) -> f64 {
        self.flat
    }

    /// The table's half width in slope.
    pub fn range(&self) -> f64 {
        self.range
    }

    /// Cells per table axis.
    pub fn bins(&self) -> usize {
        self.bins
    }

    /// The cells' cumulative probability (u fastest), ending at 1: what
    /// the WGSL kernel searches.
    pub fn normalised_cumulative(&self) -> impl Iterator<Item = f64> + '_ {
        let total = self.cumulative.last().copied().unwrap_or(1.0).max(1e-300);
        self.cumulative.iter().map(move |c| c / total)
    }

    fn cell_width(&self) -> f64 {
        2.0 * self.range / self.bins as f64
    }

    /// The slope density P22 at `s` (per unit slope area; the flat share
    /// is apart).
    pub fn slope_density(&self, s: [f64; 2]) -> f64 {
        let w = self.cell_width();
        let cell = |x: f64| {
            let k = ((x + self.range) / w).floor();
            (k >= 0.0 && k < self.bins as f64).then_some(k as usize)
        };
        match (cell(s[0]), cell(s[1])) {
            (Some(i), Some(j)) => self.probability[j * self.bins + i] / (w * w),
            _ => 0.0,
        }
    }

    /// The reflected direction of `wo` (local frame, wo_z > 0) off a
    /// visible facet, from a stream of uniforms; None where the
    /// reflection is lost into the surface or no facet was accepted.
    pub fn sample(&self, wo: [f64; 3], next: &mut dyn FnMut() -> f64) -> Option<[f64; 3]> {
        let m = self.sample_facet(wo, next)?;
        let d = wo[0] * m[0] + wo[1] * m[1] + wo[2] * m[2];
        let wi = [
            2.0 * d * m[0] - wo[0],
            2.0 * d * m[1] - wo[1],
            2.0 * d * m[2] - wo[2],
        ];
        (wi[2] > 0.0).then_some(wi)
    }

    /// The unit normal of a facet visible from `wo` (local frame, wo_z >
    /// 0), drawn in proportion to its slope probability times its
    /// projected area toward `wo`; None where no facet was accepted.
    pub fn sample_facet(&self, wo: [f64; 3], next: &mut dyn FnMut() -> f64) -> Option<[f64; 3]> {
        let wo = glam::Vec3A::new(wo[0] as f32, wo[1] as f32, wo[2] as f32);
        self.facet(wo, || next() as f32)
            .map(|m| [f64::from(m.x), f64::from(m.y), f64::from(m.z)])
    }

    /// [`FinishBrdf::sample_facet`] as the tracer runs it: single
    /// precision, a cell by the alias table, the uniforms from `next`.
    #[inline(always)]
    pub fn facet(&self, wo: glam::Vec3A, mut next: impl FnMut() -> f32) -> Option<glam::Vec3A> {
        let range = self.range as f32;
        // visible = wo_z − wo_xy·s ≤ wo_z + |wo_xy|·|s|max.
        let bound = wo.z + self.steepest as f32 * wo.x.hypot(wo.y);
        let n = self.alias.len();
        let land = n - 1;
        let width = 2.0 * range / self.bins as f32;
        for _ in 0..MAX_TRIES {
            let i = ((next() * n as f32) as usize).min(n - 1);
            let (keep, other) = self.alias[i];
            let k = if next() < keep { i } else { other as usize };
            let (sx, sy) = if k == land {
                (0.0, 0.0)
            } else {
                let (ci, cj) = (k % self.bins, k / self.bins);
                // The place in the cell from one draw: its low 12 bits
                // along u, the whole across v (independent at a 4096th of
                // a cell).
                let jitter = next();
                let ju = (jitter * 4096.0).fract();
                (
                    -range + (ci as f32 + ju) * width,
                    -range + (cj as f32 + jitter) * width,
                )
            };
            let visible = wo.z - wo.x * sx - wo.y * sy;
            if visible > 0.0 && next() * bound < visible {
                return Some(glam::Vec3A::new(-sx, -sy, 1.0).normalize());
            }
        }
        None
    }

    /// The share of the light arriving from `wo` that a mirror of
    /// reflectance 1 with this finish sends back out (the rest is
    /// reflected into the surface and lost: the shadowing), by
    /// quadrature over the table.
    pub fn reflected_share(&self, wo: [f64; 3]) -> f64 {
        let w = self.cell_width();
        let sub = 4;
        let (mut out, mut all) = (self.flat * wo[2], self.flat * wo[2]);
        for j in 0..self.bins {
            for i in 0..self.bins {
                let p = self.probability[j * self.bins + i];
                if p == 0.0 {
                    continue;
                }
                for b in 0..sub {
                    for a in 0..sub {
                        let s = [
                            -self.range + (i as f64 + (a as f64 + 0.5) / sub as f64) * w,
                            -self.range + (j as f64 + (b as f64 + 0.5) / sub as f64) * w,
                        ];
                        let visible = (wo[2] - wo[0] * s[0] - wo[1] * s[1]).max(0.0);
                        let q = p * visible / (sub * sub) as f64;
                        all += q;
                        let len2 = 1.0 + s[0] * s[0] + s[1] * s[1];
                        // wi_z = 2 (wo·m) m_z − wo_z, m = (−s, 1)/√len2.
                        let wi_z = 2.0 * visible / len2 - wo[2];
                        if wi_z > 0.0 {
                            out += q;
                        }
                    }
                }
            }
        }
        out / all
    }

    /// The expected visible projected area from `wo` per unit surface
    /// (the normalisation of the visible facets): the flat share's wo_z
    /// plus the table's ∫P22·(wo_z − wo·s)⁺.
    pub fn visible_area(&self, wo: [f64; 3]) -> f64 {
        let w = self.cell_width();
        let sub = 4;
        let mut total = self.flat * wo[2];
        for j in 0..self.bins {
            for i in 0..self.bins {
                let p = self.probability[j * self.bins + i];
                if p == 0.0 {
                    continue;
                }
                // The projected area is linear in s: its mean over a cell
                // is its value at the centre, except where it changes
                // sign inside the cell (sub-sampled there).
                let mut acc = 0.0;
                for b in 0..sub {
                    for a in 0..sub {
                        let s = [
                            -self.range + (i as f64 + (a as f64 + 0.5) / sub as f64) * w,
                            -self.range + (j as f64 + (b as f64 + 0.5) / sub as f64) * w,
                        ];
                        acc += (wo[2] - wo[0] * s[0] - wo[1] * s[1]).max(0.0);
                    }
                }
                total += p * acc / (sub * sub) as f64;
            }
        }
        total
    }

    /// The density over solid angle of a reflection `wi` of `wo` off the
    /// table's facets (the flat land's mirror share is a delta at the
    /// mirror direction, weighted [`FinishBrdf::flat_weight`]):
    /// P22(s)·(wo·m)/m_z / A(wo) / (m_z³ · 4 wo·m), with m the half vector.
    pub fn density(&self, wo: [f64; 3], wi: [f64; 3], visible_area: f64) -> f64 {
        let h = [wo[0] + wi[0], wo[1] + wi[1], wo[2] + wi[2]];
        let len = (h[0] * h[0] + h[1] * h[1] + h[2] * h[2]).sqrt();
        if !(len > 0.0 && h[2] > 0.0) {
            return 0.0;
        }
        let m = [h[0] / len, h[1] / len, h[2] / len];
        let s = [-m[0] / m[2], -m[1] / m[2]];
        let d = wo[0] * m[0] + wo[1] * m[1] + wo[2] * m[2];
        if d <= 0.0 {
            return 0.0;
        }
        let visible = d / m[2];
        self.slope_density(s) * visible / visible_area / (m[2].powi(3) * 4.0 * d)
    }

    /// The share of the visible reflection that is the flat land's
    /// mirror image.
    pub fn flat_weight(&self, wo: [f64; 3], visible_area: f64) -> f64 {
        self.flat * wo[2] / visible_area
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lucerna_scene::finish::{DimplePattern, Finish, Ripple, WaveShape};

    /// A small linear congruential stream of uniforms (the test's own,
    /// independent of the tracer's generator).
    fn stream(seed: u64) -> impl FnMut() -> f64 {
        let mut x = seed;
        move || {
            x = x
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((x >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        }
    }

    /// Samples reflections and compares their histogram over a grid of
    /// (wi_x, wi_y) with the density integrated over each cell (χ² over
    /// the cells expecting ≥ 20); the flat share's count with its weight.
    fn chi_square(finish: &Finish, theta_deg: f64) -> (f64, usize) {
        let brdf = FinishBrdf::new(&finish.statistics());
        let th = theta_deg.to_radians();
        let wo = [th.sin() * 0.8, th.sin() * 0.6, th.cos()];
        let mirror = [-wo[0], -wo[1], wo[2]];
        let area = brdf.visible_area(wo);
        let n = 400_000;
        let grid = 40;
        // The histogram around the mirror direction, as wide as the
        // reflections can turn (twice the steepest slope), at most ±0.5.
        let span = (4.4 * brdf.range).min(1.0);
        let lo = -0.5 * span;
        let mut counts = vec![0usize; grid * grid];
        let (mut flat, mut lost) = (0usize, 0usize);
        let mut next = stream(42 + theta_deg as u64);
        for _ in 0..n {
            match brdf.sample(wo, &mut next) {
                None => lost += 1,
                Some(wi) => {
                    if (wi[0] - mirror[0]).abs() < 1e-12 && (wi[1] - mirror[1]).abs() < 1e-12 {
                        flat += 1;
                        continue;
                    }
                    let (x, y) = (wi[0] - mirror[0], wi[1] - mirror[1]);
                    let (i, j) = (
                        ((x - lo) / span * grid as f64),
                        ((y - lo) / span * grid as f64),
                    );
                    if i >= 0.0 && j >= 0.0 && (i as usize) < grid && (j as usize) < grid {
                        counts[j as usize * grid + i as usize] += 1;
                    }
                }
            }
        }
        let _ = lost;
        // Expected: n × ∫ density dω over each cell, dω = dx dy / wi_z.
        // Fine enough to integrate the table's steps and the dimples'
        // sharp steepest slope within a cell.
        let sub = 40;
        let cell = span / grid as f64;
        let (mut chi2, mut dof) = (0.0, 0usize);
        for j in 0..grid {
            for i in 0..grid {
                let mut integral = 0.0;
                for b in 0..sub {
                    for a in 0..sub {
                        let x = lo + (i as f64 + (a as f64 + 0.5) / sub as f64) * cell;
                        let y = lo + (j as f64 + (b as f64 + 0.5) / sub as f64) * cell;
                        let wi = [mirror[0] + x, mirror[1] + y];
                        let z2 = 1.0 - wi[0] * wi[0] - wi[1] * wi[1];
                        if z2 <= 0.0 {
                            continue;
                        }
                        let wi = [wi[0], wi[1], z2.sqrt()];
                        integral += brdf.density(wo, wi, area) / wi[2];
                    }
                }
                let expected = n as f64 * integral * (cell * cell) / (sub * sub) as f64;
                if expected >= 20.0 {
                    let o = counts[j * grid + i] as f64;
                    chi2 += (o - expected).powi(2) / expected;
                    dof += 1;
                }
            }
        }
        let want_flat = n as f64 * brdf.flat_weight(wo, area);
        if want_flat >= 20.0 {
            chi2 += (flat as f64 - want_flat).powi(2) / want_flat;
            dof += 1;
        }
        (chi2, dof)
    }

    #[test]
    fn sampled_reflections_follow_the_evaluated_density() {
        let finishes = [
            Finish::Dimples {
                pitch: 2e-3,
                depth: 0.15e-3,
                radius: 3.4e-3,
                pattern: DimplePattern::Hexagonal,
            },
            Finish::Slopes {
                sigma_u: 0.05,
                sigma_v: 0.02,
                orientation_deg: 30.0,
            },
            // Orange peel: crossed waves, a sine and a trochoid.
            Finish::Ripples {
                waves: vec![
                    Ripple {
                        amplitude: 0.01e-3,
                        wavelength: 1e-3,
                        direction_deg: 0.0,
                        shape: WaveShape::Sine,
                    },
                    Ripple {
                        amplitude: 0.02e-3,
                        wavelength: 1.7e-3,
                        direction_deg: 90.0,
                        shape: WaveShape::Trochoid,
                    },
                ],
            },
        ];
        for f in &finishes {
            for theta in [0.0, 30.0, 60.0] {
                let (chi2, dof) = chi_square(f, theta);
                // χ²/dof of a right density is 1 ± √(2/dof); 1.3 is
                // beyond 4σ for these dof.
                eprintln!(
                    "{f:?} at {theta}°: χ²/dof {:.3} over {dof}",
                    chi2 / dof as f64
                );
                assert!(dof > 30, "{dof}");
                assert!(
                    chi2 / (dof as f64) < 1.3,
                    "{f:?} at {theta}°: {}",
                    chi2 / dof as f64
                );
            }
        }
    }

    #[test]
    fn a_wrong_density_fails_the_same_test() {
        // The sampler of one finish against the density of a Gaussian of
        // the same variance: the test must see the difference.
        let dimples = Finish::Dimples {
            pitch: 2e-3,
            depth: 0.15e-3,
            radius: 3.4e-3,
            pattern: DimplePattern::Hexagonal,
        };
        let c = dimples.statistics().covariance;
        let gaussian = Finish::Slopes {
            sigma_u: c[0].sqrt(),
            sigma_v: c[2].sqrt(),
            orientation_deg: 0.0,
        };
        let sampled = FinishBrdf::new(&dimples.statistics());
        let evaluated = FinishBrdf::new(&gaussian.statistics());
        let wo = [0.0, 0.0, 1.0];
        let area = evaluated.visible_area(wo);
        let mut next = stream(7);
        let n = 100_000;
        let grid = 20;
        let mut counts = vec![0usize; grid * grid];
        for _ in 0..n {
            if let Some(wi) = sampled.sample(wo, &mut next) {
                let i = ((wi[0] + 0.5) * grid as f64) as usize;
                let j = ((wi[1] + 0.5) * grid as f64) as usize;
                if i < grid && j < grid {
                    counts[j * grid + i] += 1;
                }
            }
        }
        let mut chi2 = 0.0;
        let mut dof = 0;
        for j in 0..grid {
            for i in 0..grid {
                let x = -0.5 + (i as f64 + 0.5) / grid as f64;
                let y = -0.5 + (j as f64 + 0.5) / grid as f64;
                let z = (1.0 - x * x - y * y).sqrt();
                let e = n as f64 * evaluated.density(wo, [x, y, z], area) / z
                    * (1.0 / grid as f64).powi(2);
                if e >= 20.0 {
                    chi2 += (counts[j * grid + i] as f64 - e).powi(2) / e;
                    dof += 1;
                }
            }
        }
        assert!(chi2 / dof as f64 > 10.0, "χ²/dof {}", chi2 / dof as f64);
    }

    #[test]
    fn a_finished_mirror_reflects_its_reflectance_less_the_computed_shadowing() {
        // Counted in whole photons: of n arriving, those reflected out
        // (reflectance R by roulette, the facet's reflection above the
        // surface) against n·R·(reflected share by quadrature), within
        // 5σ of the binomial; never more than arrived.
        let steep = Finish::Slopes {
            sigma_u: 0.5,
            sigma_v: 0.4,
            orientation_deg: 20.0,
        };
        let dimples = Finish::Dimples {
            pitch: 2e-3,
            depth: 0.6e-3,
            radius: 1.1e-3,
            pattern: DimplePattern::Square,
        };
        for f in [steep, dimples] {
            let brdf = FinishBrdf::new(&f.statistics());
            for theta in [0.0f64, 40.0] {
                let th = theta.to_radians();
                let wo = [th.sin(), 0.0, th.cos()];
                let reflectance = 0.85;
                let n = 400_000u64;
                let mut next = stream(11 + theta as u64);
                let mut out = 0u64;
                for _ in 0..n {
                    if next() < reflectance && brdf.sample(wo, &mut next).is_some() {
                        out += 1;
                    }
                }
                let p = reflectance * brdf.reflected_share(wo);
                let sigma = (n as f64 * p * (1.0 - p)).sqrt();
                eprintln!(
                    "{f:?} at {theta}°: {out} of {n}, expected {:.0}",
                    n as f64 * p
                );
                assert!(out <= n);
                assert!(
                    (out as f64 - n as f64 * p).abs() < 5.0 * sigma,
                    "{out} vs {}",
                    n as f64 * p
                );
                // The shadowing is real for these steep finishes.
                assert!(
                    brdf.reflected_share(wo) < 0.995,
                    "{}",
                    brdf.reflected_share(wo)
                );
            }
        }
    }
}
