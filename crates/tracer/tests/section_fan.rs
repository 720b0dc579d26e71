#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! The section view's ray fan against the laws it follows: a paraboloid
//! sends its focus's rays along the axis, a flat mirror reflects by the
//! law of reflection, a glass slab refracts by Snell's law and gives the
//! ray back parallel, a diffuse surface ends it; the fan lies in its
//! plane and starts where the emitter is.

use std::path::Path;

use glam::Vec3;
use lucerna_scene::{parse_scene, tessellate};
use lucerna_tracer::cpu::Fate;
use lucerna_tracer::{PhotonPath, PreparedScene, SectionPlane, section_fan, trace_principal_ray};

fn prepare(text: &str) -> PreparedScene {
    let dir = Path::new(".");
    let scene = parse_scene(text, Path::new("fan.toml")).unwrap();
    let t = tessellate(&scene, dir).unwrap();
    PreparedScene::new(&scene, &t, dir).unwrap()
}

/// A downward disk LED of `radius` (m) at the origin, and `parts`.
fn scene(radius: f64, materials: &str, parts: &str) -> String {
    format!(
        "format_version = 1\nname = \"fan\"\n{materials}\n[[emitter]]\nname = \"LED\"\nflux_lm = 100.0\nshape = {{ type = \"disk\", radius = {radius} }}\n{parts}"
    )
}

fn escape(p: &PhotonPath) -> Option<Vec3> {
    match p.fate {
        Fate::Escaped(d) => Some(d.into()),
        _ => None,
    }
}

#[test]
fn a_paraboloid_sends_its_focus_rays_along_the_axis() {
    // Focal length 20 mm, the LED at the focus facing up into it.
    let text = scene(
        0.0015,
        "[materials.m]\ntype = \"mirror\"\nreflectance = 1.0\n",
        "[[part]]\nname = \"reflector\"\nmaterial = \"m\"\nshape = { type = \"paraboloid\", focal_length = 0.02, aperture_diameter = 0.1, segments_around = 256, segments_along = 96 }\n",
    )
    .replace(
        "radius = 0.0015 }\n",
        "radius = 0.0015 }\ntransform = { rotate_deg = [180.0, 0.0, 0.0] }\n",
    );
    let s = prepare(&text);
    for c_deg in [0.0, 37.0, 90.0] {
        let plane = SectionPlane::of_c_plane(Vec3::ZERO, c_deg);
        let fan = section_fan(&s, plane, 15, 8);
        // Centre and two edges, 15 directions each.
        assert_eq!(fan.len(), 45);
        let mut reflected = 0;
        for (k, p) in fan.iter().enumerate() {
            for &q in &p.points {
                let (_, off) = plane.coordinates(q);
                assert!(
                    off.abs() < 1e-5,
                    "C{c_deg} ray {k} leaves the plane by {off} m"
                );
            }
            // The centre's rays: the first 15.
            if k < 15
                && p.bounces == 1
                && let Some(d) = escape(p)
            {
                let tilt = d.angle_between(Vec3::NEG_Z).to_degrees();
                assert!(tilt < 0.5, "C{c_deg} ray {k}: {tilt}° off the axis");
                reflected += 1;
            }
        }
        assert!(reflected >= 10, "C{c_deg}: {reflected} rays reflected");
        // The edges start just inside the 1.5 mm radius either side of the
        // centre, in the plane.
        let starts: Vec<f64> = [0, 15, 30]
            .iter()
            .map(|&k| plane.coordinates(fan[k].points[0]).0[0])
            .collect();
        assert!(starts[0].abs() < 1e-6);
        assert!(
            (starts[1].abs() - 0.95 * 0.0015).abs() < 1e-5 && (starts[1] + starts[2]).abs() < 1e-6
        );
    }
}

#[test]
fn a_flat_mirror_reflects_by_the_law_of_reflection() {
    // A plate 10 mm below the LED, tilted 30° about y.
    let text = scene(
        0.001,
        "[materials.m]\ntype = \"mirror\"\nreflectance = 1.0\n",
        "[[part]]\nname = \"mirror\"\nmaterial = \"m\"\nshape = { type = \"plate\", width = 0.2, depth = 0.2 }\ntransform = { translate = [0.0, 0.0, -0.01], rotate_deg = [0.0, 30.0, 0.0] }\n",
    );
    let s = prepare(&text);
    let n = Vec3::new(30f32.to_radians().sin(), 0.0, 30f32.to_radians().cos());
    let fan = section_fan(&s, SectionPlane::of_c_plane(Vec3::ZERO, 0.0), 9, 4);
    let mut checked = 0;
    for p in &fan {
        let Some(out) = escape(p) else { continue };
        if p.bounces != 1 {
            continue;
        }
        let d = (p.points[1] - p.points[0]).normalize();
        let want = d - 2.0 * d.dot(n) * n;
        assert!(out.angle_between(want) < 1e-4, "{out} vs {want}");
        checked += 1;
    }
    assert!(checked >= 20, "{checked}");
}

#[test]
fn a_glass_slab_refracts_by_snells_law_and_gives_the_ray_back_parallel() {
    let text = scene(
        0.001,
        "[materials.glass]\ntype = \"dielectric\"\nior = 1.5\n",
        "[[part]]\nname = \"slab\"\nmaterial = \"glass\"\nshape = { type = \"box\", size = [0.4, 0.4, 0.01] }\ntransform = { translate = [0.0, 0.0, -0.02] }\n",
    );
    let s = prepare(&text);
    let mut checked = 0;
    for angle_deg in [0.0f32, 10.0, 25.0, 40.0, 60.0] {
        let a = angle_deg.to_radians();
        let d = Vec3::new(a.sin(), 0.0, -a.cos());
        let p = trace_principal_ray(&s, Vec3::new(0.0, 0.0, -0.001), d, 8);
        assert_eq!(p.bounces, 2, "{angle_deg}°: {p:?}");
        let out = escape(&p).unwrap();
        assert!(out.angle_between(d) < 1e-4, "{angle_deg}°: {out} vs {d}");
        let inside = (p.points[2] - p.points[1]).normalize();
        let sin_t = (inside.x * inside.x + inside.y * inside.y).sqrt();
        assert!(
            (sin_t - a.sin() / 1.5).abs() < 1e-4,
            "{angle_deg}°: sin θt {sin_t}"
        );
        checked += 1;
    }
    assert_eq!(checked, 5);
}

#[test]
fn a_diffuse_surface_ends_the_ray_where_it_scatters() {
    let text = scene(
        0.001,
        "[materials.white]\ntype = \"lambertian\"\nalbedo = 0.9\n",
        "[[part]]\nname = \"floor\"\nmaterial = \"white\"\nshape = { type = \"plate\", width = 2.0, depth = 2.0 }\ntransform = { translate = [0.0, 0.0, -0.05] }\n",
    );
    let s = prepare(&text);
    let fan = section_fan(&s, SectionPlane::of_c_plane(Vec3::ZERO, 90.0), 7, 4);
    assert_eq!(fan.len(), 21);
    for p in &fan {
        assert_eq!(p.fate, Fate::Absorbed, "{p:?}");
        assert_eq!(p.points.len(), 2);
        assert!((p.points[1].z + 0.05).abs() < 1e-5);
    }
}
