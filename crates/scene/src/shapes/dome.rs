//! Spherical cap (bells, diffuser domes).

use glam::DVec2;
use serde::{Deserialize, Serialize};

use super::ShapeGenerator;
use crate::check::{Checker, FieldPath};
use crate::exact::{ExactSurface, elliptic_arc};
use crate::generators::{revolution_triangle_count, revolve};
use crate::mesh::TriangleMesh;
use crate::profile::sample_curve;

/// Spherical cap (bell, diffuser dome): pole at z = `height`, rim in the
/// z = 0 plane, normals towards the sphere's centre.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Dome {
    /// Radius of the sphere (m).
    pub radius: f64,
    /// From the rim's plane up to the pole (m), at most 2 × `radius`.
    pub height: f64,
    #[serde(default = "crate::shapes::defaults::default_around")]
    pub segments_around: u32,
    /// Segments from the pole to the rim.
    #[serde(default = "crate::shapes::defaults::default_along")]
    pub segments_along: u32,
}

impl ShapeGenerator for Dome {
    fn kind(&self) -> &'static str {
        "dome"
    }

    fn segments_around(&self) -> Option<u32> {
        Some(self.segments_around)
    }

    fn validate(&self, at: &FieldPath, check: &mut Checker<'_>) {
        check.length(at, "radius", self.radius);
        check.length(at, "height", self.height);
        if self.height > 2.0 * self.radius {
            check.fail(
                at.key("height"),
                format!(
                    "a spherical cap is at most 2 × radius = {} high",
                    2.0 * self.radius
                ),
            );
        }
        check.segments(at, "segments_around", self.segments_around, 3);
        check.segments(at, "segments_along", self.segments_along, 1);
    }

    fn triangle_count(&self) -> Option<u64> {
        Some(revolution_triangle_count(
            self.segments_around,
            u64::from(self.segments_along),
        ))
    }

    fn generate(&self) -> Option<TriangleMesh> {
        let radius = self.radius;
        // Sphere centre at z = height − radius; polar angle φ from the pole.
        let centre_z = self.height - radius;
        let phi_rim = ((-centre_z) / radius).clamp(-1.0, 1.0).acos();
        let strip = sample_curve(
            0.0,
            phi_rim,
            self.segments_along,
            |phi| DVec2::new(radius * phi.sin(), centre_z + radius * phi.cos()),
            |phi| DVec2::new(phi.cos(), -phi.sin()),
        );
        Some(revolve(&[strip], self.segments_around, false))
    }

    fn exact(&self) -> Option<Vec<ExactSurface>> {
        let (radius, centre_z) = (self.radius, self.height - self.radius);
        let phi_rim = ((-centre_z) / radius).clamp(-1.0, 1.0).acos();
        Some(vec![ExactSurface::Revolution(elliptic_arc(
            centre_z, radius, radius, 0.0, phi_rim,
        ))])
    }
}
