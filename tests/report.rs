#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! End-to-end: `lucerna report` writes the datasheet of real files and of
//! a scene, its PDF renders to pages a person can read (pdftoppm), its
//! JSON carries the UGR table, and bad input is refused or left out with
//! a reason.

use std::path::Path;
use std::process::Command;

mod common;
use common::{assets, lucerna, text};

fn report(input: &Path, out: &Path, extra: &[&str]) -> std::process::Output {
    let mut args = vec![
        "report",
        input.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    lucerna(&args)
}

/// The fraction of a PNG page's pixels that are not white: ink.
fn ink(png: &Path) -> f64 {
    let bytes = std::fs::read(png).unwrap();
    // pdftoppm writes 8-bit RGB; decode with the image crate the
    // workspace uses through lucerna-pictures' own test dependency.
    let img = image::load_from_memory(&bytes).unwrap().to_rgb8();
    let dark = img
        .pixels()
        .filter(|p| p.0.iter().any(|&c| c < 200))
        .count();
    dark as f64 / (img.width() * img.height()) as f64
}

#[test]
fn report_of_a_real_file_writes_html_pdf_and_json_whose_pages_render() {
    let dir = tempfile::tempdir().unwrap();
    let file = assets().join("profiles/examples/linear_louvre.ies");
    let o = report(&file, dir.path(), &["--ugr-spacing", "0.25,1"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let stem = dir.path().join("linear_louvre_datasheet");
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(stem.with_extension("json")).unwrap()).unwrap();
    let ugr = &json["ugr"];
    assert_eq!(ugr["spacing"], 0.25);
    assert_eq!(ugr["reflectances"][0], serde_json::json!([0.7, 0.5, 0.2]));
    assert_eq!(ugr["rooms"].as_array().unwrap().len(), 19);
    assert_eq!(ugr["rooms"][0], serde_json::json!([2.0, 2.0]));
    for side in ["crosswise", "endwise"] {
        let rows = ugr[side].as_array().unwrap();
        assert_eq!(rows.len(), 19);
        for row in rows {
            let row = row.as_array().unwrap();
            assert_eq!(row.len(), 5);
            let v = row[0].as_f64().unwrap();
            assert!((5.0..35.0).contains(&v), "UGR {v}");
            assert!(row.iter().all(|v| v.is_number()));
        }
    }
    assert_eq!(json["ugr_other_spacings"][0]["spacing"], 1.0);
    assert_eq!(json["cie_flux_code"].as_array().unwrap().len(), 5);
    let html = std::fs::read_to_string(stem.with_extension("html")).unwrap();
    assert!(html.contains("<svg") && html.contains("Viewed crosswise"));
    assert!(html.contains("@font-face"));
    let pdf = stem.with_extension("pdf");
    assert!(std::fs::read(&pdf).unwrap().starts_with(b"%PDF-"));
    // The pages, as a reader sees them.
    let pages = dir.path().join("page");
    let ran = Command::new("pdftoppm")
        .args(["-r", "50", "-png"])
        .arg(&pdf)
        .arg(&pages)
        .status();
    match ran {
        Ok(status) => {
            assert!(status.success(), "pdftoppm failed on the datasheet");
            for n in 1..=3 {
                let png = dir.path().join(format!("page-{n}.png"));
                let ink = ink(&png);
                // Text, diagrams and tables: ink, but not a black page.
                assert!(
                    (0.01..0.5).contains(&ink),
                    "page {n}: {:.1} % ink",
                    100.0 * ink
                );
            }
        }
        Err(e) if std::env::var_os("CI").is_none() => {
            eprintln!("pdftoppm not found ({e}): pages not rendered");
        }
        Err(e) => panic!("pdftoppm is needed under CI: {e}"),
    }
}

#[test]
fn report_with_json_prints_every_figure() {
    let dir = tempfile::tempdir().unwrap();
    let file = assets().join("profiles/samples/rab_roadway1_2002_quadrant.ies");
    let o = report(&file, dir.path(), &["--json"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    // A roadway luminaire is rated as an outdoor one.
    let bug = json["bug"]["label"].as_str().unwrap();
    assert!(
        bug.starts_with('B') && bug.contains(" U") && bug.contains(" G"),
        "{bug}"
    );
    assert!(json["luminaire"]["luminaire_flux_lm"].as_f64().unwrap() > 0.0);
    assert_eq!(json["zonal_lumens"].as_array().unwrap().len(), 5);
}

#[test]
fn upward_light_and_a_missing_opening_are_left_out_with_reasons() {
    let dir = tempfile::tempdir().unwrap();
    // An uplight: no UGR, no luminance table.
    let up = assets().join("profiles/samples/erco_33499000_isym2.ldt");
    let o = report(&up, dir.path(), &["--json"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let why = json["ugr"]["omitted"].as_str().unwrap();
    assert!(why.contains("not applicable"), "{why}");
    assert!(json["luminance"]["omitted"].as_str().is_some());
    // No luminous opening: both left out, saying so.
    let ies = "IESNA:LM-63-2002\n[TEST] none\nTILT=NONE\n1 1000 1 3 1 1 2 0 0 0\n1 1 10\n0 45 90\n0\n100 70 0\n";
    let file = dir.path().join("no_opening.ies");
    std::fs::write(&file, ies).unwrap();
    let o = report(&file, dir.path(), &["--json"]);
    assert!(o.status.success(), "{}", text(&o.stderr));
    let json: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    for section in ["ugr", "luminance"] {
        let why = json[section]["omitted"].as_str().unwrap();
        assert!(why.contains("no luminous opening"), "{section}: {why}");
    }
}

#[test]
fn absurd_input_is_refused_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    // A 5 km luminous opening: refused by the same checks as `info`.
    let ies =
        "IESNA:LM-63-2002\nTILT=NONE\n1 1000 1 3 1 1 2 5000 5000 0\n1 1 10\n0 45 90\n0\n100 70 0\n";
    let file = dir.path().join("huge.ies");
    std::fs::write(&file, ies).unwrap();
    let out = dir.path().join("out");
    let o = report(&file, &out, &[]);
    assert!(!o.status.success());
    let err = text(&o.stderr);
    assert!(err.contains("beyond any real luminaire"), "{err}");
    let info = lucerna(&["info", file.to_str().unwrap()]);
    assert!(!info.status.success());
    assert!(!out.exists() || std::fs::read_dir(&out).unwrap().next().is_none());
    // A spacing the method has no array for.
    let o = report(
        &assets().join("profiles/examples/opal_bell.ies"),
        &out,
        &["--ugr-spacing", "0.3"],
    );
    assert!(!o.status.success());
    assert!(
        text(&o.stderr).contains("--ugr-spacing"),
        "{}",
        text(&o.stderr)
    );
}

#[test]
fn report_of_a_scene_bakes_it_first() {
    let dir = tempfile::tempdir().unwrap();
    let scene = assets().join("luminaires/parabolic_spot.toml");
    let o = report(
        &scene,
        dir.path(),
        &[
            "--photons",
            "200000",
            "--resolution",
            "32",
            "--backend",
            "cpu",
            "--date",
            "2026-01-02",
        ],
    );
    assert!(o.status.success(), "{}", text(&o.stderr));
    let json: serde_json::Value = serde_json::from_slice(
        &std::fs::read(dir.path().join("parabolic_spot_datasheet.json")).unwrap(),
    )
    .unwrap();
    // A spot: narrow beam, cone diagram, UGR table.
    let beam = json["angles"]["beam_angle_deg"][0].as_f64().unwrap();
    assert!(beam < 20.0, "beam {beam}");
    assert_eq!(json["cone"]["rows"].as_array().unwrap().len(), 5);
    // Seen from the wall, a 7° spot shines towards no eye: the cells are
    // null (printed "–"), not an error.
    assert_eq!(json["ugr"]["rooms"].as_array().unwrap().len(), 19);
    assert!(json["ugr"]["crosswise"][0][0].is_null(), "{}", json["ugr"]);
}
