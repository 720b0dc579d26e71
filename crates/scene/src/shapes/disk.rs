//! Flat circular disk (PCBs, canopies, round covers).

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::ShapeGenerator;
use crate::check::{Checker, FieldPath};
use crate::exact::ExactSurface;
use crate::generators::disk;
use crate::mesh::TriangleMesh;

/// Circular flat disk in the z = 0 plane, centred, normal −z.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Disk {
    /// Radius (m).
    pub radius: f64,
    #[serde(default = "crate::shapes::defaults::default_around")]
    pub segments_around: u32,
}

impl ShapeGenerator for Disk {
    fn kind(&self) -> &'static str {
        "disk"
    }

    fn segments_around(&self) -> Option<u32> {
        Some(self.segments_around)
    }

    fn validate(&self, at: &FieldPath, check: &mut Checker<'_>) {
        check.length(at, "radius", self.radius);
        check.segments(at, "segments_around", self.segments_around, 3);
    }

    fn triangle_count(&self) -> Option<u64> {
        Some(u64::from(self.segments_around))
    }

    fn generate(&self) -> Option<TriangleMesh> {
        Some(disk(self.radius, 0.0, self.segments_around, DVec3::NEG_Z))
    }

    fn exact(&self) -> Option<Vec<ExactSurface>> {
        Some(vec![ExactSurface::Disk {
            radius: self.radius,
            z: 0.0,
        }])
    }
}
