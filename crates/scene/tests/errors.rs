#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! Broken scenes and meshes give errors naming the file, line and field.

use std::path::Path;

use lucerna_scene::{LoadSceneError, TessellateError, parse_scene, tessellate};

use lucerna_scene::test_support::SMALL_SCENE as GOOD;

fn parse(text: &str) -> Result<lucerna_scene::Scene, LoadSceneError> {
    parse_scene(text, Path::new("lamp.toml"))
}

fn invalid(text: &str) -> Vec<lucerna_scene::file::Located> {
    match parse(text) {
        Err(LoadSceneError::Invalid { problems, .. }) => problems,
        other => panic!("expected an invalid-scene error, got {other:?}"),
    }
}

#[test]
fn the_baseline_is_valid() {
    parse(GOOD).expect("valid");
}

#[test]
fn unknown_field_is_a_syntax_error_with_its_line() {
    let text = GOOD.replace("reflectance = 0.9", "reflectance = 0.9\nshininess = 3");
    match parse(&text) {
        Err(LoadSceneError::Syntax {
            line,
            message,
            path,
            ..
        }) => {
            assert_eq!(line, 7, "{message}");
            assert!(message.contains("shininess"), "{message}");
            assert_eq!(path, Path::new("lamp.toml"));
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn wrong_type_is_a_syntax_error_with_its_line() {
    let text = GOOD.replace("flux_lm = 100.0", "flux_lm = \"bright\"");
    match parse(&text) {
        Err(e @ LoadSceneError::Syntax { line: 10, .. }) => {
            assert!(e.to_string().starts_with("lamp.toml:10:"), "{e}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn out_of_range_values_name_line_and_field() {
    let text = GOOD.replace("reflectance = 0.9", "reflectance = 1.4");
    let p = invalid(&text);
    assert_eq!(p.len(), 1);
    assert_eq!(p[0].field, "materials.alu.reflectance");
    assert_eq!(p[0].line, Some(6));

    let text = GOOD.replace("focal_length = 0.02", "focal_length = -0.02");
    let p = invalid(&text);
    assert_eq!(p[0].field, "part[0].shape.focal_length");
    assert_eq!(p[0].line, Some(16));

    let text = GOOD.replace("flux_lm = 100.0", "flux_lm = nan");
    let p = invalid(&text);
    assert_eq!(p[0].field, "emitter[0].flux_lm");
    assert_eq!(p[0].line, Some(10));
}

#[test]
fn energy_and_physics_limits_are_checked() {
    let cases = [
        (
            "type = \"mirror\"\nreflectance = 0.9",
            "type = \"diffuser\"\nreflectance = 0.6\ntransmittance = 0.5",
            "materials.alu.transmittance",
        ),
        (
            "type = \"mirror\"\nreflectance = 0.9",
            "type = \"dielectric\"\nior = 0.8",
            "materials.alu.ior",
        ),
        (
            "type = \"mirror\"\nreflectance = 0.9",
            "type = \"lambertian\"\nalbedo = -0.1",
            "materials.alu.albedo",
        ),
        (
            "type = \"mirror\"\nreflectance = 0.9",
            "type = \"rough_conductor\"\nreflectance = 0.9\nroughness_u = 0.0\nroughness_v = 0.1",
            "materials.alu.roughness_u",
        ),
        (
            "aperture_diameter = 0.08 }",
            "aperture_diameter = 0.08, segments_around = 100000 }",
            "part[0].shape.segments_around",
        ),
        (
            "aperture_diameter = 0.08 }",
            "aperture_diameter = 0.08, neck_diameter = 0.09 }",
            "part[0].shape.neck_diameter",
        ),
        (
            "radius = 0.002 }",
            "radius = 0.002 }\ntransform = { scale = [0.0, 1.0, 1.0] }",
            "emitter[0].transform.scale",
        ),
        ("format_version = 1", "format_version = 7", "format_version"),
    ];
    for (from, to, field) in cases {
        let text = GOOD.replace(from, to);
        let p = invalid(&text);
        assert!(
            p.iter().any(|x| x.field == field && x.line.is_some()),
            "expected a located problem at {field}, got {p:?}"
        );
    }
}

#[test]
fn unknown_material_lists_the_known_ones() {
    let text = GOOD.replace("material = \"alu\"", "material = \"gold\"");
    let p = invalid(&text);
    assert_eq!(p[0].field, "part[0].material");
    assert_eq!(p[0].line, Some(15));
    assert!(p[0].message.contains("gold") && p[0].message.contains("alu"));
}

#[test]
fn a_scene_without_emitter_is_rejected() {
    let text = GOOD.replace(
        "[[emitter]]\nname = \"LED\"",
        "[[emitter]]\nname = \"LED\"\nenabled = false",
    );
    let p = invalid(&text);
    assert!(p.iter().any(|x| x.field == "emitter"), "{p:?}");
}

#[test]
fn not_toml_at_all_is_a_syntax_error() {
    for text in ["\u{0}\u{1}binary", "name = ", "[[part]\n", ""] {
        assert!(parse(text).is_err(), "{text:?} must not parse");
    }
}

fn scene_with_obj(
    dir: &Path,
    obj: &str,
) -> Result<lucerna_scene::TessellatedScene, TessellateError> {
    std::fs::write(dir.join("part.obj"), obj).expect("write obj");
    let text = GOOD.replace(
        "shape = { type = \"paraboloid\", focal_length = 0.02, aperture_diameter = 0.08 }",
        "shape = { type = \"mesh\", path = \"part.obj\" }",
    );
    let scene = parse(&text).expect("valid scene");
    tessellate(&scene, dir)
}

#[test]
fn missing_obj_file_names_the_part_and_path() {
    let dir = tempfile::tempdir().expect("temp dir");
    let text = GOOD.replace(
        "shape = { type = \"paraboloid\", focal_length = 0.02, aperture_diameter = 0.08 }",
        "shape = { type = \"mesh\", path = \"nowhere.obj\" }",
    );
    let scene = parse(&text).expect("valid scene");
    match tessellate(&scene, dir.path()) {
        Err(e @ TessellateError::Obj { .. }) => {
            let s = e.to_string();
            assert!(s.contains("reflector") && s.contains("nowhere.obj"), "{s}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn obj_with_nan_is_reported() {
    let dir = tempfile::tempdir().expect("temp dir");
    let r = scene_with_obj(dir.path(), "v 0 0 0\nv 0.1 0 0\nv 0 nan 0\nf 1 2 3\n");
    assert!(
        matches!(
            r,
            Err(TessellateError::Obj { .. }) | Err(TessellateError::Mesh { .. })
        ),
        "{r:?}"
    );
}

#[test]
fn obj_with_degenerate_face_is_reported() {
    let dir = tempfile::tempdir().expect("temp dir");
    // The second face is collinear: zero area.
    let r = scene_with_obj(
        dir.path(),
        "v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nv 0.2 0 0\nf 1 2 3\nf 1 2 4\n",
    );
    match r {
        Err(TessellateError::Mesh {
            defect:
                lucerna_scene::MeshDefect::Degenerate {
                    count: 1, first: 1, ..
                },
            ..
        }) => {}
        other => panic!("{other:?}"),
    }
}

#[test]
fn obj_of_absurd_size_is_reported() {
    let dir = tempfile::tempdir().expect("temp dir");
    // 1200 m across: millimetres without the scale.
    let r = scene_with_obj(dir.path(), "v 0 0 0\nv 1200 0 0\nv 0 1200 0\nf 1 2 3\n");
    match r {
        Err(
            e @ TessellateError::Mesh {
                defect: lucerna_scene::MeshDefect::AbsurdSize { .. },
                ..
            },
        ) => {
            let chain = format!("{e}: {}", std::error::Error::source(&e).unwrap());
            assert!(chain.contains("scale"), "{chain}");
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn obj_with_bad_index_is_reported_not_panicking() {
    let dir = tempfile::tempdir().expect("temp dir");
    let r = scene_with_obj(dir.path(), "v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nf 1 2 9\n");
    assert!(r.is_err(), "{r:?}");
}

#[test]
fn an_impossible_finish_names_its_field_and_the_limit() {
    let with = |finish: &str| {
        GOOD.replace(
            "aperture_diameter = 0.08 }",
            &format!("aperture_diameter = 0.08 }}\nfinish = {finish}"),
        )
    };
    let cases = [
        (
            r#"{ type = "dimples", pitch = 0.001, depth = 0.00015, radius = 0.0034 }"#,
            "part[0].finish.pitch",
            "the pitch must be at least",
        ),
        (
            r#"{ type = "dimples", pitch = 0.002, depth = 0.004, radius = 0.0034 }"#,
            "part[0].finish.depth",
            "at most as deep as its sphere's radius",
        ),
        (
            r#"{ type = "ripples", waves = [{ amplitude = -0.00001, wavelength = 0.001 }] }"#,
            "part[0].finish.waves[0].amplitude",
            "positive length",
        ),
        (
            r#"{ type = "ripples", waves = [{ amplitude = 0.00001, wavelength = nan }] }"#,
            "part[0].finish.waves[0].wavelength",
            "NaN",
        ),
        (
            r#"{ type = "slopes", sigma_u = 1.2, sigma_v = 0.5 }"#,
            "part[0].finish.sigma_u",
            "above 1: its facets would face away",
        ),
        (
            r#"{ type = "facets", size_along = 0.0, size_around = 0.003 }"#,
            "part[0].finish.size_along",
            "positive length",
        ),
    ];
    for (finish, field, why) in cases {
        let problems = invalid(&with(finish));
        assert!(
            problems
                .iter()
                .any(|p| p.field == field && p.message.contains(why) && p.line == Some(17)),
            "{finish}: {problems:?}"
        );
    }
    // A finish on a lens is refused; a sound one loads.
    let lens = with(r#"{ type = "slopes", sigma_u = 0.1, sigma_v = 0.1 }"#).replace(
        "type = \"mirror\"\nreflectance = 0.9",
        "type = \"dielectric\"\nior = 1.5",
    );
    let problems = invalid(&lens);
    assert!(
        problems
            .iter()
            .any(|p| p.field == "part[0].finish" && p.message.contains("dielectric")),
        "{problems:?}"
    );
    parse(&with(
        r#"{ type = "dimples", pitch = 0.002, depth = 0.00015, radius = 0.0034 }"#,
    ))
    .expect("a hammered reflector");
}

#[test]
fn a_height_map_that_cannot_be_read_or_has_no_pixel_size_is_refused() {
    let with = |finish: &str| {
        GOOD.replace(
            "aperture_diameter = 0.08 }",
            &format!("aperture_diameter = 0.08 }}\nfinish = {finish}"),
        )
    };
    let problems = invalid(&with(
        r#"{ type = "height_map", path = "no_such_scan.png", pixel_size = 1e-5, height_step = 1e-9 }"#,
    ));
    assert!(
        problems.iter().any(|p| p.field == "part[0].finish.path"
            && p.message.contains("the height map cannot be read")),
        "{problems:?}"
    );
    match parse(&with(
        r#"{ type = "height_map", path = "scan.png", height_step = 1e-9 }"#,
    )) {
        Err(LoadSceneError::Syntax { message, line, .. }) => {
            assert!(message.contains("pixel_size"), "{message}");
            assert_eq!(line, 17);
        }
        other => panic!("{other:?}"),
    }
}
