//! What a light gives at one shading point, whichever rule computed it,
//! and the far-field baseline every rule falls back to.

use glam::DVec3;

use crate::light::PlacedLight;

/// What a rule (the cubature, the polar rule, the point source) gives at
/// one shading point.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct CubatureResult {
    /// Illuminance on the surface (lx).
    pub lux: f64,
    /// ∫ cos dω over the visible opening (sr), eq. 15: divides `lux` into
    /// the energy-equivalent radiance of eq. 16.
    pub cosine_solid_angle: f64,
}

impl CubatureResult {
    /// Energy-equivalent uniform radiance of the opening (cd/m²), eq. 16.
    pub fn equivalent_radiance(&self) -> f64 {
        if self.cosine_solid_angle > 1e-12 {
            self.lux / self.cosine_solid_angle
        } else {
            0.0
        }
    }
}

/// The far-field (point-source) illuminance E = I cos θ / d², the
/// baseline every photometric tool uses.
pub fn point_illuminance(light: &PlacedLight, x: DVec3, n: DVec3) -> CubatureResult {
    let to_x = x - light.position;
    let d2 = to_x.length_squared();
    if d2 <= 0.0 {
        return CubatureResult::default();
    }
    let omega = to_x / d2.sqrt();
    let cos = (-omega).dot(n).max(0.0);
    CubatureResult {
        lux: light.candela_towards(omega) * cos / d2,
        cosine_solid_angle: 0.0,
    }
}
