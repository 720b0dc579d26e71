#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! The hostile inputs of `hostile.rs`, and `/dev/zero` as every file a
//! scene reads, are refused within a 1 GiB address space: a runaway
//! allocation fails there (and aborts the child process this test runs
//! in) instead of being left to the OOM killer.

#![cfg(target_os = "linux")]

use std::path::Path;

use lucerna_scene::shapes::Paraboloid;
use lucerna_scene::{LoadSceneError, Shape, TessellateError, load_scene, parse_scene, tessellate};

use lucerna_scene::test_support::in_address_limited_child as in_limited_child;

use lucerna_scene::test_support::SMALL_SCENE as GOOD;

const PARABOLOID: &str =
    "shape = { type = \"paraboloid\", focal_length = 0.02, aperture_diameter = 0.08 }";

use lucerna_scene::test_support::error_chain as chain;

/// The scene with its part made of the OBJ at `path`, tessellated.
fn tessellate_obj(
    dir: &Path,
    path: &str,
) -> Result<lucerna_scene::TessellatedScene, TessellateError> {
    let shape = format!("shape = {{ type = \"mesh\", path = \"{path}\" }}");
    let scene = parse_scene(&GOOD.replace(PARABOLOID, &shape), Path::new("lamp.toml")).unwrap();
    tessellate(&scene, dir)
}

#[test]
fn hostile_scene_inputs_are_refused_within_1_gib() {
    if !in_limited_child("hostile_scene_inputs_are_refused_within_1_gib") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let dir = dir.path();

    // The scene file, the OBJ and the MTL as an endless stream of zeros.
    match load_scene(Path::new("/dev/zero")) {
        Err(e @ LoadSceneError::Read(_)) => assert!(e.to_string().contains("larger than"), "{e}"),
        other => panic!("{other:?}"),
    }
    let e = tessellate_obj(dir, "/dev/zero").unwrap_err();
    assert!(chain(&e).contains("larger than 64 MiB"), "{}", chain(&e));
    std::fs::write(
        dir.join("m.obj"),
        "mtllib /dev/zero\nv 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nf 1 2 3\n",
    )
    .unwrap();
    let e = tessellate_obj(dir, "m.obj").unwrap_err();
    assert!(chain(&e).contains("larger than 16 MiB"), "{}", chain(&e));

    // The lines tobj crashes on.
    std::fs::write(dir.join("m.mtl"), "Ks\n").unwrap();
    std::fs::write(
        dir.join("m.obj"),
        "mtllib m.mtl\nv 0 0 0\nv 0.1 0 0\nv 0 0.1 0\nf 1 2 3\n",
    )
    .unwrap();
    let e = tessellate_obj(dir, "m.obj").unwrap_err();
    assert!(chain(&e).contains("m.mtl:1"), "{}", chain(&e));
    std::fs::write(dir.join("i.obj"), "v 9 5 6\nvt 9 1\nf 1/-8 1 1\n").unwrap();
    let e = tessellate_obj(dir, "i.obj").unwrap_err();
    assert!(chain(&e).contains("i.obj:3"), "{}", chain(&e));

    // 344 bytes asking for 3 GB, and four of them.
    let huge = "aperture_diameter = 0.08, segments_around = 4096, segments_along = 4096 }";
    let text = GOOD.replace("aperture_diameter = 0.08 }", huge);
    assert!(matches!(
        parse_scene(&text, Path::new("lamp.toml")),
        Err(LoadSceneError::Invalid { .. })
    ));
    let part = &text[text.find("[[part]]").unwrap()..];
    let four = format!("{text}{part}{part}{part}");
    assert!(matches!(
        parse_scene(&four, Path::new("lamp.toml")),
        Err(LoadSceneError::Invalid { .. })
    ));
    // The same part built in code, never validated, is refused when
    // tessellated, before its mesh is allocated.
    let mut scene = parse_scene(GOOD, Path::new("lamp.toml")).unwrap();
    scene.parts[0].shape = Shape::Paraboloid(Paraboloid {
        focal_length: 0.02,
        aperture_diameter: 0.08,
        neck_diameter: 0.0,
        segments_around: 4096,
        segments_along: 4096,
        faceted: true,
    });
    assert!(matches!(
        tessellate(&scene, dir),
        Err(TessellateError::PartTriangles { .. })
    ));

    // Thousands of problems, each of whose messages listed every material.
    let mut text = String::from("format_version = 1\nname = \"generated\"\n");
    for i in 0..2000 {
        text.push_str(&format!("[materials.m{i}]\ntype = \"absorber\"\n"));
    }
    for i in 0..4000 {
        text.push_str(&format!(
            "[[part]]\nname = \"p{i}\"\nmaterial = \"nope\"\nshape = {{ type = \"disk\", radius = 0.1 }}\n"
        ));
    }
    let e = parse_scene(&text, Path::new("lamp.toml")).unwrap_err();
    assert!(
        e.to_string().len() < 100_000,
        "{} bytes",
        e.to_string().len()
    );
}
