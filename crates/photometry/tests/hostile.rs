//! Findings of the hostile-input campaign, each a regression test: what a
//! reader refuses it says so, what a writer writes its reader reads back.

use lucerna_photometry::format_number;
use lucerna_photometry::{
    CPlaneSymmetry, CandelaTable, IesVersion, Photometry, WritePhotometryError, read_photometry,
    to_latin1, write_ies, write_ldt,
};

/// A small valid IES file with `vertical` angles and `horizontal` planes,
/// every intensity `cd`, and extra text spliced into the numbers line.
fn ies(vertical: &str, horizontal: &[f64], cd: f64, opening: &str) -> String {
    let nv = vertical.split_whitespace().count();
    let mut s = format!(
        "IESNA:LM-63-2002\r\n[TEST] t\r\nTILT=NONE\r\n1 1000 1 {nv} {} 1 2 {opening}\r\n1 1 0\r\n{vertical}\r\n",
        horizontal.len()
    );
    s.push_str(
        &horizontal
            .iter()
            .map(|h| h.to_string())
            .collect::<Vec<_>>()
            .join(" "),
    );
    s.push_str("\r\n");
    for _ in horizontal {
        s.push_str(&vec![cd.to_string(); nv].join(" "));
        s.push_str("\r\n");
    }
    s
}

fn example() -> Photometry {
    read_photometry(ies("0 45 90", &[0.0], 100.0, "0.1 0.1 0").as_bytes()).expect("reads")
}

#[test]
fn angles_equal_in_radians_are_refused_not_integrated_to_nan() {
    let text = ies("0 5e-324 90", &[0.0], 100.0, "0.1 0.1 0");
    let e = read_photometry(text.as_bytes()).expect_err("refused");
    assert!(e.to_string().contains("0.0001"), "{e}");
}

#[test]
fn a_writer_refuses_angles_its_reader_could_not_tell_apart() {
    let mut p = example();
    p.table = CandelaTable {
        c_planes_deg: vec![0.0],
        gammas_deg: vec![0.0, 1e-5, 90.0],
        candela: vec![1.0; 3],
    };
    for result in [write_ies(&p, IesVersion::Lm63_2019), write_ldt(&p)] {
        assert!(
            matches!(result, Err(WritePhotometryError::Angles { .. })),
            "{result:?}"
        );
    }
}

#[test]
fn more_planes_than_eulumdat_holds_are_refused_and_ies_reads_them_back() {
    let mut p = example();
    p.table = CandelaTable::from_fn(0.09, 5.0, |_, g| 100.0 * g.to_radians().cos().max(0.0));
    p.symmetry = CPlaneSymmetry::None;
    assert_eq!(p.table.c_planes_deg.len(), 4000);
    assert!(matches!(
        write_ldt(&p),
        Err(WritePhotometryError::TooMany { max: 3600, .. })
    ));
    // 4000 planes read in n log n (was quadratic: 10 000 planes took 1 s).
    let back = read_photometry(
        write_ies(&p, IesVersion::Lm63_2019)
            .expect("writes")
            .as_bytes(),
    )
    .expect("reads");
    assert_eq!(back.table.c_planes_deg.len(), 4000);
}

#[test]
fn an_ldt_whose_company_starts_like_an_ies_file_is_still_an_ldt() {
    let mut p = example();
    p.meta.manufacturer = "IESNA Lighting Ltd".to_owned();
    let bytes = to_latin1(&write_ldt(&p).expect("writes"));
    let back = read_photometry(&bytes).expect("reads");
    assert_eq!(back.format, lucerna_photometry::Format::Eulumdat);
    assert_eq!(back.meta.manufacturer, "IESNA Lighting Ltd");
}

#[test]
fn tiny_and_huge_numbers_are_written_so_they_read_back() {
    assert_eq!(format_number(1e-13, 7), "1e-13");
    assert_eq!(format_number(2.5e-13, 7), "2.5e-13");
    assert!(format_number(1e300, 7).len() < 12);
    let mut p = example();
    p.table = p.table.scaled(1e-12);
    for lamp in &mut p.meta.lamps {
        lamp.flux_lm = 3e-13;
    }
    for bytes in [
        write_ies(&p, IesVersion::Lm63_2019)
            .expect("writes")
            .into_bytes(),
        to_latin1(&write_ldt(&p).expect("writes")),
    ] {
        let back = read_photometry(&bytes).expect("reads");
        let (a, b) = (back.figures(), p.figures());
        assert!(
            (a.flux_lm / b.flux_lm - 1.0).abs() < 1e-5,
            "{} vs {}",
            a.flux_lm,
            b.flux_lm
        );
        assert!((a.peak_cd / b.peak_cd - 1.0).abs() < 1e-5);
    }
}

#[test]
fn lone_cr_line_ends_read_like_crlf() {
    let text = ies("0 45 90", &[0.0], 100.0, "0.1 0.1 0").replace("\r\n", "\r");
    let p = read_photometry(text.as_bytes()).expect("reads");
    assert_eq!(p.table.gammas_deg, vec![0.0, 45.0, 90.0]);
    let ldt = to_latin1(&write_ldt(&p).expect("writes"));
    let cr_only: Vec<u8> = String::from_utf8_lossy(&ldt)
        .replace("\r\n", "\r")
        .into_bytes();
    assert!(read_photometry(&cr_only).is_ok());
}

#[test]
fn absurd_sizes_and_lamp_counts_are_refused_by_name() {
    let text = ies("0 45 90", &[0.0], 100.0, "1e308 0.1 0");
    let e = read_photometry(text.as_bytes()).expect_err("refused");
    assert!(e.to_string().contains("luminous opening width"), "{e}");
    // An LDT with −1e10 lamps (was clamped to i32::MIN in silence).
    let p = example();
    let ldt = String::from_utf8_lossy(&to_latin1(&write_ldt(&p).expect("writes"))).into_owned();
    let mut lines: Vec<&str> = ldt.split("\r\n").collect();
    lines[26] = "-1e10";
    let e = read_photometry(lines.join("\r\n").as_bytes()).expect_err("refused");
    assert!(e.to_string().contains("number of lamps"), "{e}");
}

#[test]
fn an_intensity_past_what_readers_accept_is_refused_by_both_writers() {
    // Found by a fuzz campaign: the IES writer wrote 2·10¹² cd, which its
    // own reader refuses; the EULUMDAT writer already refused it.
    let mut p = example();
    p.table = CandelaTable {
        c_planes_deg: vec![0.0],
        gammas_deg: vec![0.0, 45.0, 90.0],
        candela: vec![2e12, 1.0, 0.0],
    };
    for result in [write_ies(&p, IesVersion::Lm63_2019), write_ldt(&p)] {
        assert!(
            matches!(result, Err(WritePhotometryError::Value { .. })),
            "{result:?}"
        );
    }
    // At the limit itself it is written, and reads back.
    p.table.candela[0] = 1e12;
    let text = write_ies(&p, IesVersion::Lm63_2019).expect("written");
    assert!(read_photometry(text.as_bytes()).is_ok());
}
