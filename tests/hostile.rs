#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! The hand-made hostile inputs of the hostile-input issue through the
//! `lucerna` binary, each under a 1 GiB address-space limit and a 60 s
//! watchdog: a clear error (or a result), never a panic, an abort on a
//! failed allocation, a timeout, or NaN/inf printed as a figure.

mod common;

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::assets;

/// Runs `lucerna ARGS` under `ulimit -v` 1 GiB; returns (exit code, stdout,
/// stderr). A signal (abort, kill) or a run past 60 s fails the test.
fn limited(args: &[&str]) -> (i32, String, String) {
    let mut script = String::from("ulimit -v 1048576 && exec \"$0\"");
    for i in 1..=args.len() {
        script.push_str(&format!(" \"${i}\""));
    }
    let mut child = Command::new("sh")
        .arg("-c")
        .arg(&script)
        .arg(env!("CARGO_BIN_EXE_lucerna"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("sh runs");
    let start = Instant::now();
    loop {
        if child.try_wait().expect("waits").is_some() {
            break;
        }
        if start.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            panic!("lucerna {args:?} ran past 60 s");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let out = child.wait_with_output().expect("output");
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    );
    let Some(code) = out.status.code() else {
        panic!("lucerna {args:?} died by a signal (out of memory?): {stderr}");
    };
    assert!(
        !stderr.contains("panicked"),
        "lucerna {args:?} panicked: {stderr}"
    );
    (code, stdout, stderr)
}

/// Refused with exit code 1 and `expected` in the message.
fn refused(args: &[&str], expected: &str) {
    let (code, _, stderr) = limited(args);
    assert_eq!(code, 1, "lucerna {args:?}: {stderr}");
    assert!(stderr.contains(expected), "lucerna {args:?}: {stderr}");
}

fn write(dir: &Path, name: &str, text: &str) -> String {
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    path.to_str().unwrap().to_owned()
}

#[test]
fn the_limit_is_really_on() {
    // A bake needs far less than 1 GiB; sh's ulimit applies to lucerna.
    let out = Command::new("sh")
        .args(["-c", "ulimit -v 1048576 && ulimit -v"])
        .output()
        .unwrap();
    assert_eq!(String::from_utf8_lossy(&out.stdout).trim(), "1048576");
}

#[test]
fn endless_files_are_read_to_a_bound() {
    if !Path::new("/dev/zero").exists() {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    refused(&["info", "/dev/zero"], "larger than");
    let out = dir.path().join("x.ies");
    refused(
        &["convert", "/dev/zero", out.to_str().unwrap()],
        "larger than",
    );
    assert!(!out.exists(), "nothing written");
    let scene = write(
        dir.path(),
        "zero_mesh.toml",
        "format_version = 1\nname = \"z\"\n[materials.m]\ntype = \"absorber\"\n[[emitter]]\nname = \"e\"\nflux_lm = 1.0\nshape = { type = \"disk\", radius = 0.001 }\n[[part]]\nname = \"p\"\nmaterial = \"m\"\nshape = { type = \"mesh\", path = \"/dev/zero\" }\n",
    );
    refused(&["validate", &scene], "larger than");
}

#[test]
fn absurd_sizes_are_refused_before_they_are_allocated() {
    let dir = tempfile::tempdir().unwrap();
    let scene = write(
        dir.path(),
        "huge.toml",
        "format_version = 1\nname = \"h\"\n[materials.m]\ntype = \"mirror\"\nreflectance = 0.9\n[[emitter]]\nname = \"e\"\nflux_lm = 1.0\nshape = { type = \"disk\", radius = 0.001 }\n[[part]]\nname = \"p\"\nmaterial = \"m\"\nshape = { type = \"paraboloid\", focal_length = 0.025, aperture_diameter = 0.1, segments_around = 4096, segments_along = 4096 }\n",
    );
    refused(&["validate", &scene], "triangles");
    let spot = assets().join("luminaires/parabolic_spot.toml");
    for flag in ["--gamma-step", "--c-step"] {
        refused(
            &[
                "bake",
                spot.to_str().unwrap(),
                flag,
                "1e-9",
                "--out",
                dir.path().to_str().unwrap(),
            ],
            flag,
        );
    }
    let office = std::fs::read_to_string(assets().join("rooms/office.toml")).unwrap();
    let huge_room = office
        .replace("width_m = 6.0", "width_m = 500.0")
        .replace("depth_m = 4.8", "depth_m = 500.0")
        .replace("spacing_m = 0.25", "spacing_m = 0.01")
        .replace(
            "../profiles/",
            &format!("{}/", assets().join("profiles").display()),
        );
    let room = write(dir.path(), "huge_room.toml", &huge_room);
    let png = dir.path().join("room.png");
    refused(
        &[
            "render",
            &room,
            "--out",
            png.to_str().unwrap(),
            "--size",
            "64x36",
        ],
        "work_plane",
    );
    assert!(!png.exists(), "nothing written");
}

#[test]
fn figures_are_numbers_or_the_file_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let zero_and_denormal = write(
        dir.path(),
        "gamma.ies",
        "IESNA:LM-63-2002\r\nTILT=NONE\r\n1 1000 1 3 1 1 2 0.1 0.1 0\r\n1 1 0\r\n0 5e-324 90\r\n0\r\n100 100 100\r\n",
    );
    refused(&["info", &zero_and_denormal], "0.0001");
    let samples = assets().join("profiles/samples");
    for entry in std::fs::read_dir(samples).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "ies" || e == "ldt") {
            let (code, stdout, stderr) = limited(&["info", path.to_str().unwrap()]);
            assert_eq!(code, 0, "{stderr}");
            for bad in ["NaN", " inf", "-inf"] {
                assert!(!stdout.contains(bad), "{}: {stdout}", path.display());
            }
        }
    }
}
