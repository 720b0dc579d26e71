#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: tests may panic
//! EULUMDAT's lamp sets are alternative equipments of one luminaire, not
//! lamps added together: the first set is the luminaire (lamp flux, LOR,
//! power, what cd/klm are per), the others are variants; a declared LOR
//! the table contradicts is reported with both numbers; conversions keep
//! the meaning (LM-63's lumens per lamp × lamps is the set's total, as
//! EULUMDAT states it directly).

use std::path::PathBuf;

use lucerna_photometry::ies::LAMP_SET_KEYWORD;
use lucerna_photometry::{
    CPlaneSymmetry, CandelaTable, Format, IesVersion, LampSet, Metadata, Photometry,
    read_photometry, to_latin1, write_ies, write_ldt,
};

fn lamp_sets_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../assets/profiles/lamp_sets")
}

fn read(name: &str) -> Photometry {
    read_photometry(&std::fs::read(lamp_sets_dir().join(name)).unwrap()).unwrap()
}

fn set(kind: &str, flux_lm: f64, watts: f64) -> LampSet {
    LampSet {
        count: 1,
        kind: kind.to_owned(),
        flux_lm,
        colour_temperature: "3000 K".to_owned(),
        colour_rendering: "70".to_owned(),
        watts,
    }
}

/// The road luminaire of the issue, by its numbers: LED110 9 408 lm / 72
/// W and LED120 10 080 lm / 79 W, LORL 78 %, a table of 78 % of the first
/// set's flux. Read as a sum it gave LOR 37.4 %, 151 W and a UGR
/// correction 2.5 too high.
fn road_luminaire() -> Photometry {
    // A Lambertian half-space table of 0.78 × 9 408 lm: I0 = Φ / π.
    let flux = 0.78 * 9408.0;
    let table = CandelaTable::from_fn(15.0, 5.0, |_, g| {
        if g <= 90.0 {
            flux / std::f64::consts::PI * g.to_radians().cos()
        } else {
            0.0
        }
    });
    Photometry {
        format: Format::Eulumdat,
        symmetry: CPlaneSymmetry::Rotational,
        table,
        meta: Metadata {
            lamps: vec![set("LED110", 9408.0, 72.0), set("LED120", 10080.0, 79.0)],
            input_watts: 72.0,
            ballast_factor: 1.0,
            declared_lor_percent: Some(78.0),
            ..Metadata::default()
        },
    }
}

#[test]
fn the_first_set_is_the_luminaire_and_the_others_are_variants() {
    let p = road_luminaire();
    assert_eq!(p.lamp_flux_lm(), Some(9408.0));
    let lor = p.figures().light_output_ratio.unwrap();
    assert!((lor - 0.78).abs() < 0.005, "LOR {lor}");
    assert_eq!(p.power_w(), Some(72.0));
    assert!(p.consistency_warnings().is_empty());
    let variants = p.variants();
    assert_eq!(variants.len(), 1);
    let v = &variants[0];
    assert_eq!(v.set, 2);
    // The same relative table at 10 080 lm: 78 % of it.
    let flux = p.table.flux_lm();
    assert!((v.luminaire_flux_lm / (flux * 10080.0 / 9408.0) - 1.0).abs() < 1e-12);
    assert!((v.efficacy_lm_per_w.unwrap() - v.luminaire_flux_lm / 79.0).abs() < 1e-9);

    // Written as EULUMDAT and read again: both sets, set 1's LOR, power.
    let ldt = read_photometry(&to_latin1(&write_ldt(&p).unwrap())).unwrap();
    assert_eq!(ldt.meta.lamps.len(), 2);
    assert_eq!(ldt.lamp_flux_lm(), Some(9408.0));
    assert_eq!(ldt.power_w(), Some(72.0));
    let declared = ldt.meta.declared_lor_percent.unwrap();
    assert!(
        (declared - 100.0 * lor).abs() < 0.01,
        "LORL written {declared}"
    );
    assert!(ldt.consistency_warnings().is_empty());
}

#[test]
fn a_declared_lor_the_table_contradicts_is_reported_with_both_numbers() {
    let mut p = road_luminaire();
    // What the summed reading would have implied of the same file.
    p.meta.declared_lor_percent = Some(37.4);
    let w = p.consistency_warnings();
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(
        w[0].contains("37.4 %") && w[0].contains("78.0 %"),
        "{}",
        w[0]
    );
    // Within two points: nothing to say.
    p.meta.declared_lor_percent = Some(79.9);
    assert!(p.consistency_warnings().is_empty());
    p.meta.declared_lor_percent = Some(80.1);
    assert_eq!(p.consistency_warnings().len(), 1);
}

#[test]
fn an_ies_of_a_multi_set_file_describes_set_1_and_names_the_others() {
    let p = road_luminaire();
    for version in [IesVersion::Lm63_2002, IesVersion::Lm63_2019] {
        let ies = write_ies(&p, version).unwrap();
        let back = read_photometry(ies.as_bytes()).unwrap();
        assert_eq!(back.lamp_flux_lm(), Some(9408.0), "{ies}");
        assert_eq!(back.meta.input_watts, 72.0);
        let lor = back.figures().light_output_ratio.unwrap();
        assert!((lor - 0.78).abs() < 0.005);
        let (_, said) = back
            .meta
            .keywords
            .iter()
            .find(|(k, _)| k == LAMP_SET_KEYWORD)
            .expect("the lamp-set keyword");
        assert!(
            said.starts_with("lamp set 1 of 2 (1 x LED110, 9408 lm, 72 W)"),
            "{said}"
        );
        assert!(
            said.contains("set 2 (1 x LED120, 10080 lm, 79 W)"),
            "{said}"
        );
        // Back to EULUMDAT: one set, the same flux per cd/klm.
        let ldt = read_photometry(&to_latin1(&write_ldt(&back).unwrap())).unwrap();
        assert_eq!(ldt.lamp_flux_lm(), Some(9408.0));
        assert!((ldt.table.flux_lm() / p.table.flux_lm() - 1.0).abs() < 1e-4);
    }
}

#[test]
fn an_ies_lamp_count_times_lumens_per_lamp_is_the_sets_total() {
    // LM-63: 4 lamps of 2 500 lm; EULUMDAT states 4 lamps, 10 000 lm.
    let mut p = road_luminaire();
    p.meta.lamps = vec![LampSet {
        count: 4,
        ..set("T5", 10_000.0, 100.0)
    }];
    p.meta.declared_lor_percent = None;
    let ies = write_ies(&p, IesVersion::Lm63_2019).unwrap();
    assert!(ies.contains("\r\n4 2500 1 "), "{ies}");
    let back = read_photometry(ies.as_bytes()).unwrap();
    assert_eq!(back.lamp_flux_lm(), Some(10_000.0));
    let ldt_text = write_ldt(&back).unwrap();
    let lines: Vec<&str> = ldt_text.split("\r\n").collect();
    // Line 27: lamps in set 1; line 29: the set's total flux.
    assert_eq!(lines[26], "4");
    assert_eq!(lines[28], "10000");
}

/// A real manufacturer's file of two sets (Tulux, MIT-licensed copy):
/// LOR 100 % of the first set, as it declares; its second set a variant
/// of 2 643 lm lamps.
#[test]
fn a_real_two_set_file_reads_as_it_means() {
    let p = read("tulux_28zhe35_two_lamp_sets.ldt");
    assert_eq!(p.meta.lamps.len(), 2);
    assert_eq!(p.lamp_flux_lm(), Some(1983.0));
    let lor = p.figures().light_output_ratio.unwrap();
    assert!((lor - 1.0).abs() < 0.005, "LOR {lor}");
    assert_eq!(p.meta.declared_lor_percent, Some(100.0));
    assert!(p.consistency_warnings().is_empty());
    assert_eq!(p.power_w(), Some(17.6));
    let v = &p.variants()[0];
    assert!((v.luminaire_flux_lm / (p.table.flux_lm() * 2643.0 / 1983.0) - 1.0).abs() < 1e-12);
    assert!((v.efficacy_lm_per_w.unwrap() - v.luminaire_flux_lm / 24.9).abs() < 1e-9);
}

/// A test fixture of three sets whose table does not give its declared
/// LOR: the warning says so with both numbers.
#[test]
fn a_file_whose_table_contradicts_its_lor_is_flagged() {
    let p = read("photometric_viewer_three_lamp_sets_synthetic.ldt");
    assert_eq!(p.meta.lamps.len(), 3);
    assert_eq!(p.lamp_flux_lm(), Some(500.0));
    assert_eq!(p.variants().len(), 2);
    let w = p.consistency_warnings();
    assert_eq!(w.len(), 1);
    assert!(
        w[0].contains("100.0 %") && w[0].contains("90.5 %"),
        "{}",
        w[0]
    );
}
