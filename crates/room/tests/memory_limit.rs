#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! The hostile room inputs of `hostile.rs`, and `/dev/zero` as the room
//! file and its OBJ, are refused within a 1 GiB address space: a runaway
//! allocation fails there (and aborts the child process this test runs
//! in) instead of being left to the OOM killer.

#![cfg(target_os = "linux")]

use std::path::Path;
use std::process::Command;

use lucerna_room::model::{load_room, parse_room};
use lucerna_room::scene::load_room_mesh;
use lucerna_room::{RoomScene, Shading, work_plane_cpu};

/// Set in the child process that runs the inputs under the limit.
const CHILD: &str = "LUCERNA_UNDER_ADDRESS_SPACE_LIMIT";
const LIMIT_BYTES: u64 = 1 << 30;

/// Runs test `name` of this binary again in a child process limited to
/// [`LIMIT_BYTES`] of address space; true in that child.
fn in_limited_child(name: &str) -> bool {
    if std::env::var_os(CHILD).is_some() {
        let limits = std::fs::read_to_string("/proc/self/limits").unwrap();
        let line = limits
            .lines()
            .find(|l| l.starts_with("Max address space"))
            .unwrap();
        assert!(
            line.contains(&LIMIT_BYTES.to_string()),
            "not limited: {line}"
        );
        return true;
    }
    let output = Command::new("sh")
        .arg("-c")
        .arg(format!(
            "ulimit -v {} && exec \"$0\" \"$@\"",
            LIMIT_BYTES >> 10
        ))
        .arg(std::env::current_exe().unwrap())
        .args([name, "--exact", "--test-threads=1", "--nocapture"])
        .env(CHILD, "1")
        // One malloc arena: each reserves 64 MiB of address space.
        .env("MALLOC_ARENA_MAX", "1")
        .env("RAYON_NUM_THREADS", "2")
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        output.status.success() && stdout.contains("1 passed"),
        "under a {} MiB address space: {}\n{stdout}\n{}",
        LIMIT_BYTES >> 20,
        output.status,
        String::from_utf8_lossy(&output.stderr)
    );
    false
}

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
