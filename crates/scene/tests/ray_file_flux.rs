#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: tests may panic
//! A ray-file emitter may leave `flux_lm` out: the file's own is read with
//! the scene (its header's, else the rays' sum); any other emitter must
//! state it.

use lucerna_photometry::tm25::{RayFileHeader, RaySet, write_ray_file};
use lucerna_scene::parse_scene;

fn scene(emitter: &str) -> String {
    format!(
        r#"
format_version = 1
name = "flux from the file"

[[emitter]]
name = "LED"
{emitter}
"#
    )
}

fn rays(header_lm: Option<f32>) -> RaySet {
    let mut header = RayFileHeader::luminous(2, 0.0);
    header.luminous_flux_lm = header_lm;
    RaySet {
        header,
        records: vec![
            0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 120.0, //
            0.0, 0.0, 0.0, 0.1, 0.0, 1.0, 130.5,
        ],
        luminous_flux_lm: vec![120.0, 130.5],
    }
}

#[test]
fn a_ray_file_emitter_without_flux_takes_the_files_own() {
    let dir = tempfile::tempdir().unwrap();
    let at = dir.path().join("s.toml");
    // The header's figure where it states one (the maker's, even where
    // the rays sum to a little less: info and validate warn about that).
    std::fs::write(
        dir.path().join("a.tm25ray"),
        write_ray_file(&rays(Some(251.0))),
    )
    .unwrap();
    let s = parse_scene(
        &scene(r#"shape = { type = "ray_file", path = "a.tm25ray" }"#),
        &at,
    )
    .unwrap();
    assert_eq!(s.emitters[0].flux_lm, 251.0);
    // No header figure: the rays' sum.
    std::fs::write(dir.path().join("b.tm25ray"), write_ray_file(&rays(None))).unwrap();
    let s = parse_scene(
        &scene(r#"shape = { type = "ray_file", path = "b.tm25ray" }"#),
        &at,
    )
    .unwrap();
    assert_eq!(s.emitters[0].flux_lm, 250.5);
    // A stated flux wins.
    let s = parse_scene(
        &scene("flux_lm = 800.0\nshape = { type = \"ray_file\", path = \"b.tm25ray\" }"),
        &at,
    )
    .unwrap();
    assert_eq!(s.emitters[0].flux_lm, 800.0);
}

#[test]
fn a_flux_nobody_gives_is_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let at = dir.path().join("s.toml");
    let e = parse_scene(
        &scene(r#"shape = { type = "ray_file", path = "missing.tm25ray" }"#),
        &at,
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains("emitter[0].flux_lm")
            && e.contains("missing.tm25ray")
            && e.contains("not given"),
        "{e}"
    );
    let e = parse_scene(&scene(r#"shape = { type = "disk", radius = 0.001 }"#), &at)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("flux_lm") && e.contains("only a ray-file emitter may leave it out"),
        "{e}"
    );
}
