//! For tests in any crate that refuse hostile input within a bounded
//! address space: a runaway allocation must fail there (aborting the child
//! process) rather than be left to the OOM killer. Behind the
//! `test-support` feature; Linux only.

#![cfg(target_os = "linux")]
#![allow(clippy::panic, clippy::expect_used)] // reason: a test harness whose failures are the point

use std::process::Command;

/// Set in the child process that runs the inputs under the limit.
const CHILD: &str = "LUCERNA_UNDER_ADDRESS_SPACE_LIMIT";
const LIMIT_BYTES: u64 = 1 << 30;

/// Runs test `name` of the calling test binary again in a child process
/// limited to [`LIMIT_BYTES`] of address space; true in that child.
pub fn in_address_limited_child(name: &str) -> bool {
    if std::env::var_os(CHILD).is_some() {
        let limits = std::fs::read_to_string("/proc/self/limits").expect("/proc/self/limits reads");
        let line = limits
            .lines()
            .find(|l| l.starts_with("Max address space"))
            .expect("an address-space line");
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
        .arg(std::env::current_exe().expect("the limited child runs"))
        .args([name, "--exact", "--test-threads=1", "--nocapture"])
        .env(CHILD, "1")
        // One malloc arena: each reserves 64 MiB of address space.
        .env("MALLOC_ARENA_MAX", "1")
        .env("RAYON_NUM_THREADS", "2")
        .output()
        .expect("the limited child runs");
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

/// A small valid scene (one LED under a mirror paraboloid) for tests to
/// break one field of at a time.
pub const SMALL_SCENE: &str = r#"format_version = 1
name = "test"

[materials.alu]
type = "mirror"
reflectance = 0.9

[[emitter]]
name = "LED"
flux_lm = 100.0
shape = { type = "disk", radius = 0.002 }

[[part]]
name = "reflector"
material = "alu"
shape = { type = "paraboloid", focal_length = 0.02, aperture_diameter = 0.08 }
"#;

/// An error and its sources on one line, `: `-separated, for matching.
pub fn error_chain(e: &dyn std::error::Error) -> String {
    let mut s = e.to_string();
    let mut source = e.source();
    while let Some(cause) = source {
        s = format!("{s}: {cause}");
        source = cause.source();
    }
    s
}
