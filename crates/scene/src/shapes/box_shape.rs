//! Axis-aligned box (housings, light boxes); `box` is a Rust keyword,
//! hence the file's and the struct's names.

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::ShapeGenerator;
use crate::check::{Checker, FieldPath, MAX_LENGTH_M};
use crate::exact::ExactSurface;
use crate::generators::{oriented_corners, oriented_quad};
use crate::mesh::TriangleMesh;

/// Axis-aligned box centred at the origin, outward normals (`type = "box"`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoxShape {
    /// Extent along x, y, z (m).
    pub size: [f64; 3],
    /// Leave out the −z face (a housing open towards the light exit).
    #[serde(default, skip_serializing_if = "crate::shapes::defaults::is_false")]
    pub open_bottom: bool,
}

impl ShapeGenerator for BoxShape {
    fn kind(&self) -> &'static str {
        "box"
    }

    fn validate(&self, at: &FieldPath, check: &mut Checker<'_>) {
        for (i, &v) in self.size.iter().enumerate() {
            if !(v.is_finite() && v > 0.0 && v <= MAX_LENGTH_M) {
                check.fail(
                    at.key("size").index(i),
                    format!("must be a length in metres, > 0 and ≤ {MAX_LENGTH_M}, got {v}"),
                );
            }
        }
    }

    fn triangle_count(&self) -> Option<u64> {
        Some(if self.open_bottom { 10 } else { 12 })
    }

    fn generate(&self) -> Option<TriangleMesh> {
        let mut mesh = TriangleMesh::default();
        for (corners, normal) in self.faces() {
            mesh.append(&oriented_quad(corners, normal));
        }
        Some(mesh)
    }

    fn exact(&self) -> Option<Vec<ExactSurface>> {
        let polygon =
            |(corners, normal)| ExactSurface::Polygon(oriented_corners(corners, normal).to_vec());
        Some(self.faces().into_iter().map(polygon).collect())
    }
}

impl BoxShape {
    /// Each face's corners and outward normal.
    fn faces(&self) -> Vec<([DVec3; 4], DVec3)> {
        let half = DVec3::from_array(self.size) * 0.5;
        let mut faces = Vec::with_capacity(6);
        for axis in 0..3 {
            for sign in [-1.0, 1.0] {
                if axis == 2 && sign < 0.0 && self.open_bottom {
                    continue;
                }
                let mut normal = DVec3::ZERO;
                normal[axis] = sign;
                let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
                let corner = |a: f64, b: f64| {
                    let mut p = DVec3::ZERO;
                    p[axis] = sign * half[axis];
                    p[u] = a * half[u];
                    p[v] = b * half[v];
                    p
                };
                let corners = [
                    corner(-1.0, -1.0),
                    corner(1.0, -1.0),
                    corner(1.0, 1.0),
                    corner(-1.0, 1.0),
                ];
                faces.push((corners, normal));
            }
        }
        faces
    }
}
