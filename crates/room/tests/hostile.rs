#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! Hostile room files: a valid room that asks for billions of work-plane
//! points, files larger than their limit and broken OBJ rooms give errors
//! naming the file and field, never a runaway allocation or a panic.

use std::path::Path;

use lucerna_room::model::{
    MAX_ROOM_FILE_BYTES, MAX_WORK_PLANE_POINTS, RoomFileError, load_room, parse_room,
};
use lucerna_room::scene::load_room_mesh;
use lucerna_scene::obj::MAX_OBJ_FILE_BYTES;

/// A valid room of `side_m` × `side_m` with work-plane points every
/// `spacing_m`, and an OBJ if given.
fn room(side_m: f64, spacing_m: f64, obj: Option<&str>) -> String {
    let obj = obj.map(|o| format!("obj = \"{o}\"\n")).unwrap_or_default();
    format!(
        "version = 1\n\n[room]\nwidth_m = {side_m}\ndepth_m = {side_m}\nheight_m = 3.0\n{obj}\n\
         [work_plane]\nspacing_m = {spacing_m}\n\n\
         [camera]\nposition = [0.5, 0.5, 1.6]\nlook_at = [5.0, 5.0, 0.5]\n\n\
         [[luminaire]]\nprofile = \"downlight.ies\"\nposition = [1.0, 1.0, 2.9]\n"
    )
}

#[test]
fn a_work_plane_of_billions_of_points_is_invalid_at_its_spacing() {
    // 500 m × 500 m at 1 cm: 2.5 billion points, one 20 GB allocation.
    let err = parse_room(&room(500.0, 0.01, None), Path::new("hall.toml")).unwrap_err();
    let s = err.to_string();
    assert!(
        s.contains("work_plane.spacing_m") && s.contains(&MAX_WORK_PLANE_POINTS.to_string()),
        "{s}"
    );
    // The largest hall at 0.5 m, and an office at 1 cm, are fine.
    parse_room(&room(500.0, 0.5, None), Path::new("hall.toml")).unwrap();
    parse_room(&room(10.0, 0.01, None), Path::new("office.toml")).unwrap();
}

#[test]
fn a_room_file_larger_than_its_limit_is_refused_unread() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("huge.toml");
    std::fs::File::create(&path)
        .unwrap()
        .set_len(MAX_ROOM_FILE_BYTES + 1)
        .unwrap();
    match load_room(&path) {
        Err(e @ RoomFileError::Read(_)) => {
            let s = e.to_string();
            assert!(
                s.contains("huge.toml") && s.contains("larger than 16 MiB"),
                "{s}"
            );
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn room_objs_that_are_too_large_or_crash_the_parser_fail_clearly() {
    let dir = tempfile::tempdir().unwrap();
    let load = |obj: &str| {
        let r = parse_room(&room(10.0, 0.25, Some(obj)), Path::new("room.toml")).unwrap();
        load_room_mesh(&r, dir.path()).unwrap_err().to_string()
    };
    std::fs::File::create(dir.path().join("huge.obj"))
        .unwrap()
        .set_len(MAX_OBJ_FILE_BYTES + 1)
        .unwrap();
    let err = load("huge.obj");
    assert!(err.contains("larger than 64 MiB"), "{err}");
    let triangle = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    std::fs::write(dir.path().join("m.mtl"), "newmtl oak\nKd 0.5 0.3\n").unwrap();
    std::fs::write(
        dir.path().join("mtl.obj"),
        format!("mtllib m.mtl\n{triangle}usemtl oak\nf 1 2 3\n"),
    )
    .unwrap();
    let err = load("mtl.obj");
    assert!(
        err.contains("m.mtl:2") && err.contains("3 numbers"),
        "{err}"
    );
    std::fs::write(
        dir.path().join("index.obj"),
        format!("{triangle}vn 0 0 1\nf 1//-5 2//1 3//1\n"),
    )
    .unwrap();
    let err = load("index.obj");
    assert!(err.contains("index.obj:5"), "{err}");
    // A missing file still names itself and why.
    let err = load("nowhere.obj");
    assert!(
        err.contains("nowhere.obj") && err.contains("No such file"),
        "{err}"
    );
}
