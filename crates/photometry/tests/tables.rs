#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! Analytic distributions through every file format and symmetry: values
//! to the printed precision, flux to 0.5 % of the closed form.

use std::f64::consts::PI;

use lucerna_photometry::resample::cube_map_from_table;
use lucerna_photometry::table::{angles, uniform_c_planes, uniform_gammas};
use lucerna_photometry::{
    CPlaneSymmetry, CandelaTable, CubeMapLayout, IesVersion, IntensityMap, LampSet, Metadata,
    Photometry, WriteOptions, figures, read_photometry, table_from_cube_map, write_ies, write_ldt,
};

struct Analytic {
    name: &'static str,
    intensity: fn(f64, f64) -> f64,
    flux_lm: f64,
    symmetry: CPlaneSymmetry,
}

const I0: f64 = 1000.0;

fn cases() -> Vec<Analytic> {
    vec![
        Analytic {
            name: "isotropic",
            intensity: |_, _| I0,
            flux_lm: 4.0 * PI * I0,
            symmetry: CPlaneSymmetry::Rotational,
        },
        Analytic {
            name: "cosine",
            intensity: |_, g| I0 * if g < 90.0 { g.to_radians().cos() } else { 0.0 },
            flux_lm: PI * I0,
            symmetry: CPlaneSymmetry::Rotational,
        },
        // A narrow spot: I0 cos^60 γ, beam ≈ 17.3°; flux 2π I0 / 61.
        Analytic {
            name: "narrow cone",
            intensity: |_, g| {
                if g < 90.0 {
                    I0 * g.to_radians().cos().powi(60)
                } else {
                    0.0
                }
            },
            flux_lm: 2.0 * PI * I0 / 61.0,
            symmetry: CPlaneSymmetry::Rotational,
        },
        // Harmonics in C integrate to zero: the flux stays π I0.
        Analytic {
            name: "C0-C180",
            intensity: |c, g| I0 * cosine_of(g) * (1.0 + 0.5 * c.to_radians().cos()),
            flux_lm: PI * I0,
            symmetry: CPlaneSymmetry::AboutC0C180,
        },
        Analytic {
            name: "C90-C270",
            intensity: |c, g| I0 * cosine_of(g) * (1.0 + 0.5 * c.to_radians().sin()),
            flux_lm: PI * I0,
            symmetry: CPlaneSymmetry::AboutC90C270,
        },
        Analytic {
            name: "quadrant",
            intensity: |c, g| I0 * cosine_of(g) * (1.0 + 0.3 * (2.0 * c.to_radians()).cos()),
            flux_lm: PI * I0,
            symmetry: CPlaneSymmetry::Quadrant,
        },
        Analytic {
            name: "asymmetric",
            intensity: |c, g| {
                I0 * cosine_of(g) * (1.0 + 0.3 * c.to_radians().cos() + 0.2 * c.to_radians().sin())
            },
            flux_lm: PI * I0,
            symmetry: CPlaneSymmetry::None,
        },
    ]
}

fn cosine_of(g: f64) -> f64 {
    if g < 90.0 { g.to_radians().cos() } else { 0.0 }
}

fn photometry(table: CandelaTable, symmetry: CPlaneSymmetry) -> Photometry {
    let flux = table.flux_lm();
    Photometry {
        format: lucerna_photometry::Format::Ies(2019),
        symmetry,
        table,
        meta: Metadata {
            manufacturer: "Lucerna tests".into(),
            luminaire: "analytic".into(),
            lamps: vec![LampSet {
                count: 1,
                kind: "LED".into(),
                flux_lm: flux,
                colour_temperature: "3000".into(),
                colour_rendering: "90".into(),
                watts: 10.0,
            }],
            ballast_factor: 1.0,
            ..Metadata::default()
        },
    }
}

#[test]
fn analytic_tables_survive_every_format_and_symmetry() {
    for case in cases() {
        let table = CandelaTable::from_fn(5.0, 1.0, case.intensity);
        assert!(
            (table.flux_lm() - case.flux_lm).abs() < 0.005 * case.flux_lm,
            "{}: table flux {} vs analytic {}",
            case.name,
            table.flux_lm(),
            case.flux_lm
        );
        let symmetry = table.detect_symmetry(1e-9);
        assert_eq!(symmetry, case.symmetry, "{}", case.name);
        let p = photometry(table.clone(), symmetry);
        let outputs = [
            (
                "IES 2002",
                write_ies(&p, IesVersion::Lm63_2002)
                    .expect("writes")
                    .into_bytes(),
            ),
            (
                "IES 2019",
                write_ies(&p, IesVersion::Lm63_2019)
                    .expect("writes")
                    .into_bytes(),
            ),
            (
                "IES 2019, 90-270 range allowed",
                lucerna_photometry::write_ies_with(
                    &p,
                    IesVersion::Lm63_2019,
                    &WriteOptions {
                        full_circle_for_c90_mirror: false,
                        ..Default::default()
                    },
                )
                .expect("writes")
                .into_bytes(),
            ),
            (
                "LDT",
                lucerna_photometry::to_latin1(&write_ldt(&p).expect("writes")),
            ),
        ];
        for (format, bytes) in outputs {
            let back = read_photometry(&bytes)
                .unwrap_or_else(|e| panic!("{} as {format}: {e}", case.name));
            // By default a C90-C270 mirror is written over the whole
            // circle (some readers refuse LM-63's 90-270 range).
            let declared = if symmetry == CPlaneSymmetry::AboutC90C270
                && (format == "IES 2002" || format == "IES 2019")
            {
                CPlaneSymmetry::None
            } else {
                symmetry
            };
            assert_eq!(back.symmetry, declared, "{} as {format}", case.name);
            for &c in &table.c_planes_deg {
                for &g in &table.gammas_deg {
                    let (a, b) = (back.table.intensity(c, g), table.intensity(c, g));
                    // Six significant digits are printed.
                    assert!(
                        (a - b).abs() <= 1e-5 * b.abs() + 1e-9,
                        "{} {format} C{c} γ{g}: {a} vs {b}",
                        case.name
                    );
                }
            }
            let flux = back.table.flux_lm();
            assert!(
                (flux - case.flux_lm).abs() < 0.005 * case.flux_lm,
                "{} {format}: flux {flux} vs {}",
                case.name,
                case.flux_lm
            );
        }
    }
}

#[test]
fn symmetrisation_averages_noise_away() {
    let noisy = CandelaTable::from_fn(10.0, 5.0, |c, g| {
        cosine_of(g) * I0 * (1.0 + 0.01 * (7.0 * c + 3.0 * g).to_radians().sin())
    });
    assert_eq!(noisy.detect_symmetry(1e-4), CPlaneSymmetry::None);
    assert_eq!(noisy.detect_symmetry(0.05), CPlaneSymmetry::Rotational);
    let smooth = noisy.symmetrised(CPlaneSymmetry::Rotational);
    assert!(smooth.asymmetry(CPlaneSymmetry::Rotational) < 1e-12);
    assert!((smooth.flux_lm() - noisy.flux_lm()).abs() < 1e-9 * noisy.flux_lm());
}

#[test]
fn beam_and_field_angles_match_the_closed_form() {
    // I = cos^n γ: 50 % at cos γ = 0.5^(1/n), 10 % at 0.1^(1/n).
    let n = 20;
    let table = CandelaTable::from_fn(15.0, 0.5, |_, g| {
        if g < 90.0 {
            I0 * g.to_radians().cos().powi(n)
        } else {
            0.0
        }
    });
    let f = figures(&table, Some(table.flux_lm()));
    let beam = 2.0 * 0.5f64.powf(1.0 / n as f64).acos().to_degrees();
    let field = 2.0 * 0.1f64.powf(1.0 / n as f64).acos().to_degrees();
    for plane in 0..2 {
        assert!(
            (f.beam_angle_deg[plane].unwrap() - beam).abs() < 0.1,
            "{:?} vs {beam}",
            f.beam_angle_deg
        );
        assert!(
            (f.field_angle_deg[plane].unwrap() - field).abs() < 0.1,
            "{:?} vs {field}",
            f.field_angle_deg
        );
    }
    assert!((f.light_output_ratio.unwrap() - 1.0).abs() < 1e-12);
    assert!((f.downward_fraction - 1.0).abs() < 1e-12);
    assert_eq!((f.peak_cd, f.peak_gamma_deg), (I0, 0.0));
}

#[test]
fn downward_and_upward_flux_split_at_the_horizon() {
    let table = CandelaTable::from_fn(0.0, 1.0, |_, _| I0);
    let f = figures(&table, None);
    assert!((f.downward_flux_lm - 2.0 * PI * I0).abs() < 1e-6 * I0);
    assert!((f.upward_flux_lm - 2.0 * PI * I0).abs() < 1e-6 * I0);
    assert_eq!(f.light_output_ratio, None);
}

#[test]
fn an_isotropic_cube_map_gives_a_flat_table() {
    let layout = CubeMapLayout::new(64);
    let map = vec![I0; layout.texel_count()];
    let t = table_from_cube_map(
        layout,
        &map,
        &uniform_c_planes(5.0),
        &uniform_gammas(2.5, 180.0),
    );
    assert!(t.candela.iter().all(|&v| (v - I0).abs() < 1e-9 * I0));
}

#[test]
fn resampling_integrates_instead_of_point_sampling() {
    // Texels alternate 0 and 2·I0 in a fine checkerboard: each table cell
    // covers many texels, so its mean is I0 (±2 % for partly covered
    // cells); point sampling would return 0 or 2·I0.
    let layout = CubeMapLayout::new(512);
    let map: Vec<f64> = (0..layout.texel_count())
        .map(|t| {
            let (_, i, j) = layout.texel_coordinates(t);
            if (i + j) % 2 == 0 { 0.0 } else { 2.0 * I0 }
        })
        .collect();
    let t = table_from_cube_map(
        layout,
        &map,
        &uniform_c_planes(10.0),
        &uniform_gammas(5.0, 180.0),
    );
    let deviation: Vec<f64> = t.candela.iter().map(|v| (v - I0).abs() / I0).collect();
    let rms = (deviation.iter().map(|d| d * d).sum::<f64>() / deviation.len() as f64).sqrt();
    let worst = deviation.iter().fold(0.0f64, |a, &b| a.max(b));
    // Point sampling would be off by 100 % everywhere; partly covered
    // texels at cell borders leave a few per cent in the smallest cells.
    assert!(rms < 0.03 && worst < 0.15, "rms {rms}, worst {worst}");
}

#[test]
fn a_traced_cosine_map_resamples_to_the_cosine_law() {
    // Counts proportional to the exact flux in each texel of a Lambertian
    // emitter (Φ/π cos γ): the table follows I(γ) = Φ/π cos γ.
    let layout = CubeMapLayout::new(128);
    let flux_lm = 1000.0;
    let mut map = IntensityMap::new(layout, flux_lm);
    let photons = 1_000_000_000u64;
    for t in 0..layout.texel_count() {
        let (_, g) = angles(layout.texel_centre_direction(t));
        let expected_photons =
            photons as f64 * (g.cos().max(0.0) / PI) * layout.texel_solid_angle(t);
        map.counts[t] = expected_photons.round() as u64;
    }
    map.photons_emitted = photons.max(map.photons_escaped());
    map.photons_absorbed = map.photons_emitted - map.photons_escaped();
    assert!(map.is_balanced());
    let table = table_from_cube_map(
        layout,
        &map.candela(),
        &uniform_c_planes(15.0),
        &uniform_gammas(5.0, 180.0),
    );
    for &g in &table.gammas_deg {
        // A cell's value is the mean of Φ/π cos γ over its solid angle,
        // γ ± 2.5° (clipped at the poles).
        let (lo, hi) = (
            (g - 2.5).max(0.0).to_radians(),
            (g + 2.5).min(180.0).to_radians(),
        );
        let steps = 1000;
        let (mut num, mut den) = (0.0, 0.0);
        for k in 0..steps {
            let t = lo + (hi - lo) * (k as f64 + 0.5) / steps as f64;
            num += flux_lm / PI * t.cos().max(0.0) * t.sin();
            den += t.sin();
        }
        let expected = num / den;
        let got = table.intensity(0.0, g);
        assert!(
            (got - expected).abs() < 0.005 * flux_lm / PI,
            "γ {g}: {got} vs {expected}"
        );
    }
    assert!(
        (table.flux_lm() - flux_lm).abs() < 0.005 * flux_lm,
        "{}",
        table.flux_lm()
    );
    assert!((map.escaped_flux_lm() - flux_lm).abs() < 1e-3 * flux_lm);
}

#[test]
fn a_table_painted_on_a_cube_map_comes_back() {
    let table = CandelaTable::from_fn(5.0, 2.5, |c, g| {
        I0 * cosine_of(g) * (1.0 + 0.3 * c.to_radians().cos())
    });
    let layout = CubeMapLayout::new(256);
    let cube = cube_map_from_table(&table, layout);
    let back = table_from_cube_map(layout, &cube, &table.c_planes_deg, &table.gammas_deg);
    assert!((back.flux_lm() - table.flux_lm()).abs() < 0.005 * table.flux_lm());
}

#[test]
fn merged_maps_add_exactly() {
    let layout = CubeMapLayout::new(4);
    let mut a = IntensityMap::new(layout, 100.0);
    a.counts[3] = 5;
    a.photons_emitted = 9;
    a.photons_absorbed = 4;
    let mut b = a.clone();
    b.counts[7] = u64::MAX / 4;
    b.photons_emitted += u64::MAX / 4;
    a.merge(&b).unwrap();
    assert_eq!(a.counts[3], 10);
    assert_eq!(a.photons_emitted, 18 + u64::MAX / 4);
    assert!(a.is_balanced());
    assert!(
        a.merge(&IntensityMap::new(CubeMapLayout::new(8), 100.0))
            .is_err()
    );
}

#[test]
fn rms_difference_is_zero_for_a_table_itself_and_exact_for_closed_forms() {
    let lambert = CandelaTable::from_fn(5.0, 1.0, |_, g| {
        if g < 90.0 {
            300.0 * g.to_radians().cos()
        } else {
            0.0
        }
    });
    assert_eq!(lambert.rms_difference_cd(&lambert), 0.0);
    // Constant tables: the difference everywhere.
    let a = CandelaTable::from_fn(15.0, 5.0, |_, _| 100.0);
    let b = CandelaTable::from_fn(22.5, 2.5, |_, _| 60.0);
    assert!((a.rms_difference_cd(&b) - 40.0).abs() < 1e-9);
    // I0 cos γ over the lower hemisphere against darkness:
    // ∫ I0² cos² γ dΩ / 4π = I0² / 6.
    let dark = CandelaTable::from_fn(90.0, 90.0, |_, _| 0.0);
    let rms = lambert.rms_difference_cd(&dark);
    let exact = 300.0 / 6f64.sqrt();
    assert!((rms - exact).abs() < 2e-3 * exact, "{rms} vs {exact}");
    // Symmetric in its arguments.
    assert!((dark.rms_difference_cd(&lambert) - rms).abs() < 1e-9);
}
