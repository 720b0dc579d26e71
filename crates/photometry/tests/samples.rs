#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! Every bundled real-world sample parses, and its peak intensity and
//! integrated flux match what an independent reader gives (SOURCES.md of
//! `shared/photometry-samples`) within 0.5 %; IES → LDT → IES keeps both.

use std::path::PathBuf;

use lucerna_photometry::{IesVersion, Photometry, read_photometry, write_ies, write_ldt};

fn samples_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../assets/profiles/samples")
}

/// (file, peak cd, integrated flux lm) from SOURCES.md.
const EXPECTED: &[(&str, f64, f64)] = &[
    ("avad_srl_isym4.ldt", 1393.9, 2757.73),
    ("bega_50975_1995_single_h.ies", 337.2, 321.247),
    ("erco_33499000_isym2.ldt", 1271.94, 1778.2),
    ("ledvance_fl_max_900w_asym_isym0.ldt", 68948.9, 122788.0),
    (
        "photompy_2019_filegen_accredited_synthetic.ies",
        10000.0,
        21668.8,
    ),
    ("rab_indoor3_2002_full360.ies", 4917.02, 13348.4),
    ("rab_roadway1_2002_quadrant.ies", 2089.81, 9218.26),
    ("tilt_include_2002_synthetic.ies", 1000.0, 3226.85),
];

fn read(name: &str) -> Photometry {
    let bytes = std::fs::read(samples_dir().join(name)).expect("sample exists");
    read_photometry(&bytes).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn close(a: f64, b: f64, tolerance: f64) -> bool {
    (a - b).abs() <= tolerance * b.abs()
}

#[test]
fn samples_match_an_independent_reader() {
    for &(name, peak, flux) in EXPECTED {
        let p = read(name);
        let (got_peak, _, _) = p.table.peak();
        let got_flux = p.table.flux_lm();
        assert!(
            close(got_peak, peak, 0.005),
            "{name}: peak {got_peak} cd, expected {peak}"
        );
        assert!(
            close(got_flux, flux, 0.005),
            "{name}: flux {got_flux} lm, expected {flux}"
        );
    }
}

#[test]
fn ies_to_ldt_to_ies_keeps_flux_and_peak() {
    for &(name, _, _) in EXPECTED {
        let original = read(name);
        let ldt = write_ldt(&original).expect("writes");
        let via_ldt =
            read_photometry(ldt.as_bytes()).unwrap_or_else(|e| panic!("{name} as LDT: {e}\n{ldt}"));
        for version in [IesVersion::Lm63_2002, IesVersion::Lm63_2019] {
            let ies = write_ies(&via_ldt, version).expect("writes");
            let back = read_photometry(ies.as_bytes())
                .unwrap_or_else(|e| panic!("{name} back to IES: {e}\n{ies}"));
            for (what, a, b) in [
                ("flux", back.table.flux_lm(), original.table.flux_lm()),
                ("peak", back.table.peak().0, original.table.peak().0),
            ] {
                assert!(
                    close(a, b, 0.005),
                    "{name} {version:?}: {what} {a} after the round trip, {b} before"
                );
            }
        }
    }
}

#[test]
fn the_2019_file_generation_field_is_not_a_ballast_factor() {
    let p = read("photompy_2019_filegen_accredited_synthetic.ies");
    assert_eq!(p.meta.file_generation_type, Some(1.1));
    assert_eq!(p.meta.ballast_factor, 1.0);
    assert_eq!(p.table.peak().0, 10000.0);
}

#[test]
fn tilt_include_is_read_and_the_table_follows_it() {
    let p = read("tilt_include_2002_synthetic.ies");
    let (angles, factors) = p.meta.tilt.clone().expect("TILT=INCLUDE data");
    assert_eq!(angles, vec![0.0, 45.0, 90.0, 180.0]);
    assert_eq!(factors, vec![1.0, 0.9, 0.8, 1.0]);
    assert_eq!(p.table.intensity(0.0, 45.0), 700.0);
}

#[test]
fn declared_symmetries_are_read() {
    use lucerna_photometry::CPlaneSymmetry::*;
    for (name, symmetry) in [
        ("avad_srl_isym4.ldt", Quadrant),
        ("bega_50975_1995_single_h.ies", Rotational),
        ("erco_33499000_isym2.ldt", AboutC0C180),
        ("ledvance_fl_max_900w_asym_isym0.ldt", None),
        ("rab_roadway1_2002_quadrant.ies", Quadrant),
        ("rab_indoor3_2002_full360.ies", None),
    ] {
        assert_eq!(read(name).symmetry, symmetry, "{name}");
    }
}
