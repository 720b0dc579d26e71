#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! The hostile room inputs of `hostile.rs`, and `/dev/zero` as the room
//! file and its OBJ, are refused within a 1 GiB address space: a runaway
//! allocation fails there (and aborts the child process this test runs
//! in) instead of being left to the OOM killer.

#![cfg(target_os = "linux")]

use std::path::Path;

use lucerna_room::model::{load_room, parse_room};
use lucerna_room::scene::load_room_mesh;
use lucerna_room::{RoomScene, Shading, work_plane_cpu};

use lucerna_scene::test_support::in_address_limited_child as in_limited_child;

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
fn hostile_room_inputs_are_refused_within_1_gib() {
    if !in_limited_child("hostile_room_inputs_are_refused_within_1_gib") {
        return;
    }
    let e = load_room(Path::new("/dev/zero")).unwrap_err();
    assert!(e.to_string().contains("larger than"), "{e}");
    let r = parse_room(&room(10.0, 0.25, Some("/dev/zero")), Path::new("room.toml")).unwrap();
    let e = load_room_mesh(&r, Path::new("/")).unwrap_err();
    assert!(e.to_string().contains("larger than"), "{e}");
    // 500 m × 500 m at 1 cm. Were it accepted, its work plane (here with
    // no lights) would ask for 20 GB.
    match parse_room(&room(500.0, 0.01, None), Path::new("hall.toml")) {
        Err(e) => assert!(e.to_string().contains("work_plane.spacing_m"), "{e}"),
        Ok(hall) => {
            let grid = work_plane_cpu(&RoomScene::new(&hall, &[]), Shading::PointLight);
            panic!("accepted, {} points", grid.lux.len());
        }
    }
}
