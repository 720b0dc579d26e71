//! Indexed triangle meshes, as generators and OBJ import produce them.

use glam::{DAffine3, DVec3, Vec3};

/// An indexed triangle mesh with per-vertex shading normals (metres).
///
/// Winding is counter-clockwise about the geometric normal
/// `(b − a) × (c − a)`, which points to the same side as the shading normals.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TriangleMesh {
    pub positions: Vec<Vec3>,
    /// Unit shading normals, one per position.
    pub normals: Vec<Vec3>,
    pub triangles: Vec<[u32; 3]>,
}

/// What is wrong with a mesh, with the first offending index.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MeshDefect {
    #[error("vertex {index} has a non-finite coordinate {value:?}")]
    NonFiniteVertex { index: usize, value: [f32; 3] },
    #[error("vertex {index} has a non-finite or zero normal {value:?}")]
    BadNormal { index: usize, value: [f32; 3] },
    #[error("triangle {index} refers to vertex {vertex}, but there are only {count}")]
    IndexOutOfRange {
        index: usize,
        vertex: u32,
        count: usize,
    },
    #[error(
        "{count} degenerate (zero-area) triangle(s), the first is triangle {first} with area {area:.3e} m²"
    )]
    Degenerate {
        count: usize,
        first: usize,
        area: f64,
    },
    #[error("the mesh has no triangles")]
    Empty,
    #[error("the mesh has {normals} normals for {positions} vertices")]
    NormalCount { normals: usize, positions: usize },
    #[error(
        "the mesh is {extent_m:.3e} m across, outside the plausible range for a luminaire part ({min_m} m to {max_m} m); check the units (transform.scale)"
    )]
    AbsurdSize {
        extent_m: f64,
        min_m: f64,
        max_m: f64,
    },
}

/// Smallest and largest plausible part extent (m): a sub-millimetre LED die
/// to a 50 m light line.
pub const MIN_EXTENT_M: f64 = 1e-5;
pub const MAX_EXTENT_M: f64 = 50.0;

impl TriangleMesh {
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// Corner positions of triangle `t` in double precision.
    pub fn corners(&self, t: usize) -> [DVec3; 3] {
        self.triangles[t].map(|i| self.positions[i as usize].as_dvec3())
    }

    /// Unnormalised geometric normal of triangle `t`; its length is twice
    /// the area.
    pub fn geometric_normal(&self, t: usize) -> DVec3 {
        let [a, b, c] = self.corners(t);
        (b - a).cross(c - a)
    }

    /// Total surface area (m²).
    pub fn area(&self) -> f64 {
        (0..self.triangles.len())
            .map(|t| 0.5 * self.geometric_normal(t).length())
            .sum()
    }

    /// Axis-aligned bounds, `None` for an empty mesh.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let first = *self.positions.first()?;
        Some(
            self.positions
                .iter()
                .fold((first, first), |(lo, hi), p| (lo.min(*p), hi.max(*p))),
        )
    }

    /// Appends `other`, re-indexing its triangles.
    pub fn append(&mut self, other: &TriangleMesh) {
        let base = self.positions.len() as u32;
        self.positions.extend_from_slice(&other.positions);
        self.normals.extend_from_slice(&other.normals);
        self.triangles
            .extend(other.triangles.iter().map(|t| t.map(|i| i + base)));
    }

    /// Applies `luminaire_from_part`; normals use the inverse transpose so
    /// they stay perpendicular under non-uniform scale, and a mirroring scale
    /// flips the winding so that it keeps agreeing with the normals.
    pub fn transformed(&self, luminaire_from_part: &DAffine3) -> TriangleMesh {
        let normal_matrix = luminaire_from_part.matrix3.inverse().transpose();
        let mirrored = luminaire_from_part.matrix3.determinant() < 0.0;
        TriangleMesh {
            positions: self
                .positions
                .iter()
                .map(|p| luminaire_from_part.transform_point3(p.as_dvec3()).as_vec3())
                .collect(),
            normals: self
                .normals
                .iter()
                .map(|n| (normal_matrix * n.as_dvec3()).normalize_or_zero().as_vec3())
                .collect(),
            triangles: self
                .triangles
                .iter()
                .map(|&[a, b, c]| if mirrored { [a, c, b] } else { [a, b, c] })
                .collect(),
        }
    }

    /// Reverses which side the mesh faces (winding and normals).
    pub fn flip(&mut self) {
        for t in &mut self.triangles {
            t.swap(1, 2);
        }
        for n in &mut self.normals {
            *n = -*n;
        }
    }

    /// Checks that the mesh can be traced: finite vertices, unit normals,
    /// valid indices, no zero-area triangle, a plausible size.
    ///
    /// A triangle is degenerate when its area is below 1e-12 of the squared
    /// extent of the mesh (float precision cannot orient it reliably).
    pub fn check(&self) -> Result<(), MeshDefect> {
        if self.triangles.is_empty() {
            return Err(MeshDefect::Empty);
        }
        if self.normals.len() != self.positions.len() {
            return Err(MeshDefect::NormalCount {
                normals: self.normals.len(),
                positions: self.positions.len(),
            });
        }
        for (index, p) in self.positions.iter().enumerate() {
            if !p.is_finite() {
                return Err(MeshDefect::NonFiniteVertex {
                    index,
                    value: p.to_array(),
                });
            }
        }
        for (index, n) in self.normals.iter().enumerate() {
            if !n.is_finite() || (n.length() - 1.0).abs() > 1e-3 {
                return Err(MeshDefect::BadNormal {
                    index,
                    value: n.to_array(),
                });
            }
        }
        let count = self.positions.len();
        for (index, t) in self.triangles.iter().enumerate() {
            if let Some(&vertex) = t.iter().find(|&&v| v as usize >= count) {
                return Err(MeshDefect::IndexOutOfRange {
                    index,
                    vertex,
                    count,
                });
            }
        }
        let (lo, hi) = self.bounds().ok_or(MeshDefect::Empty)?;
        let extent_m = f64::from((hi - lo).max_element());
        if !(MIN_EXTENT_M..=MAX_EXTENT_M).contains(&extent_m) {
            return Err(MeshDefect::AbsurdSize {
                extent_m,
                min_m: MIN_EXTENT_M,
                max_m: MAX_EXTENT_M,
            });
        }
        let min_area = 1e-12 * extent_m * extent_m;
        let mut degenerate = None;
        let mut degenerate_count = 0;
        for t in 0..self.triangles.len() {
            let area = 0.5 * self.geometric_normal(t).length();
            if area <= min_area {
                degenerate_count += 1;
                degenerate.get_or_insert((t, area));
            }
        }
        if let Some((first, area)) = degenerate {
            return Err(MeshDefect::Degenerate {
                count: degenerate_count,
                first,
                area,
            });
        }
        Ok(())
    }
}
