#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! End-to-end: `lucerna design` writes the designed scene (which
//! validates and keeps the start file's comments), its IES and LDT,
//! design.csv and design.png, all of them; bad input gets a clear error
//! and nothing is written.

mod common;
use common::{assets, lucerna, text};

#[test]
fn a_design_writes_every_file_and_a_bad_one_writes_none() {
    let dir = tempfile::tempdir().unwrap();
    let scene = assets().join("luminaires/parabolic_spot.toml");
    let target = dir.path().join("target");
    // A target: the spot itself, baked.
    let out = lucerna(&[
        "bake",
        scene.to_str().unwrap(),
        "--photons",
        "400000",
        "--resolution",
        "64",
        "--formats",
        "ies",
        "--out",
        target.to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let ies = target.join("parabolic_spot.ies");
    let designed = dir.path().join("designed");
    let out = lucerna(&[
        "design",
        scene.to_str().unwrap(),
        "--target",
        ies.to_str().unwrap(),
        "--vary",
        "reflector.focal_length",
        "--evaluations",
        "6",
        "--resolution",
        "64",
        "--photons",
        "200000",
        "--date",
        "2026-12-04",
        "--out",
        designed.to_str().unwrap(),
    ]);
    let stdout = text(&out.stdout);
    assert!(out.status.success(), "{}\n{stdout}", text(&out.stderr));
    assert!(
        stdout.contains("remaining difference (relative L2 on the sphere"),
        "{stdout}"
    );
    for name in [
        "parabolic_spot.toml",
        "parabolic_spot.ies",
        "parabolic_spot.ldt",
        "design.csv",
        "design.png",
    ] {
        assert!(designed.join(name).is_file(), "{name} missing");
    }
    let toml = std::fs::read_to_string(designed.join("parabolic_spot.toml")).unwrap();
    assert!(toml.starts_with("# A parabolic spot"), "{toml}");
    let csv = std::fs::read_to_string(designed.join("design.csv")).unwrap();
    assert!(
        csv.starts_with(
            "evaluation,elapsed_s,photons,merit,measure,phase,reflector.focal_length\n"
        ),
        "{csv}"
    );
    assert!(csv.lines().count() >= 7, "{csv}");
    let out = lucerna(&[
        "validate",
        designed.join("parabolic_spot.toml").to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));

    // Bad input: a clear error, nothing written.
    for (vary, says) in [
        (
            "reflector.segments_around",
            "is a count, not a continuous parameter",
        ),
        ("lamp.focal_length", "has no part 'lamp'"),
        ("reflector.profile", "which has no profile"),
    ] {
        let none = dir.path().join(format!("none-{vary}"));
        let out = lucerna(&[
            "design",
            scene.to_str().unwrap(),
            "--target",
            ies.to_str().unwrap(),
            "--vary",
            vary,
            "--out",
            none.to_str().unwrap(),
        ]);
        assert!(!out.status.success());
        assert!(text(&out.stderr).contains(says), "{}", text(&out.stderr));
        assert!(!none.exists());
    }
    let none = dir.path().join("none-time");
    let out = lucerna(&[
        "design",
        scene.to_str().unwrap(),
        "--target",
        ies.to_str().unwrap(),
        "--vary",
        "reflector.focal_length",
        "--time",
        "0s",
        "--out",
        none.to_str().unwrap(),
    ]);
    assert!(!out.status.success());
    assert!(
        text(&out.stderr).contains("is not a positive duration"),
        "{}",
        text(&out.stderr)
    );
    assert!(!none.exists());
}
