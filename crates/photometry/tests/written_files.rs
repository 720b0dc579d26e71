//! The writers' side of the round-trip invariant (issue 23): free text
//! cannot break a layout, lines keep to their format's limits, a symmetry
//! the format cannot index is not stated (the flux is kept), and a writer
//! refuses what its reader would.

use lucerna_photometry::{
    CPlaneSymmetry, CandelaTable, Format, IesVersion, LampSet, Metadata, Photometry,
    read_photometry, to_latin1, write_ies, write_ldt,
};

fn photometry(table: CandelaTable, symmetry: CPlaneSymmetry) -> Photometry {
    Photometry {
        format: Format::Eulumdat,
        symmetry,
        table,
        meta: Metadata {
            lamps: vec![LampSet {
                count: 1,
                kind: "LED".to_owned(),
                flux_lm: 1000.0,
                colour_temperature: "3000 K".to_owned(),
                colour_rendering: "90".to_owned(),
                watts: 10.0,
            }],
            ..Metadata::default()
        },
    }
}

fn downlight() -> CandelaTable {
    CandelaTable::from_fn(15.0, 5.0, |_, g| {
        if g < 90.0 {
            300.0 * g.to_radians().cos()
        } else {
            0.0
        }
    })
}

#[test]
fn line_and_paragraph_separators_become_spaces_in_both_formats() {
    let mut p = photometry(downlight(), CPlaneSymmetry::Rotational);
    p.meta.luminaire = "Spot\u{2028}25\u{2029}wide\u{85}beam\r\nend".to_owned();
    p.meta.manufacturer = "Ac\u{2028}me".to_owned();
    let ldt = to_latin1(&write_ldt(&p).unwrap());
    let back = read_photometry(&ldt).expect("the LDT reads back");
    assert_eq!(back.meta.luminaire, "Spot 25 wide beam  end");
    assert_eq!(back.meta.manufacturer, "Ac me");
    let ies = write_ies(&p, IesVersion::Lm63_2019).unwrap();
    assert!(ies.contains("[LUMINAIRE] Spot 25 wide beam end"), "{ies}");
    assert!(read_photometry(ies.as_bytes()).is_ok());
}

#[test]
fn ies_lines_stay_short_whatever_the_keywords() {
    let mut p = photometry(downlight(), CPlaneSymmetry::Rotational);
    p.meta.luminaire = "x".repeat(300);
    p.meta.keywords.push((
        "A_VERY_LONG_KEYWORD_NAME_".repeat(8),
        format!("{} tail", "y".repeat(500)),
    ));
    for version in [IesVersion::Lm63_2002, IesVersion::Lm63_2019] {
        let ies = write_ies(&p, version).unwrap();
        for line in ies.split("\r\n") {
            assert!(line.len() <= 80, "{} characters: {line}", line.len());
        }
        let back = read_photometry(ies.as_bytes()).unwrap();
        // [MORE] continues the text; readers join its lines with a space.
        assert_eq!(back.meta.luminaire.replace(' ', ""), p.meta.luminaire);
    }
}

#[test]
fn ldt_free_text_keeps_to_its_field_widths() {
    let mut p = photometry(downlight(), CPlaneSymmetry::Rotational);
    p.meta.luminaire = "L".repeat(200);
    p.meta.lamps[0].kind = "K".repeat(100);
    let ldt = write_ldt(&p).unwrap();
    let lines: Vec<&str> = ldt.split("\r\n").collect();
    assert_eq!(lines[8].len(), 78);
    assert_eq!(lines[27].len(), 24);
    assert!(read_photometry(ldt.as_bytes()).is_ok());
}

/// Non-uniform planes mirrored about C90-C270: EULUMDAT's index
/// arithmetic (Mc1 = 3Mc/4 + 1) would store the wrong half, so the table
/// is written whole and its flux kept.
#[test]
fn a_mirror_the_ldt_cannot_index_is_written_whole_with_its_flux() {
    // Mirrored about C90-C270 (c and 180° - c), but C270 is the 6th of 8
    // planes where the format's Mc1 = 3Mc/4 + 1 takes the 7th.
    let planes = vec![30.0, 90.0, 150.0, 210.0, 240.0, 270.0, 300.0, 330.0];
    let gammas: Vec<f64> = (0..=18).map(|k| k as f64 * 10.0).collect();
    let mut candela = Vec::new();
    for &c in &planes {
        for &g in &gammas {
            // Brighter towards C90 than towards C270, mirror about C90-C270.
            let c_rad = f64::to_radians(c);
            let v = if g < 90.0 {
                (200.0 + 150.0 * c_rad.sin()) * g.to_radians().cos()
            } else {
                0.0
            };
            candela.push(v);
        }
    }
    let table = CandelaTable::new(planes, gammas, candela).unwrap();
    assert!(table.asymmetry(CPlaneSymmetry::AboutC90C270) < 1e-9);
    let p = photometry(table, CPlaneSymmetry::AboutC90C270);
    let flux = p.figures().flux_lm;
    let back = read_photometry(&to_latin1(&write_ldt(&p).unwrap())).unwrap();
    let f = back.figures().flux_lm;
    assert!((f / flux - 1.0).abs() < 1e-4, "{flux} lm written as {f} lm");
    assert!(!lucerna_photometry::ldt::states_symmetry(
        CPlaneSymmetry::AboutC90C270,
        &p.table
    ));
}

#[test]
fn the_ies_writer_refuses_more_lamps_than_its_reader_takes() {
    let mut p = photometry(downlight(), CPlaneSymmetry::Rotational);
    p.meta.lamps[0].count = 2_000_000;
    let e = write_ies(&p, IesVersion::Lm63_2019).unwrap_err();
    assert!(e.to_string().contains("number of lamps"), "{e}");
}

/// EULUMDAT's lamp sets are alternatives (two sets of 600 000 lamps were
/// once added up to 1.2 M and refused): an IES describes the first, its
/// lumens per lamp × lamps being that set's flux, and names the others.
#[test]
fn an_ies_of_several_lamp_sets_describes_the_first_and_names_the_others() {
    let mut p = photometry(downlight(), CPlaneSymmetry::Rotational);
    let set = p.meta.lamps[0].clone();
    p.meta.lamps = vec![
        LampSet {
            count: 600_000,
            flux_lm: 6.0e6,
            ..set.clone()
        },
        LampSet {
            count: 600_000,
            kind: "LED120".to_owned(),
            flux_lm: 7.2e6,
            ..set
        },
    ];
    let ies = write_ies(&p, IesVersion::Lm63_2019).unwrap();
    let back = read_photometry(ies.as_bytes()).unwrap();
    let (_, statement) = back
        .meta
        .keywords
        .iter()
        .find(|(k, _)| k == "_LAMPSET")
        .expect("a [_LAMPSET] keyword");
    assert!(
        statement.starts_with("lamp set 1 of 2 (600000 x LED, 6000000 lm, 10 W)"),
        "{statement}"
    );
    assert!(
        statement.ends_with("set 2 (600000 x LED120, 7200000 lm, 10 W)"),
        "{statement}"
    );
    assert_eq!(back.meta.lamps.len(), 1);
    assert_eq!(back.meta.lamps[0].count, 600_000);
    assert!((back.lamp_flux_lm().unwrap() / 6.0e6 - 1.0).abs() < 1e-7);
    // The LDT states each set's count, which its reader takes.
    let ldt = read_photometry(&to_latin1(&write_ldt(&p).unwrap())).unwrap();
    assert_eq!(ldt.meta.lamps.len(), 2);
    assert_eq!(ldt.lamp_flux_lm(), Some(6.0e6));
}
