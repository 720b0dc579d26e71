#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! End-to-end: the `lucerna` binary on the bundled examples and samples,
//! and on broken input.

use std::path::Path;
use std::process::Command;

mod common;
use common::{assets, bake_on_cpu, lucerna, text};

#[test]
fn validate_accepts_every_example() {
    let dir = assets().join("luminaires");
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let out = lucerna(&["validate", path.to_str().unwrap(), "--json"]);
        assert!(
            out.status.success(),
            "{}: {}",
            path.display(),
            text(&out.stderr)
        );
        let report: serde_json::Value = serde_json::from_slice(&out.stdout).expect("JSON report");
        assert!(report["triangles"].as_u64().unwrap() > 0);
    }
}

#[test]
fn validate_names_file_line_and_field_of_a_broken_scene() {
    let dir = tempfile::tempdir().unwrap();
    let good = std::fs::read_to_string(assets().join("luminaires/parabolic_spot.toml")).unwrap();
    let broken = good.replace("reflectance = 0.9", "reflectance = 1.9");
    let path = dir.path().join("broken.toml");
    std::fs::write(&path, &broken).unwrap();
    let out = lucerna(&["validate", path.to_str().unwrap()]);
    assert!(!out.status.success());
    let err = text(&out.stderr);
    let line = broken.lines().position(|l| l.contains("1.9")).unwrap() + 1;
    assert!(err.contains("broken.toml"), "{err}");
    assert!(err.contains(&format!("line {line}")), "{err}");
    assert!(err.contains("materials.polished_alu.reflectance"), "{err}");
}

#[test]
fn validate_reports_a_missing_obj() {
    let dir = tempfile::tempdir().unwrap();
    let scene = std::fs::read_to_string(assets().join("luminaires/obj_cone.toml")).unwrap();
    let path = dir.path().join("moved.toml");
    std::fs::write(&path, scene).unwrap();
    let out = lucerna(&["validate", path.to_str().unwrap()]);
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert!(
        err.contains("cone_reflector.obj") && err.contains("reflector"),
        "{err}"
    );
}

#[test]
fn info_reports_flux_and_peak_of_every_sample() {
    for entry in std::fs::read_dir(assets().join("profiles/samples")).unwrap() {
        let path = entry.unwrap().path();
        if path.extension().is_some_and(|e| e == "md") {
            continue;
        }
        let out = lucerna(&["info", path.to_str().unwrap(), "--json"]);
        assert!(
            out.status.success(),
            "{}: {}",
            path.display(),
            text(&out.stderr)
        );
        let r: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
        assert!(r["figures"]["flux_lm"].as_f64().unwrap() > 0.0);
        assert!(r["figures"]["peak_cd"].as_f64().unwrap() > 0.0);
    }
}

fn figures(path: &Path) -> (f64, f64) {
    let out = lucerna(&["info", path.to_str().unwrap(), "--json"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let r: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    (
        r["figures"]["flux_lm"].as_f64().unwrap(),
        r["figures"]["peak_cd"].as_f64().unwrap(),
    )
}

#[test]
fn convert_round_trips_keep_flux_and_peak_within_one_percent() {
    let dir = tempfile::tempdir().unwrap();
    for name in [
        "rab_indoor3_2002_full360.ies",
        "avad_srl_isym4.ldt",
        "bega_50975_1995_single_h.ies",
    ] {
        let input = assets().join("profiles/samples").join(name);
        let ldt = dir.path().join("a.ldt");
        let ies = dir.path().join("b.ies");
        let ies2002 = dir.path().join("c.ies");
        for (from, to, extra) in [
            (&input, &ldt, None),
            (&ldt, &ies, None),
            (&ies, &ies2002, Some("ies2002")),
        ] {
            let mut args = vec!["convert", from.to_str().unwrap(), to.to_str().unwrap()];
            if let Some(e) = extra {
                args.extend(["--to", e]);
            }
            let out = lucerna(&args);
            assert!(out.status.success(), "{name}: {}", text(&out.stderr));
        }
        assert!(
            std::fs::read_to_string(&ies)
                .unwrap()
                .starts_with("IES:LM-63-2019")
        );
        assert!(
            std::fs::read_to_string(&ies2002)
                .unwrap()
                .starts_with("IESNA:LM-63-2002")
        );
        let (f0, p0) = figures(&input);
        for out in [&ldt, &ies, &ies2002] {
            let (f, p) = figures(out);
            assert!(
                (f - f0).abs() < 0.01 * f0 && (p - p0).abs() < 0.01 * p0,
                "{name} -> {}: {f} lm {p} cd vs {f0} lm {p0} cd",
                out.display()
            );
        }
    }
}

#[test]
fn convert_of_a_bad_file_fails_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let bad = dir.path().join("bad.ies");
    std::fs::write(
        &bad,
        "IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 3 1 1 2 0 0 0\n1 1 1\n0 45\n",
    )
    .unwrap();
    let out_path = dir.path().join("out.ldt");
    let out = lucerna(&["convert", bad.to_str().unwrap(), out_path.to_str().unwrap()]);
    assert!(!out.status.success());
    assert!(
        text(&out.stderr).contains("IES line"),
        "{}",
        text(&out.stderr)
    );
    assert!(!out_path.exists());
    // An unknown extension is refused before anything is written.
    let good = assets().join("profiles/samples/avad_srl_isym4.ldt");
    let odd = dir.path().join("out.xyz");
    let out = lucerna(&["convert", good.to_str().unwrap(), odd.to_str().unwrap()]);
    assert!(!out.status.success() && !odd.exists());
}

#[test]
fn bake_writes_every_output_and_the_files_read_back() {
    let dir = tempfile::tempdir().unwrap();
    let scene = assets().join("luminaires/parabolic_spot.toml");
    let out = bake_on_cpu(&scene, 200_000, 64, dir.path(), &[]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    for name in [
        "parabolic_spot.ies",
        "parabolic_spot.ldt",
        "parabolic_spot.exr",
        "parabolic_spot_cube.png",
        "parabolic_spot_polar.png",
    ] {
        let path = dir.path().join(name);
        assert!(
            std::fs::metadata(&path)
                .map(|m| m.len() > 100)
                .unwrap_or(false),
            "{name} missing or empty"
        );
    }
    let ies = std::fs::read_to_string(dir.path().join("parabolic_spot.ies")).unwrap();
    assert!(ies.starts_with("IES:LM-63-2019"));
    assert!(ies.contains("[FILEGENINFO]") && ies.contains("200000 photons"));
    assert!(
        ies.lines().any(|l| l.ends_with(" 1.00010 0")),
        "file-generation type: computer simulation"
    );
    // Mirror R = 0.9, one bounce: 90 % of 800 lm leaves, within noise.
    for file in ["parabolic_spot.ies", "parabolic_spot.ldt"] {
        let (flux, peak) = figures(&dir.path().join(file));
        assert!((flux - 720.0).abs() < 0.02 * 720.0, "{file}: {flux} lm");
        assert!(
            peak > 50_000.0,
            "{file}: a spot has a high peak, got {peak} cd"
        );
    }
}

#[test]
fn bake_is_deterministic_for_a_seed() {
    let dir = tempfile::tempdir().unwrap();
    let scene = assets().join("luminaires/opal_bell.toml");
    let bake = |sub: &str, seed: &str| {
        let out_dir = dir.path().join(sub);
        let out = lucerna(&[
            "bake",
            scene.to_str().unwrap(),
            "--photons",
            "50000",
            "--resolution",
            "32",
            "--seed",
            seed,
            "--out",
            out_dir.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{}", text(&out.stderr));
        std::fs::read_to_string(out_dir.join("opal_bell.ldt")).unwrap()
    };
    // The date is in the file; compare the intensity lines only.
    let tail = |s: String| s.lines().skip(60).collect::<Vec<_>>().join("\n");
    assert_eq!(tail(bake("a", "3")), tail(bake("b", "3")));
    assert_ne!(tail(bake("c", "3")), tail(bake("d", "4")));
}

#[test]
fn bake_refuses_absurd_parameters_clearly() {
    let dir = tempfile::tempdir().unwrap();
    let scene = assets().join("luminaires/opal_bell.toml");
    for (flag, value, expected) in [
        ("--resolution", "100000", "--resolution"),
        ("--photons", "0", "--photons"),
        ("--time", "3 fortnights", "unit"),
        ("--rel-error", "5", "--rel-error"),
        ("--c-step", "7", "--c-step"),
    ] {
        let out = lucerna(&[
            "bake",
            scene.to_str().unwrap(),
            flag,
            value,
            "--out",
            dir.path().to_str().unwrap(),
        ]);
        assert!(!out.status.success(), "{flag} {value} accepted");
        assert!(
            text(&out.stderr).contains(expected),
            "{flag} {value}: {}",
            text(&out.stderr)
        );
    }
}

#[test]
fn bench_measures_every_example_on_the_cpu() {
    let out = lucerna(&["bench", "--photons", "20000", "--cpu-only"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let report = text(&out.stdout);
    for name in [
        "faceted_downlight",
        "parabolic_spot",
        "opal_bell",
        "linear_louvre",
    ] {
        let line = report
            .lines()
            .find(|l| l.starts_with(name))
            .unwrap_or_else(|| panic!("{name} missing:\n{report}"));
        let rate: f64 = line
            .split_whitespace()
            .rev()
            .nth(2)
            .unwrap()
            .parse()
            .unwrap();
        assert!(rate > 0.0, "{line}");
    }
}

#[test]
fn ctrl_c_stops_a_bake_cleanly_and_still_writes() {
    let dir = tempfile::tempdir().unwrap();
    let scene = assets().join("luminaires/opal_bell.toml");
    let child = Command::new(env!("CARGO_BIN_EXE_lucerna"))
        .args([
            "bake",
            scene.to_str().unwrap(),
            "--time",
            "120s",
            "--resolution",
            "32",
            "--backend",
            "cpu",
            "--out",
            dir.path().to_str().unwrap(),
        ])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // The Ctrl+C handler is in place once the bake says what it traces on.
    let mut child = child;
    let mut stderr = std::io::BufReader::new(child.stderr.take().unwrap());
    let mut line = String::new();
    while std::io::BufRead::read_line(&mut stderr, &mut line).unwrap() > 0
        && !line.contains("tracing on")
    {
        line.clear();
    }
    assert!(
        line.contains("tracing on"),
        "the bake never started tracing"
    );
    std::thread::sleep(std::time::Duration::from_millis(300));
    let status = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    // Keep draining stderr so the progress bar never blocks on a full pipe.
    std::thread::spawn(move || std::io::copy(&mut stderr, &mut std::io::sink()));
    let start = std::time::Instant::now();
    let out = child.wait_with_output().unwrap();
    assert!(
        start.elapsed().as_secs() < 30,
        "the bake did not stop promptly"
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(
        text(&out.stdout).contains("interrupted"),
        "{}",
        text(&out.stdout)
    );
    let (flux, _) = figures(&dir.path().join("opal_bell.ies"));
    assert!(flux > 0.0);
}

#[test]
fn bake_can_export_the_filtered_map() {
    let dir = tempfile::tempdir().unwrap();
    let scene = assets().join("luminaires/opal_bell.toml");
    let raw_dir = dir.path().join("raw");
    let filtered_dir = dir.path().join("filtered");
    for (out_dir, filter) in [(&raw_dir, "none"), (&filtered_dir, "auto")] {
        let out = bake_on_cpu(&scene, 200_000, 64, out_dir, &["--filter", filter]);
        assert!(out.status.success(), "{}", text(&out.stderr));
    }
    let (raw_flux, _) = figures(&raw_dir.join("opal_bell.ies"));
    let (filtered_flux, _) = figures(&filtered_dir.join("opal_bell.ies"));
    assert!(
        (filtered_flux - raw_flux).abs() < 0.01 * raw_flux,
        "{filtered_flux} vs {raw_flux}"
    );
    assert_ne!(
        std::fs::read(raw_dir.join("opal_bell.ldt")).unwrap(),
        std::fs::read(filtered_dir.join("opal_bell.ldt")).unwrap()
    );
    let out = lucerna(&[
        "bake",
        scene.to_str().unwrap(),
        "--filter",
        "lots",
        "--out",
        dir.path().to_str().unwrap(),
    ]);
    assert!(!out.status.success());
}

#[test]
fn bake_pools_photons_over_the_luminaires_symmetry() {
    // The faceted downlight has all eight symmetries: with `--symmetry
    // auto` the exported table is the same in C-planes a quarter turn or a
    // mirror apart; with `none` they differ by the photon noise.
    let dir = tempfile::tempdir().unwrap();
    let scene = assets().join("luminaires/faceted_downlight.toml");
    let mut tables = Vec::new();
    for choice in ["auto", "none"] {
        let out_dir = dir.path().join(choice);
        let out = bake_on_cpu(&scene, 200_000, 64, &out_dir, &["--symmetry", choice]);
        assert!(out.status.success(), "{}", text(&out.stderr));
        let said = text(&out.stderr).contains("symmetry: quarter turns and four mirror planes");
        assert_eq!(said, choice == "auto", "{}", text(&out.stderr));
        // The files declare the symmetry they were pooled over.
        for file in ["faceted_downlight.ies", "faceted_downlight.ldt"] {
            let bytes = std::fs::read(out_dir.join(file)).unwrap();
            let declared = lucerna_photometry::read_photometry(&bytes)
                .unwrap()
                .symmetry;
            let expected = if choice == "auto" {
                lucerna_photometry::CPlaneSymmetry::Quadrant
            } else {
                lucerna_photometry::CPlaneSymmetry::None
            };
            assert_eq!(declared, expected, "{choice} {file}");
        }
        let bytes = std::fs::read(out_dir.join("faceted_downlight.ies")).unwrap();
        tables.push(lucerna_photometry::read_photometry(&bytes).unwrap().table);
    }
    // RMS difference between I(C, γ) and I at the image of C, relative to
    // the mean intensity, over the lit hemisphere.
    let asymmetry = |table: &lucerna_photometry::CandelaTable, image: fn(f64) -> f64| {
        let g = table.gammas_deg.len();
        let at = |c: f64| {
            let c = c.rem_euclid(360.0);
            table
                .c_planes_deg
                .iter()
                .position(|&x| (x - c).abs() < 1e-6)
        };
        let (mut sum, mut sq, mut n) = (0.0, 0.0, 0);
        for (i, &c) in table.c_planes_deg.iter().enumerate() {
            let Some(j) = at(image(c)) else { continue };
            for k in 0..g {
                if table.gammas_deg[k] > 60.0 {
                    continue;
                }
                let (a, b) = (table.candela[i * g + k], table.candela[j * g + k]);
                sum += a;
                sq += (a - b).powi(2);
                n += 1;
            }
        }
        (sq / n as f64).sqrt() / (sum / n as f64)
    };
    type Image = fn(f64) -> f64;
    let images: [(&str, Image); 3] = [
        ("quarter turn", |c| c + 90.0),
        ("mirror in C0-C180", |c| 360.0 - c),
        ("mirror in C45-C225", |c| 90.0 - c),
    ];
    for (name, image) in images {
        let (pooled, traced) = (asymmetry(&tables[0], image), asymmetry(&tables[1], image));
        eprintln!("{name}: asymmetry {pooled:.5} pooled, {traced:.5} as traced");
        assert!(pooled < 0.1 * traced, "{name}: {pooled} vs {traced}");
    }
    let flux = |t: &lucerna_photometry::CandelaTable| t.flux_lm();
    assert!((flux(&tables[0]) / flux(&tables[1]) - 1.0).abs() < 0.01);
}

#[test]
fn convert_warns_of_unequal_c_steps_in_an_ldt_and_resamples_on_request() {
    let dir = tempfile::tempdir().unwrap();
    let input = dir.path().join("unequal.ies");
    let mut lines = vec![
        "IESNA:LM-63-2002",
        "[TEST] unequal C steps",
        "TILT=NONE",
        "1 1000 1 3 5 1 2 0.1 0.1 0",
        "1 1 0",
        "0 45 90",
        "0 10 30 90 360",
    ];
    lines.extend(std::iter::repeat_n("100 80 10", 5));
    std::fs::write(&input, lines.join("\r\n") + "\r\n").unwrap();
    let plain = dir.path().join("plain.ldt");
    let out = lucerna(&["convert", input.to_str().unwrap(), plain.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(
        text(&out.stderr).contains("unequal C-plane steps"),
        "{}",
        text(&out.stderr)
    );
    let even = dir.path().join("even.ldt");
    let out = lucerna(&[
        "convert",
        input.to_str().unwrap(),
        even.to_str().unwrap(),
        "--resample-c",
        "15",
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(!text(&out.stderr).contains("unequal"));
    let back = lucerna_photometry::read_photometry(&std::fs::read(&even).unwrap()).unwrap();
    assert_eq!(back.table.uniform_c_step(), Some(15.0));
    let original = lucerna_photometry::read_photometry(&std::fs::read(&input).unwrap()).unwrap();
    // Linear interpolation in C keeps the peak; the flux moves little.
    let (a, b) = (back.figures(), original.figures());
    assert!((a.peak_cd - b.peak_cd).abs() < 1e-6 * b.peak_cd);
    assert!(
        (a.flux_lm / b.flux_lm - 1.0).abs() < 0.01,
        "{} vs {}",
        a.flux_lm,
        b.flux_lm
    );
}

#[test]
fn a_bake_where_nothing_escapes_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let scene = dir.path().join("boxed.toml");
    std::fs::write(
        &scene,
        r#"format_version = 1
name = "Boxed LED"

[materials.mirror]
type = "mirror"
reflectance = 0.95

[[emitter]]
name = "LED"
flux_lm = 100.0
shape = { type = "disk", radius = 0.002 }

[[part]]
name = "box"
material = "mirror"
shape = { type = "box", size = [0.1, 0.1, 0.1] }
"#,
    )
    .unwrap();
    let out = lucerna(&[
        "bake",
        scene.to_str().unwrap(),
        "--photons",
        "20000",
        "--backend",
        "cpu",
        "--resolution",
        "16",
        "--out",
        dir.path().to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    assert!(
        text(&out.stderr).contains("warning: no photon left the luminaire"),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn edit_without_a_display_points_to_bake() {
    // With the editor beside `lucerna` it refuses for want of a display;
    // without it, `edit` says how to get it. Either way: a clear failure.
    let out = Command::new(env!("CARGO_BIN_EXE_lucerna"))
        .arg("edit")
        .arg(assets().join("luminaires/parabolic_spot.toml"))
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    assert!(!out.status.success());
    let all = format!("{}{}", text(&out.stdout), text(&out.stderr));
    assert!(all.contains("lucerna bake"), "{all}");
}

/// Everything the editor's export dialog offers, `bake` offers too: the
/// files, the IES edition, grid, raw or filtered, the declared symmetry,
/// the base name and date; the scene's `[export]` keywords are used by
/// themselves. With the date given, the files are the library's export of
/// a bake with the same seed and photons, byte for byte.
#[test]
fn bake_writes_what_the_export_dialog_offers_with_the_scenes_keywords() {
    let dir = tempfile::tempdir().unwrap();
    let original = assets().join("luminaires/parabolic_spot.toml");
    let mut scene = lucerna_scene::load_scene(&original).unwrap();
    scene.export.catalogue_number = "PS-25".to_owned();
    scene.export.test_lab = "Acme photometry".to_owned();
    let scene_path = dir.path().join("spot.toml");
    lucerna_scene::save_scene(&scene, &scene_path).unwrap();
    let out_dir = dir.path().join("out");
    let out = bake_on_cpu(
        &scene_path,
        40_000,
        32,
        &out_dir,
        &[
            "--formats",
            "ies,ldt",
            "--ies-version",
            "2002",
            "--c-step",
            "15",
            "--gamma-step",
            "2.5",
            "--filter",
            "auto",
            "--symmetrise",
            "none",
            "--name",
            "catalogue",
            "--date",
            "2026-03-04",
        ],
    );
    assert!(out.status.success(), "{}", text(&out.stderr));
    let mut written: Vec<String> = std::fs::read_dir(&out_dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    written.sort();
    assert_eq!(written, ["catalogue.ies", "catalogue.ldt"]);
    let ies = std::fs::read_to_string(out_dir.join("catalogue.ies")).unwrap();
    assert!(ies.starts_with("IESNA:LM-63-2002"), "{ies}");
    for line in [
        "[LUMCAT] PS-25",
        "[TESTLAB] Acme photometry",
        "[ISSUEDATE] 2026-03-04",
    ] {
        assert!(ies.contains(line), "{line} missing");
    }
    let info = lucerna(&[
        "info",
        out_dir.join("catalogue.ies").to_str().unwrap(),
        "--json",
    ]);
    let r: serde_json::Value = serde_json::from_slice(&info.stdout).unwrap();
    assert_eq!(r["c_planes"].as_u64(), Some(24), "{r}");
    assert_eq!(r["c_step_deg"].as_f64(), Some(15.0), "{r}");
    assert_eq!(r["gamma_step_deg"].as_f64(), Some(2.5), "{r}");
    assert!(r["symmetry"].as_str().unwrap().starts_with("none"), "{r}");
    assert_eq!(r["catalog_number"].as_str(), Some("PS-25"));

    // The same export from the library.
    let luminaire = std::sync::Arc::new(lucerna_simulation::Luminaire::load(&scene_path).unwrap());
    let settings = lucerna_simulation::SimulationSettings {
        resolution: 32,
        backend: lucerna_simulation::BackendRequest::Cpu,
        filter: lucerna_simulation::FilterChoice::Automatic,
        stop: lucerna_simulation::StoppingRule {
            photons: Some(40_000),
            ..Default::default()
        },
        table: lucerna_simulation::TableGrid {
            c_step_deg: 15.0,
            gamma_step_deg: Some(2.5),
        },
        ..Default::default()
    };
    let snapshot = lucerna_simulation::bake(luminaire, settings).unwrap();
    let options = lucerna_simulation::ExportOptions {
        symmetrise: Some(lucerna_photometry::CPlaneSymmetry::None),
        date: "2026-03-04".to_owned(),
        seed: 1,
        scene_file: "spot.toml".to_owned(),
        labels: None,
    };
    let mut request =
        lucerna_simulation::ExportRequest::new(&snapshot, options, dir.path(), "catalogue");
    request.formats.ies = Some(lucerna_photometry::IesVersion::Lm63_2002);
    let exported = request.render(&snapshot).unwrap();
    let expected = exported.photometry.figures();
    for name in ["catalogue.ies", "catalogue.ldt"] {
        let (flux, peak) = figures(&out_dir.join(name));
        assert!(
            (flux / expected.flux_lm - 1.0).abs() < 0.005,
            "{name}: {flux} lm"
        );
        assert!(
            (peak / expected.peak_cd - 1.0).abs() < 0.005,
            "{name}: {peak} cd"
        );
    }
    let files = exported.files;
    for name in ["catalogue.ies", "catalogue.ldt"] {
        let library = &files.iter().find(|(p, _)| p.ends_with(name)).unwrap().1;
        let cli = std::fs::read(out_dir.join(name)).unwrap();
        assert!(cli == *library, "{name}: the CLI and the library differ");
    }

    let bad = bake_on_cpu(&scene_path, 1000, 16, &out_dir, &["--name", "a/b"]);
    assert!(!bad.status.success() && text(&bad.stderr).contains("--name"));
}

/// `convert` prints the flux of the file it wrote (read back), not of the
/// one it read: the two agree to the printed digit on every sample.
#[test]
fn convert_prints_the_written_files_flux() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["avad_srl_isym4.ldt", "rab_roadway1_2002_quadrant.ies"] {
        let input = assets().join("profiles/samples").join(name);
        for out_name in ["x.ldt", "x.ies"] {
            let output = dir.path().join(out_name);
            let o = lucerna(&["convert", input.to_str().unwrap(), output.to_str().unwrap()]);
            assert!(o.status.success(), "{}", text(&o.stderr));
            let said = text(&o.stdout);
            assert!(said.contains("(as written)"), "{said}");
            let (flux, _) = figures(&output);
            assert!(
                said.contains(&format!("{flux:.1} lm")),
                "{said} vs {flux:.1} lm"
            );
        }
    }
}

#[test]
fn export_geometry_writes_every_example_and_refuses_bad_input_writing_nothing() {
    let dir = tempfile::tempdir().unwrap();
    for name in [
        "parabolic_spot",
        "faceted_downlight",
        "linear_louvre",
        "obj_cone",
        "opal_bell",
    ] {
        let scene = assets().join(format!("luminaires/{name}.toml"));
        let out_dir = dir.path().join(name);
        let out = lucerna(&[
            "export-geometry",
            scene.to_str().unwrap(),
            "--out",
            out_dir.to_str().unwrap(),
        ]);
        assert!(out.status.success(), "{name}: {}", text(&out.stderr));
        // The same bytes as the library's (and so the editor's) export.
        let parsed = lucerna_scene::load_scene(&scene).unwrap();
        let files = lucerna_cad::geometry_files(
            &parsed,
            scene.parent().unwrap(),
            name,
            &lucerna_cad::GeometryRequest::default(),
        )
        .unwrap();
        for (file, bytes) in files {
            assert_eq!(std::fs::read(out_dir.join(&file)).unwrap(), bytes, "{file}");
        }
    }
    let spot = assets().join("luminaires/parabolic_spot.toml");
    let target = dir.path().join("refused");
    let refused = |args: &[&str], says: &str| {
        let mut all = vec!["export-geometry"];
        all.extend_from_slice(args);
        let out = lucerna(&all);
        assert!(!out.status.success());
        let err = text(&out.stderr);
        assert!(err.contains(says), "{args:?}: {err}");
        assert!(!target.exists(), "{args:?} wrote {}", target.display());
    };
    let spot_path = spot.to_str().unwrap();
    let target_path = target.to_str().unwrap();
    refused(
        &[spot_path, "--out", target_path, "--parts", "reflecter"],
        "no part or emitter named 'reflecter'",
    );
    refused(
        &[spot_path, "--out", target_path, "--formats", "step,iges"],
        "unknown geometry format 'iges'",
    );
    let broken = dir.path().join("broken.toml");
    std::fs::write(
        &broken,
        std::fs::read_to_string(&spot)
            .unwrap()
            .replace("reflectance = 0.9", "reflectance = 1.9"),
    )
    .unwrap();
    refused(
        &[broken.to_str().unwrap(), "--out", target_path],
        "reflectance",
    );
    let blocker = dir.path().join("a-file");
    std::fs::write(&blocker, "x").unwrap();
    let out = lucerna(&[
        "export-geometry",
        spot_path,
        "--out",
        blocker.join("sub").to_str().unwrap(),
    ]);
    assert!(!out.status.success());
    assert!(
        text(&out.stderr).contains("cannot write"),
        "{}",
        text(&out.stderr)
    );
}

#[test]
fn info_and_convert_read_a_tm25_ray_file() {
    let rays = assets().join("rayfiles/synthetic_led.tm25ray");
    let out = lucerna(&["info", rays.to_str().unwrap(), "--json"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(report["rays"], 20000);
    assert!((report["rays_luminous_flux_lm"].as_f64().unwrap() - 100.0).abs() < 1e-3);
    // The 1 mm die.
    for axis in 0..2 {
        let (lo, hi) = (
            report["extent_min_mm"][axis].as_f64().unwrap(),
            report["extent_max_mm"][axis].as_f64().unwrap(),
        );
        assert!(
            lo > -0.5 && lo < -0.499 && hi < 0.5 && hi > 0.499,
            "{lo}..{hi}"
        );
    }
    // The synthetic LED emits along +z, Lambertian: all of it upward,
    // the far field's flux that of the rays.
    let far = &report["far_field"];
    assert!(
        (far["flux_lm"].as_f64().unwrap() - 100.0).abs() < 0.5,
        "{far}"
    );
    assert!(far["downward_fraction"].as_f64().unwrap() < 0.01, "{far}");
    let dir = tempfile::tempdir().unwrap();
    let ldt = dir.path().join("led.ldt");
    let out = lucerna(&["convert", rays.to_str().unwrap(), ldt.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let (flux, _) = figures(&ldt);
    assert!((flux - 100.0).abs() < 0.5, "{flux}");
    // A damaged ray file: a clear error naming the file and the field.
    let mut bytes = std::fs::read(&rays).unwrap();
    bytes.truncate(bytes.len() - 3);
    let broken = dir.path().join("broken.tm25ray");
    std::fs::write(&broken, &bytes).unwrap();
    let out = lucerna(&["info", broken.to_str().unwrap()]);
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert!(
        err.contains("broken.tm25ray") && err.contains("ray data") && err.contains("truncated"),
        "{err}"
    );
}

#[test]
fn bake_writes_a_tm25_ray_file_that_info_reads() {
    let dir = tempfile::tempdir().unwrap();
    let scene = assets().join("luminaires/parabolic_spot.toml");
    let out = lucerna(&[
        "bake",
        scene.to_str().unwrap(),
        "--photons",
        "100000",
        "--resolution",
        "32",
        "--backend",
        "cpu",
        "--formats",
        "ies,tm25",
        "--rays",
        "20000",
        "--date",
        "2026-12-04",
        "--out",
        dir.path().to_str().unwrap(),
    ]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let rays = dir.path().join("parabolic_spot.tm25ray");
    let out = lucerna(&["info", rays.to_str().unwrap(), "--json"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(report["rays"], 20000);
    let (ies_flux, _) = figures(&dir.path().join("parabolic_spot.ies"));
    let declared = report["declared_luminous_flux_lm"].as_f64().unwrap();
    assert!(
        (declared - ies_flux).abs() < 1e-3 * ies_flux,
        "{declared} vs {ies_flux}"
    );
    assert!(report["description"].to_string().contains("Lucerna"));
    // The spot's beam points down: nearly all of it below the horizontal.
    assert!(report["far_field"]["downward_fraction"].as_f64().unwrap() > 0.99);
}

/// `validate` reads every ray file a scene names, as a bake will: a
/// missing or truncated one fails it, naming the emitter and the file.
#[test]
fn validate_fails_on_a_missing_or_truncated_ray_file() {
    let dir = tempfile::tempdir().unwrap();
    let scene = std::fs::read_to_string(assets().join("rayfiles/parabolic_spot_ray_file_led.toml"))
        .unwrap();
    let path = dir.path().join("spot.toml");
    std::fs::write(&path, &scene).unwrap();
    // Missing.
    let out = lucerna(&["validate", path.to_str().unwrap()]);
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert!(
        err.contains("synthetic_led.tm25ray") && err.contains("ray file"),
        "{err}"
    );
    // Truncated by 3 bytes.
    let mut bytes = std::fs::read(assets().join("rayfiles/synthetic_led.tm25ray")).unwrap();
    bytes.truncate(bytes.len() - 3);
    std::fs::write(dir.path().join("synthetic_led.tm25ray"), &bytes).unwrap();
    let out = lucerna(&["validate", path.to_str().unwrap()]);
    assert!(!out.status.success());
    let err = text(&out.stderr);
    assert!(err.contains("truncated"), "{err}");
    // Whole: ok.
    std::fs::copy(
        assets().join("rayfiles/synthetic_led.tm25ray"),
        dir.path().join("synthetic_led.tm25ray"),
    )
    .unwrap();
    let out = lucerna(&["validate", path.to_str().unwrap()]);
    assert!(out.status.success(), "{}", text(&out.stderr));
}

/// An LED file emitting toward +z has beam and field angles (the walk
/// wraps over the zenith), within 1° of an independent binning of its
/// rays; `convert` names its input a ray file.
#[test]
fn an_led_ray_file_emitting_upward_has_its_beam_angle() {
    let rays = assets().join("rayfiles/synthetic_led.tm25ray");
    let out = lucerna(&["info", rays.to_str().unwrap(), "--json"]);
    assert!(out.status.success(), "{}", text(&out.stderr));
    let report: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    let beam = report["far_field"]["beam_angle_deg"][0]
        .as_f64()
        .expect("a beam angle for an LED emitting along +z");
    // Independently: the rays' own histogram of the angle from +z, each
    // ray's flux over the solid angle of its 1° ring; half the peak.
    let set = lucerna_photometry::tm25::read_ray_file(&rays).unwrap();
    let mut ring = vec![0.0f64; 90];
    for i in 0..set.len() {
        let d = set.direction(i).map(f64::from);
        let theta = (d[2] / (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt())
            .acos()
            .to_degrees();
        if theta < 90.0 {
            ring[theta as usize] += f64::from(set.luminous_flux_lm[i]);
        }
    }
    let intensity: Vec<f64> = (0..90)
        .map(|k| {
            let (a, b) = ((k as f64).to_radians(), ((k + 1) as f64).to_radians());
            ring[k] / (std::f64::consts::TAU * (a.cos() - b.cos()))
        })
        .collect();
    let peak = intensity[..10].iter().sum::<f64>() / 10.0;
    let half = (0..90)
        .find(|&k| intensity[k] < 0.5 * peak)
        .map(|k| k as f64)
        .unwrap();
    assert!(
        (beam - 2.0 * half).abs() < 2.0,
        "{beam}° against {}°",
        2.0 * half
    );
    let ldt = tempfile::tempdir().unwrap();
    let out_path = ldt.path().join("led.ldt");
    let out = lucerna(&[
        "convert",
        rays.to_str().unwrap(),
        out_path.to_str().unwrap(),
    ]);
    let said = text(&out.stdout);
    assert!(
        said.contains("TM-25 ray file") && !said.contains("LM-63-2019"),
        "{said}"
    );
}

/// A command whose output is closed early ends quietly: no panic, no
/// backtrace (`lucerna validate … | head -1`).
#[test]
fn a_closed_output_ends_a_command_quietly() {
    use std::io::Read;
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_lucerna"))
        .args([
            "validate",
            assets()
                .join("luminaires/faceted_downlight.toml")
                .to_str()
                .unwrap(),
        ])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    // Close the pipe before it prints (it loads and tessellates first):
    // every line it writes then meets a closed pipe.
    drop(child.stdout.take());
    let mut err = String::new();
    child
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    let _ = child.wait().unwrap();
    assert!(
        !err.contains("panicked") && !err.contains("Broken pipe"),
        "{err}"
    );
}
