//! Shape generators: each parametric [`Shape`] tessellated into a
//! [`TriangleMesh`] in the part's local frame (metres).

use std::f64::consts::TAU;

use glam::{DVec2, DVec3, Vec3};

use crate::mesh::TriangleMesh;
use crate::model::Shape;
use crate::profile::{ProfileSample, Strip, sample_curve, sample_profile};

/// Builds the mesh of a generated shape. `Shape::Mesh` is not generated
/// here (see [`crate::obj`]); it yields `None`.
///
/// Parameters must have passed [`crate::validate`]; the generators do not
/// re-check them.
pub fn generate(shape: &Shape) -> Option<TriangleMesh> {
    Some(match shape {
        &Shape::Paraboloid {
            focal_length: f,
            aperture_diameter,
            neck_diameter,
            segments_around,
            segments_along,
            faceted,
        } => {
            // Focus at the origin, vertex at z = f: z(r) = f − r²/(4f).
            let strip = sample_curve(
                0.5 * neck_diameter,
                0.5 * aperture_diameter,
                segments_along,
                |r| DVec2::new(r, f - r * r / (4.0 * f)),
                |r| DVec2::new(1.0, -r / (2.0 * f)),
            );
            revolve(&[strip], segments_around, faceted)
        }
        &Shape::Ellipsoid {
            focal_distance,
            vertex_distance,
            cut_below_focus,
            neck_diameter,
            segments_around,
            segments_along,
            faceted,
        } => {
            let e = Ellipse::new(focal_distance, vertex_distance);
            let t0 = (0.5 * neck_diameter / e.b).clamp(0.0, 1.0).asin();
            let t1 = e.parameter_at_z(-cut_below_focus);
            let strip = sample_curve(
                t0,
                t1,
                segments_along,
                |t| DVec2::new(e.b * t.sin(), e.centre_z + e.a * t.cos()),
                |t| DVec2::new(e.b * t.cos(), -e.a * t.sin()),
            );
            revolve(&[strip], segments_around, faceted)
        }
        Shape::Revolved {
            profile,
            interpolation,
            segments_around,
            segments_per_span,
            faceted,
        } => revolve(
            &sample_profile(profile, *interpolation, *segments_per_span),
            *segments_around,
            *faceted,
        ),
        Shape::Extruded {
            profile,
            length,
            interpolation,
            segments_per_span,
            end_caps,
        } => extrude(
            &sample_profile(profile, *interpolation, *segments_per_span),
            *length,
            *end_caps,
        ),
        &Shape::Louvre {
            blade_count,
            spacing,
            blade_height,
            blade_length,
            tilt_deg,
            cross_blade_count,
            cross_spacing,
        } => louvre(
            blade_count,
            spacing,
            blade_height,
            blade_length,
            tilt_deg.to_radians(),
            cross_blade_count,
            cross_spacing,
        ),
        &Shape::Plate { width, depth } => {
            let (hw, hd) = (0.5 * width, 0.5 * depth);
            quad(
                [
                    DVec3::new(-hw, -hd, 0.0),
                    DVec3::new(-hw, hd, 0.0),
                    DVec3::new(hw, hd, 0.0),
                    DVec3::new(hw, -hd, 0.0),
                ],
                DVec3::NEG_Z,
            )
        }
        &Shape::Disk {
            radius,
            segments_around,
        } => disk(radius, 0.0, segments_around, DVec3::NEG_Z),
        &Shape::Dome {
            radius,
            height,
            segments_around,
            segments_along,
        } => {
            // Sphere centre at z = height − radius; polar angle φ from the pole.
            let centre_z = height - radius;
            let phi_rim = ((-centre_z) / radius).clamp(-1.0, 1.0).acos();
            let strip = sample_curve(
                0.0,
                phi_rim,
                segments_along,
                |phi| DVec2::new(radius * phi.sin(), centre_z + radius * phi.cos()),
                |phi| DVec2::new(phi.cos(), -phi.sin()),
            );
            revolve(&[strip], segments_around, false)
        }
        &Shape::Cylinder {
            radius,
            height,
            cap_top,
            cap_bottom,
            segments_around,
        } => {
            let h = 0.5 * height;
            // Bottom to top: the right-hand normal of the profile points out.
            let side = sample_curve(
                -h,
                h,
                1,
                |z| DVec2::new(radius, z),
                |_| DVec2::new(0.0, 1.0),
            );
            let mut mesh = revolve(&[side], segments_around, false);
            if cap_top {
                mesh.append(&disk(radius, h, segments_around, DVec3::Z));
            }
            if cap_bottom {
                mesh.append(&disk(radius, -h, segments_around, DVec3::NEG_Z));
            }
            mesh
        }
        &Shape::Box { size, open_bottom } => box_mesh(DVec3::from_array(size) * 0.5, open_bottom),
        Shape::Mesh { .. } => return None,
    })
}

/// Ellipse of revolution with its near focus at the origin and its far
/// focus at z = −`focal_distance`.
struct Ellipse {
    a: f64,
    b: f64,
    centre_z: f64,
}

impl Ellipse {
    fn new(focal_distance: f64, vertex_distance: f64) -> Self {
        let c = 0.5 * focal_distance;
        let a = c + vertex_distance;
        Ellipse {
            a,
            b: (a * a - c * c).sqrt(),
            centre_z: -c,
        }
    }

    /// Parameter t (z = centre + a cos t) where the ellipse crosses `z`.
    fn parameter_at_z(&self, z: f64) -> f64 {
        ((z - self.centre_z) / self.a).clamp(-1.0, 1.0).acos()
    }
}

/// Radius below which a profile point is taken to lie on the axis.
fn on_axis(r: f64, scale: f64) -> bool {
    r.abs() <= 1e-9 * scale.max(1e-9)
}

/// The shading normal of a profile sample in the r-z (or x-z) plane: the
/// tangent turned clockwise, i.e. on the right of the direction of travel.
fn profile_normal(s: &ProfileSample) -> DVec2 {
    DVec2::new(s.tangent.y, -s.tangent.x)
}

/// Fills in zero tangents (cusps of a spline) from neighbouring points.
fn repaired(strip: &Strip) -> Strip {
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

/// Pushes a triangle with its own three vertices and flat normal.
fn push_flat(mesh: &mut TriangleMesh, corners: [DVec3; 3]) {
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
fn quad(corners: [DVec3; 4], normal: DVec3) -> TriangleMesh {
    TriangleMesh {
        positions: corners.iter().map(|c| c.as_vec3()).collect(),
        normals: vec![normal.as_vec3(); 4],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
    }
}

/// A disk at height `z` facing `normal` (±z), as a fan around its centre.
fn disk(radius: f64, z: f64, segments_around: u32, normal: DVec3) -> TriangleMesh {
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

/// Extrudes profile strips (x-z) along y over `length`, centred; normals
/// on the right of the profile's direction. End caps close each end with
/// the polygon of the profile and its chord, facing the side the sheet's
/// normals face, so the sheet and caps bound one region consistently.
pub fn extrude(strips: &[Strip], length: f64, end_caps: bool) -> TriangleMesh {
    let hy = 0.5 * length;
    let mut mesh = TriangleMesh::default();
    for strip in strips {
        let strip = repaired(strip);
        let base = mesh.positions.len() as u32;
        for s in &strip {
            let n2 = profile_normal(s);
            let normal = DVec3::new(n2.x, 0.0, n2.y).as_vec3();
            for y in [-hy, hy] {
                mesh.positions
                    .push(DVec3::new(s.point.x, y, s.point.y).as_vec3());
                mesh.normals.push(normal);
            }
        }
        for j in 0..strip.len() as u32 - 1 {
            let (a, b, c, d) = (
                base + 2 * j,
                base + 2 * j + 1,
                base + 2 * j + 3,
                base + 2 * j + 2,
            );
            mesh.triangles.push([a, b, c]);
            mesh.triangles.push([a, c, d]);
        }
    }
    if end_caps {
        let mut outline: Vec<DVec2> = Vec::new();
        for p in strips.iter().flatten().map(|s| s.point) {
            if outline.last().is_none_or(|q| q.distance(p) > 1e-12) {
                outline.push(p);
            }
        }
        if outline.len() > 2 && outline[0].distance(outline[outline.len() - 1]) <= 1e-12 {
            outline.pop();
        }
        let signed_area = polygon_signed_area(&outline);
        let extent = outline
            .iter()
            .map(|p| p.abs().max_element())
            .fold(0.0, f64::max);
        if signed_area.abs() > 1e-9 * extent * extent {
            // Clockwise outline (negative area): the sheet's right-hand
            // normals point into the enclosed region, so the caps do too.
            let inward = signed_area < 0.0;
            let triangles = ear_clip(&outline);
            for (y, cap_normal_y) in [(-hy, 1.0), (hy, -1.0)] {
                let normal_y = if inward { cap_normal_y } else { -cap_normal_y };
                let normal = DVec3::new(0.0, normal_y, 0.0);
                for &[i, j, k] in &triangles {
                    let corners =
                        [outline[i], outline[j], outline[k]].map(|p| DVec3::new(p.x, y, p.y));
                    let g = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
                    let corners = if g.dot(normal) < 0.0 {
                        [corners[0], corners[2], corners[1]]
                    } else {
                        corners
                    };
                    push_flat(&mut mesh, corners);
                }
            }
        }
    }
    mesh
}

/// Twice-signed area / 2 of a polygon in the x-z plane (positive when
/// counter-clockwise with x right and z up).
fn polygon_signed_area(points: &[DVec2]) -> f64 {
    let n = points.len();
    0.5 * (0..n)
        .map(|i| points[i].perp_dot(points[(i + 1) % n]))
        .sum::<f64>()
}

/// Triangulates a simple polygon by ear clipping, returning index triples.
/// Collinear vertices are dropped without emitting a zero-area triangle.
fn ear_clip(points: &[DVec2]) -> Vec<[usize; 3]> {
    let orientation = polygon_signed_area(points).signum();
    let mut remaining: Vec<usize> = (0..points.len()).collect();
    let mut triangles = Vec::new();
    let scale = points
        .iter()
        .map(|p| p.abs().max_element())
        .fold(0.0, f64::max);
    let eps = 1e-12 * scale * scale;
    let mut guard = 0;
    while remaining.len() > 2 && guard < 4 * points.len() * points.len() {
        guard += 1;
        let m = remaining.len();
        let mut clipped = false;
        for k in 0..m {
            let (ia, ib, ic) = (
                remaining[(k + m - 1) % m],
                remaining[k],
                remaining[(k + 1) % m],
            );
            let (a, b, c) = (points[ia], points[ib], points[ic]);
            let cross = (b - a).perp_dot(c - b) * orientation;
            if cross.abs() <= eps {
                remaining.remove(k);
                clipped = true;
                break;
            }
            if cross < 0.0 {
                continue; // reflex vertex
            }
            let contains_other = remaining
                .iter()
                .any(|&o| o != ia && o != ib && o != ic && point_in_triangle(points[o], a, b, c));
            if !contains_other {
                triangles.push([ia, ib, ic]);
                remaining.remove(k);
                clipped = true;
                break;
            }
        }
        if !clipped {
            break; // not a simple polygon; keep what was clipped
        }
    }
    triangles
}

fn point_in_triangle(p: DVec2, a: DVec2, b: DVec2, c: DVec2) -> bool {
    let d1 = (b - a).perp_dot(p - a);
    let d2 = (c - b).perp_dot(p - b);
    let d3 = (a - c).perp_dot(p - c);
    let has_neg = d1 < 0.0 || d2 < 0.0 || d3 < 0.0;
    let has_pos = d1 > 0.0 || d2 > 0.0 || d3 > 0.0;
    !(has_neg && has_pos)
}

/// Blades are thin two-sided sheets; their normals face +x (cross blades
/// +y) before tilting.
fn louvre(
    blade_count: u32,
    spacing: f64,
    blade_height: f64,
    blade_length: f64,
    tilt: f64,
    cross_blade_count: u32,
    cross_spacing: f64,
) -> TriangleMesh {
    let mut mesh = TriangleMesh::default();
    let hl = 0.5 * blade_length;
    let hh = 0.5 * blade_height;
    let (st, ct) = tilt.sin_cos();
    for k in 0..blade_count {
        let x = (f64::from(k) - 0.5 * f64::from(blade_count - 1)) * spacing;
        // Tilt about the blade's long axis through its centre (x, −h/2).
        let at = |dz: f64, y: f64| DVec3::new(x - dz * st, y, -hh + dz * ct);
        let normal = DVec3::new(ct, 0.0, st);
        let corners = [at(-hh, -hl), at(-hh, hl), at(hh, hl), at(hh, -hl)];
        mesh.append(&oriented_quad(corners, normal));
    }
    let span_x = f64::from(blade_count.saturating_sub(1)) * spacing;
    for k in 0..cross_blade_count {
        let y = (f64::from(k) - 0.5 * f64::from(cross_blade_count - 1)) * cross_spacing;
        let hx = 0.5 * span_x;
        let corners = [
            DVec3::new(-hx, y, -blade_height),
            DVec3::new(hx, y, -blade_height),
            DVec3::new(hx, y, 0.0),
            DVec3::new(-hx, y, 0.0),
        ];
        mesh.append(&oriented_quad(corners, DVec3::Y));
    }
    mesh
}

/// A planar quad whose winding is made to agree with `normal`.
fn oriented_quad(corners: [DVec3; 4], normal: DVec3) -> TriangleMesh {
    let g = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
    if g.dot(normal) < 0.0 {
        quad([corners[0], corners[3], corners[2], corners[1]], normal)
    } else {
        quad(corners, normal)
    }
}

fn box_mesh(half: DVec3, open_bottom: bool) -> TriangleMesh {
    let mut mesh = TriangleMesh::default();
    for axis in 0..3 {
        for sign in [-1.0, 1.0] {
            if axis == 2 && sign < 0.0 && open_bottom {
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
            mesh.append(&oriented_quad(corners, normal));
        }
    }
    mesh
}
