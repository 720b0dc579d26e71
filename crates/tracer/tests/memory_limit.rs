#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! `/dev/zero` as an emission profile is refused within a 1 GiB address
//! space: a runaway read fails there (and aborts the child process this
//! test runs in) instead of being left to the OOM killer.

#![cfg(target_os = "linux")]

use std::path::Path;
use std::process::Command;

use lucerna_scene::{parse_scene, tessellate};
use lucerna_tracer::PreparedScene;

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

#[test]
fn an_endless_emission_profile_is_refused_within_1_gib() {
    if !in_limited_child("an_endless_emission_profile_is_refused_within_1_gib") {
        return;
    }
    let text = "format_version = 1\nname = \"led\"\n\n[[emitter]]\nname = \"LED\"\nflux_lm = 100.0\n\
                shape = { type = \"disk\", radius = 0.002 }\nemission = { profile = \"/dev/zero\" }\n";
    let scene = parse_scene(text, Path::new("led.toml")).unwrap();
    let t = tessellate(&scene, Path::new("/")).unwrap();
    let e = PreparedScene::new(&scene, &t, Path::new("/"))
        .err()
        .unwrap();
    let cause = std::error::Error::source(&e).unwrap().to_string();
    assert!(cause.contains("larger than"), "{e}: {cause}");
}
