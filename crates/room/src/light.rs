//! A photometric light placed in the room: its profile, its luminous
//! opening as a convex polygon, and its pose.

use std::sync::Arc;

use glam::{DMat3, DVec3};
use smallvec::SmallVec;

/// A polygon's vertices without a heap allocation in the common case
/// (rectangles have 4 vertices, 5 after clipping; disks spill to the heap).
pub type Polygon = SmallVec<[DVec3; 6]>;

use crate::profile::ProfileGrid;

/// Number of sides of the polygon standing in for a circular opening (same
/// area as the disk). The cubature's cost grows with the vertex count.
pub const DISK_SIDES: usize = 12;

/// Longest side over shortest side of the pieces an elongated rectangular
/// opening is cut into: one closest point cannot shape the light of a
/// linear luminaire along its whole length.
pub const MAX_PIECE_ASPECT: f64 = 2.0;
/// Most pieces per opening.
pub const MAX_PIECES: usize = 8;

/// The luminous opening in luminaire coordinates (the z = 0 plane, centred
/// on the origin): what the cubature integrates over.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Opening {
    /// Length along C0-C180 (x) × width along C90-C270 (y), metres.
    Rectangle { length_m: f64, width_m: f64 },
    /// Diameter (m).
    Disk { diameter_m: f64 },
    /// No extent: shaded as a point source.
    Point,
}

impl Opening {
    /// The opening's vertices, counter-clockwise seen from below (about −z,
    /// the emitting normal), in luminaire coordinates.
    pub fn polygon(self) -> Polygon {
        match self {
            Opening::Rectangle { length_m, width_m } => {
                let (a, b) = (length_m / 2.0, width_m / 2.0);
                [
                    DVec3::new(-a, -b, 0.0),
                    DVec3::new(-a, b, 0.0),
                    DVec3::new(a, b, 0.0),
                    DVec3::new(a, -b, 0.0),
                ]
                .into_iter()
                .collect()
            }
            Opening::Disk { diameter_m } => {
                let n = DISK_SIDES as f64;
                let area = std::f64::consts::PI * diameter_m * diameter_m / 4.0;
                // Circumradius of the regular n-gon with the disk's area.
                let r = (2.0 * area / (n * (std::f64::consts::TAU / n).sin())).sqrt();
                (0..DISK_SIDES)
                    .map(|i| {
                        let phi = -(i as f64) * std::f64::consts::TAU / n;
                        DVec3::new(r * phi.cos(), r * phi.sin(), 0.0)
                    })
                    .collect()
            }
            Opening::Point => Polygon::new(),
        }
    }

    pub fn area_m2(self) -> f64 {
        match self {
            Opening::Rectangle { length_m, width_m } => length_m * width_m,
            Opening::Disk { diameter_m } => std::f64::consts::PI * diameter_m * diameter_m / 4.0,
            Opening::Point => 0.0,
        }
    }
}

/// A luminaire in the room.
#[derive(Debug, Clone)]
pub struct PlacedLight {
    pub profile: Arc<ProfileGrid>,
    pub opening: Opening,
    /// Centre of the opening (m, room coordinates).
    pub position: DVec3,
    /// Luminaire → room rotation.
    pub rotation: DMat3,
}

impl PlacedLight {
    /// Rotation from Euler angles (degrees) about the room's x, then y,
    /// then z axes.
    pub fn rotation_from_euler_deg(deg: [f64; 3]) -> DMat3 {
        DMat3::from_rotation_z(deg[2].to_radians())
            * DMat3::from_rotation_y(deg[1].to_radians())
            * DMat3::from_rotation_x(deg[0].to_radians())
    }

    /// Opening vertices in room coordinates.
    pub fn world_polygon(&self) -> Polygon {
        self.opening
            .polygon()
            .into_iter()
            .map(|v| self.position + self.rotation * v)
            .collect()
    }

    /// The emitting normal (the luminaire's nadir) in room coordinates.
    pub fn normal(&self) -> DVec3 {
        self.rotation * DVec3::NEG_Z
    }

    /// Intensity (cd) towards a room direction.
    pub fn candela_towards(&self, world_dir: DVec3) -> f64 {
        self.profile.candela(self.rotation.transpose() * world_dir)
    }

    /// Number of pieces the cubature shades separately (rectangles longer
    /// than `MAX_PIECE_ASPECT` : 1 are cut across their long side).
    pub fn piece_count(&self) -> usize {
        match self.opening {
            Opening::Rectangle { length_m, width_m } => {
                let (long, short) = (length_m.max(width_m), length_m.min(width_m).max(1e-9));
                ((long / short / MAX_PIECE_ASPECT).ceil() as usize).clamp(1, MAX_PIECES)
            }
            _ => 1,
        }
    }

    /// Largest extent of the opening (m).
    pub fn size_m(&self) -> f64 {
        match self.opening {
            Opening::Rectangle { length_m, width_m } => length_m.hypot(width_m),
            Opening::Disk { diameter_m } => diameter_m,
            Opening::Point => 0.0,
        }
    }
}

/// Piece `j` of `k` of a quadrilateral (a parallelogram, vertices in
/// order) cut into strips across its longer pair of sides, keeping the
/// orientation; any other polygon, or k = 1, is returned whole. Twin of
/// the shader's `piece_vertex`.
pub fn quad_piece(polygon: &[DVec3], k: usize, j: usize) -> Polygon {
    if polygon.len() != 4 || k <= 1 {
        return polygon.iter().copied().collect();
    }
    let (v0, v1, v3) = (polygon[0], polygon[1], polygon[3]);
    let e01 = v1 - v0;
    let e03 = v3 - v0;
    let (t0, t1) = (j as f64 / k as f64, (j + 1) as f64 / k as f64);
    let corners = if e01.length_squared() > e03.length_squared() {
        [v0 + e01 * t0, v0 + e01 * t1, v3 + e01 * t1, v3 + e01 * t0]
    } else {
        [v0 + e03 * t0, v1 + e03 * t0, v1 + e03 * t1, v0 + e03 * t1]
    };
    corners.into_iter().collect()
}
