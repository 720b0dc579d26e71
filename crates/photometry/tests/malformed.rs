#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! Malformed photometric files give errors, never panics.

use std::path::PathBuf;

use lucerna_photometry::read_photometry;
use proptest::prelude::*;

fn sample(name: &str) -> Vec<u8> {
    std::fs::read(
        PathBuf::from(env!("CARGO_MANIFEST_DIR"))
            .join("../../assets/profiles/samples")
            .join(name),
    )
    .expect("sample")
}

const SAMPLES: &[&str] = &[
    "avad_srl_isym4.ldt",
    "bega_50975_1995_single_h.ies",
    "erco_33499000_isym2.ldt",
    "ledvance_fl_max_900w_asym_isym0.ldt",
    "photompy_2019_filegen_accredited_synthetic.ies",
    "rab_indoor3_2002_full360.ies",
    "rab_roadway1_2002_quadrant.ies",
    "tilt_include_2002_synthetic.ies",
];

fn error_of(bytes: &[u8]) -> String {
    match read_photometry(bytes) {
        Ok(_) => panic!("expected an error for {:?}", String::from_utf8_lossy(bytes)),
        Err(e) => e.to_string(),
    }
}

const GOOD_IES: &str = "IESNA:LM-63-2002\n[TEST] t\n[MANUFAC] m\nTILT=NONE\n1 1000 1 3 1 1 2 0.1 0.1 0\n1 1 10\n0 45 90\n0\n100 70 10\n";

#[test]
fn the_minimal_ies_reference_reads() {
    let p = read_photometry(GOOD_IES.as_bytes()).expect("valid");
    assert_eq!(p.table.intensity(0.0, 45.0), 70.0);
}

#[test]
fn specific_mistakes_get_specific_errors() {
    let cases: &[(&str, &str, &str)] = &[
        ("1 1000 1 3 1 1 2", "1 1000 1 3 1 2 2", "type B"),
        ("1 1000 1 3 1 1 2", "1 1000 1 3 1 3 2", "type A"),
        ("100 70 10", "100 seventy 10", "'seventy' is not a number"),
        ("100 70 10", "100 NaN 10", "not a finite number"),
        ("100 70 10", "100 70", "ends where"),
        ("0 45 90", "0 90 45", "strictly ascending"),
        ("0 45 90", "-10 45 90", "0..180"),
        ("1 1000 1 3 1 1 2", "1 1000 1 3000000 1 1 2", "1 to 10000"),
        ("1 1000 1 3 1 1 2", "1 1000 0 3 1 1 2", "multiplier"),
        ("1 1000 1 3 1 1 2", "1 1000 1 3 1 1 7", "units"),
    ];
    for (from, to, expected) in cases {
        let text = GOOD_IES.replacen(from, to, 1);
        assert_ne!(text, GOOD_IES, "case {to} did not change the file");
        let e = error_of(text.as_bytes());
        assert!(
            e.contains(expected),
            "{to}: '{e}' should mention '{expected}'"
        );
        assert!(e.contains("line"), "{to}: '{e}' should give a line");
    }
}

#[test]
fn a_partial_horizontal_range_is_rejected() {
    let text = GOOD_IES
        .replace("1 1000 1 3 1 1 2", "1 1000 1 3 2 1 2")
        .replace("\n0\n100 70 10\n", "\n0 45\n100 70 10\n100 70 10\n");
    assert!(error_of(text.as_bytes()).contains("horizontal angle set"));
}

#[test]
fn empty_binary_and_unknown_files_are_rejected() {
    assert!(error_of(b"").contains("empty"));
    assert!(error_of(&[0u8, 159, 146, 150, 0, 1, 2]).contains("binary"));
    assert!(error_of(b"hello world\nthis is not photometry\n").contains("neither"));
}

#[test]
fn negative_candela_is_clamped_with_a_warning() {
    let text = GOOD_IES.replace("100 70 10", "100 70 -0.5");
    let p = read_photometry(text.as_bytes()).expect("reads");
    assert_eq!(p.table.intensity(0.0, 90.0), 0.0);
    assert!(p.meta.warnings.iter().any(|w| w.contains("negative")));
}

#[test]
fn every_truncation_of_every_sample_is_an_error_or_a_smaller_valid_file() {
    for name in SAMPLES {
        let bytes = sample(name);
        for cut in (0..bytes.len()).step_by(7) {
            // Must not panic; an early cut is an error.
            let r = read_photometry(&bytes[..cut]);
            if cut < bytes.len() / 2 {
                assert!(r.is_err(), "{name} cut at {cut} read as valid");
            }
        }
    }
}

#[test]
fn ldt_with_decimal_commas_and_latin1_reads() {
    let mut bytes = sample("avad_srl_isym4.ldt");
    let text: String = String::from_utf8(bytes.clone())
        .unwrap()
        .replace("379.5", "379,5");
    bytes = text.into_bytes();
    // A Latin-1 'é' (0xE9) in the luminaire name.
    let pos = bytes.windows(3).position(|w| w == b"SRL").unwrap();
    bytes[pos] = 0xE9;
    let p = read_photometry(&bytes).expect("reads");
    assert!(p.meta.luminaire.starts_with('é'), "{}", p.meta.luminaire);
    assert!((p.table.peak().0 - 1393.9).abs() < 0.5);
}

fn mutate(bytes: &[u8], ops: &[(usize, u8, u8)]) -> Vec<u8> {
    let mut out = bytes.to_vec();
    for &(at, kind, value) in ops {
        if out.is_empty() {
            break;
        }
        let i = at % out.len();
        match kind % 5 {
            0 => out[i] = value,
            1 => {
                out.remove(i);
            }
            2 => out.insert(i, value),
            3 => {
                let garbage: &[u8] = [
                    &b"NaN"[..],
                    b"-1",
                    b"1e308",
                    b"inf",
                    b"999999999",
                    b",",
                    b"\n",
                ][value as usize % 7];
                out.splice(i..i, garbage.iter().copied());
            }
            _ => out.truncate(i),
        }
    }
    out
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]
    #[test]
    fn mutated_samples_never_panic(which in 0usize..SAMPLES.len(), ops in prop::collection::vec((any::<usize>(), any::<u8>(), any::<u8>()), 1..6)) {
        let bytes = mutate(&sample(SAMPLES[which]), &ops);
        if let Ok(p) = read_photometry(&bytes) {
            // Whatever reads is physically sane.
            prop_assert!(p.table.candela.iter().all(|v| v.is_finite() && *v >= 0.0));
            prop_assert!(p.table.flux_lm().is_finite());
        }
    }
}
