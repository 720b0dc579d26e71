#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! Every part shape: its kind name is the `type` of the file format, it
//! round-trips through TOML, its defaults are those of the file format,
//! and it validates and tessellates through the `Shape` dispatch.

use std::collections::BTreeMap;
use std::path::Path;

use lucerna_scene::exact::{ExactSurface, ProfileCurve};
use lucerna_scene::shapes::{
    BoxShape, Cylinder, Disk, Dome, Ellipsoid, Extruded, Louvre, Mesh, Paraboloid, Plate, Revolved,
};
use lucerna_scene::{
    Emission, Emitter, EmitterShape, Interpolation, LoadSceneError, Material, Part, Scene, Shape,
    Transform, parse_scene, scene_to_toml, tessellate, validate,
};

/// One shape of each kind, every optional field away from its default so
/// that all of them are written out.
fn examples() -> Vec<Shape> {
    vec![
        Shape::Paraboloid(Paraboloid {
            focal_length: 0.025,
            aperture_diameter: 0.1,
            neck_diameter: 0.02,
            segments_around: 24,
            segments_along: 12,
            faceted: true,
        }),
        Shape::Ellipsoid(Ellipsoid {
            focal_distance: 0.1,
            vertex_distance: 0.015,
            cut_below_focus: 0.03,
            neck_diameter: 0.01,
            segments_around: 24,
            segments_along: 12,
            faceted: true,
        }),
        Shape::Revolved(Revolved {
            profile: vec![[0.01, 0.0], [0.02, -0.01], [0.04, -0.05]],
            interpolation: Interpolation::Linear,
            segments_around: 24,
            segments_per_span: 4,
            faceted: true,
        }),
        Shape::Extruded(Extruded {
            profile: vec![[-0.04, -0.05], [0.0, 0.0], [0.04, -0.05]],
            length: 0.5,
            interpolation: Interpolation::Linear,
            segments_per_span: 4,
            end_caps: false,
        }),
        Shape::Louvre(Louvre {
            blade_count: 3,
            spacing: 0.02,
            blade_height: 0.015,
            blade_length: 0.3,
            tilt_deg: 15.0,
            cross_blade_count: 4,
            cross_spacing: 0.05,
        }),
        Shape::Plate(Plate {
            width: 0.1,
            depth: 0.05,
        }),
        Shape::Disk(Disk {
            radius: 0.05,
            segments_around: 24,
        }),
        Shape::Dome(Dome {
            radius: 0.15,
            height: 0.1,
            segments_around: 24,
            segments_along: 12,
        }),
        Shape::Cylinder(Cylinder {
            radius: 0.05,
            height: 0.1,
            cap_top: false,
            cap_bottom: false,
            segments_around: 24,
        }),
        Shape::Box(BoxShape {
            size: [0.1, 0.2, 0.05],
            open_bottom: true,
        }),
        Shape::Mesh(Mesh {
            path: "../meshes/cone_reflector.obj".to_owned(),
            group_materials: BTreeMap::from([("BlackMatte".to_owned(), "black".to_owned())]),
        }),
    ]
}

fn scene_of(shapes: Vec<Shape>) -> Scene {
    Scene {
        opening: None,
        export: Default::default(),
        format_version: 1,
        name: "shapes".into(),
        description: String::new(),
        manufacturer: String::new(),
        materials: BTreeMap::from([
            ("alu".to_owned(), Material::Mirror { reflectance: 0.9 }),
            ("black".to_owned(), Material::Absorber),
        ]),
        emitters: vec![Emitter {
            name: "LED".into(),
            shape: EmitterShape::Disk { radius: 0.002 },
            flux_lm: 100.0,
            emission: Emission::Lambertian,
            material: None,
            enabled: true,
            transform: Default::default(),
        }],
        parts: shapes
            .into_iter()
            .map(|shape| Part {
                name: shape.kind().to_owned(),
                // The OBJ is in millimetres.
                transform: match shape {
                    Shape::Mesh(_) => Transform {
                        scale: [0.001; 3],
                        ..Transform::default()
                    },
                    _ => Transform::default(),
                },
                shape,
                material: "alu".into(),
                enabled: true,
                finish: None,
            })
            .collect(),
    }
}

fn luminaires_dir() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires")
}

#[test]
fn every_shape_type_of_the_file_format_has_an_example() {
    // The file format's own list: serde names every variant it accepts.
    let err = toml::from_str::<Shape>("type = \"no_such_shape\"").unwrap_err();
    let message = err.message();
    let accepted: Vec<&str> = message
        .split("expected one of ")
        .nth(1)
        .unwrap_or_else(|| panic!("unexpected serde message: {message}"))
        .split(", ")
        .map(|s| s.trim().trim_matches('`'))
        .collect();
    let kinds: Vec<&str> = examples().iter().map(Shape::kind).collect();
    assert_eq!(
        kinds, accepted,
        "each shape needs one example here, in the enum's order"
    );
}

#[test]
fn kind_is_the_type_written_in_the_file() {
    for shape in examples() {
        let table = toml::Table::try_from(&shape).expect("a shape serialises to a table");
        assert_eq!(
            table.get("type").and_then(toml::Value::as_str),
            Some(shape.kind()),
            "{shape:?}"
        );
    }
}

#[test]
fn every_shape_round_trips_through_toml() {
    let scene = scene_of(examples());
    assert_eq!(validate(&scene), vec![], "the examples are valid");
    let text = scene_to_toml(&scene).expect("serialises");
    let again = parse_scene(&text, Path::new("saved.toml"))
        .unwrap_or_else(|e| panic!("re-read: {e}\n{text}"));
    assert_eq!(scene, again, "{text}");
}

#[test]
fn omitted_fields_take_the_file_formats_defaults() {
    let cases = [
        (
            "type = \"paraboloid\"\nfocal_length = 0.02\naperture_diameter = 0.08",
            Shape::Paraboloid(Paraboloid {
                focal_length: 0.02,
                aperture_diameter: 0.08,
                neck_diameter: 0.0,
                segments_around: 64,
                segments_along: 32,
                faceted: false,
            }),
        ),
        (
            "type = \"ellipsoid\"\nfocal_distance = 0.1\nvertex_distance = 0.015\ncut_below_focus = 0.03",
            Shape::Ellipsoid(Ellipsoid {
                focal_distance: 0.1,
                vertex_distance: 0.015,
                cut_below_focus: 0.03,
                neck_diameter: 0.0,
                segments_around: 64,
                segments_along: 32,
                faceted: false,
            }),
        ),
        (
            "type = \"revolved\"\nprofile = [[0.01, 0.0], [0.02, -0.01]]",
            Shape::Revolved(Revolved {
                profile: vec![[0.01, 0.0], [0.02, -0.01]],
                interpolation: Interpolation::CatmullRom,
                segments_around: 64,
                segments_per_span: 8,
                faceted: false,
            }),
        ),
        (
            "type = \"extruded\"\nprofile = [[0.01, 0.0], [0.02, -0.01]]\nlength = 1.0",
            Shape::Extruded(Extruded {
                profile: vec![[0.01, 0.0], [0.02, -0.01]],
                length: 1.0,
                interpolation: Interpolation::CatmullRom,
                segments_per_span: 8,
                end_caps: true,
            }),
        ),
        (
            "type = \"louvre\"\nblade_count = 3\nspacing = 0.02\nblade_height = 0.01\nblade_length = 0.5",
            Shape::Louvre(Louvre {
                blade_count: 3,
                spacing: 0.02,
                blade_height: 0.01,
                blade_length: 0.5,
                tilt_deg: 0.0,
                cross_blade_count: 0,
                cross_spacing: 0.0,
            }),
        ),
        (
            "type = \"plate\"\nwidth = 0.1\ndepth = 0.2",
            Shape::Plate(Plate {
                width: 0.1,
                depth: 0.2,
            }),
        ),
        (
            "type = \"disk\"\nradius = 0.1",
            Shape::Disk(Disk {
                radius: 0.1,
                segments_around: 64,
            }),
        ),
        (
            "type = \"dome\"\nradius = 0.1\nheight = 0.05",
            Shape::Dome(Dome {
                radius: 0.1,
                height: 0.05,
                segments_around: 64,
                segments_along: 32,
            }),
        ),
        (
            "type = \"cylinder\"\nradius = 0.1\nheight = 0.05",
            Shape::Cylinder(Cylinder {
                radius: 0.1,
                height: 0.05,
                cap_top: true,
                cap_bottom: true,
                segments_around: 64,
            }),
        ),
        (
            "type = \"box\"\nsize = [0.1, 0.2, 0.3]",
            Shape::Box(BoxShape {
                size: [0.1, 0.2, 0.3],
                open_bottom: false,
            }),
        ),
        (
            "type = \"mesh\"\npath = \"a.obj\"",
            Shape::Mesh(Mesh {
                path: "a.obj".to_owned(),
                group_materials: BTreeMap::new(),
            }),
        ),
    ];
    for (text, expected) in cases {
        let shape: Shape = toml::from_str(text).unwrap_or_else(|e| panic!("{text}: {e}"));
        assert_eq!(shape, expected, "{text}");
        let written = toml::to_string(&shape).expect("serialises");
        assert_eq!(
            toml::from_str::<Shape>(&written).ok(),
            Some(expected),
            "{written}"
        );
    }
}

#[test]
fn every_example_tessellates_through_the_dispatch() {
    let shapes = examples();
    for shape in &shapes {
        let generated = shape.generator().generate();
        assert_eq!(generated.is_none(), matches!(shape, Shape::Mesh(_)));
        if let Some(mesh) = generated {
            mesh.check().unwrap_or_else(|e| panic!("{shape:?}: {e}"));
        }
        let surfaces = shape
            .generator()
            .tessellate(&luminaires_dir())
            .unwrap_or_else(|e| panic!("{shape:?}: {e}"));
        assert!(!surfaces.is_empty(), "{shape:?}");
    }
    let t = tessellate(&scene_of(shapes), &luminaires_dir()).expect("tessellates");
    t.mesh.check().expect("a clean luminaire");
    // Ten generated parts, two OBJ groups, one emitter.
    assert_eq!(t.surfaces.len(), 13);
}

#[test]
fn an_unknown_field_in_a_shape_is_a_syntax_error_at_its_line() {
    let mut scene = scene_of(vec![examples().swap_remove(7)]);
    scene.parts[0].name = "bell".into();
    let text = scene_to_toml(&scene)
        .expect("serialises")
        .replace("height = 0.1", "height = 0.1\nthickness = 0.002");
    let line = 1 + text
        .lines()
        .position(|l| l.starts_with("thickness"))
        .expect("inserted");
    match parse_scene(&text, Path::new("bell.toml")) {
        Err(LoadSceneError::Syntax {
            line: at, message, ..
        }) => {
            assert_eq!(at, line, "{message}\n{text}");
            assert!(message.contains("thickness"), "{message}");
        }
        other => panic!("{other:?}\n{text}"),
    }
}

/// The examples and their variants with the other choice of every switch
/// that changes the triangles (closed necks, smooth surfaces, caps).
fn examples_and_variants() -> Vec<Shape> {
    let mut shapes = examples();
    for shape in examples() {
        shapes.push(match shape {
            Shape::Paraboloid(s) => Shape::Paraboloid(Paraboloid {
                neck_diameter: 0.0,
                faceted: false,
                ..s
            }),
            Shape::Ellipsoid(s) => Shape::Ellipsoid(Ellipsoid {
                neck_diameter: 0.0,
                faceted: false,
                ..s
            }),
            Shape::Revolved(s) => Shape::Revolved(Revolved {
                profile: vec![[0.0, 0.0], [0.02, -0.01], [0.04, -0.05]],
                interpolation: Interpolation::CatmullRom,
                faceted: false,
                ..s
            }),
            Shape::Extruded(s) => Shape::Extruded(Extruded {
                interpolation: Interpolation::CatmullRom,
                end_caps: true,
                ..s
            }),
            Shape::Cylinder(s) => Shape::Cylinder(Cylinder {
                cap_top: true,
                cap_bottom: true,
                ..s
            }),
            Shape::Box(s) => Shape::Box(BoxShape {
                open_bottom: false,
                ..s
            }),
            other => other,
        });
    }
    shapes
}

#[test]
fn triangle_count_bounds_the_generated_mesh_closely() {
    for shape in examples_and_variants() {
        let generator = shape.generator();
        let Some(mesh) = generator.generate() else {
            assert_eq!(generator.triangle_count(), None, "{shape:?}");
            continue;
        };
        let (generated, counted) = (mesh.triangle_count() as u64, generator.triangle_count());
        let counted = counted.unwrap_or_else(|| panic!("{shape:?} counts no triangles"));
        // At most a ring on the axis (one step around per fan) too many.
        assert!(
            generated <= counted && counted <= generated + generated / 10,
            "{shape:?}: generates {generated}, counts {counted}"
        );
    }
    for shape in [
        EmitterShape::Disk { radius: 0.01 },
        EmitterShape::Rectangle {
            width: 0.01,
            depth: 0.02,
        },
        EmitterShape::Sphere { radius: 0.01 },
        EmitterShape::Cylinder {
            radius: 0.01,
            height: 0.05,
        },
    ] {
        let generated = lucerna_scene::emitter_mesh(&shape).triangle_count() as u64;
        let counted = lucerna_scene::tessellate::emitter_triangle_count(&shape);
        assert!(
            generated <= counted && counted <= generated + generated / 10,
            "{shape:?}: generates {generated}, counts {counted}"
        );
    }
}

/// Distance from `p` (metres, part frame) to one exact surface, sampling
/// curves densely enough that the chord error is far below f32 rounding.
fn distance_to_exact(surface: &ExactSurface, p: glam::DVec3) -> f64 {
    let to_curves = |curves: &[ProfileCurve], q: glam::DVec2| {
        let mut best = f64::INFINITY;
        for c in curves {
            const N: usize = 4000;
            let mut a = c.point(0.0);
            for i in 1..=N {
                let b = c.point(i as f64 / N as f64);
                let ab = b - a;
                let t = ((q - a).dot(ab) / ab.length_squared().max(1e-300)).clamp(0.0, 1.0);
                best = best.min(q.distance(a + ab * t));
                a = b;
            }
        }
        best
    };
    match surface {
        ExactSurface::Revolution(curves) => {
            to_curves(curves, glam::DVec2::new(p.x.hypot(p.y), p.z))
        }
        ExactSurface::Extrusion {
            profile, length, ..
        } => {
            let off_ends = (p.y.abs() - 0.5 * length).max(0.0);
            to_curves(profile, glam::DVec2::new(p.x, p.z)).hypot(off_ends)
        }
        ExactSurface::Disk { radius, z } => {
            (p.z - z).abs().hypot((p.x.hypot(p.y) - radius).max(0.0))
        }
        ExactSurface::Polygon(corners) => {
            let n = (corners[1] - corners[0])
                .cross(corners[2] - corners[0])
                .normalize();
            let (lo, hi) = corners
                .iter()
                .fold((corners[0], corners[0]), |(lo, hi), c| {
                    (lo.min(*c), hi.max(*c))
                });
            let outside = (lo - p).max(p - hi).max(glam::DVec3::ZERO).length();
            (p - corners[0]).dot(n).abs().hypot(outside)
        }
    }
}

#[test]
fn every_tessellation_vertex_lies_on_the_shapes_exact_surface() {
    let mut checked = 0;
    for shape in examples_and_variants() {
        let generator = shape.generator();
        let Some(exact) = generator.exact() else {
            continue;
        };
        let mesh = generator.generate().unwrap();
        let scale = mesh
            .positions
            .iter()
            .map(|p| p.abs().max_element())
            .fold(0.0f32, f32::max) as f64;
        for p in &mesh.positions {
            let p = p.as_dvec3();
            let d = exact
                .iter()
                .map(|s| distance_to_exact(s, p))
                .fold(f64::INFINITY, f64::min);
            // f32 positions: a few ulps of the shape's extent.
            assert!(d <= 4e-7 * scale, "{shape:?}: vertex {p} is {d} m off");
        }
        checked += 1;
    }
    assert!(checked >= 10, "only {checked} shapes have exact surfaces");
}

#[test]
fn faceted_shapes_and_meshes_have_no_exact_surface_but_their_facets() {
    for shape in examples_and_variants() {
        let faceted = match &shape {
            Shape::Paraboloid(s) => s.faceted,
            Shape::Ellipsoid(s) => s.faceted,
            Shape::Revolved(s) => s.faceted,
            Shape::Mesh(_) => true,
            _ => false,
        };
        assert_eq!(shape.generator().exact().is_none(), faceted, "{shape:?}");
    }
}
