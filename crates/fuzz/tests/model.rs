//! Structure-aware generation for the round-trip invariant: photometric
//! models built at the model level (grids, symmetries, values at the
//! readers' limits, lamp sets, odd text) rather than by mutating bytes,
//! whose mutations rarely reach a near-coincident pair of planes or a
//! value one part in 10⁷ under a limit. Every file a writer writes from
//! such a model must read back with the same flux, peak and lamp flux, or
//! the writer must refuse it with a reason (`targets::written_files`).

use lucerna_fuzz::targets::written_files;
use lucerna_photometry::limits::MAX_CANDELA;
use lucerna_photometry::photometry::expand_planes;
use lucerna_photometry::{
    CPlaneSymmetry, CandelaTable, Dimensions, Format, LampSet, Metadata, Photometry,
    limits as plausible,
};
use proptest::prelude::*;

/// Angles a generator draws from: uniform steps, listed ones, pairs just
/// at and around the readers' closest spacing, the ends of the range.
fn angle_list(lo: f64, hi: f64, max_len: usize) -> impl Strategy<Value = Vec<f64>> {
    let uniform = (1usize..=max_len).prop_map(move |n| {
        let step = (hi - lo) / n as f64;
        (0..n).map(|k| lo + k as f64 * step).collect::<Vec<f64>>()
    });
    let listed = proptest::collection::vec(
        prop_oneof![
            4 => lo..hi,
            1 => Just(lo),
            1 => (0u32..8).prop_map(move |k| lo + (hi - lo) * f64::from(k) / 7.0),
        ],
        1..max_len,
    );
    // A near-coincident pair: at, just over and under the 1e-4° the
    // readers require, and at the digits a writer prints.
    let near = (
        proptest::collection::vec(lo..hi, 1..max_len),
        lo..hi,
        prop_oneof![
            Just(1e-4),
            Just(1.0001e-4),
            Just(0.9999e-4),
            Just(4e-8),
            Just(2e-4),
            Just(1e-3),
        ],
    )
        .prop_map(|(mut v, a, d)| {
            v.push(a);
            v.push(a + d);
            v
        });
    prop_oneof![uniform, listed, near].prop_map(move |mut v| {
        v.retain(|x| x.is_finite() && *x >= lo && *x < hi);
        v.sort_by(f64::total_cmp);
        v.dedup_by(|b, a| *b - *a < plausible::MIN_ANGLE_STEP_DEG);
        v
    })
}

/// γ angles within [0, 180], with or without the ends.
fn gammas() -> impl Strategy<Value = Vec<f64>> {
    (angle_list(0.0, 180.0, 40), any::<bool>(), any::<bool>()).prop_map(|(mut g, zero, end)| {
        if zero && g.first() != Some(&0.0) {
            g.insert(0, 0.0);
        }
        if end
            && g.last()
                .is_some_and(|&l| 180.0 - l >= plausible::MIN_ANGLE_STEP_DEG)
        {
            g.push(180.0);
        }
        g.dedup_by(|b, a| *b - *a < plausible::MIN_ANGLE_STEP_DEG);
        g
    })
}

/// Intensities at and around every limit: zero, the smallest subnormal,
/// ordinary values, values one part in 10⁷ under and at the 10¹² cd a
/// reader accepts.
fn candela() -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => 0.0..5000.0,
        1 => Just(0.0),
        1 => Just(5e-324),
        1 => Just(MAX_CANDELA),
        1 => Just(MAX_CANDELA * (1.0 - 1e-7)),
        1 => Just(MAX_CANDELA * (1.0 - 3.3e-7)),
        1 => 1e11..MAX_CANDELA,
        1 => 1e-9..1e-3,
    ]
}

/// Lamp fluxes and counts at and around the readers' limits.
fn lamp_set() -> impl Strategy<Value = LampSet> {
    (
        prop_oneof![
            4 => 1i32..4,
            1 => Just(-1),
            1 => Just(1_000_000),
            1 => Just(0),
        ],
        prop_oneof![
            4 => 1.0..50_000.0,
            1 => Just(plausible::MAX_FLUX_LM),
            1 => Just(plausible::MAX_FLUX_LM * (1.0 - 1e-8)),
            1 => 1e-6..1e-2,
            1 => Just(0.0),
        ],
        prop_oneof![3 => 0.0..500.0, 1 => Just(plausible::MAX_WATTS)],
        text(30),
    )
        .prop_map(|(count, flux_lm, watts, kind)| LampSet {
            count,
            kind,
            flux_lm,
            colour_temperature: "3000 K".to_owned(),
            colour_rendering: "80".to_owned(),
            watts,
        })
}

/// Free text: ASCII, Latin-1, other scripts, controls, line and paragraph
/// separators, long words.
fn text(max: usize) -> impl Strategy<Value = String> {
    prop_oneof![
        3 => proptest::string::string_regex(&format!("[ -~]{{0,{max}}}")).expect("regex"),
        1 => proptest::string::string_regex(&format!("[ -~éüß°µ\u{2028}\u{2029}\r\n\t\u{0}中文]{{0,{max}}}"))
            .expect("regex"),
        1 => Just("W".repeat(300)),
    ]
}

fn dimension() -> impl Strategy<Value = f64> {
    prop_oneof![
        4 => 0.0..2.0,
        1 => Just(plausible::MAX_DIMENSION_M),
        1 => Just(0.0),
    ]
}

prop_compose! {
    /// A model as a reader would make it: the stored planes of a
    /// symmetry, expanded over the circle as the readers expand them.
    fn model()(
        symmetry in prop_oneof![
            Just(CPlaneSymmetry::None),
            Just(CPlaneSymmetry::AboutC0C180),
            Just(CPlaneSymmetry::AboutC90C270),
            Just(CPlaneSymmetry::Quadrant),
            Just(CPlaneSymmetry::Rotational),
        ],
        c_full in angle_list(0.0, 360.0, 48),
        c_half in angle_list(0.0, 180.0, 24),
        c_quarter in angle_list(0.0, 90.0, 12),
        c_mirror in angle_list(90.0, 270.0, 24),
        ends in any::<(bool, bool)>(),
        gammas in gammas(),
        values in proptest::collection::vec(candela(), 1..4096),
        lamps in proptest::collection::vec(lamp_set(), 1..4),
        absolute in any::<bool>(),
        name in text(100),
        manufacturer in text(90),
        area in (dimension(), dimension(), dimension(), any::<bool>()),
        watts in prop_oneof![3 => 0.0..200.0, 1 => Just(plausible::MAX_WATTS)],
    ) -> Option<Photometry> {
        // The stored planes each symmetry's files list, with their ends
        // where the format needs them (or not: listed sets may stop short).
        let with_ends = |mut v: Vec<f64>, lo: f64, hi: f64| {
            if ends.0 && v.first().is_none_or(|&f| f - lo >= plausible::MIN_ANGLE_STEP_DEG) {
                v.insert(0, lo);
            }
            if ends.1 && v.last().is_none_or(|&l| hi - l >= plausible::MIN_ANGLE_STEP_DEG) {
                v.push(hi);
            }
            v
        };
        let stored = match symmetry {
            CPlaneSymmetry::None => c_full,
            CPlaneSymmetry::AboutC0C180 => with_ends(c_half, 0.0, 180.0),
            CPlaneSymmetry::Quadrant => with_ends(c_quarter, 0.0, 90.0),
            CPlaneSymmetry::AboutC90C270 => with_ends(c_mirror, 90.0, 270.0),
            CPlaneSymmetry::Rotational => vec![0.0],
        };
        let ng = gammas.len();
        if stored.is_empty() || ng < 2 {
            return None;
        }
        let rows: Vec<Vec<f64>> = (0..stored.len())
            .map(|i| (0..ng).map(|j| values[(i * ng + j) % values.len()]).collect())
            .collect();
        let (planes, rows) = expand_planes(symmetry, &stored, &rows);
        let table = CandelaTable::new(planes, gammas, rows.concat()).ok()?;
        let absolute = absolute || lamps[0].count < 0;
        Some(Photometry {
            format: Format::Eulumdat,
            symmetry,
            table,
            meta: Metadata {
                luminaire: name,
                manufacturer,
                lamps,
                absolute,
                ballast_factor: 1.0,
                input_watts: watts,
                luminous_area: Dimensions {
                    length_m: area.0,
                    width_m: if area.3 { 0.0 } else { area.1 },
                    height_m: area.2,
                    circular: area.3,
                },
                ..Metadata::default()
            },
        })
    }
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 3000,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn every_written_file_reads_back_or_is_refused_with_a_reason(p in model()) {
        if let Some(p) = p
            && let Err(e) = written_files(&p)
        {
            prop_assert!(
                false,
                "{e}\nsymmetry {:?}\nC {:?}\nγ {:?}\nlamps {:?}",
                p.symmetry,
                p.table.c_planes_deg,
                p.table.gammas_deg,
                p.meta.lamps
            );
        }
    }
}
