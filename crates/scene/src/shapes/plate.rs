//! Flat rectangular plate (covers, PCBs, baffles).

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::ShapeGenerator;
use crate::check::{Checker, FieldPath};
use crate::exact::ExactSurface;
use crate::generators::quad;
use crate::mesh::TriangleMesh;

/// Rectangular flat plate in the z = 0 plane, centred, normal −z.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Plate {
    /// Extent along x (m).
    pub width: f64,
    /// Extent along y (m).
    pub depth: f64,
}

impl Plate {
    fn corners(&self) -> [DVec3; 4] {
        let (hw, hd) = (0.5 * self.width, 0.5 * self.depth);
        [
            DVec3::new(-hw, -hd, 0.0),
            DVec3::new(-hw, hd, 0.0),
            DVec3::new(hw, hd, 0.0),
            DVec3::new(hw, -hd, 0.0),
        ]
    }
}

impl ShapeGenerator for Plate {
    fn kind(&self) -> &'static str {
        "plate"
    }

    fn validate(&self, at: &FieldPath, check: &mut Checker<'_>) {
        check.length(at, "width", self.width);
        check.length(at, "depth", self.depth);
    }

    fn triangle_count(&self) -> Option<u64> {
        Some(2)
    }

    fn generate(&self) -> Option<TriangleMesh> {
        Some(quad(self.corners(), DVec3::NEG_Z))
    }

    fn exact(&self) -> Option<Vec<ExactSurface>> {
        Some(vec![ExactSurface::Polygon(self.corners().to_vec())])
    }
}
