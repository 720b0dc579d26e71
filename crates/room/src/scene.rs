//! The room ready to shade: box geometry with its six surfaces, the placed
//! lights (profiles sampled on the shading grid), camera and work plane.

use std::path::Path;
use std::sync::Arc;

use glam::DVec3;
use lucerna_photometry::{Dimensions, Photometry};

use crate::light::{Opening, PlacedLight};
use crate::model::{Camera, Indirect, OpeningSpec, RoomFile, RoomFileError, Surface, WorkPlane};
use crate::profile::ProfileGrid;

/// Surface indices: floor (z = 0), ceiling (z = height), walls at x = 0,
/// x = width, y = 0, y = depth.
pub const FLOOR: usize = 0;
pub const CEILING: usize = 1;

#[derive(Debug, Clone)]
pub struct RoomScene {
    /// (width, depth, height) in metres.
    pub size: DVec3,
    /// Floor, ceiling, the four walls, then the OBJ's named materials.
    pub surfaces: Vec<Surface>,
    /// Triangles replacing the box in the views (an OBJ room).
    pub mesh: Option<RoomMesh>,
    pub lights: Vec<PlacedLight>,
    pub camera: Camera,
    pub work_plane: WorkPlane,
    pub indirect: Indirect,
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
            surfaces: [r.floor, r.ceiling, r.walls, r.walls, r.walls, r.walls]
                .into_iter()
                .chain(r.materials.values().copied())
                .collect(),
            mesh: None,
            lights,
            camera: room.camera,
            work_plane: room.work_plane,
            indirect: room.room.indirect,
        }
    }

    /// Uniform indirect illuminance (lx) by the integrating-sphere formula
    /// Φ ρ̄ / (A (1 − ρ̄)), or 0 for direct light only.
    pub fn indirect_lux(&self) -> f64 {
        if self.indirect == Indirect::None {
            return 0.0;
        }
        let flux: f64 = self.lights.iter().map(|l| l.profile.flux_lm()).sum();
        let (mut area, mut reflected) = (0.0, 0.0);
        match &self.mesh {
            Some(mesh) => {
                for (t, &s) in mesh.triangles.iter().zip(&mesh.surface) {
                    let a = 0.5 * (t[1] - t[0]).cross(t[2] - t[0]).length();
                    area += a;
                    reflected += a * self.surfaces[s as usize].reflectance;
                }
            }
            None => {
                let (w, d, h) = (self.size.x, self.size.y, self.size.z);
                let faces = [w * d, w * d, d * h, d * h, w * h, w * h];
                for (a, s) in faces.iter().zip(&self.surfaces) {
                    area += a;
                    reflected += a * s.reflectance;
                }
            }
        }
        if area <= 0.0 {
            return 0.0;
        }
        let rho = (reflected / area).min(0.99);
        flux * rho / (area * (1.0 - rho))
    }

    /// The first room surface along a ray from inside the room.
    pub fn cast(&self, origin: DVec3, dir: DVec3) -> SurfaceHit {
        if let Some(mesh) = &self.mesh {
            return mesh.cast(origin, dir);
        }
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

/// Most triangles of an OBJ room: views cast every ray against every
/// triangle (no acceleration structure), so this keeps a frame bounded.
pub const MAX_ROOM_TRIANGLES: usize = 20_000;

/// An OBJ room: triangles with a surface index each.
#[derive(Debug, Clone, PartialEq)]
pub struct RoomMesh {
    pub triangles: Vec<[DVec3; 3]>,
    /// Index into `RoomScene::surfaces`.
    pub surface: Vec<u32>,
}

impl RoomMesh {
    /// Nearest triangle along a ray (Möller–Trumbore), its normal turned
    /// towards the ray's origin; nothing hit gives an infinitely far floor.
    pub fn cast(&self, origin: DVec3, dir: DVec3) -> SurfaceHit {
        let mut best = SurfaceHit {
            distance: f64::INFINITY,
            surface: FLOOR,
            normal: DVec3::Z,
        };
        for (k, t) in self.triangles.iter().enumerate() {
            let e1 = t[1] - t[0];
            let e2 = t[2] - t[0];
            let p = dir.cross(e2);
            let det = e1.dot(p);
            if det.abs() < 1e-14 {
                continue;
            }
            let inv = 1.0 / det;
            let s = origin - t[0];
            let u = s.dot(p) * inv;
            if !(0.0..=1.0).contains(&u) {
                continue;
            }
            let q = s.cross(e1);
            let v = dir.dot(q) * inv;
            if v < 0.0 || u + v > 1.0 {
                continue;
            }
            let d = e2.dot(q) * inv;
            if d > 1e-9 && d < best.distance {
                let n = e1.cross(e2).normalize();
                best = SurfaceHit {
                    distance: d,
                    surface: self.surface[k] as usize,
                    normal: if n.dot(dir) > 0.0 { -n } else { n },
                };
            }
        }
        best
    }
}

/// An error and its sources, as one line.
fn error_chain(e: &dyn std::error::Error) -> String {
    let mut s = e.to_string();
    let mut source = e.source();
    while let Some(cause) = source {
        s.push_str(": ");
        s.push_str(&cause.to_string());
        source = cause.source();
    }
    s
}

/// Loads the OBJ a room file names (if any): each object/group takes the
/// surface named after it, else after its `usemtl` material, else the
/// walls'. Zero-area triangles are dropped.
pub fn load_room_mesh(room: &RoomFile, base: &Path) -> Result<Option<RoomMesh>, RoomFileError> {
    let Some(obj) = &room.room.obj else {
        return Ok(None);
    };
    let path = base.join(obj);
    let groups = lucerna_scene::obj::load_obj(&path).map_err(|e| RoomFileError::Invalid {
        path: path.clone(),
        problems: error_chain(&e),
    })?;
    let names: Vec<&String> = room.room.materials.keys().collect();
    let scale = room.room.obj_scale;
    let mut mesh = RoomMesh {
        triangles: Vec::new(),
        surface: Vec::new(),
    };
    for g in &groups {
        let by_name = |n: &str| names.iter().position(|k| k.as_str() == n);
        let surface = by_name(&g.name)
            .or_else(|| g.obj_material.as_deref().and_then(by_name))
            .map_or(2, |i| 6 + i) as u32;
        for t in &g.mesh.triangles {
            let v = t.map(|i| g.mesh.positions[i as usize].as_dvec3() * scale);
            if (v[1] - v[0]).cross(v[2] - v[0]).length_squared() <= 0.0 {
                continue;
            }
            mesh.triangles.push(v);
            mesh.surface.push(surface);
        }
    }
    if mesh.triangles.is_empty() {
        return Err(RoomFileError::Invalid {
            path,
            problems: "the OBJ has no triangles with area".to_owned(),
        });
    }
    if mesh.triangles.len() > MAX_ROOM_TRIANGLES {
        return Err(RoomFileError::Invalid {
            path,
            problems: format!(
                "{} triangles; at most {MAX_ROOM_TRIANGLES} (every view ray is tested against each)",
                mesh.triangles.len()
            ),
        });
    }
    Ok(Some(mesh))
}
