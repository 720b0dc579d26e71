//! A drawn profile extruded along y (linear reflectors, troughs).

use glam::{DVec2, DVec3};
use serde::{Deserialize, Serialize};

use super::ShapeGenerator;
use crate::check::{Checker, FieldPath};
use crate::exact::ExactSurface;
use crate::generators::{profile_normal, push_flat, repaired};
use crate::mesh::TriangleMesh;
use crate::profile::Interpolation;
use crate::profile::{Strip, exact_profile, sample_profile};

/// A profile `[x, z]` extruded along y over `length` (centred), for
/// linear reflectors and troughs; end caps close the profile's chord.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Extruded {
    /// Control points `[x, z]` (m).
    pub profile: Vec<[f64; 2]>,
    /// Extent along y (m).
    pub length: f64,
    #[serde(default)]
    pub interpolation: Interpolation,
    /// Segments per span between two control points.
    #[serde(default = "crate::shapes::defaults::default_per_span")]
    pub segments_per_span: u32,
    /// Close both ends with the polygon of the profile and its chord.
    #[serde(
        default = "crate::shapes::defaults::yes",
        skip_serializing_if = "crate::shapes::defaults::is_true"
    )]
    pub end_caps: bool,
}

impl ShapeGenerator for Extruded {
    fn kind(&self) -> &'static str {
        "extruded"
    }

    fn validate(&self, at: &FieldPath, check: &mut Checker<'_>) {
        check.profile(at, &self.profile, |_| None);
        check.length(at, "length", self.length);
        check.profile_segments(at, self.profile.len(), self.segments_per_span);
    }

    /// Two per profile segment along the sheet; each end cap is the
    /// outline's polygon, at most one triangle fewer than its segments.
    fn triangle_count(&self) -> Option<u64> {
        let spans = self.profile.len().saturating_sub(1) as u64;
        let segments = spans.saturating_mul(u64::from(self.segments_per_span));
        let caps = if self.end_caps {
            2 * segments.saturating_sub(1)
        } else {
            0
        };
        Some(segments.saturating_mul(2).saturating_add(caps))
    }

    fn generate(&self) -> Option<TriangleMesh> {
        Some(extrude(
            &sample_profile(&self.profile, self.interpolation, self.segments_per_span),
            self.length,
            self.end_caps,
        ))
    }

    fn exact(&self) -> Option<Vec<ExactSurface>> {
        Some(vec![ExactSurface::Extrusion {
            profile: exact_profile(&self.profile, self.interpolation),
            length: self.length,
            end_caps: self.end_caps,
        }])
    }
}

/// Extrudes profile strips (x-z) along y over `length`, centred; normals
/// on the right of the profile's direction. End caps close each end with
/// the polygon of the profile and its chord, facing the side the sheet's
/// normals face, so the sheet and caps bound one region consistently.
fn extrude(strips: &[Strip], length: f64, end_caps: bool) -> TriangleMesh {
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
