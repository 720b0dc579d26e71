//! What the shape generators share (the dispatch to each shape's own
//! generator is [`crate::shapes::generate`]): the mesh builders more
//! than one shape is made of (revolution, planar quads, disks, flat
//! triangles). Meshes are in the part's local frame (metres).

use std::f64::consts::TAU;

use glam::{DVec2, DVec3, Vec3};

use crate::mesh::TriangleMesh;
use crate::profile::{ProfileSample, Strip};

/// Radius below which a profile point is taken to lie on the axis.
fn on_axis(r: f64, scale: f64) -> bool {
    r.abs() <= 1e-9 * scale.max(1e-9)
}

/// The shading normal of a profile sample in the r-z (or x-z) plane: the
/// tangent turned clockwise, i.e. on the right of the direction of travel.
pub(crate) fn profile_normal(s: &ProfileSample) -> DVec2 {
    DVec2::new(s.tangent.y, -s.tangent.x)
}

/// Fills in zero tangents (cusps of a spline) from neighbouring points.
pub(crate) fn repaired(strip: &Strip) -> Strip {
    let mut out = strip.clone();
    for i in 0..out.len() {
        if out[i].tangent.length_squared() < 0.5 {
            let a = strip[i.saturating_sub(1)].point;
            let b = strip[(i + 1).min(strip.len() - 1)].point;
            out[i].tangent = (b - a).normalize_or(DVec2::X);
        }
    }
    out
}

/// Revolves profile strips about the z axis with `segments_around` steps.
/// Smooth strips share vertices and carry analytic normals; `faceted` gives
/// every quad its own flat normal. Rings on the axis become triangle fans so
/// that no zero-area triangle is produced.
pub fn revolve(strips: &[Strip], segments_around: u32, faceted: bool) -> TriangleMesh {
    let n = segments_around as usize;
    let scale = strips
        .iter()
        .flatten()
        .map(|s| s.point.abs().max_element())
        .fold(0.0, f64::max);
    let angle = |i: usize| TAU * i as f64 / n as f64;
    let at = |p: DVec2, i: usize| {
        let (s, c) = angle(i % n).sin_cos();
        DVec3::new(p.x * c, p.x * s, p.y)
    };
    let mut mesh = TriangleMesh::default();
    for strip in strips {
        let strip = repaired(strip);
        if faceted {
            for j in 0..strip.len() - 1 {
                let (p, q) = (strip[j].point, strip[j + 1].point);
                for i in 0..n {
                    let corners = [at(p, i), at(p, i + 1), at(q, i + 1), at(q, i)];
                    if on_axis(p.x, scale) {
                        push_flat(&mut mesh, [corners[0], corners[2], corners[3]]);
                    } else if on_axis(q.x, scale) {
                        push_flat(&mut mesh, [corners[0], corners[1], corners[2]]);
                    } else {
                        push_flat(&mut mesh, [corners[0], corners[1], corners[2]]);
                        push_flat(&mut mesh, [corners[0], corners[2], corners[3]]);
                    }
                }
            }
            continue;
        }
        // One ring of vertices per sample (a single vertex on the axis).
        let mut ring_start = Vec::with_capacity(strip.len());
        for s in &strip {
            ring_start.push(mesh.positions.len() as u32);
            let nrz = profile_normal(s);
            if on_axis(s.point.x, scale) {
                mesh.positions
                    .push(DVec3::new(0.0, 0.0, s.point.y).as_vec3());
                mesh.normals
                    .push(Vec3::new(0.0, 0.0, nrz.y.signum() as f32));
            } else {
                for i in 0..n {
                    let (sn, cs) = angle(i).sin_cos();
                    mesh.positions.push(at(s.point, i).as_vec3());
                    mesh.normals.push(
                        DVec3::new(nrz.x * cs, nrz.x * sn, nrz.y)
                            .normalize()
                            .as_vec3(),
                    );
                }
            }
        }
        let vertex = |j: usize, i: usize| -> u32 {
            if on_axis(strip[j].point.x, scale) {
                ring_start[j]
            } else {
                ring_start[j] + (i % n) as u32
            }
        };
        for j in 0..strip.len() - 1 {
            let (apex0, apex1) = (
                on_axis(strip[j].point.x, scale),
                on_axis(strip[j + 1].point.x, scale),
            );
            for i in 0..n {
                let (a, b, c, d) = (
                    vertex(j, i),
                    vertex(j, i + 1),
                    vertex(j + 1, i + 1),
                    vertex(j + 1, i),
                );
                if !apex0 {
                    mesh.triangles.push([a, b, c]);
                }
                if !apex1 {
                    mesh.triangles.push([a, c, d]);
                }
            }
        }
    }
    mesh
}

/// The most triangles [`revolve`] builds from strips with
/// `profile_segments` segments in all: two per segment and step around,
/// one fewer where a ring lies on the axis.
pub fn revolution_triangle_count(segments_around: u32, profile_segments: u64) -> u64 {
    2u64.saturating_mul(u64::from(segments_around))
        .saturating_mul(profile_segments)
}

/// Pushes a triangle with its own three vertices and flat normal.
pub(crate) fn push_flat(mesh: &mut TriangleMesh, corners: [DVec3; 3]) {
    let normal = (corners[1] - corners[0])
        .cross(corners[2] - corners[0])
        .normalize_or_zero()
        .as_vec3();
    let base = mesh.positions.len() as u32;
    for c in corners {
        mesh.positions.push(c.as_vec3());
        mesh.normals.push(normal);
    }
    mesh.triangles.push([base, base + 1, base + 2]);
}

/// A planar quad (corners counter-clockwise about `normal`).
pub(crate) fn quad(corners: [DVec3; 4], normal: DVec3) -> TriangleMesh {
    TriangleMesh {
        positions: corners.iter().map(|c| c.as_vec3()).collect(),
        normals: vec![normal.as_vec3(); 4],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
    }
}

/// A disk at height `z` facing `normal` (±z), as a fan around its centre.
pub(crate) fn disk(radius: f64, z: f64, segments_around: u32, normal: DVec3) -> TriangleMesh {
    let n = segments_around;
    let mut mesh = TriangleMesh {
        positions: vec![DVec3::new(0.0, 0.0, z).as_vec3()],
        normals: vec![normal.as_vec3(); n as usize + 1],
        triangles: Vec::with_capacity(n as usize),
    };
    for i in 0..n {
        let (s, c) = (TAU * f64::from(i) / f64::from(n)).sin_cos();
        mesh.positions
            .push(DVec3::new(radius * c, radius * s, z).as_vec3());
    }
    for i in 0..n {
        let (a, b) = (1 + i, 1 + (i + 1) % n);
        // Counter-clockwise seen from +z faces +z.
        mesh.triangles
            .push(if normal.z > 0.0 { [0, a, b] } else { [0, b, a] });
    }
    mesh
}

/// A planar quad whose winding is made to agree with `normal`.
pub(crate) fn oriented_quad(corners: [DVec3; 4], normal: DVec3) -> TriangleMesh {
    quad(oriented_corners(corners, normal), normal)
}

/// A planar quad's corners in the order whose winding agrees with
/// `normal` (counter-clockwise seen from where it points).
pub(crate) fn oriented_corners(corners: [DVec3; 4], normal: DVec3) -> [DVec3; 4] {
    let g = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
    if g.dot(normal) < 0.0 {
        [corners[0], corners[3], corners[2], corners[1]]
    } else {
        corners
    }
}
