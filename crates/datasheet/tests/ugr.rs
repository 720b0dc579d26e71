//! The UGR table against independent truth: CIE 190's own published
//! table for its worked example, Relux's tables of real luminaires, and
//! a direct evaluation of the formula in the same rooms (radiosity
//! background) for real files and the examples.

use std::path::{Path, PathBuf};

use lucerna_datasheet::direct::direct_ugr;
use lucerna_datasheet::ugr::{ROOMS, ugr_table};
use lucerna_datasheet::{Datasheet, DatasheetOptions, Opening, Section};
use lucerna_photometry::{Photometry, read_photometry};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/eulumdat-ugr").join(name)
}

fn read(path: &Path) -> Photometry {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    read_photometry(&bytes).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// 19 rows of 10 values (5 crosswise, 5 endwise).
fn csv(path: &Path) -> Vec<[f64; 10]> {
    let text = std::fs::read_to_string(path).expect("reference table");
    text.lines()
        .filter(|l| !l.trim().is_empty())
        .map(|l| {
            let v: Vec<f64> = l.split(',').map(|x| x.trim().trim_start_matches('<').parse().expect("number")).collect();
            v.try_into().expect("10 columns")
        })
        .collect()
}

fn sheet(p: &Photometry, spacings: Vec<f64>) -> Datasheet {
    Datasheet::new(p, &DatasheetOptions { ugr_spacings: spacings, ..Default::default() }).expect("datasheet")
}

/// Cell-by-cell differences (ours − reference), printed; (mean |Δ|, max |Δ|).
fn compare(name: &str, ours: &lucerna_datasheet::UgrTable, reference: &[[f64; 10]], offset: f64) -> (f64, f64) {
    assert_eq!(reference.len(), ROOMS.len());
    let (mut sum, mut max, mut n) = (0.0f64, 0.0f64, 0);
    println!("{name}: ours − reference per cell (crosswise | endwise)");
    for (r, row) in reference.iter().enumerate() {
        let mut line = format!("  {:>2}H×{:<2}H", ROOMS[r].0, ROOMS[r].1);
        for k in 0..10 {
            let v = if k < 5 { ours.crosswise[r][k] } else { ours.endwise[r][k - 5] } + offset;
            let d = v - row[k];
            sum += d.abs();
            max = max.max(d.abs());
            n += 1;
            line += &format!(" {d:+.1}");
            if k == 4 {
                line += " |";
            }
        }
        println!("{line}");
    }
    (sum / n as f64, max)
}

#[test]
fn cie_190_worked_example_is_reproduced() {
    let p = read(&data("sample_11.ldt"));
    let s = sheet(&p, vec![1.0]);
    let Section::Shown(t) = &s.ugr else { panic!("no UGR: {:?}", s.ugr) };
    assert_eq!(t.spacing, 1.0);
    // CIE 190 section 5: 2H × 4H, 70/50/20.
    assert_eq!((t.crosswise[2][0], t.endwise[2][0]), (11.0, 13.1));
    let (mean, max) = compare("CIE 190 worked example, S = H", t, &csv(&data("ugr_table_11_cie190.csv")), 0.0);
    println!("mean |Δ| {mean:.3}, max |Δ| {max:.2}");
    assert!(max <= 0.15, "max {max}");
}

#[test]
fn relux_tables_of_real_luminaires_are_reproduced() {
    let mut worst = 0.0f64;
    for n in ["01", "03", "08", "10", "11"] {
        let p = read(&data(&format!("sample_{n}.ldt")));
        let s = sheet(&p, vec![0.25]);
        let Section::Shown(t) = &s.ugr else { panic!("sample {n}: no UGR: {:?}", s.ugr) };
        let (mean, max) = compare(&format!("sample {n} against Relux (S = 0.25H, corrected {:+.2})", t.correction), t, &csv(&data(&format!("ugr_table_{n}_Relux.csv"))), t.correction);
        println!("sample {n}: mean |Δ| {mean:.3}, max |Δ| {max:.2}");
        worst = worst.max(max);
        assert!(mean <= 0.25, "sample {n}: mean {mean}");
    }
    assert!(worst <= 0.5, "worst cell {worst}");
}
