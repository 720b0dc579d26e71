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
    for i in 1..polygon.len() - 1 {
        let (a, b, c) = (polygon[0], polygon[i], polygon[i + 1]);
        let tri_area = 0.5 * (b - a).cross(c - a).length();
        let k = ((samples as f64 * tri_area / area).sqrt().ceil() as usize).max(1);
        let weight = tri_area / (k * k) as f64;
        for si in 0..k {
            for sj in 0..k {
                let u = (si as f64 + rng.next_f64()) / k as f64;
                let v = (sj as f64 + rng.next_f64()) / k as f64;
                // Area-preserving square → triangle map.
                let su = u.sqrt();
                let p = a * (1.0 - su) + b * (su * (1.0 - v)) + c * (su * v);
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
