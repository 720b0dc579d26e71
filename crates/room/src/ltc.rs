//! Specular reflection of a polygonal light by Linearly Transformed
//! Cosines (Heitz et al. 2016) with the GGX fit of the public reference
//! implementation (`data/ltc_ggx.txt`, licence in `data/LICENSE-LTC.txt`),
//! lit by the energy-equivalent radiance of Luksch et al. 2020, eq. 12–16.

use std::sync::OnceLock;

use glam::{DMat3, DVec3};

use crate::cubature::clip_polygon;

/// Entries per side of the fitted table.
pub const LTC_SIZE: usize = 64;

const LTC_TEXT: &str = include_str!("../data/ltc_ggx.txt");

/// The fitted table: per (roughness, view angle) the inverse transform's
/// four free entries and the BRDF's magnitude and Fresnel terms.
#[derive(Debug)]
pub struct LtcTable {
    /// `[m00, m20, m02, m22, magnitude, fresnel, unused, sphere]`, index
    /// `roughness_index + LTC_SIZE * theta_index`.
    pub entries: Vec<[f32; 8]>,
}

/// The GGX table, parsed once.
pub fn ggx_table() -> &'static LtcTable {
    static TABLE: OnceLock<LtcTable> = OnceLock::new();
    TABLE.get_or_init(|| {
        let entries: Vec<[f32; 8]> = LTC_TEXT
            .lines()
            .filter(|l| !l.starts_with('#') && !l.trim().is_empty())
            .map(|l| {
                let mut row = [0.0f32; 8];
                for (slot, word) in row.iter_mut().zip(l.split_whitespace()) {
                    *slot = word.parse().unwrap_or(0.0);
                }
                row
            })
            .collect();
        debug_assert_eq!(entries.len(), LTC_SIZE * LTC_SIZE);
        LtcTable { entries }
    })
}

impl LtcTable {
    /// Bilinear lookup at perceptual roughness r ∈ [0, 1] (GGX α = r²) and
    /// cos θ of the view direction.
    pub fn lookup(&self, roughness: f64, cos_theta: f64) -> [f64; 8] {
        let n = (LTC_SIZE - 1) as f64;
        let u = roughness.clamp(0.0, 1.0) * n;
        let v = (1.0 - cos_theta.clamp(0.0, 1.0)).sqrt() * n;
        let (u0, v0) = (
            (u.floor() as usize).min(LTC_SIZE - 2),
            (v.floor() as usize).min(LTC_SIZE - 2),
        );
        let (tu, tv) = (u - u0 as f64, v - v0 as f64);
        let at = |a: usize, t: usize| &self.entries[a + LTC_SIZE * t];
        let mut out = [0.0; 8];
        for k in 0..8 {
            let low = at(u0, v0)[k] as f64 * (1.0 - tu) + at(u0 + 1, v0)[k] as f64 * tu;
            let high = at(u0, v0 + 1)[k] as f64 * (1.0 - tu) + at(u0 + 1, v0 + 1)[k] as f64 * tu;
            out[k] = low * (1.0 - tv) + high * tv;
        }
        out
    }
}

/// Cosine-weighted fraction of the hemisphere (form factor) covered by a
/// polygon of directions: ∫ max(z, 0) dω / π over the polygon, clipped to
/// z ≥ 0 first. Two-sided.
pub fn polygon_form_factor(local: &[DVec3]) -> f64 {
    let clipped = clip_polygon(local, |p| p.z);
    if clipped.len() < 3 {
        return 0.0;
    }
    let mut sum = 0.0;
    for i in 0..clipped.len() {
        let a = clipped[i].normalize_or_zero();
        let b = clipped[(i + 1) % clipped.len()].normalize_or_zero();
        let c = a.cross(b);
        let s = c.length();
        if s > 1e-15 {
            // θ · (a × b / |a × b|) · z, with θ from atan2 for small edges.
            sum += s.atan2(a.dot(b)) * c.z / s;
        }
    }
    (sum / (2.0 * std::f64::consts::PI)).abs()
}

/// Specular radiance (cd/m²) at x towards the viewer: GGX of perceptual
/// roughness `roughness` and normal-incidence reflectance `f0`, lit by a
/// polygon of uniform radiance `radiance` (the energy-equivalent radiance).
pub fn specular_radiance(
    polygon: &[DVec3],
    x: DVec3,
    n: DVec3,
    to_viewer: DVec3,
    roughness: f64,
    f0: f64,
    radiance: f64,
) -> f64 {
    if radiance <= 0.0 || f0 <= 0.0 {
        return 0.0;
    }
    let cos_v = to_viewer.dot(n);
    if cos_v <= 0.0 {
        return 0.0;
    }
    let t = ggx_table().lookup(roughness, cos_v);
    let mut t1 = to_viewer - n * cos_v;
    if t1.length_squared() < 1e-18 {
        t1 = n.any_orthonormal_vector();
    }
    let t1 = t1.normalize();
    let t2 = n.cross(t1);
    // Rows: inverse LTC matrix (m11 = 1) times the change to the local frame.
    let m_inv = DMat3::from_cols(
        DVec3::new(t[0], 0.0, t[1]),
        DVec3::new(0.0, 1.0, 0.0),
        DVec3::new(t[2], 0.0, t[3]),
    );
    let local: crate::light::Polygon = polygon
        .iter()
        .map(|&p| {
            let d = p - x;
            m_inv * DVec3::new(d.dot(t1), d.dot(t2), d.dot(n))
        })
        .collect();
    let brdf_albedo = f0 * t[4] + (1.0 - f0) * t[5];
    radiance * polygon_form_factor(&local) * brdf_albedo
}
