//! The room ready to shade: box geometry with its six surfaces, the placed
//! lights (profiles sampled on the shading grid), camera and work plane.

use std::sync::Arc;

use glam::DVec3;
use lucerna_photometry::{Dimensions, Photometry};

use crate::light::{Opening, PlacedLight};
use crate::model::{Camera, OpeningSpec, RoomFile, Surface, WorkPlane};
use crate::profile::ProfileGrid;

/// Surface indices: floor (z = 0), ceiling (z = height), walls at x = 0,
/// x = width, y = 0, y = depth.
pub const FLOOR: usize = 0;
pub const CEILING: usize = 1;

#[derive(Debug, Clone)]
pub struct RoomScene {
    /// (width, depth, height) in metres.
    pub size: DVec3,
    pub surfaces: [Surface; 6],
    pub lights: Vec<PlacedLight>,
    pub camera: Camera,
    pub work_plane: WorkPlane,
}

/// A room surface hit by a view ray.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceHit {
    pub distance: f64,
    pub surface: usize,
    /// Inward unit normal.
    pub normal: DVec3,
}

impl RoomScene {
    /// Places the file's luminaires; `photometry[i]` is the profile of
    /// `room.luminaires[i]`.
    pub fn new(room: &RoomFile, photometry: &[Photometry]) -> RoomScene {
        let mut lights = Vec::new();
        for (spec, phot) in room.luminaires.iter().zip(photometry) {
            let table = phot.table.scaled(spec.flux_factor);
            let profile = Arc::new(ProfileGrid::from_table(&table));
            let opening = match spec.opening {
                Some(OpeningSpec::Rectangle { length_m, width_m }) => {
                    Opening::Rectangle { length_m, width_m }
                }
                Some(OpeningSpec::Disk { diameter_m }) => Opening::Disk { diameter_m },
                Some(OpeningSpec::Point) => Opening::Point,
                None => opening_from_dimensions(phot.meta.luminous_area),
            };
            let rotation = PlacedLight::rotation_from_euler_deg(spec.rotation_deg);
            for p in spec.positions() {
                lights.push(PlacedLight {
                    profile: profile.clone(),
                    opening,
                    position: DVec3::from_array(p),
                    rotation,
                });
            }
        }
        let r = &room.room;
        RoomScene {
            size: DVec3::new(r.width_m, r.depth_m, r.height_m),
            surfaces: [r.floor, r.ceiling, r.walls, r.walls, r.walls, r.walls],
            lights,
            camera: room.camera,
            work_plane: room.work_plane,
        }
    }

    /// The first room surface along a ray from inside the room.
    pub fn cast(&self, origin: DVec3, dir: DVec3) -> SurfaceHit {
        let mut best = SurfaceHit {
            distance: f64::INFINITY,
            surface: FLOOR,
            normal: DVec3::Z,
        };
        for axis in 0..3 {
            let d = dir[axis];
            if d == 0.0 {
                continue;
            }
            let (plane, surface, normal) = if d > 0.0 {
                let s = [3, 5, CEILING][axis];
                (self.size[axis], s, -unit(axis))
            } else {
                let s = [2, 4, FLOOR][axis];
                (0.0, s, unit(axis))
            };
            let t = (plane - origin[axis]) / d;
            if t < best.distance {
                best = SurfaceHit {
                    distance: t.max(0.0),
                    surface,
                    normal,
                };
            }
        }
        best
    }
}

fn unit(axis: usize) -> DVec3 {
    [DVec3::X, DVec3::Y, DVec3::Z][axis]
}

/// Openings smaller than this (m²) are shaded as points: a polygon of no
/// area has no finite radiance.
pub const MIN_OPENING_M2: f64 = 1e-6;

/// The luminous opening a photometric file declares: a disk, a rectangle,
/// or a point when it gives no usable area.
pub fn opening_from_dimensions(d: Dimensions) -> Opening {
    if d.circular && d.length_m > 0.0 {
        return Opening::Disk {
            diameter_m: d.length_m,
        };
    }
    if d.length_m * d.width_m >= MIN_OPENING_M2 {
        Opening::Rectangle {
            length_m: d.length_m,
            width_m: d.width_m,
        }
    } else {
        Opening::Point
    }
}
