//! Files every reader accepts, and the luminous opening's axes through
//! both formats: IES length lies along C0-C180, EULUMDAT length along
//! C90-C270 (EN 13032-1, GLDF); Lucerna's `Dimensions` keep IES's terms.

use std::path::Path;

use lucerna_photometry::{
    CPlaneSymmetry, CandelaTable, Dimensions, IesVersion, Photometry, WriteOptions,
    read_photometry, to_latin1, write_ies, write_ldt, write_ldt_with,
};

fn linear_louvre() -> Photometry {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets/profiles/examples/linear_louvre.ies");
    read_photometry(&std::fs::read(path).expect("the example")).expect("reads")
}

/// The lines of an LDT file (CR LF).
fn ldt_lines(bytes: &[u8]) -> Vec<String> {
    String::from_utf8_lossy(bytes)
        .split("\r\n")
        .map(str::to_owned)
        .collect()
}

#[test]
fn a_linear_luminaire_keeps_its_long_axis_through_both_formats() {
    let ies = linear_louvre();
    // The example's opening is 1.18 m along C90-C270 (y), 0.09 m along x.
    let area = ies.meta.luminous_area;
    assert!((area.width_m - 1.18).abs() < 1e-9 && (area.length_m - 0.09).abs() < 1e-9);
    let ldt_bytes = to_latin1(&write_ldt(&ies).expect("writes"));
    let lines = ldt_lines(&ldt_bytes);
    // EULUMDAT lines 16/17: luminous area length (along C90-C270) and
    // width (along C0-C180), in mm.
    assert_eq!(lines[15].trim(), "1180");
    assert_eq!(lines[16].trim(), "90");
    let ldt = read_photometry(&ldt_bytes).expect("reads");
    assert_eq!(ldt.meta.luminous_area, area);
    // IES -> LDT -> IES keeps length and width.
    let back = read_photometry(
        write_ies(&ldt, IesVersion::Lm63_2019)
            .expect("writes")
            .as_bytes(),
    )
    .expect("reads");
    assert_eq!(back.meta.luminous_area, area);
    assert_eq!(
        back.meta.luminaire_dimensions,
        ies.meta.luminaire_dimensions
    );
}

#[test]
fn round_openings_are_a_diameter_in_both_formats() {
    let mut p = linear_louvre();
    p.meta.luminous_area = Dimensions {
        length_m: 0.2,
        width_m: 0.0,
        height_m: 0.0,
        circular: true,
    };
    let ldt = read_photometry(&to_latin1(&write_ldt(&p).expect("writes"))).expect("reads");
    assert_eq!(ldt.meta.luminous_area, p.meta.luminous_area);
    let ies = read_photometry(
        write_ies(&p, IesVersion::Lm63_2019)
            .expect("writes")
            .as_bytes(),
    )
    .expect("reads");
    assert_eq!(ies.meta.luminous_area, p.meta.luminous_area);
}

#[test]
fn free_text_is_written_as_ascii_by_default() {
    let mut p = linear_louvre();
    p.meta.manufacturer = "Lumière Größe 25 °C ±5 %".to_owned();
    p.meta.luminaire = "Leuchte “Ω”".to_owned();
    let ies = write_ies(&p, IesVersion::Lm63_2002).expect("writes");
    let ldt = to_latin1(&write_ldt(&p).expect("writes"));
    assert!(ies.is_ascii());
    assert!(ldt.is_ascii());
    for bytes in [ies.as_bytes(), &ldt[..]] {
        let back = read_photometry(bytes).expect("reads");
        assert!(
            back.meta.manufacturer.starts_with("Lumiere Grosse 25"),
            "{}",
            back.meta.manufacturer
        );
    }
    // Asked for, Latin-1 text stays (a reader that wants it).
    let latin1 = to_latin1(
        &write_ldt_with(
            &p,
            &WriteOptions {
                ascii_text: false,
                ..Default::default()
            },
        )
        .expect("writes"),
    );
    assert!(!latin1.is_ascii());
    assert!(
        read_photometry(&latin1)
            .expect("reads")
            .meta
            .manufacturer
            .starts_with("Lumière")
    );
}

#[test]
fn a_c90_mirror_is_written_over_the_whole_circle() {
    // I(C) = I(180° − C): legal LM-63 stores 90°-270°, which some readers
    // refuse; the default writes 0°-360°, the intensities unchanged.
    let table = CandelaTable::from_fn(15.0, 5.0, |c, g| {
        100.0 + 50.0 * c.to_radians().sin() * g.to_radians().sin()
    });
    assert_eq!(table.detect_symmetry(1e-9), CPlaneSymmetry::AboutC90C270);
    let mut p = linear_louvre();
    p.table = table.clone();
    p.symmetry = CPlaneSymmetry::AboutC90C270;
    let text = write_ies(&p, IesVersion::Lm63_2019).expect("writes");
    let back = read_photometry(text.as_bytes()).expect("reads");
    assert_eq!(back.symmetry, CPlaneSymmetry::None);
    assert_eq!(back.table.c_planes_deg.first(), Some(&0.0));
    for &c in &table.c_planes_deg {
        for &g in &table.gammas_deg {
            let (a, b) = (back.table.intensity(c, g), table.intensity(c, g));
            assert!((a - b).abs() <= 1e-5 * b, "C{c} γ{g}: {a} vs {b}");
        }
    }
}
