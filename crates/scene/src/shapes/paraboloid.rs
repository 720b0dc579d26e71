//! Paraboloid reflector (spotlights, parabolic downlights).

use glam::DVec2;
use serde::{Deserialize, Serialize};

use super::ShapeGenerator;
use crate::check::{Checker, FieldPath};
use crate::exact::{ExactSurface, parabola};
use crate::generators::{revolution_triangle_count, revolve};
use crate::mesh::TriangleMesh;
use crate::profile::sample_curve;

/// Paraboloid reflector with its focus at the origin, opening downwards
/// (−z): vertex at z = f, `r² = 4 f (f − z)`. `neck_diameter` cuts a hole
/// around the vertex for the lamp.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Paraboloid {
    /// f, from the focus to the vertex (m).
    pub focal_length: f64,
    /// Diameter of the rim (m).
    pub aperture_diameter: f64,
    /// Diameter of the hole around the vertex (m); 0 closes it.
    #[serde(default, skip_serializing_if = "crate::shapes::defaults::is_zero")]
    pub neck_diameter: f64,
    #[serde(default = "crate::shapes::defaults::default_around")]
    pub segments_around: u32,
    /// Segments from the neck to the rim.
    #[serde(default = "crate::shapes::defaults::default_along")]
    pub segments_along: u32,
    /// Flat facets (`segments_around` × `segments_along`) instead of a
    /// smooth surface.
    #[serde(default, skip_serializing_if = "crate::shapes::defaults::is_false")]
    pub faceted: bool,
}

impl ShapeGenerator for Paraboloid {
    fn kind(&self) -> &'static str {
        "paraboloid"
    }

    fn segments_around(&self) -> Option<u32> {
        Some(self.segments_around)
    }

    fn validate(&self, at: &FieldPath, check: &mut Checker<'_>) {
        check.length(at, "focal_length", self.focal_length);
        check.length(at, "aperture_diameter", self.aperture_diameter);
        check.non_negative(at, "neck_diameter", self.neck_diameter);
        if self.neck_diameter >= self.aperture_diameter {
            check.fail(
                at.key("neck_diameter"),
                format!(
                    "must be smaller than aperture_diameter ({}), got {}",
                    self.aperture_diameter, self.neck_diameter
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
        let f = self.focal_length;
        // Focus at the origin, vertex at z = f: z(r) = f − r²/(4f).
        let strip = sample_curve(
            0.5 * self.neck_diameter,
            0.5 * self.aperture_diameter,
            self.segments_along,
            |r| DVec2::new(r, f - r * r / (4.0 * f)),
            |r| DVec2::new(1.0, -r / (2.0 * f)),
        );
        Some(revolve(&[strip], self.segments_around, self.faceted))
    }

    fn exact(&self) -> Option<Vec<ExactSurface>> {
        (!self.faceted).then(|| {
            vec![ExactSurface::Revolution(vec![parabola(
                self.focal_length,
                0.5 * self.neck_diameter,
                0.5 * self.aperture_diameter,
            )])]
        })
    }
}
