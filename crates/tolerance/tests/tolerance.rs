#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: tests may panic
//! Tolerance analysis against truth: the first-order optics of a moved
//! LED, the analytic yield of one tolerance, a tolerance that cannot
//! change the light, a form error that vanishes, and common random
//! numbers against independent streams.

use std::path::Path;
use std::sync::atomic::AtomicBool;

use lucerna_design::{Spec, Target};
use lucerna_scene::{Scene, parse_scene};
use lucerna_tolerance::analysis::{Budget, Reference, Settings, Setup, Streams};
use lucerna_tolerance::figures::{Figure, flux_vector};
use lucerna_tolerance::report::Report;
use lucerna_tolerance::tolerances;

fn spot() -> Scene {
    parse_scene(
        include_str!("../../../assets/luminaires/parabolic_spot.toml"),
        Path::new("spot.toml"),
    )
    .unwrap()
}

fn spec(text: &str) -> Target {
    Target::Spec(Spec::parse(text).unwrap())
}

fn setup(scene: Scene, target: Target, tolerances_text: &str, settings: Settings) -> Setup {
    let t = tolerances::parse(tolerances_text, &scene).unwrap();
    Setup::new(scene, Path::new("."), target, None, t, settings).unwrap()
}

/// The first-order turn of the flux vector of a mirror paraboloid of
/// focal length `f` (focus at the origin, vertex up at z = f, rim at
/// radius `rim`) about a Lambertian point source facing its vertex, when
/// the source moves by `d` along x: each reflected ray turns by the
/// reflection of −d⊥/ρ (d across the incident ray over the distance
/// from the focus to its point); light past the rim goes up, outside the
/// downward flux whose vector is measured. Returns the turn of the
/// downward flux vector's direction in the x–z plane (radians, signed).
fn predicted_turn(f: f64, rim: f64, d: f64) -> f64 {
    let n = 600;
    let (mut dvx, vx, mut vz) = (0.0, 0.0, 0.0);
    for i in 0..n {
        let th = (i as f64 + 0.5) / n as f64 * std::f64::consts::FRAC_PI_2;
        let rho = 2.0 * f / (1.0 + th.cos());
        let reflected = rho * th.sin() <= rim;
        for j in 0..n {
            let ph = (j as f64 + 0.5) / n as f64 * std::f64::consts::TAU;
            let u = [th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()];
            let w = th.cos() * th.sin();
            if !reflected {
                continue;
            }
            vz -= w;
            let du = [
                -(d - d * u[0] * u[0]) / rho,
                -(-d * u[0] * u[1]) / rho,
                -(-d * u[0] * u[2]) / rho,
            ];
            let nl = (u[0] * u[0] + u[1] * u[1] + (u[2] + 1.0).powi(2)).sqrt();
            let nrm = [u[0] / nl, u[1] / nl, (u[2] + 1.0) / nl];
            let dn = du[0] * nrm[0] + du[1] * nrm[1] + du[2] * nrm[2];
            dvx += w * (du[0] - 2.0 * dn * nrm[0]);
        }
    }
    (vx + dvx).atan2(-vz) - f64::atan2(vx, -vz)
}

/// The traced turn of the flux vector in the x–z plane, the LED moved
/// by `d` (the same photons as the nominal's).
fn traced_turn(setup: &Setup, d: f64) -> f64 {
    let mut ev = setup.evaluator(setup.settings.seed);
    let angle = |scene: &Scene, ev: &mut lucerna_design::traced::evaluate::Evaluator| {
        let traced = ev.trace(scene, setup.settings.photons).unwrap();
        let v = flux_vector(&traced.map);
        v[0].atan2(-v[2])
    };
    let nominal = angle(&setup.model.nominal, &mut ev);
    let mut moved = setup.model.nominal.clone();
    moved.emitters[0].transform.translate[0] += d;
    angle(&moved, &mut ev) - nominal
}

#[test]
fn an_led_moved_sideways_turns_the_beam_as_first_order_optics_predicts() {
    let settings = Settings {
        photons: 400_000,
        resolution: 256,
        ..Settings::default()
    };
    let tol = "[[tolerance]]\nat = \"LED.translate_x\"\nnormal = { sigma = 1e-4 }\n";
    let f = 0.025;
    // The deep example spot (rim at the focal plane): its rays come from
    // far from the focus, 0.71 × atan(d/f). A shallow one (30 mm
    // aperture, rim at 33° from the axis): 0.92 × atan(d/f).
    for (aperture, expect_ratio) in [(0.1, 0.71), (0.03, 0.92)] {
        let mut scene = spot();
        if let lucerna_scene::Shape::Paraboloid(p) = &mut scene.parts[0].shape {
            p.aperture_diameter = aperture;
        }
        let s = setup(scene, spec("beam_angle_deg = 3.2"), tol, settings);
        for d in [0.25e-3, 0.5e-3, 1.0e-3] {
            let want = predicted_turn(f, 0.5 * aperture, d);
            let got = traced_turn(&s, d);
            let ratio = got / want;
            eprintln!(
                "aperture {aperture}: d {d}: traced {:.4}°, predicted {:.4}° (×{:.3} of atan(d/f)), ratio {ratio:.4}",
                got.to_degrees(),
                want.to_degrees(),
                want.abs() / (d / f).atan()
            );
            assert!((ratio - 1.0).abs() < 0.03, "d {d}: ratio {ratio}");
            let r = want.abs() / (d / f).atan();
            assert!((r - expect_ratio).abs() < 0.015, "the prediction's {r}");
        }
    }
}

#[test]
fn the_yield_of_one_uniform_tolerance_is_its_analytic_fraction() {
    // UGR grows with the lamp flux as 8·log10(Φ) exactly (CIE 190's
    // table at 1000 lm plus its correction), so the yield of a uniform
    // flux tolerance against a UGR limit is the uniform's fraction below
    // the flux that reaches the limit (a downlight: a 3° spot has no UGR
    // table).
    let scene = parse_scene(
        include_str!("../../../assets/luminaires/faceted_downlight.toml"),
        Path::new("downlight.toml"),
    )
    .unwrap();
    let settings = Settings {
        photons: 20_000,
        resolution: 64,
        noise_runs: 2,
        ..Settings::default()
    };
    let tol = "[[tolerance]]\nat = \"LED.flux_lm\"\nuniform = { half_width = 300.0 }\n";
    let probe = setup(scene.clone(), spec("ugr_max = 40"), tol, settings);
    let reference = probe.reference().unwrap();
    let ugr_at = |r: &Reference| {
        let k = probe
            .figures
            .iter()
            .position(|f| *f == Figure::Ugr)
            .unwrap();
        r.nominal.values[k]
    };
    let nominal_ugr = ugr_at(&reference);
    assert!(nominal_ugr.is_finite(), "{nominal_ugr}");
    let limit = nominal_ugr + 0.25;
    let flux_at_limit = 1200.0 * 10f64.powf((limit - nominal_ugr) / 8.0);
    let distribution = probe.model.tolerances.scalars[0].distribution;
    let analytic = distribution.cdf(flux_at_limit - 1200.0);
    assert!(analytic > 0.2 && analytic < 0.8, "{analytic}");

    let s = setup(scene, spec(&format!("ugr_max = {limit}")), tol, settings);
    let reference = s.reference().unwrap();
    let indices: Vec<u32> = (0..64).collect();
    let (records, stopped) = s.run(
        indices.iter().copied(),
        &Budget {
            samples: Some(64),
            ..Budget::default()
        },
        &AtomicBool::new(false),
        &mut |_, _| {},
    );
    let report = Report::new(&s, &reference, &records, stopped, 1.0);
    let y = report.overall;
    eprintln!(
        "yield {:.4} [{:.4}, {:.4}], analytic {analytic:.4}",
        y.value, y.low, y.high
    );
    assert!(y.low <= analytic && analytic <= y.high);
    // Sobol points: far closer than the interval.
    assert!(
        (y.value - analytic).abs() < 2.0 / 64.0,
        "{} vs {analytic}",
        y.value
    );
}

#[test]
fn a_part_behind_the_leds_board_drives_nothing() {
    // A board under the LED shades the middle of the reflected beam; a
    // cover behind it is in its shadow whatever its place.
    let mut scene = spot();
    let text = r#"
[materials.black]
type = "absorber"

[[part]]
name = "board"
material = "black"
shape = { type = "disk", radius = 0.004 }
transform = { translate = [0.0, 0.0, -0.002] }

[[part]]
name = "cover"
material = "black"
shape = { type = "disk", radius = 0.002 }
transform = { translate = [0.0, 0.0, -0.003] }
"#;
    let extra = parse_scene(
        &format!(
            "format_version = 1\nname = \"x\"\n[[emitter]]\nname = \"e\"\nflux_lm = 1.0\nshape = {{ type = \"disk\", radius = 0.001 }}\n{text}"
        ),
        Path::new("x.toml"),
    )
    .unwrap();
    scene.materials.extend(extra.materials);
    scene.parts.extend(extra.parts);
    let tol = "[[tolerance]]\nat = \"LED.translate_x\"\nnormal = { sigma = 0.15e-3 }\n\n[[tolerance]]\nat = \"cover.translate_x\"\nuniform = { half_width = 0.5e-3 }\n";
    let settings = Settings {
        photons: 100_000,
        resolution: 128,
        noise_runs: 2,
        ..Settings::default()
    };
    let s = setup(scene, spec("beam_angle_deg = 3.2"), tol, settings);
    let reference = s.reference().unwrap();
    let indices: Vec<u32> = (0..48).collect();
    let (records, stopped) = s.run(
        indices.iter().copied(),
        &Budget {
            samples: Some(48),
            ..Budget::default()
        },
        &AtomicBool::new(false),
        &mut |_, _| {},
    );
    assert!(records.iter().all(|r| r.measured.is_some()), "{records:?}");
    let report = Report::new(&s, &reference, &records, stopped, 1.0);
    let share = |figure: &str, tolerance: &str| {
        report
            .sensitivities
            .iter()
            .find(|x| x.figure == figure && x.tolerance == tolerance)
            .unwrap()
            .share
    };
    for f in ["beam_deg", "centroid_gamma_deg", "lor_percent", "peak_cd"] {
        let cover = share(f, "cover.translate_x");
        eprintln!(
            "{f}: cover {cover:?}, LED {:?}",
            share(f, "LED.translate_x")
        );
        assert!(cover.share <= 3.0 * cover.noise, "{f}: {cover:?}");
    }
    // The same measure sees the LED's offset turn the beam.
    let led = share("centroid_gamma_deg", "LED.translate_x");
    assert!(led.share > 10.0 * led.noise, "{led:?}");
}

#[test]
fn a_vanishing_form_error_leaves_the_nominal_figures() {
    let settings = Settings {
        photons: 200_000,
        resolution: 128,
        noise_runs: 3,
        ..Settings::default()
    };
    let tol = "[[form_error]]\npart = \"reflector\"\nsigma = 1e-12\ncorrelation_length = 1e-6\n";
    let s = setup(spot(), spec("beam_angle_deg = 3.2"), tol, settings);
    let reference = s.reference().unwrap();
    let indices: Vec<u32> = (0..3).collect();
    let (records, _) = s.run(
        indices.iter().copied(),
        &Budget {
            samples: Some(3),
            ..Budget::default()
        },
        &AtomicBool::new(false),
        &mut |_, _| {},
    );
    for r in &records {
        let m = r.measured.as_ref().unwrap();
        for (k, fig) in s.figures.iter().enumerate() {
            if matches!(
                fig,
                Figure::PeakC | Figure::CentroidC | Figure::CentroidGamma
            ) {
                // Directions of a beam on the axis: where the noise puts them.
                continue;
            }
            let (got, want, noise) = (
                m.values[k],
                reference.nominal.values[k],
                reference.noise_sd[k],
            );
            eprintln!("{}: {got} against {want} (noise {noise})", fig.key());
            assert!(
                (got - want).abs() <= 3.0 * noise + 1e-9 * want.abs(),
                "{}: {got} against {want} (noise {noise})",
                fig.key()
            );
        }
    }
}

#[test]
fn common_random_numbers_leave_only_the_geometrys_spread() {
    // A tolerance far below anything the light can show: the spread with
    // the nominal's photons is (almost) nothing, with a stream per
    // sample it is the photon noise.
    let tol = "[[tolerance]]\nat = \"LED.translate_x\"\nnormal = { sigma = 1e-9 }\n";
    let spread = |streams: Streams| {
        let settings = Settings {
            photons: 50_000,
            resolution: 128,
            noise_runs: 4,
            streams,
            ..Settings::default()
        };
        let s = setup(spot(), spec("beam_angle_deg = 3.2"), tol, settings);
        let reference = s.reference().unwrap();
        let indices: Vec<u32> = (0..12).collect();
        let (records, stopped) = s.run(
            indices.iter().copied(),
            &Budget {
                samples: Some(12),
                ..Budget::default()
            },
            &AtomicBool::new(false),
            &mut |_, _| {},
        );
        let report = Report::new(&s, &reference, &records, stopped, 1.0);
        let peak = report
            .figures
            .iter()
            .find(|f| f.figure == Figure::PeakCandela.key())
            .unwrap();
        (peak.spread.sd, peak.photon_noise_sd)
    };
    let (common, noise) = spread(Streams::Common);
    let (independent, _) = spread(Streams::Independent);
    eprintln!("peak σ: common {common}, independent {independent}, photon noise {noise}");
    assert!(common < 0.05 * independent, "{common} vs {independent}");
    assert!(
        independent > 0.4 * noise && independent < 2.5 * noise,
        "{independent} vs noise {noise}"
    );
}

#[test]
fn a_target_distribution_is_judged_by_its_relative_l2_and_a_slope_error_widens_the_beam() {
    let settings = Settings {
        photons: 100_000,
        resolution: 128,
        noise_runs: 2,
        ..Settings::default()
    };
    let tol = "[[tolerance]]\nat = \"LED.translate_x\"\nnormal = { sigma = 0.3e-3 }\n\n[[slope_error]]\npart = \"reflector\"\nsigma_rad = 2e-3\n";
    // The nominal's own light as the target: a table on the spec grid.
    let probe = setup(spot(), spec("beam_angle_deg = 3.2"), tol, settings);
    let mut ev = probe.evaluator(99);
    let table = ev
        .trace(&probe.model.nominal, 400_000)
        .expect("traced")
        .table;
    let target = Target::Distribution {
        table,
        absolute: false,
        name: "nominal.ies".to_owned(),
    };
    let scene = spot();
    let t = tolerances::parse(tol, &scene).unwrap();
    assert!(
        Setup::new(
            scene.clone(),
            Path::new("."),
            target.clone(),
            None,
            t.clone(),
            settings
        )
        .is_err(),
        "a distribution needs its largest relative L2"
    );
    let s = Setup::new(scene, Path::new("."), target, Some(0.3), t, settings).unwrap();
    let reference = s.reference().unwrap();
    let l2 = s
        .figures
        .iter()
        .position(|f| *f == Figure::RelativeL2)
        .unwrap();
    let beam = s.figures.iter().position(|f| *f == Figure::Beam).unwrap();
    let built = reference
        .as_built
        .as_ref()
        .expect("a slope error gives an as-built nominal");
    eprintln!(
        "nominal: L2 {:.4}, beam {:.3}°; as built (2 mrad slope error): L2 {:.4}, beam {:.3}°",
        reference.nominal.values[l2],
        reference.nominal.values[beam],
        built.values[l2],
        built.values[beam]
    );
    // The nominal against its own light with other photons: close.
    assert!(reference.nominal.values[l2] < 0.1);
    // 2 mrad of slope turns reflected rays by about 4 mrad (0.23°) each
    // way: the flat-topped beam's edges soften (its 50 % width hardly
    // moves, its 10 % width grows), and the light moves away from the
    // target.
    let field = s.figures.iter().position(|f| *f == Figure::Field).unwrap();
    eprintln!(
        "field {:.3}° -> {:.3}° (noise {:.4}°)",
        reference.nominal.values[field], built.values[field], reference.noise_sd[field]
    );
    assert!(built.values[beam] >= reference.nominal.values[beam]);
    assert!(
        built.values[field]
            > reference.nominal.values[field] + 0.1 + 3.0 * reference.noise_sd[field]
    );
    assert!(built.values[l2] > 2.0 * reference.nominal.values[l2]);
    assert_eq!(reference.nominal.terms.len(), 1);
    assert!(reference.nominal.terms[0].term.starts_with("relative L2"));
}
