//! Ground truths for the near-field rules: the exact quadrature of the
//! polar sweep (`exact_illuminance`, adaptive Gauss–Kronrod between the
//! integrand's kinks), Monte Carlo integration of eq. 1 of Luksch et al.
//! 2020 over the opening, and the exact polygon-to-point form factor for a
//! uniform (Lambertian) opening.

use glam::DVec3;
use rand_xoshiro::SplitMix64;
use rand_xoshiro::rand_core::{RngCore, SeedableRng};

use crate::light::{Opening, PlacedLight};
use crate::ltc::polygon_form_factor;
use crate::polar::{PolarSetup, setup};
use crate::profile::ProfileGrid;
use crate::radial::Partial;
use crate::shading::point_illuminance;

/// The references' seeded random numbers: rand_xoshiro's SplitMix64 (the
/// workspace's one), with uniform reals and directions on top.
#[derive(Debug, Clone)]
pub struct SplitMix(SplitMix64);

impl SplitMix {
    pub fn new(seed: u64) -> SplitMix {
        SplitMix(SplitMix64::seed_from_u64(seed))
    }

    /// Uniform in [0, 1), 53 bits.
    pub fn next_f64(&mut self) -> f64 {
        (self.0.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }

    /// A direction uniform on the unit sphere.
    pub fn unit_vector(&mut self) -> DVec3 {
        let z = 2.0 * self.next_f64() - 1.0;
        let phi = std::f64::consts::TAU * self.next_f64();
        let r = (1.0 - z * z).max(0.0).sqrt();
        DVec3::new(r * phi.cos(), r * phi.sin(), z)
    }
}

/// One fan triangle (a, b, c) of a convex polygon with k × k jittered
/// strata, k² about its share of the samples.
#[derive(Debug, Clone, Copy)]
struct FanStrata {
    a: DVec3,
    b: DVec3,
    c: DVec3,
    k: usize,
    area: f64,
}

impl FanStrata {
    /// A jittered point of stratum (si, sj), by the area-preserving
    /// square → triangle map.
    fn point(&self, si: usize, sj: usize, rng: &mut SplitMix) -> DVec3 {
        let u = (si as f64 + rng.next_f64()) / self.k as f64;
        let v = (sj as f64 + rng.next_f64()) / self.k as f64;
        let su = u.sqrt();
        self.a * (1.0 - su) + self.b * (su * (1.0 - v)) + self.c * (su * v)
    }
}

fn fan_strata(polygon: &[DVec3], area: f64, samples: usize) -> Vec<FanStrata> {
    (1..polygon.len().saturating_sub(1))
        .map(|i| {
            let (a, b, c) = (polygon[0], polygon[i], polygon[i + 1]);
            let tri_area = 0.5 * (b - a).cross(c - a).length();
            let k = ((samples as f64 * tri_area / area).sqrt().round() as usize).max(1);
            FanStrata {
                a,
                b,
                c,
                k,
                area: tri_area,
            }
        })
        .collect()
}

/// Illuminance (lx) at x (unit normal n) by integrating
/// E = 1/A ∫_A I(x − x′) cos θ / r² dA′ with about `samples` jittered
/// stratified points on the opening (each fan triangle gets its share).
pub fn monte_carlo_illuminance(
    light: &PlacedLight,
    x: DVec3,
    n: DVec3,
    samples: usize,
    seed: u64,
) -> f64 {
    if light.opening == Opening::Point {
        return crate::cubature::point_illuminance(light, x, n).lux;
    }
    let polygon = light.world_polygon();
    let area = light.opening.area_m2();
    let mut rng = SplitMix::new(seed ^ 0x5DEE_CE66_D1CE_5EED);
    let mut sum = 0.0;
    for fan in fan_strata(&polygon, area, samples) {
        let weight = fan.area / (fan.k * fan.k) as f64;
        for si in 0..fan.k {
            for sj in 0..fan.k {
                let p = fan.point(si, sj, &mut rng);
                let to_x = x - p;
                let r2 = to_x.length_squared();
                if r2 <= 0.0 {
                    continue;
                }
                let omega = to_x / r2.sqrt();
                let cos = (-omega).dot(n);
                if cos > 0.0 {
                    sum += weight * light.candela_towards(omega) * cos / r2;
                }
            }
        }
    }
    sum / area
}

/// Exact illuminance (lx) at x from an opening of uniform radiance
/// `radiance` (cd/m²): E = L · π · F, F the polygon-to-point form factor
/// of the part above x's horizon.
pub fn uniform_polygon_illuminance(polygon: &[DVec3], radiance: f64, x: DVec3, n: DVec3) -> f64 {
    let t1 = n.any_orthonormal_vector();
    let t2 = n.cross(t1);
    let local: Vec<DVec3> = polygon
        .iter()
        .map(|&p| {
            let d = p - x;
            DVec3::new(d.dot(t1), d.dot(t2), d.dot(n))
        })
        .collect();
    radiance * std::f64::consts::PI * polygon_form_factor(&local)
}

/// Directions drawn in proportion to a profile's intensity: a discrete
/// distribution over the grid's cells (weight = mean corner candela × the
/// cell's solid angle), uniform in cos γ and C within a cell.
#[derive(Debug, Clone)]
pub struct ProfileDirectionSampler {
    cdf: Vec<f64>,
    /// Probability of each cell divided by its solid angle (1/sr).
    density: Vec<f64>,
    c_cells: usize,
    gamma_cells: usize,
    c_step: f64,
    gamma_step: f64,
}

impl ProfileDirectionSampler {
    pub fn new(profile: &crate::profile::ProfileGrid) -> Option<ProfileDirectionSampler> {
        let rotational = profile.c_count == 1;
        let c_cells = if rotational { 1 } else { profile.c_count - 1 };
        let gamma_cells = profile.gamma_count - 1;
        let c_step = if rotational {
            std::f64::consts::TAU
        } else {
            profile.c_step_deg.to_radians()
        };
        let gamma_step = profile.gamma_step_deg.to_radians();
        let at = |c: usize, g: usize| {
            let c = if rotational { 0 } else { c };
            profile.candela[c * profile.gamma_count + g] as f64
        };
        let mut weights = Vec::with_capacity(c_cells * gamma_cells);
        let mut solid = Vec::with_capacity(c_cells * gamma_cells);
        for c in 0..c_cells {
            for g in 0..gamma_cells {
                let (c1, g1) = (if rotational { 0 } else { c + 1 }, g + 1);
                let mean = (at(c, g) + at(c, g1) + at(c1, g) + at(c1, g1)) / 4.0;
                let omega =
                    ((g as f64 * gamma_step).cos() - (g1 as f64 * gamma_step).cos()) * c_step;
                weights.push(mean * omega);
                solid.push(omega);
            }
        }
        let total: f64 = weights.iter().sum();
        if total.is_nan() || total <= 0.0 {
            return None;
        }
        let mut acc = 0.0;
        let cdf = weights
            .iter()
            .map(|w| {
                acc += w / total;
                acc
            })
            .collect();
        let density = weights
            .iter()
            .zip(&solid)
            .map(|(w, o)| if *o > 0.0 { w / total / o } else { 0.0 })
            .collect();
        Some(ProfileDirectionSampler {
            cdf,
            density,
            c_cells,
            gamma_cells,
            c_step,
            gamma_step,
        })
    }

    /// A luminaire-frame direction from three uniform numbers.
    pub fn sample(&self, u: f64, v: f64, w: f64) -> DVec3 {
        let cell = self.cdf.partition_point(|&c| c < u).min(self.cdf.len() - 1);
        let (c, g) = (cell / self.gamma_cells, cell % self.gamma_cells);
        let (cos0, cos1) = (
            (g as f64 * self.gamma_step).cos(),
            ((g + 1) as f64 * self.gamma_step).cos(),
        );
        let cos_g = cos0 + (cos1 - cos0) * v;
        let sin_g = (1.0 - cos_g * cos_g).max(0.0).sqrt();
        let phi = (c as f64 + w) * self.c_step;
        DVec3::new(sin_g * phi.cos(), sin_g * phi.sin(), -cos_g)
    }

    /// Density (1/sr) of a luminaire-frame direction.
    pub fn pdf(&self, d: DVec3) -> f64 {
        let horizontal = (d.x * d.x + d.y * d.y).sqrt();
        let gamma = horizontal.atan2(-d.z);
        let g = ((gamma / self.gamma_step) as usize).min(self.gamma_cells - 1);
        let c = if self.c_cells == 1 {
            0
        } else {
            let phi = d.y.atan2(d.x).rem_euclid(std::f64::consts::TAU);
            ((phi / self.c_step) as usize).min(self.c_cells - 1)
        };
        self.density[c * self.gamma_cells + g]
    }
}

/// Illuminance (lx) at x by multiple importance sampling of two
/// techniques, `samples` each: points on the opening (good for wide
/// profiles near the light) and directions drawn from the profile (good
/// for narrow beams, which area sampling misses), balance heuristic. The
/// ground truth for the near-field evaluation.
pub fn mis_illuminance(
    light: &PlacedLight,
    sampler: &ProfileDirectionSampler,
    x: DVec3,
    n: DVec3,
    samples: usize,
    seed: u64,
) -> f64 {
    if light.opening == Opening::Point {
        return crate::cubature::point_illuminance(light, x, n).lux;
    }
    let polygon = light.world_polygon();
    let area = light.opening.area_m2();
    let normal_a = light.normal();
    let to_luminaire = light.rotation.transpose();
    let mut rng = SplitMix::new(seed ^ 0xA5A5_5A5A_0F0F_F0F0);
    let n_f = samples as f64;
    // Integrand L cos θx (per steradian) and the area technique's density
    // for the direction from x towards a point p of the opening.
    let contribution = |p: DVec3| -> Option<(f64, f64, DVec3)> {
        let to_p = p - x;
        let r2 = to_p.length_squared();
        if r2 <= 0.0 {
            return None;
        }
        let d = to_p / r2.sqrt();
        let cos_x = d.dot(n);
        let cos_a = d.dot(normal_a).abs();
        if cos_x <= 0.0 || cos_a <= 1e-12 {
            return None;
        }
        let emit = to_luminaire * -d;
        let f = light.profile.candela(emit) / (area * cos_a) * cos_x;
        let p_area = r2 / (area * cos_a);
        Some((f, p_area, emit))
    };
    // Stratified k × k points per fan triangle: their density on triangle
    // i is `share` × N / A per unit area.
    let fans: Vec<(FanStrata, f64)> = fan_strata(&polygon, area, samples)
        .into_iter()
        .map(|f| (f, (f.k * f.k) as f64 / (n_f * f.area / area)))
        .collect();
    let share_at = |p: DVec3| -> f64 {
        for &(f, share) in &fans {
            let (v0, v1, v2) = (f.b - f.a, f.c - f.a, p - f.a);
            let (d00, d01, d11) = (v0.dot(v0), v0.dot(v1), v1.dot(v1));
            let (d20, d21) = (v2.dot(v0), v2.dot(v1));
            let den = d00 * d11 - d01 * d01;
            if den <= 0.0 {
                continue;
            }
            let v = (d11 * d20 - d01 * d21) / den;
            let w = (d00 * d21 - d01 * d20) / den;
            if v >= -1e-9 && w >= -1e-9 && v + w <= 1.0 + 1e-9 {
                return share;
            }
        }
        1.0
    };
    let mut sum = 0.0;
    // Technique 1: stratified points on the opening (fan triangles).
    for &(fan, share) in &fans {
        for si in 0..fan.k {
            for sj in 0..fan.k {
                let p = fan.point(si, sj, &mut rng);
                if let Some((f, p_area, emit)) = contribution(p) {
                    let p_dir = sampler.pdf(emit);
                    // This triangle's points have density share × N × p_area.
                    sum += f / (share * n_f * p_area + n_f * p_dir);
                }
            }
        }
    }
    // Technique 2: directions from the profile, kept if the line from x
    // back along them meets the opening.
    for _ in 0..samples {
        let emit = sampler.sample(rng.next_f64(), rng.next_f64(), rng.next_f64());
        let d = -(light.rotation * emit); // from x towards the light
        let denom = d.dot(normal_a);
        if denom.abs() < 1e-12 {
            continue;
        }
        let t = (light.position - x).dot(normal_a) / denom;
        if t <= 0.0 {
            continue;
        }
        let p = x + d * t;
        let q = crate::cubature::closest_point_on_polygon(&polygon, normal_a, p);
        if (q - p).length_squared() > 1e-18 {
            continue;
        }
        if let Some((f, p_area, _)) = contribution(p) {
            let p_dir = sampler.pdf(emit);
            sum += f / (share_at(p) * n_f * p_area + n_f * p_dir);
        }
    }
    sum
}

/// Gauss–Kronrod 7–15 on [−1, 1]: Kronrod nodes (positive half, the last
/// is 0), Kronrod weights, and the Gauss weights of every other node.
const KRONROD_NODES: [f64; 8] = [
    0.991_455_371_120_812_6,
    0.949_107_912_342_758_5,
    0.864_864_423_359_769_1,
    0.741_531_185_599_394_4,
    0.586_087_235_467_691_1,
    0.405_845_151_377_397_2,
    0.207_784_955_007_898_5,
    0.0,
];
const KRONROD_WEIGHTS: [f64; 8] = [
    0.022_935_322_010_529_2,
    0.063_092_092_629_978_6,
    0.104_790_010_322_250_2,
    0.140_653_259_715_525_9,
    0.169_004_726_639_267_9,
    0.190_350_578_064_785_4,
    0.204_432_940_075_298_9,
    0.209_482_141_084_728,
];
/// Gauss weights of Kronrod nodes 1, 3, 5 and 7 (0-based).
const GAUSS7_WEIGHTS: [f64; 4] = [
    0.129_484_966_168_869_7,
    0.279_705_391_489_276_7,
    0.381_830_050_505_118_9,
    0.417_959_183_673_469_4,
];

/// (Kronrod estimate, |Kronrod − Gauss|) of ∫ f over [a, b].
pub fn gauss_kronrod(f: &mut impl FnMut(f64) -> f64, a: f64, b: f64) -> (f64, f64) {
    let centre = 0.5 * (a + b);
    let half = 0.5 * (b - a);
    let mid = f(centre);
    let mut kronrod = KRONROD_WEIGHTS[7] * mid;
    let mut gauss = GAUSS7_WEIGHTS[3] * mid;
    for i in 0..7 {
        let pair = f(centre - half * KRONROD_NODES[i]) + f(centre + half * KRONROD_NODES[i]);
        kronrod += KRONROD_WEIGHTS[i] * pair;
        if i % 2 == 1 {
            gauss += GAUSS7_WEIGHTS[i / 2] * pair;
        }
    }
    (kronrod * half, ((kronrod - gauss) * half).abs())
}

/// Most bisections of one adaptive integral.
const MAX_BISECTIONS: usize = 2000;

/// Adaptive Gauss–Kronrod: bisects until each piece's error estimate is
/// below its share (by length) of the absolute `tolerance` for [a, b], or
/// at rounding, 40 levels deep or `MAX_BISECTIONS` done.
pub fn adaptive(f: &mut impl FnMut(f64) -> f64, a: f64, b: f64, tolerance: f64) -> f64 {
    let mut total = 0.0;
    let mut stack = vec![(a, b, 0u32)];
    let length = (b - a).abs().max(1e-300);
    let mut bisections = 0;
    while let Some((lo, hi, depth)) = stack.pop() {
        let (value, error) = gauss_kronrod(f, lo, hi);
        // Rounding bounds what bisection can win; a budget bounds its cost.
        let settled = error <= tolerance * (hi - lo).abs() / length
            || error <= 1e-13 * value.abs()
            || depth >= 40
            || bisections >= MAX_BISECTIONS;
        if settled {
            total += value;
        } else {
            bisections += 1;
            let mid = 0.5 * (lo + hi);
            stack.push((lo, mid, depth + 1));
            stack.push((mid, hi, depth + 1));
        }
    }
    total
}

/// The directions in (lo, hi) where the integrand has a kink: where the
/// ray's C-plane crosses a grid column, and where the ray's end on an
/// edge's line crosses a γ node (ρ = h tan θⱼ). Between them, and the
/// sweep's vertex directions, it is analytic.
fn kinks(grid: &ProfileGrid, s: &PolarSetup, lo: f64, hi: f64) -> Vec<f64> {
    let pi = std::f64::consts::PI;
    let mut out = Vec::new();
    if grid.c_count > 1 {
        // C = φ + π: columns at φ = k·step − π.
        let step = grid.c_step_deg.to_radians();
        for k in ((lo + pi) / step).floor() as i64..=((hi + pi) / step).ceil() as i64 {
            out.push(k as f64 * step - pi);
        }
    }
    let m = s.polygon.len();
    let half = (grid.gamma_count - 1) / 2;
    let step = grid.gamma_step_deg.to_radians();
    for i in 0..m {
        let a = s.polygon[i];
        let edge = s.polygon[(i + 1) % m] - a;
        let length2 = edge.length_squared();
        if length2 == 0.0 {
            continue;
        }
        let foot = a - edge * (a.dot(edge) / length2);
        let d = foot.length();
        let normal_angle = foot.y.atan2(foot.x);
        for j in 1..half {
            let rho = s.height * (j as f64 * step).tan();
            if rho > d {
                let spread = (d / rho).acos();
                for phi in [normal_angle - spread, normal_angle + spread] {
                    for turn in [-2.0 * pi, 0.0, 2.0 * pi] {
                        out.push(phi + turn);
                    }
                }
            }
        }
    }
    out.retain(|&p| p > lo && p < hi);
    out.sort_by(f64::total_cmp);
    out
}

/// Exact illuminance (lx) of receiver x (normal n) for the profile grid's
/// bilinear interpolant, to about `relative` (1e-9 is cheap): the sweep
/// integrated in φ by Gauss–Kronrod between the integrand's kinks,
/// bisected where its error estimate asks, with exact radial integrals.
/// Receivers in the opening's plane take the front-side limit.
pub fn exact_illuminance(light: &PlacedLight, x: DVec3, n: DVec3, relative: f64) -> f64 {
    if light.opening == Opening::Point {
        return point_illuminance(light, x, n).lux;
    }
    let Some(s) = setup(light, x, n) else {
        return 0.0;
    };
    let grid = &light.profile;
    let inside = s.foot_inside();
    let sweep = s.sweep(inside);
    let (Some(&(first, _)), Some(&(last, _))) = (sweep.first(), sweep.last()) else {
        return 0.0;
    };
    let mut cuts: Vec<f64> = sweep.iter().map(|&(a, _)| a).collect();
    cuts.extend(kinks(grid, &s, first, last));
    cuts.sort_by(f64::total_cmp);
    cuts.dedup();
    let mut f = |phi: f64| s.ray_integral(grid, phi, inside, Partial::Exact);
    let first_pass: Vec<(f64, f64)> = cuts
        .windows(2)
        .map(|w| gauss_kronrod(&mut f, w[0], w[1]))
        .collect();
    let scale: f64 = first_pass.iter().map(|(v, _)| v.abs()).sum();
    let tolerance = relative * scale / first_pass.len().max(1) as f64;
    let mut sum = 0.0;
    for (w, &(value, error)) in cuts.windows(2).zip(&first_pass) {
        sum += if error <= tolerance {
            value
        } else {
            adaptive(&mut f, w[0], w[1], tolerance)
        };
    }
    (sum / light.opening.area_m2()).max(0.0)
}
