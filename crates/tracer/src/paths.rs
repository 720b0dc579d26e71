//! A sample of traced photons as polylines, for drawing: what engineers
//! look at first to find a stray reflection.

use glam::{Vec3, Vec3A};
pub use lucerna_scene::section::SectionPlane;

use crate::cpu::{Fate, trace_photon_recorded};
use crate::prepared::PreparedScene;
use crate::rng::PhotonRng;

/// One photon from its emitter to its end.
#[derive(Debug, Clone, PartialEq)]
pub struct PhotonPath {
    /// Where it left the emitter, then every surface point it reached (m,
    /// luminaire coordinates).
    pub points: Vec<Vec3>,
    pub fate: Fate,
    /// Surface interactions it survived.
    pub bounces: u32,
}

impl PhotonPath {
    /// The direction it left the luminaire in, if it escaped.
    pub fn escape_direction(&self) -> Option<Vec3> {
        match self.fate {
            Fate::Escaped(d) => Some(d.into()),
            _ => None,
        }
    }
}

/// The first `count` photons of a run with `seed` (iteration 0), traced
/// again with their points recorded: the very photons the run counted.
pub fn sample_photon_paths(
    scene: &PreparedScene,
    seed: u32,
    max_bounces: u32,
    count: u32,
) -> Vec<PhotonPath> {
    if scene.emitters.is_empty() {
        return Vec::new();
    }
    (0..count)
        .map(|photon| {
            let mut rng = PhotonRng::new(seed, 0, photon);
            let mut points = Vec::new();
            let (fate, bounces, _) =
                trace_photon_recorded(scene, max_bounces, &mut rng, |p| points.push(p.into()));
            PhotonPath {
                points,
                fate,
                bounces,
            }
        })
        .collect()
}

/// A photon leaving the luminaire: where it last touched a surface (or
/// left its emitter, if it escaped at once) and the way it went (m,
/// luminaire coordinates). The last interaction, not a crossing of some
/// bounding surface: it is where the light really leaves from, and needs
/// no surface of our choosing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EscapingRay {
    pub position: Vec3,
    pub direction: Vec3,
}

/// The first `wanted` photons of a run with `seed` (iteration 0, the run's
/// own first photons, then on in its stream) that leave the luminaire,
/// tracing at most `max_photons`; also returns the photons traced. Traced
/// in parallel in fixed chunks, kept in photon order: the same seed gives
/// the same rays.
pub fn escaping_rays(
    scene: &PreparedScene,
    seed: u32,
    max_bounces: u32,
    wanted: usize,
    max_photons: u32,
) -> (Vec<EscapingRay>, u32) {
    use rayon::prelude::*;
    const CHUNK: u32 = 16_384;
    let mut rays = Vec::with_capacity(wanted);
    let mut traced = 0u32;
    if scene.emitters.is_empty() {
        return (rays, 0);
    }
    while rays.len() < wanted && traced < max_photons {
        // Enough chunks for what is missing at the escape rate so far.
        let rate = if traced == 0 {
            1.0
        } else {
            (rays.len() as f64 / f64::from(traced)).max(1e-3)
        };
        let missing = ((wanted - rays.len()) as f64 / rate).ceil() as u64;
        let chunks = missing.div_ceil(u64::from(CHUNK)).clamp(1, 64) as u32;
        let start = traced;
        let batches: Vec<Vec<EscapingRay>> = (0..chunks)
            .into_par_iter()
            .map(|c| {
                let first = start.saturating_add(c * CHUNK);
                let last = first.saturating_add(CHUNK).min(max_photons);
                (first..last)
                    .filter_map(|photon| {
                        let mut rng = PhotonRng::new(seed, 0, photon);
                        let mut last_point = Vec3::ZERO;
                        let (fate, _, _) =
                            trace_photon_recorded(scene, max_bounces, &mut rng, |p| {
                                last_point = p.into();
                            });
                        match fate {
                            Fate::Escaped(d) => Some(EscapingRay {
                                position: last_point,
                                direction: d.into(),
                            }),
                            _ => None,
                        }
                    })
                    .collect()
            })
            .collect();
        traced = start.saturating_add(chunks * CHUNK).min(max_photons);
        for batch in batches {
            rays.extend(batch);
        }
    }
    rays.truncate(wanted);
    (rays, traced)
}

/// A ray followed without chance: off a mirror or a rough conductor its
/// specular reflection (the lobe's centre), through a dielectric its
/// refraction (its reflection where it is totally reflected); it ends on
/// a diffuse surface, where its light scatters ([`Fate::Absorbed`]), when
/// it leaves the luminaire, or after `max_bounces`. What an optics
/// drawing shows: where the geometry sends the light.
pub fn trace_principal_ray(
    scene: &PreparedScene,
    origin: Vec3,
    direction: Vec3,
    max_bounces: u32,
) -> PhotonPath {
    use crate::cpu::{dielectric_directions, facing_normals, shading_normal, specular};
    use crate::prepared::{TriangleShading, kind};
    let mut o = Vec3A::from(origin);
    let mut d = Vec3A::from(direction).normalize_or(Vec3A::NEG_Z);
    let mut points = vec![origin];
    let mut bounces = 0;
    let fate = loop {
        let Some(hit) = scene.bvh.intersect(o, d, f32::INFINITY) else {
            break Fate::Escaped(d);
        };
        let p = o + d * hit.t;
        points.push(p.into());
        if bounces >= max_bounces {
            break Fate::CutOff;
        }
        let m = &scene.materials[TriangleShading::material_of_tag(hit.tag) as usize];
        let geometric = hit.normal;
        let shading = shading_normal(scene, &hit);
        let (ng, ns) = facing_normals(geometric, shading, d);
        let next = match m.kind {
            kind::MIRROR | kind::ROUGH_CONDUCTOR => specular(d, ns, ng),
            kind::DIELECTRIC => {
                let ways = dielectric_directions(m, d, geometric, shading);
                if ways.fresnel >= 1.0 {
                    ways.reflected
                } else {
                    ways.transmitted
                }
            }
            _ => break Fate::Absorbed,
        };
        let side = if next.dot(geometric) > 0.0 {
            geometric
        } else {
            -geometric
        };
        o = p + side * scene.epsilon;
        d = next;
        bounces += 1;
    };
    PhotonPath {
        points,
        fate,
        bounces,
    }
}

/// Where a fan's edge rays start: this share of the way from an
/// emitter's centre to its edge.
const EDGE_INSET: f32 = 0.95;

/// A fan of principal rays ([`trace_principal_ray`]) in `plane` from each
/// emitter with a surface: from the centre and both edges of a disk's or
/// rectangle's cut by the plane (the edges 5 % inside), `rays_per_point` directions evenly over
/// the emitting half of the plane (not grazing); from a sphere's or
/// cylinder's centre, `2 × rays_per_point` directions all round, each
/// starting on its surface. Ray-file emitters have no surface to fan
/// from. Deterministic: the same geometry gives the same fan.
pub fn section_fan(
    scene: &PreparedScene,
    plane: SectionPlane,
    rays_per_point: usize,
    max_bounces: u32,
) -> Vec<PhotonPath> {
    use lucerna_scene::EmitterShape;
    let up = Vec3::Z;
    let along = plane.along.normalize_or(Vec3::X);
    let in_plane = |v: Vec3| (along * v.dot(along) + up * v.dot(up)).normalize_or_zero();
    let mut fan = Vec::new();
    let n = rays_per_point.max(1);
    for e in &scene.emitters {
        let to_luminaire =
            |p: Vec3| Vec3::from(e.luminaire_from_emitter.transform_point3a(p.into()));
        let centre = to_luminaire(Vec3::ZERO);
        let launch = |fan: &mut Vec<PhotonPath>, from: Vec3, d: Vec3| {
            let start = from + d * scene.epsilon;
            fan.push(trace_principal_ray(scene, start, d, max_bounces));
        };
        match e.shape {
            EmitterShape::Disk { .. } | EmitterShape::Rectangle { .. } => {
                let normal = in_plane(Vec3::from(e.normal_matrix * Vec3A::NEG_Z));
                if normal == Vec3::ZERO {
                    continue;
                }
                // The emitter's extent along the plane: the local direction
                // of `along`, to the edge of the disk or rectangle.
                let local = e.luminaire_from_emitter.matrix3.inverse() * Vec3A::from(along);
                let local = Vec3::new(local.x, local.y, 0.0).normalize_or(Vec3::X);
                let reach = match e.shape {
                    EmitterShape::Disk { radius } => radius as f32,
                    EmitterShape::Rectangle { width, depth } => {
                        let x = if local.x.abs() > 1e-6 {
                            0.5 * width as f32 / local.x.abs()
                        } else {
                            f32::INFINITY
                        };
                        let y = if local.y.abs() > 1e-6 {
                            0.5 * depth as f32 / local.y.abs()
                        } else {
                            f32::INFINITY
                        };
                        x.min(y)
                    }
                    _ => 0.0,
                };
                // The normal turned a right angle within the plane.
                let tangent = along * normal.dot(up) - up * normal.dot(along);
                // Just inside the edges: an emitter set into a reflector
                // touches it at its rim, where a ray would start on the
                // mirror itself.
                let edge = local * reach * EDGE_INSET;
                for point in [Vec3::ZERO, edge, -edge] {
                    let from = to_luminaire(point);
                    for k in 0..n {
                        // Evenly over (−85°, 85°) from the normal.
                        let t = if n == 1 {
                            0.0
                        } else {
                            k as f32 / (n - 1) as f32 * 2.0 - 1.0
                        };
                        let angle = t * 85f32.to_radians();
                        launch(&mut fan, from, normal * angle.cos() + tangent * angle.sin());
                    }
                }
            }
            EmitterShape::Sphere { radius } | EmitterShape::Cylinder { radius, .. } => {
                for k in 0..2 * n {
                    let angle = (k as f32 + 0.5) / (2 * n) as f32 * std::f32::consts::TAU;
                    let d = along * angle.cos() + up * angle.sin();
                    // A cylinder about its own z emits from its side only,
                    // from the point whose outward normal is nearest d.
                    let side = match e.shape {
                        EmitterShape::Cylinder { .. } => {
                            let axis = Vec3::from(e.luminaire_from_emitter.matrix3 * Vec3A::Z)
                                .normalize_or(up);
                            (d - axis * d.dot(axis)).normalize_or_zero()
                        }
                        _ => d,
                    };
                    if side == Vec3::ZERO {
                        continue;
                    }
                    launch(&mut fan, centre + side * radius as f32, d);
                }
            }
            EmitterShape::RayFile { .. } => {}
        }
    }
    fan
}
