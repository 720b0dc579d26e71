#![allow(clippy::unwrap_used, clippy::expect_used)]
//! The paper's near-field evaluation (section 6, Figure 10) on our data:
//! every example luminaire's baked profile and every manufacturer sample.

use std::path::PathBuf;
use std::sync::Arc;

use lucerna_photometry::read_photometry;
use lucerna_room::ProfileGrid;
use lucerna_room::evaluation::{HEIGHTS, NearFieldSettings, Reference, nrms, stitched_images};

fn profiles() -> Vec<(String, Arc<ProfileGrid>)> {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../assets/profiles");
    let mut out = Vec::new();
    for dir in ["examples", "samples"] {
        let mut entries: Vec<_> = std::fs::read_dir(root.join(dir))
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("ies" | "ldt")))
            .collect();
        entries.sort();
        for p in entries {
            let phot = read_photometry(&std::fs::read(&p).unwrap()).unwrap();
            let name = p.file_stem().unwrap().to_string_lossy().into_owned();
            out.push((name, Arc::new(ProfileGrid::from_table(&phot.table))));
        }
    }
    out
}

/// NRMS of the cubature against the Monte Carlo reference (MIS of area
/// and profile sampling, 1024 samples each), per profile and height,
/// printed as a table: the default (prefiltered) rule, then in brackets
/// the exact-cosine rule and the paper's eq. 10. The bounds are what the
/// default rule achieves with about 20 % margin (worst: 0.227, 0.070,
/// 0.037); the paper's Figure 10 is a chart whose values the text does not
/// give, so it cannot serve as the bound. The 3°-beam parabolic spot has its own bound: no
/// five-sample cubature resolves a beam narrower than the opening's
/// angular size, but prefiltering must still beat eq. 10 tenfold there.
/// Summed over the profiles, the default rule must beat eq. 10 at every
/// height.
#[test]
fn near_field_nrms_per_profile_and_height() {
    let settings = NearFieldSettings {
        pixels: 20,
        reference: Reference::MonteCarlo { samples: 1024 },
    };
    let bounds = [0.28, 0.085, 0.045];
    let spot_bound = 0.65;
    let mut table = String::from(
        "profile                                   h=0.1 (exact-cos eq.10)    h=1.0 (exact-cos eq.10)    h=2.5 (exact-cos eq.10)\n",
    );
    let mut failures = Vec::new();
    let mut sums = [(0.0, 0.0); 3];
    let all = profiles();
    assert!(
        all.len() >= 13,
        "expected 5 examples and 8 samples, found {}",
        all.len()
    );
    for (name, profile) in &all {
        table.push_str(&format!("{name:40}"));
        for (k, &h) in HEIGHTS.iter().enumerate() {
            let images = stitched_images(profile, h, settings);
            let ours = nrms(&images.prefiltered, &images.reference);
            let exact = nrms(&images.exact_cosine, &images.reference);
            let paper = nrms(&images.paper, &images.reference);
            sums[k].0 += ours;
            sums[k].1 += paper;
            table.push_str(&format!("  {ours:.4} ({exact:.4} {paper:.4})"));
            let narrow_spot = name == "parabolic_spot";
            let bound = if narrow_spot { spot_bound } else { bounds[k] };
            if ours.is_nan() || ours > bound {
                failures.push(format!("{name} h={h}: NRMS {ours:.4} > {bound}"));
            }
            if narrow_spot && (ours.is_nan() || ours * 10.0 > paper) {
                failures.push(format!(
                    "{name} h={h}: {ours:.4} not 10× better than eq. 10 ({paper:.4})"
                ));
            }
        }
        table.push('\n');
    }
    eprintln!("{table}");
    for (k, (ours, paper)) in sums.iter().enumerate() {
        eprintln!(
            "h = {}: mean NRMS {:.4}, eq. 10 {:.4}",
            HEIGHTS[k],
            ours / all.len() as f64,
            paper / all.len() as f64
        );
        if ours.is_nan() || ours >= paper {
            failures.push(format!(
                "h={}: prefiltered {ours:.3} not better than eq. 10 {paper:.3}",
                HEIGHTS[k]
            ));
        }
    }

    assert!(failures.is_empty(), "{failures:?}");
}
