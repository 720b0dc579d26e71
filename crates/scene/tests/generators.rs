#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! Generators: consistent winding and normals, no degenerate triangles,
//! and the analytic shapes they claim to be.

use std::collections::HashMap;
use std::f64::consts::PI;

use glam::DVec3;
use lucerna_scene::shapes::generate;
use lucerna_scene::shapes::{
    BoxShape, Cylinder, Disk, Dome, Ellipsoid, Extruded, Louvre, Paraboloid, Plate, Revolved,
};
use lucerna_scene::{Interpolation, Shape, TriangleMesh};

fn all_default_shapes() -> Vec<Shape> {
    let profile = vec![[0.01, 0.0], [0.02, -0.01], [0.035, -0.03], [0.04, -0.05]];
    let mut shapes = vec![
        Shape::Paraboloid(Paraboloid {
            focal_length: 0.025,
            aperture_diameter: 0.1,
            neck_diameter: 0.0,
            segments_around: 64,
            segments_along: 32,
            faceted: false,
        }),
        Shape::Paraboloid(Paraboloid {
            focal_length: 0.025,
            aperture_diameter: 0.1,
            neck_diameter: 0.02,
            segments_around: 64,
            segments_along: 32,
            faceted: false,
        }),
        Shape::Paraboloid(Paraboloid {
            focal_length: 0.025,
            aperture_diameter: 0.1,
            neck_diameter: 0.0,
            segments_around: 12,
            segments_along: 6,
            faceted: true,
        }),
        Shape::Ellipsoid(Ellipsoid {
            focal_distance: 0.1,
            vertex_distance: 0.015,
            cut_below_focus: 0.03,
            neck_diameter: 0.0,
            segments_around: 64,
            segments_along: 32,
            faceted: false,
        }),
        Shape::Ellipsoid(Ellipsoid {
            focal_distance: 0.1,
            vertex_distance: 0.015,
            cut_below_focus: 0.03,
            neck_diameter: 0.01,
            segments_around: 16,
            segments_along: 8,
            faceted: true,
        }),
        Shape::Plate(Plate {
            width: 0.1,
            depth: 0.05,
        }),
        Shape::Disk(Disk {
            radius: 0.05,
            segments_around: 64,
        }),
        Shape::Dome(Dome {
            radius: 0.15,
            height: 0.1,
            segments_around: 64,
            segments_along: 32,
        }),
        Shape::Dome(Dome {
            radius: 0.15,
            height: 0.3,
            segments_around: 64,
            segments_along: 32,
        }),
        Shape::Cylinder(Cylinder {
            radius: 0.05,
            height: 0.1,
            cap_top: true,
            cap_bottom: true,
            segments_around: 64,
        }),
        Shape::Box(BoxShape {
            size: [0.1, 0.2, 0.05],
            open_bottom: false,
        }),
        Shape::Box(BoxShape {
            size: [0.1, 0.2, 0.05],
            open_bottom: true,
        }),
        Shape::Louvre(Louvre {
            blade_count: 5,
            spacing: 0.02,
            blade_height: 0.015,
            blade_length: 0.5,
            tilt_deg: 20.0,
            cross_blade_count: 10,
            cross_spacing: 0.04,
        }),
    ];
    for interpolation in [Interpolation::Linear, Interpolation::CatmullRom] {
        for faceted in [false, true] {
            shapes.push(Shape::Revolved(Revolved {
                profile: profile.clone(),
                interpolation,
                segments_around: 48,
                segments_per_span: 8,
                faceted,
            }));
        }
        shapes.push(Shape::Revolved(Revolved {
            profile: vec![[0.0, 0.02], [0.02, 0.0], [0.03, -0.03]],
            interpolation,
            segments_around: 48,
            segments_per_span: 8,
            faceted: false,
        }));
        shapes.push(Shape::Extruded(Extruded {
            profile: vec![
                [-0.04, -0.05],
                [-0.02, -0.015],
                [0.0, 0.0],
                [0.02, -0.015],
                [0.04, -0.05],
            ],
            length: 1.0,
            interpolation,
            segments_per_span: 8,
            end_caps: true,
        }));
        // Counter-clockwise profile: caps must follow the other orientation.
        shapes.push(Shape::Extruded(Extruded {
            profile: vec![[0.04, -0.05], [0.0, 0.0], [-0.04, -0.05]],
            length: 0.5,
            interpolation,
            segments_per_span: 4,
            end_caps: true,
        }));
    }
    shapes
}

/// Each triangle's winding agrees with the shading normals at its corners.
fn assert_normals_agree_with_winding(mesh: &TriangleMesh, what: &str) {
    for t in 0..mesh.triangle_count() {
        let g = mesh.geometric_normal(t).normalize();
        for &v in &mesh.triangles[t] {
            let n = mesh.normals[v as usize].as_dvec3();
            assert!(
                g.dot(n) > 0.0,
                "{what}: triangle {t} winds against its vertex normal (g = {g}, n = {n})"
            );
        }
    }
}

/// No edge is used twice in the same direction: neighbouring triangles
/// are wound the same way (all normals on one side of the sheet).
fn assert_consistent_orientation(mesh: &TriangleMesh, what: &str) {
    let key = |i: u32| {
        let p = mesh.positions[i as usize].as_dvec3() * 1e7;
        (p.x.round() as i64, p.y.round() as i64, p.z.round() as i64)
    };
    let mut seen: HashMap<_, usize> = HashMap::new();
    for (t, tri) in mesh.triangles.iter().enumerate() {
        for k in 0..3 {
            let edge = (key(tri[k]), key(tri[(k + 1) % 3]));
            if let Some(other) = seen.insert(edge, t) {
                panic!("{what}: triangles {other} and {t} share the directed edge {edge:?}");
            }
        }
    }
}

#[test]
fn every_generator_gives_clean_consistently_wound_meshes() {
    for shape in all_default_shapes() {
        let what = format!("{shape:?}");
        let mesh = generate(&shape).expect("a generated shape");
        mesh.check().unwrap_or_else(|e| panic!("{what}: {e}"));
        assert_normals_agree_with_winding(&mesh, &what);
        assert_consistent_orientation(&mesh, &what);
    }
}

#[test]
fn surfaces_of_revolution_face_the_axis() {
    let shape = Shape::Paraboloid(Paraboloid {
        focal_length: 0.025,
        aperture_diameter: 0.1,
        neck_diameter: 0.0,
        segments_around: 32,
        segments_along: 16,
        faceted: false,
    });
    let mesh = generate(&shape).unwrap();
    for t in 0..mesh.triangle_count() {
        let [a, b, c] = mesh.corners(t);
        let centroid = (a + b + c) / 3.0;
        // The focus at the origin sees the reflecting side.
        assert!(mesh.geometric_normal(t).dot(-centroid) > 0.0);
    }
}

#[test]
fn paraboloid_vertices_lie_on_the_paraboloid() {
    let f = 0.025;
    let shape = Shape::Paraboloid(Paraboloid {
        focal_length: f,
        aperture_diameter: 0.1,
        neck_diameter: 0.01,
        segments_around: 64,
        segments_along: 32,
        faceted: false,
    });
    let mesh = generate(&shape).unwrap();
    for p in &mesh.positions {
        let p = p.as_dvec3();
        // In the vertex frame (vertex at the origin, z' = f − z): r² = 4 f z'.
        let r2 = p.x * p.x + p.y * p.y;
        let z_vertex_frame = f - p.z;
        assert!((r2 - 4.0 * f * z_vertex_frame).abs() < 1e-8, "{p}");
    }
    let r_max = mesh
        .positions
        .iter()
        .map(|p| p.truncate().length())
        .fold(0.0f32, f32::max);
    assert!((r_max - 0.05).abs() < 1e-6);
}

#[test]
fn ellipsoid_vertices_sum_to_the_major_axis() {
    let (fd, vd) = (0.1, 0.015);
    let shape = Shape::Ellipsoid(Ellipsoid {
        focal_distance: fd,
        vertex_distance: vd,
        cut_below_focus: 0.03,
        neck_diameter: 0.0,
        segments_around: 32,
        segments_along: 16,
        faceted: false,
    });
    let mesh = generate(&shape).unwrap();
    let (f1, f2) = (DVec3::ZERO, DVec3::new(0.0, 0.0, -fd));
    let major = fd + 2.0 * vd;
    for p in &mesh.positions {
        let p = p.as_dvec3();
        assert!(((p - f1).length() + (p - f2).length() - major).abs() < 1e-7);
        assert!(p.z >= -0.03 - 1e-7);
    }
}

#[test]
fn dome_area_matches_the_spherical_cap() {
    for (r, h) in [(0.15, 0.15), (0.1, 0.04), (0.1, 0.18)] {
        let mesh = generate(&Shape::Dome(Dome {
            radius: r,
            height: h,
            segments_around: 256,
            segments_along: 128,
        }))
        .unwrap();
        let exact = 2.0 * PI * r * h;
        assert!(
            (mesh.area() - exact).abs() / exact < 1e-3,
            "r {r} h {h}: {} vs {exact}",
            mesh.area()
        );
    }
}

/// Exact area of a surface of revolution, ∫ 2π r |c'| ds, by composite
/// Gauss–Legendre quadrature of the spline itself.
fn revolution_area(profile: &[[f64; 2]]) -> f64 {
    use lucerna_scene::profile::evaluate;
    let points: Vec<glam::DVec2> = profile
        .iter()
        .map(|&p| glam::DVec2::from_array(p))
        .collect();
    let nodes = [
        (-0.861_136_311_594_053, 0.347_854_845_137_454),
        (-0.339_981_043_584_856, 0.652_145_154_862_546),
        (0.339_981_043_584_856, 0.652_145_154_862_546),
        (0.861_136_311_594_053, 0.347_854_845_137_454),
    ];
    let pieces = 2000;
    let spans = (points.len() - 1) as f64;
    let h = spans / pieces as f64;
    let mut area = 0.0;
    for i in 0..pieces {
        let mid = (i as f64 + 0.5) * h;
        for (x, w) in nodes {
            let (p, d) = evaluate(&points, Interpolation::CatmullRom, mid + 0.5 * h * x);
            area += w * 0.5 * h * 2.0 * PI * p.x * d.length();
        }
    }
    area
}

#[test]
fn revolved_area_converges_to_the_surface_of_revolution() {
    let profile = vec![
        [0.01, 0.0],
        [0.025, -0.012],
        [0.038, -0.03],
        [0.048, -0.05],
        [0.055, -0.072],
    ];
    let exact = revolution_area(&profile);
    let mut previous = f64::INFINITY;
    for n in [8u32, 16, 32, 64, 128] {
        let mesh = generate(&Shape::Revolved(Revolved {
            profile: profile.clone(),
            interpolation: Interpolation::CatmullRom,
            segments_around: 4 * n,
            segments_per_span: n,
            faceted: false,
        }))
        .unwrap();
        let error = (mesh.area() - exact).abs() / exact;
        assert!(
            error < previous,
            "error must shrink with resolution: {error} after {previous}"
        );
        previous = error;
    }
    assert!(
        previous < 2e-4,
        "relative area error at the finest resolution: {previous}"
    );
}

#[test]
fn a_mirroring_transform_keeps_winding_and_normals_consistent() {
    let mesh = generate(&Shape::Dome(Dome {
        radius: 0.1,
        height: 0.05,
        segments_around: 16,
        segments_along: 8,
    }))
    .unwrap();
    let t = lucerna_scene::Transform {
        scale: [1.0, -2.0, 0.5],
        rotate_deg: [30.0, 10.0, 5.0],
        translate: [0.1, 0.0, 0.0],
    };
    let moved = mesh.transformed(&t.matrix());
    moved.check().unwrap();
    assert_normals_agree_with_winding(&moved, "mirrored dome");
}
