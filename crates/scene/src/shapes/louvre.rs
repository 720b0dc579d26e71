//! Blade and cell louvres below an opening (glare control).

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::ShapeGenerator;
use crate::check::{Checker, FieldPath, MAX_SEGMENTS};
use crate::exact::ExactSurface;
use crate::generators::{oriented_corners, oriented_quad};
use crate::mesh::TriangleMesh;

/// Parallel thin blades along y, spaced along x, hanging from z = 0 down
/// to −`blade_height`, each tilted by `tilt_deg` about its own long axis;
/// optional cross blades along x make a cell louvre.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Louvre {
    pub blade_count: u32,
    /// Centre-to-centre distance of the blades along x (m).
    pub spacing: f64,
    /// Extent of each blade along z before tilting (m).
    pub blade_height: f64,
    /// Extent of each blade along y (m).
    pub blade_length: f64,
    /// Tilt of each blade about its long axis (degrees, within ±89).
    #[serde(default, skip_serializing_if = "crate::shapes::defaults::is_zero")]
    pub tilt_deg: f64,
    /// Cross blades spanning between the outer blades; 0 for none.
    #[serde(default, skip_serializing_if = "crate::shapes::defaults::is_zero_u32")]
    pub cross_blade_count: u32,
    /// Centre-to-centre distance of the cross blades along y (m).
    #[serde(default, skip_serializing_if = "crate::shapes::defaults::is_zero")]
    pub cross_spacing: f64,
}

impl ShapeGenerator for Louvre {
    fn kind(&self) -> &'static str {
        "louvre"
    }

    fn validate(&self, at: &FieldPath, check: &mut Checker<'_>) {
        check.segments(at, "blade_count", self.blade_count, 1);
        check.length(at, "spacing", self.spacing);
        check.length(at, "blade_height", self.blade_height);
        check.length(at, "blade_length", self.blade_length);
        let tilt_deg = self.tilt_deg;
        if check.finite(at, "tilt_deg", tilt_deg) && tilt_deg.abs() >= 89.0 {
            check.fail(
                at.key("tilt_deg"),
                format!("must be within ±89°, got {tilt_deg}"),
            );
        }
        let cross_blade_count = self.cross_blade_count;
        if cross_blade_count > MAX_SEGMENTS {
            check.fail(
                at.key("cross_blade_count"),
                format!("must be ≤ {MAX_SEGMENTS}, got {cross_blade_count}"),
            );
        }
        if cross_blade_count > 0 {
            check.length(at, "cross_spacing", self.cross_spacing);
            if self.blade_count < 2 {
                check.fail(
                    at.key("cross_blade_count"),
                    "cross blades span between blades: needs blade_count ≥ 2",
                );
            }
        }
    }

    /// Every blade and cross blade is one quad.
    fn triangle_count(&self) -> Option<u64> {
        Some(2 * (u64::from(self.blade_count) + u64::from(self.cross_blade_count)))
    }

    /// Blades are thin two-sided sheets; their normals face +x (cross
    /// blades +y) before tilting.
    fn generate(&self) -> Option<TriangleMesh> {
        let mut mesh = TriangleMesh::default();
        for (corners, normal) in self.blades() {
            mesh.append(&oriented_quad(corners, normal));
        }
        Some(mesh)
    }

    fn exact(&self) -> Option<Vec<ExactSurface>> {
        let polygon =
            |(corners, normal)| ExactSurface::Polygon(oriented_corners(corners, normal).to_vec());
        Some(self.blades().into_iter().map(polygon).collect())
    }
}

impl Louvre {
    /// Each blade's corners and the side its normal faces.
    fn blades(&self) -> Vec<([DVec3; 4], DVec3)> {
        let (blade_count, spacing) = (self.blade_count, self.spacing);
        let (blade_height, cross_blade_count) = (self.blade_height, self.cross_blade_count);
        let mut blades = Vec::new();
        let hl = 0.5 * self.blade_length;
        let hh = 0.5 * blade_height;
        let (st, ct) = self.tilt_deg.to_radians().sin_cos();
        for k in 0..blade_count {
            let x = (f64::from(k) - 0.5 * f64::from(blade_count - 1)) * spacing;
            // Tilt about the blade's long axis through its centre (x, −h/2).
            let at = |dz: f64, y: f64| DVec3::new(x - dz * st, y, -hh + dz * ct);
            let normal = DVec3::new(ct, 0.0, st);
            let corners = [at(-hh, -hl), at(-hh, hl), at(hh, hl), at(hh, -hl)];
            blades.push((corners, normal));
        }
        let span_x = f64::from(blade_count.saturating_sub(1)) * spacing;
        for k in 0..cross_blade_count {
            let y = (f64::from(k) - 0.5 * f64::from(cross_blade_count - 1)) * self.cross_spacing;
            let hx = 0.5 * span_x;
            let corners = [
                DVec3::new(-hx, y, -blade_height),
                DVec3::new(hx, y, -blade_height),
                DVec3::new(hx, y, 0.0),
                DVec3::new(-hx, y, 0.0),
            ];
            blades.push((corners, DVec3::Y));
        }
        blades
    }
}
