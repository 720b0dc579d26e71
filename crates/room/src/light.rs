//! A photometric light placed in the room: its profile, its luminous
//! opening as a convex polygon, and its pose.

use std::sync::Arc;

use glam::{DMat3, DVec3};

use crate::profile::ProfileGrid;

/// Number of sides of the polygon standing in for a circular opening (same
/// area as the disk). The cubature's cost grows with the vertex count.
pub const DISK_SIDES: usize = 12;

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
    pub fn polygon(self) -> Vec<DVec3> {
        match self {
            Opening::Rectangle { length_m, width_m } => {
                let (a, b) = (length_m / 2.0, width_m / 2.0);
                vec![
                    DVec3::new(-a, -b, 0.0),
                    DVec3::new(-a, b, 0.0),
                    DVec3::new(a, b, 0.0),
                    DVec3::new(a, -b, 0.0),
                ]
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
            Opening::Point => Vec::new(),
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
    pub fn world_polygon(&self) -> Vec<DVec3> {
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

    /// Largest extent of the opening (m).
    pub fn size_m(&self) -> f64 {
        match self.opening {
            Opening::Rectangle { length_m, width_m } => length_m.hypot(width_m),
            Opening::Disk { diameter_m } => diameter_m,
            Opening::Point => 0.0,
        }
    }
}
