//! A drawn profile revolved about the axis (custom reflectors, cones).

use serde::{Deserialize, Serialize};

use super::ShapeGenerator;
use crate::check::{Checker, FieldPath};
use crate::exact::ExactSurface;
use crate::generators::{revolution_triangle_count, revolve};
use crate::mesh::TriangleMesh;
use crate::profile::Interpolation;
use crate::profile::{exact_profile, sample_profile};

/// A profile `[r, z]` (metres, r ≥ 0) revolved about the z axis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Revolved {
    /// Control points `[r, z]` (m).
    pub profile: Vec<[f64; 2]>,
    #[serde(default)]
    pub interpolation: Interpolation,
    #[serde(default = "crate::shapes::defaults::default_around")]
    pub segments_around: u32,
    /// Segments per span between two control points.
    #[serde(default = "crate::shapes::defaults::default_per_span")]
    pub segments_per_span: u32,
    /// Flat facets instead of a smooth surface.
    #[serde(default, skip_serializing_if = "crate::shapes::defaults::is_false")]
    pub faceted: bool,
}

impl ShapeGenerator for Revolved {
    fn kind(&self) -> &'static str {
        "revolved"
    }

    fn validate(&self, at: &FieldPath, check: &mut Checker<'_>) {
        let negative_radius = |p: [f64; 2]| {
            (p[0] < 0.0)
                .then(|| format!("radius r must be ≥ 0 in a revolved profile, got {}", p[0]))
        };
        if check.profile(at, &self.profile, negative_radius) {
            // A span lying on the axis revolves into nothing.
            let profile = &self.profile;
            for i in 1..profile.len() {
                if profile[i][0] == 0.0 && profile[i - 1][0] == 0.0 {
                    check.fail(
                        at.key("profile").index(i),
                        "two consecutive points on the axis (r = 0) give a zero-area surface",
                    );
                }
            }
        }
        check.segments(at, "segments_around", self.segments_around, 3);
        check.profile_segments(at, self.profile.len(), self.segments_per_span);
    }

    fn triangle_count(&self) -> Option<u64> {
        let spans = self.profile.len().saturating_sub(1) as u64;
        Some(revolution_triangle_count(
            self.segments_around,
            spans.saturating_mul(u64::from(self.segments_per_span)),
        ))
    }

    fn generate(&self) -> Option<TriangleMesh> {
        Some(revolve(
            &sample_profile(&self.profile, self.interpolation, self.segments_per_span),
            self.segments_around,
            self.faceted,
        ))
    }

    fn exact(&self) -> Option<Vec<ExactSurface>> {
        (!self.faceted).then(|| {
            vec![ExactSurface::Revolution(exact_profile(
                &self.profile,
                self.interpolation,
            ))]
        })
    }
}
