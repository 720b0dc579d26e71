#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! End-to-end: `lucerna tolerance` writes every file of its analysis; a
//! run split into parts and merged gives the same CSVs as one run; bad
//! input gets an error naming file, line and field, and nothing is
//! written.

mod common;
use std::path::Path;

use common::{assets, lucerna, text};

const TOLERANCES: &str = r#"# The LED's placement and the reflector's form error.
[[tolerance]]
at = "LED.translate_x"
normal = { sigma = 0.1e-3 }

[[tolerance]]
at = "LED.translate_z"
uniform = { half_width = 0.15e-3 }
truncate = 0.1e-3

[[form_error]]
part = "reflector"
sigma = 0.05e-3
correlation_length = 10e-3
"#;

const SPEC: &str = "beam_angle_deg = 3.2\nbeam_tolerance_deg = 1.0\ncutoff_gamma_deg = 3.0\ncutoff_max_fraction = 0.2\n";

fn run(args: &[&str]) -> (bool, String, String) {
    let out = lucerna(args);
    (out.status.success(), text(&out.stdout), text(&out.stderr))
}

fn common_args<'a>(scene: &'a str, spec: &'a str, tol: &'a str) -> Vec<&'a str> {
    vec![
        "tolerance",
        scene,
        "--spec",
        spec,
        "--tolerances",
        tol,
        "--samples",
        "7",
        "--photons",
        "20000",
        "--resolution",
        "64",
        "--noise-runs",
        "2",
    ]
}

fn files_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .map(|d| {
            d.flatten()
                .map(|e| e.file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    names.sort();
    names
}

#[test]
fn a_split_run_merges_to_the_same_files_as_one_run() {
    let dir = tempfile::tempdir().unwrap();
    let scene = assets().join("luminaires/parabolic_spot.toml");
    let scene = scene.to_str().unwrap();
    let spec = dir.path().join("spec.toml");
    std::fs::write(&spec, SPEC).unwrap();
    let tol = dir.path().join("tolerances.toml");
    std::fs::write(&tol, TOLERANCES).unwrap();
    let (spec, tol) = (spec.to_str().unwrap(), tol.to_str().unwrap());

    let one = dir.path().join("one");
    let mut args = common_args(scene, spec, tol);
    args.extend(["--out", one.to_str().unwrap()]);
    let (ok, stdout, stderr) = run(&args);
    assert!(ok, "{stderr}");
    assert!(stdout.contains("yield:"), "{stdout}");
    assert_eq!(
        files_in(&one),
        [
            "figures.csv",
            "histograms.png",
            "samples.csv",
            "sensitivities.csv",
            "sensitivities.png",
            "tolerance.json",
            "worst.toml",
            "yield.csv"
        ]
    );
    // The worst sample opens as a scene.
    let (ok, _, stderr) = run(&["validate", one.join("worst.toml").to_str().unwrap()]);
    assert!(ok, "{stderr}");

    let parts = dir.path().join("parts");
    for k in ["1/3", "2/3", "3/3"] {
        let mut args = common_args(scene, spec, tol);
        args.extend(["--part", k, "--out", parts.to_str().unwrap()]);
        let (ok, _, stderr) = run(&args);
        assert!(ok, "{stderr}");
    }
    let merged = dir.path().join("merged");
    let mut args = common_args(scene, spec, tol);
    args.extend([
        "--merge",
        parts.to_str().unwrap(),
        "--out",
        merged.to_str().unwrap(),
    ]);
    let (ok, _, stderr) = run(&args);
    assert!(ok, "{stderr}");
    for name in [
        "samples.csv",
        "figures.csv",
        "yield.csv",
        "sensitivities.csv",
        "worst.toml",
    ] {
        assert_eq!(
            std::fs::read(one.join(name)).unwrap(),
            std::fs::read(merged.join(name)).unwrap(),
            "{name}"
        );
    }
    let samples = std::fs::read_to_string(one.join("samples.csv")).unwrap();
    assert_eq!(samples.lines().count(), 8, "{samples}");

    // A missing part is named, and nothing is written.
    std::fs::remove_file(parts.join("tolerance.part-2-of-3.json")).unwrap();
    let lost = dir.path().join("lost");
    let mut args = common_args(scene, spec, tol);
    args.extend([
        "--merge",
        parts.to_str().unwrap(),
        "--out",
        lost.to_str().unwrap(),
    ]);
    let (ok, _, stderr) = run(&args);
    assert!(!ok);
    assert!(stderr.contains("parts 2 of 3 are missing"), "{stderr}");
    assert!(!lost.exists());
}

#[test]
fn bad_input_names_the_file_line_and_field_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let scene = assets().join("luminaires/parabolic_spot.toml");
    let scene = scene.to_str().unwrap();
    let spec = dir.path().join("spec.toml");
    std::fs::write(&spec, SPEC).unwrap();
    let out = dir.path().join("out");
    let cases: [(&str, &str, &str); 5] = [
        (
            "[[tolerance]]\nat = \"lens.translate_x\"\nnormal = { sigma = 1e-4 }\n",
            "tol.toml:2: tolerance[0].at",
            "no part or emitter 'lens'",
        ),
        (
            "[[tolerance]]\nat = \"reflector.focal_lenght\"\nnormal = { sigma = 1e-4 }\n",
            "tol.toml:2: tolerance[0].at",
            "focal_length",
        ),
        (
            "[[tolerance]]\nat = \"LED.translate_x\"\nnormal = { sigma = -1e-4 }\n",
            "tol.toml:3: tolerance[0].normal.sigma",
            "positive",
        ),
        (
            "[[tolerance]]\nat = \"LED.translate_x\"\nnormal = { sigma = 1e-4 }\ntruncate = -0.5e-4\n",
            "tol.toml:4: tolerance[0].truncate",
            "positive",
        ),
        (
            "\n[[form_error]]\npart = \"reflector\"\nsigma = nan\ncorrelation_length = 0.01\n",
            "tol.toml:4: form_error[0].sigma",
            "positive",
        ),
    ];
    for (tol_text, place, why) in cases {
        let tol = dir.path().join("tol.toml");
        std::fs::write(&tol, tol_text).unwrap();
        let mut args = common_args(scene, spec.to_str().unwrap(), tol.to_str().unwrap());
        args.extend(["--out", out.to_str().unwrap()]);
        let (ok, _, stderr) = run(&args);
        assert!(!ok, "{tol_text}");
        assert!(
            stderr.contains(place) && stderr.contains(why),
            "{tol_text}: {stderr}"
        );
        assert!(!out.exists());
    }
    // A spec with no term.
    let empty = dir.path().join("empty.toml");
    std::fs::write(&empty, "beam_tolerance_deg = 2.0\n").unwrap();
    let tol = dir.path().join("tol.toml");
    std::fs::write(&tol, TOLERANCES).unwrap();
    let mut args = common_args(scene, empty.to_str().unwrap(), tol.to_str().unwrap());
    args.extend(["--out", out.to_str().unwrap()]);
    let (ok, _, stderr) = run(&args);
    assert!(!ok);
    assert!(
        stderr.contains("empty.toml") && stderr.contains("no term"),
        "{stderr}"
    );
    assert!(!out.exists());
}

#[test]
fn a_perturbation_that_cannot_be_built_is_a_failed_sample_not_a_crash() {
    // An LED moved 24.5 mm up along the axis sits half a millimetre under
    // the reflector's vertex: through it.
    let dir = tempfile::tempdir().unwrap();
    let scene = assets().join("luminaires/parabolic_spot.toml");
    let spec = dir.path().join("spec.toml");
    std::fs::write(&spec, SPEC).unwrap();
    let tol = dir.path().join("tol.toml");
    std::fs::write(
        &tol,
        "[[tolerance]]\nat = \"LED.translate_z\"\nnormal = { sigma = 1e-6 }\noffset = 0.0245\n",
    )
    .unwrap();
    let out = dir.path().join("out");
    let mut args = common_args(
        scene.to_str().unwrap(),
        spec.to_str().unwrap(),
        tol.to_str().unwrap(),
    );
    args.extend(["--out", out.to_str().unwrap()]);
    let (ok, stdout, stderr) = run(&args);
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("could not be built and count as failed")
            && stdout.contains("passes through emitter 'LED'"),
        "{stdout}"
    );
    let samples = std::fs::read_to_string(out.join("samples.csv")).unwrap();
    assert!(samples.contains("refused"), "{samples}");
}

#[test]
fn ctrl_c_writes_the_samples_done() {
    let dir = tempfile::tempdir().unwrap();
    let scene = assets().join("luminaires/parabolic_spot.toml");
    let spec = dir.path().join("spec.toml");
    std::fs::write(&spec, SPEC).unwrap();
    let tol = dir.path().join("tol.toml");
    std::fs::write(&tol, TOLERANCES).unwrap();
    let out = dir.path().join("out");
    let child = std::process::Command::new(env!("CARGO_BIN_EXE_lucerna"))
        .args([
            "tolerance",
            scene.to_str().unwrap(),
            "--spec",
            spec.to_str().unwrap(),
            "--tolerances",
            tol.to_str().unwrap(),
            "--samples",
            "100000",
            "--photons",
            "20000",
            "--resolution",
            "64",
            "--noise-runs",
            "2",
            "--out",
            out.to_str().unwrap(),
        ])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_secs(4));
    let sent = std::process::Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(sent.success());
    let done = child.wait_with_output().unwrap();
    let (stdout, stderr) = (text(&done.stdout), text(&done.stderr));
    assert!(done.status.success(), "{stderr}");
    assert!(stderr.contains("interrupted: writing the"), "{stderr}");
    let samples = std::fs::read_to_string(out.join("samples.csv")).unwrap();
    let rows = samples.lines().count() - 1;
    assert!(rows > 0 && rows < 100_000, "{rows} samples");
    assert!(
        stdout.contains(&format!("of {rows} built luminaires")),
        "{stdout}"
    );
}
