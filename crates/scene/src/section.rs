//! A planar section through a luminaire: the vertical plane of a C-plane,
//! and where it cuts each tessellated part and emitter, as an optics
//! drawing shows a luminaire in cross-section.

use glam::Vec3;

use crate::tessellate::TessellatedScene;

/// A plane that holds the vertical (+z): through `origin`, `along` its
/// horizontal direction (unit, z = 0), as a section in the C-plane of
/// `along` is drawn.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SectionPlane {
    pub origin: Vec3,
    pub along: Vec3,
}

impl SectionPlane {
    /// The plane of C-plane `c_deg` (C0 along +x, C90 along +y) through
    /// `origin`.
    pub fn of_c_plane(origin: Vec3, c_deg: f64) -> SectionPlane {
        let (s, c) = c_deg.to_radians().sin_cos();
        SectionPlane {
            origin,
            along: Vec3::new(c as f32, s as f32, 0.0),
        }
    }

    /// The plane's normal: horizontal, a right angle from `along`.
    pub fn normal(&self) -> Vec3 {
        Vec3::new(-self.along.y, self.along.x, 0.0)
    }

    /// A point's coordinates in the plane: along it and up (m), and its
    /// signed distance off it.
    pub fn coordinates(&self, p: Vec3) -> ([f64; 2], f64) {
        let q = p - self.origin;
        (
            [f64::from(self.along.dot(q)), f64::from(q.z)],
            f64::from(self.normal().dot(q)),
        )
    }
}

/// Where the plane cuts one surface of the tessellation: segments in the
/// plane's coordinates (m).
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceCut {
    /// Index into [`TessellatedScene::surfaces`].
    pub surface: usize,
    pub segments: Vec<[[f64; 2]; 2]>,
}

/// The cut of every surface the plane crosses, in the tessellation's
/// order; a triangle lying in the plane is left out (it has no edge
/// across it).
pub fn section_cuts(t: &TessellatedScene, plane: &SectionPlane) -> Vec<SurfaceCut> {
    let n = plane.normal();
    let distance = |p: Vec3| f64::from(n.dot(p - plane.origin));
    let mut cuts = Vec::new();
    for (surface, range) in t.surfaces.iter().enumerate() {
        let mut segments = Vec::new();
        for tri in &t.mesh.triangles[range.triangles.clone()] {
            let p = tri.map(|i| t.mesh.positions[i as usize]);
            let d = p.map(distance);
            // The vertices on the plane, and where edges cross it from one
            // side to the other.
            let mut crossing: Vec<[f64; 2]> = Vec::with_capacity(3);
            for k in 0..3 {
                if d[k] == 0.0 {
                    crossing.push(plane.coordinates(p[k]).0);
                }
                let (a, b) = (k, (k + 1) % 3);
                let (da, db) = (d[a], d[b]);
                if (da < 0.0 && db > 0.0) || (da > 0.0 && db < 0.0) {
                    let s = (da / (da - db)) as f32;
                    crossing.push(plane.coordinates(p[a] + (p[b] - p[a]) * s).0);
                }
            }
            // Two points: a segment; three: the triangle lies in the
            // plane; fewer: it touches the plane at a vertex at most.
            if crossing.len() == 2 && crossing[0] != crossing[1] {
                segments.push([crossing[0], crossing[1]]);
            }
        }
        // An edge in the plane is cut from both its triangles: once.
        for seg in &mut segments {
            if seg[1] < seg[0] {
                seg.swap(0, 1);
            }
        }
        segments.sort_by(|a, b| a.partial_cmp(b).unwrap_or(std::cmp::Ordering::Equal));
        segments.dedup();
        if !segments.is_empty() {
            cuts.push(SurfaceCut { surface, segments });
        }
    }
    cuts
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{parse_scene, tessellate};

    fn tessellated(parts: &str) -> TessellatedScene {
        let text = format!(
            "format_version = 1\nname = \"cut\"\n[materials.m]\ntype = \"mirror\"\nreflectance = 0.9\n[[emitter]]\nname = \"LED\"\nflux_lm = 100.0\nshape = {{ type = \"disk\", radius = 0.001 }}\n{parts}"
        );
        let scene = parse_scene(&text, std::path::Path::new("cut.toml")).unwrap();
        tessellate(&scene, std::path::Path::new(".")).unwrap()
    }

    fn length(cut: &SurfaceCut) -> f64 {
        cut.segments
            .iter()
            .map(|[a, b]| (a[0] - b[0]).hypot(a[1] - b[1]))
            .sum()
    }

    #[test]
    fn a_box_cut_through_its_centre_is_its_outline_in_that_plane() {
        // 40 × 20 × 10 mm, centred 30 mm below the LED.
        let t = tessellated(
            "[[part]]\nname = \"box\"\nmaterial = \"m\"\nshape = { type = \"box\", size = [0.04, 0.02, 0.01] }\ntransform = { translate = [0.0, 0.0, -0.03] }\n",
        );
        let part = t.surfaces.iter().position(|s| s.name == "box").unwrap();
        for (c_deg, across) in [(0.0, 0.04), (90.0, 0.02)] {
            let cuts = section_cuts(&t, &SectionPlane::of_c_plane(Vec3::ZERO, c_deg));
            let cut = cuts.iter().find(|c| c.surface == part).unwrap();
            // The rectangle across × 10 mm: its perimeter.
            let want = 2.0 * (across + 0.01);
            assert!(
                (length(cut) - want).abs() < 1e-6,
                "C{c_deg}: {} vs {want}",
                length(cut)
            );
            for [a, b] in &cut.segments {
                for p in [a, b] {
                    assert!(p[0].abs() <= 0.5 * across + 1e-7, "C{c_deg}: {p:?}");
                    assert!((-0.035 - 1e-7..=-0.025 + 1e-7).contains(&p[1]), "{p:?}");
                }
            }
        }
        // At 45° the plane leaves the 40 × 20 mm footprint through its long
        // sides (y = ±10 mm at x = ±10 mm): 20√2 mm across.
        let cuts = section_cuts(&t, &SectionPlane::of_c_plane(Vec3::ZERO, 45.0));
        let cut = cuts.iter().find(|c| c.surface == part).unwrap();
        let across = 0.02 * std::f64::consts::SQRT_2;
        assert!(
            (length(cut) - 2.0 * (across + 0.01)).abs() < 1e-6,
            "{}",
            length(cut)
        );
    }

    #[test]
    fn a_cylinder_cut_through_its_vertices_shows_both_sides() {
        // 64 segments around: C0 and C90 pass through vertices on the plane.
        let t = tessellated(
            "[[part]]\nname = \"can\"\nmaterial = \"m\"\nshape = { type = \"cylinder\", radius = 0.05, height = 0.04, cap_bottom = false, segments_around = 64 }\n",
        );
        let part = t.surfaces.iter().position(|s| s.name == "can").unwrap();
        for c_deg in [0.0, 90.0, 33.0] {
            let cuts = section_cuts(&t, &SectionPlane::of_c_plane(Vec3::ZERO, c_deg));
            let cut = cuts.iter().find(|c| c.surface == part).unwrap();
            // Both walls (2 × 40 mm) and the cap across (100 mm, a little
            // less off the vertices: the 64-gon's chord).
            let walls: f64 = cut
                .segments
                .iter()
                .filter(|[a, b]| (a[0] - b[0]).abs() < 1e-9)
                .map(|[a, b]| (a[1] - b[1]).abs())
                .sum();
            let cap: f64 = cut
                .segments
                .iter()
                .filter(|[a, b]| (a[1] - b[1]).abs() < 1e-9)
                .map(|[a, b]| (a[0] - b[0]).abs())
                .sum();
            assert!((walls - 0.08).abs() < 1e-6, "C{c_deg}: walls {walls}");
            assert!(
                (0.0995..=0.100 + 1e-7).contains(&cap),
                "C{c_deg}: cap {cap}"
            );
            let xs: Vec<f64> = cut.segments.iter().flatten().map(|p| p[0]).collect();
            let (lo, hi) = xs
                .iter()
                .fold((0.0f64, 0.0f64), |(l, h), &x| (l.min(x), h.max(x)));
            assert!(lo < -0.0499 && hi > 0.0499, "C{c_deg}: {lo} … {hi}");
        }
    }

    #[test]
    fn a_plane_beside_a_part_does_not_cut_it() {
        let t = tessellated(
            "[[part]]\nname = \"box\"\nmaterial = \"m\"\nshape = { type = \"box\", size = [0.01, 0.01, 0.01] }\ntransform = { translate = [0.0, 0.05, -0.03] }\n",
        );
        let part = t.surfaces.iter().position(|s| s.name == "box").unwrap();
        let cuts = section_cuts(&t, &SectionPlane::of_c_plane(Vec3::ZERO, 0.0));
        assert!(cuts.iter().all(|c| c.surface != part));
        // Through its centre it is cut.
        let through = SectionPlane::of_c_plane(Vec3::new(0.0, 0.05, 0.0), 0.0);
        assert!(section_cuts(&t, &through).iter().any(|c| c.surface == part));
    }
}
