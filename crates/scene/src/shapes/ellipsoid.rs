//! Ellipsoidal reflector section (profile spots, double-focus optics).

use glam::DVec2;
use serde::{Deserialize, Serialize};

use super::ShapeGenerator;
use crate::check::{Checker, FieldPath};
use crate::exact::{ExactSurface, elliptic_arc};
use crate::generators::{revolution_triangle_count, revolve};
use crate::mesh::TriangleMesh;
use crate::profile::sample_curve;

/// Ellipsoidal reflector section: near focus at the origin, far focus at
/// (0, 0, −`focal_distance`), vertex `vertex_distance` above the near
/// focus; the section ends at the plane z = −`cut_below_focus`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Ellipsoid {
    /// Distance between the two foci (m).
    pub focal_distance: f64,
    /// From the near focus up to the vertex (m).
    pub vertex_distance: f64,
    /// Depth of the cut plane below the near focus (m); negative cuts above it.
    pub cut_below_focus: f64,
    /// Diameter of the hole around the vertex (m); 0 closes it.
    #[serde(default, skip_serializing_if = "crate::shapes::defaults::is_zero")]
    pub neck_diameter: f64,
    #[serde(default = "crate::shapes::defaults::default_around")]
    pub segments_around: u32,
    /// Segments from the neck to the cut plane.
    #[serde(default = "crate::shapes::defaults::default_along")]
    pub segments_along: u32,
    /// Flat facets instead of a smooth surface.
    #[serde(default, skip_serializing_if = "crate::shapes::defaults::is_false")]
    pub faceted: bool,
}

impl ShapeGenerator for Ellipsoid {
    fn kind(&self) -> &'static str {
        "ellipsoid"
    }

    fn segments_around(&self) -> Option<u32> {
        Some(self.segments_around)
    }

    fn validate(&self, at: &FieldPath, check: &mut Checker<'_>) {
        let (focal_distance, vertex_distance) = (self.focal_distance, self.vertex_distance);
        let (cut_below_focus, neck_diameter) = (self.cut_below_focus, self.neck_diameter);
        check.length(at, "focal_distance", focal_distance);
        check.length(at, "vertex_distance", vertex_distance);
        check.non_negative(at, "neck_diameter", neck_diameter);
        if check.finite(at, "cut_below_focus", cut_below_focus) {
            // The section must run from the vertex (z = vertex_distance)
            // to the cut plane, above the far vertex.
            let far_vertex = focal_distance + vertex_distance;
            if !(cut_below_focus > -vertex_distance && cut_below_focus < far_vertex) {
                check.fail(
                    at.key("cut_below_focus"),
                    format!(
                        "must lie between −vertex_distance ({}) and the far vertex ({far_vertex}), got {cut_below_focus}",
                        -vertex_distance
                    ),
                );
            }
        }
        let e = Ellipse::new(focal_distance, vertex_distance);
        if neck_diameter >= 2.0 * e.b {
            check.fail(
                at.key("neck_diameter"),
                format!(
                    "must be smaller than the ellipsoid's minor diameter {}",
                    2.0 * e.b
                ),
            );
        } else if cut_below_focus.is_finite() && neck_diameter > 0.0 {
            let z_neck = e.point(e.parameter_at_radius(0.5 * neck_diameter)).y;
            if -cut_below_focus >= z_neck {
                check.fail(
                    at.key("cut_below_focus"),
                    "the cut plane lies above the neck: the section is empty",
                );
            }
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
        let e = Ellipse::new(self.focal_distance, self.vertex_distance);
        let t0 = e.parameter_at_radius(0.5 * self.neck_diameter);
        let t1 = e.parameter_at_z(-self.cut_below_focus);
        let strip = sample_curve(
            t0,
            t1,
            self.segments_along,
            |t| e.point(t),
            |t| DVec2::new(e.b * t.cos(), -e.a * t.sin()),
        );
        Some(revolve(&[strip], self.segments_around, self.faceted))
    }

    fn exact(&self) -> Option<Vec<ExactSurface>> {
        if self.faceted {
            return None;
        }
        let e = Ellipse::new(self.focal_distance, self.vertex_distance);
        let t0 = e.parameter_at_radius(0.5 * self.neck_diameter);
        let t1 = e.parameter_at_z(-self.cut_below_focus);
        Some(vec![ExactSurface::Revolution(elliptic_arc(
            e.centre_z, e.a, e.b, t0, t1,
        ))])
    }
}

/// Ellipse of revolution with its near focus at the origin and its far
/// focus at z = −`focal_distance`, parametrised from the vertex:
/// (r, z) = (b sin t, centre + a cos t).
struct Ellipse {
    a: f64,
    b: f64,
    centre_z: f64,
}

impl Ellipse {
    fn new(focal_distance: f64, vertex_distance: f64) -> Self {
        let c = 0.5 * focal_distance;
        let a = c + vertex_distance;
        Ellipse {
            a,
            b: (a * a - c * c).sqrt(),
            centre_z: -c,
        }
    }

    /// (r, z) at parameter `t`.
    fn point(&self, t: f64) -> DVec2 {
        DVec2::new(self.b * t.sin(), self.centre_z + self.a * t.cos())
    }

    /// Parameter t ∈ [0, π/2] where the ellipse reaches radius `r`
    /// (π/2, the equator, for r ≥ b).
    fn parameter_at_radius(&self, r: f64) -> f64 {
        (r / self.b).clamp(0.0, 1.0).asin()
    }

    /// Parameter t (z = centre + a cos t) where the ellipse crosses `z`.
    fn parameter_at_z(&self, z: f64) -> f64 {
        ((z - self.centre_z) / self.a).clamp(-1.0, 1.0).acos()
    }
}
