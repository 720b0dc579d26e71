//! Ground truths for the cubature: Monte Carlo integration of eq. 1 of
//! Luksch et al. 2020 over the opening, and the exact polygon-to-point
//! form factor for a uniform (Lambertian) opening.

use glam::DVec3;

use crate::light::{Opening, PlacedLight};
use crate::ltc::polygon_form_factor;

/// splitmix64: a small seeded generator for stratified jitter.
#[derive(Debug, Clone)]
pub struct SplitMix(pub u64);

impl SplitMix {
    pub fn next_f64(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
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
    let mut rng = SplitMix(seed ^ 0x5DEE_CE66_D1CE_5EED);
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
    let mut rng = SplitMix(seed ^ 0xA5A5_5A5A_0F0F_F0F0);
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
