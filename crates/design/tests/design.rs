#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: tests may panic
//! `lucerna design` against truth: a focal length recovered from the
//! bake of its own scene, a start that already matches staying put, a
//! spec met on a bake with another seed, a survey of a variable's range
//! checked by independent bakes, common random numbers measured
//! against independent streams, the same seed giving the same scene, and
//! every bad input refused with a clear error.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::time::Duration;

use lucerna_design::merit::Aim;
use lucerna_design::traced::evaluate::Evaluator;
use lucerna_design::variables::{self, apply};
use lucerna_design::{Budget, DesignError, DesignRequest, Spec, Target};
use lucerna_photometry::{AxialSymmetry, figures};
use lucerna_scene::load_scene;
use lucerna_simulation::{BackendRequest, Luminaire, SimulationSettings, StoppingRule};

const RESOLUTION: u32 = 128;

fn spot_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires/parabolic_spot.toml")
}

fn designs_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/designs")
}

/// The example spot with another focal length, written beside a copy.
fn spot_with_focal_length(dir: &Path, f: f64) -> PathBuf {
    let text = std::fs::read_to_string(spot_path()).unwrap();
    let text = text.replace("focal_length = 0.025", &format!("focal_length = {f}"));
    let path = dir.join(format!("spot_f{}.toml", (f * 1e4).round()));
    std::fs::write(&path, text).unwrap();
    path
}

/// A scene's bake as a distribution target (the table a file of it holds).
fn baked_target(scene: &Path, photons: u64, seed: u32) -> Target {
    let snapshot = bake(Luminaire::load(scene).unwrap(), photons, seed);
    Target::Distribution {
        table: snapshot.table.as_ref().clone(),
        absolute: false,
        name: "target".to_owned(),
    }
}

/// `luminaire` baked on the CPU with `photons` of `seed`'s stream.
fn bake(luminaire: Luminaire, photons: u64, seed: u32) -> lucerna_simulation::Snapshot {
    lucerna_simulation::bake(
        Arc::new(luminaire),
        SimulationSettings {
            resolution: RESOLUTION,
            seed,
            backend: BackendRequest::Cpu,
            stop: StoppingRule {
                photons: Some(photons),
                ..StoppingRule::default()
            },
            ..SimulationSettings::default()
        },
    )
    .unwrap()
}

fn request(scene: PathBuf, target: Target, vary: &str) -> DesignRequest {
    DesignRequest {
        scene_path: scene,
        target,
        vary: vec![vary.to_owned()],
        free_ends: false,
        budget: Budget {
            time: Duration::from_secs(600),
            evaluations: None,
            max_photons: Some(1_600_000),
        },
        seed: 1,
        resolution: RESOLUTION,
        direct: true,
        least_squares: false,
        points: None,
        fallback: Default::default(),
    }
}

fn focal_length(scene: &lucerna_scene::Scene) -> f64 {
    match &scene.parts[0].shape {
        lucerna_scene::Shape::Paraboloid(p) => p.focal_length,
        other => panic!("not a paraboloid: {other:?}"),
    }
}

#[test]
fn a_focal_length_is_recovered_from_its_own_target() {
    let dir = tempfile::tempdir().unwrap();
    let target = baked_target(&spot_with_focal_length(dir.path(), 0.03), 4_000_000, 99);
    let design = lucerna_design::design(
        &request(spot_path(), target, "reflector.focal_length"),
        &AtomicBool::new(false),
        &mut |_| {},
    )
    .unwrap();
    let f = focal_length(&design.scene);
    eprintln!(
        "f = {:.4} mm after {} candidates ({:?}), merit {:.5}",
        f * 1e3,
        design.found.history.len(),
        design.found.stopped,
        design.found.merit
    );
    assert!((f - 0.03).abs() < 0.2e-3, "{f}");
    assert!(design.start_merit > 0.1, "{}", design.start_merit);
}

#[test]
fn damped_least_squares_recovers_a_focal_length_too() {
    let dir = tempfile::tempdir().unwrap();
    let target = baked_target(&spot_with_focal_length(dir.path(), 0.027), 4_000_000, 99);
    let mut r = request(spot_path(), target, "reflector.focal_length");
    r.least_squares = true;
    let design = lucerna_design::design(&r, &AtomicBool::new(false), &mut |_| {}).unwrap();
    let f = focal_length(&design.scene);
    eprintln!(
        "f = {:.4} mm after {} candidates",
        f * 1e3,
        design.found.history.len()
    );
    assert!((f - 0.027).abs() < 0.2e-3, "{f}");
    // After the start, its early stages measure the cumulative flux, its
    // last the L2.
    let measures: Vec<&str> = design
        .found
        .history
        .iter()
        .filter(|r| r.phase == lucerna_design::Phase::Refinement)
        .map(|r| r.measure.as_str())
        .collect();
    assert_eq!(measures.first(), Some(&"cumulative"));
    assert_eq!(measures.last(), Some(&"l2"));
}

#[test]
fn a_start_that_matches_its_target_stays_within_the_noise() {
    let dir = tempfile::tempdir().unwrap();
    let scene = spot_with_focal_length(dir.path(), 0.03);
    let target = baked_target(&scene, 4_000_000, 99);
    let design = lucerna_design::design(
        &request(scene, target, "reflector.focal_length"),
        &AtomicBool::new(false),
        &mut |_| {},
    )
    .unwrap();
    let f = focal_length(&design.scene);
    eprintln!("f = {:.4} mm, merit {:.5}", f * 1e3, design.found.merit);
    assert!((f - 0.03).abs() < 0.1e-3, "{f}");
}

/// With the same photons two nearby candidates' merits differ by their
/// geometry; with independent streams the difference is buried in noise.
#[test]
fn common_random_numbers_make_nearby_candidates_comparable() {
    let scene = load_scene(&spot_path()).unwrap();
    let dir = spot_path().parent().unwrap().to_path_buf();
    let variables =
        variables::parse(&scene, &["reflector.focal_length".to_owned()], false).unwrap();
    let aim = Aim::new(baked_target(&spot_path(), 4_000_000, 99));
    let merit = |seed: u32, f: f64| -> f64 {
        let mut e = Evaluator::new(
            &dir,
            seed,
            RESOLUTION,
            AxialSymmetry::None,
            &variables,
            aim.grid(),
        );
        let s = apply(&scene, &variables, &[f]).unwrap();
        let t = e.trace(&s, 100_000).unwrap();
        aim.merit(&t.table, t.map.light_output_ratio(), 800.0, &t.opening)
    };
    let (f0, f1) = (0.0252, 0.0253);
    let spread = |d: &[f64]| {
        let mean = d.iter().sum::<f64>() / d.len() as f64;
        (d.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (d.len() - 1) as f64).sqrt()
    };
    let common: Vec<f64> = (1..=6).map(|s| merit(s, f1) - merit(s, f0)).collect();
    let independent: Vec<f64> = (1..=6).map(|s| merit(s, f1) - merit(s + 100, f0)).collect();
    let (sc, si) = (spread(&common), spread(&independent));
    eprintln!(
        "merit differences: common {common:?} (sd {sc:.2e}); independent {independent:?} (sd {si:.2e})"
    );
    assert!(sc * 5.0 < si, "common {sc} vs independent {si}");
}

#[test]
fn a_spec_design_meets_its_spec_on_a_bake_with_another_seed() {
    let spec = Spec::parse(
        "beam_angle_deg = 6.0\nbeam_tolerance_deg = 0.5\ncutoff_gamma_deg = 20.0\ncutoff_max_fraction = 0.01\n",
    )
    .unwrap();
    let mut r = request(spot_path(), Target::Spec(spec), "reflector.focal_length");
    r.budget.max_photons = Some(400_000);
    let design = lucerna_design::design(&r, &AtomicBool::new(false), &mut |_| {}).unwrap();
    // Baked again, with other photons.
    let luminaire = Luminaire::new(design.scene.clone(), spot_path().parent().unwrap()).unwrap();
    let snapshot = bake(luminaire, 2_000_000, 4242);
    let f = figures(&snapshot.table, Some(800.0));
    eprintln!(
        "f = {:.3} mm: beam {:?}",
        focal_length(&design.scene) * 1e3,
        f.beam_angle_deg
    );
    for beam in f.beam_angle_deg {
        let beam = beam.unwrap();
        assert!((beam - 6.0).abs() <= 0.5, "beam {beam}");
    }
    // Its survey traced a candidate meeting the beam, and says nothing is
    // out of reach.
    let survey = design.survey.as_ref().expect("one variable is surveyed");
    let beam = survey
        .terms
        .iter()
        .find(|t| t.term == "beam angle")
        .unwrap();
    assert!(beam.lowest < 6.0 && 6.0 < beam.highest, "{beam:?}");
    assert!(survey.findings().is_empty(), "{:?}", survey.findings());
    let t = &snapshot.table;
    let n = t.gammas_deg.len();
    let above = (0..t.candela.len())
        .filter(|k| t.gammas_deg[k % n] >= 20.0)
        .map(|k| t.candela[k])
        .fold(0.0, f64::max);
    assert!(
        above <= 0.01 * f.peak_cd,
        "{above} cd above 20°, peak {}",
        f.peak_cd
    );
}

/// A 40° beam from a parabolic spot's focal length: the survey traces
/// the range (¼ to 4 × 25 mm), its beam range holds what an independent
/// bake of its ends gives, and it says the beam is out of this
/// variable's reach, and that the best lies on a bound.
#[test]
fn a_survey_says_what_one_variable_cannot_reach() {
    let spec = Spec::parse("beam_angle_deg = 40.0\nbeam_tolerance_deg = 1.0\n").unwrap();
    let mut r = request(spot_path(), Target::Spec(spec), "reflector.focal_length");
    r.budget.max_photons = Some(400_000);
    r.budget.evaluations = Some(15);
    let design = lucerna_design::design(&r, &AtomicBool::new(false), &mut |_| {}).unwrap();
    let survey = design.survey.as_ref().expect("one variable is surveyed");
    assert_eq!(survey.axes[0].points, 5, "a third of 15 candidates");
    assert_eq!(survey.traced, 5);
    let beam = survey
        .terms
        .iter()
        .find(|t| t.term == "beam angle")
        .unwrap();
    assert_eq!(beam.met_by, 0);
    // Independent bakes (another seed) of the range's ends.
    let axis = &survey.axes[0];
    let baked_beam = |f: f64| -> f64 {
        let scene = apply(&design.start, &design.variables, &[f]).unwrap();
        let luminaire = Luminaire::new(scene, spot_path().parent().unwrap()).unwrap();
        let s = bake(luminaire, 2_000_000, 777);
        let b = figures(&s.table, Some(800.0)).beam_angle_deg;
        b[0].unwrap().max(b[1].unwrap())
    };
    let ends = [baked_beam(axis.lower), baked_beam(axis.upper)];
    eprintln!("survey {beam:?}; baked ends {ends:?}");
    for e in ends {
        assert!(
            beam.lowest - 0.5 <= e && e <= beam.highest + 0.5,
            "{e} outside {beam:?}"
        );
    }
    assert!(beam.highest < 39.0);
    let findings = survey.findings();
    assert!(
        findings[0].contains("meets the beam angle (40° ± 1°)")
            && findings[0].contains("this variable most likely cannot reach it"),
        "{findings:?}"
    );
    // The widest beam is at the shortest focal length: the range stops it.
    assert!(
        findings.iter().any(|f| f.contains("at its lower bound")),
        "{findings:?}"
    );
    assert!((design.found.values[0] - axis.lower).abs() < 0.1 * axis.lower);
}

#[test]
fn the_same_seed_and_budget_give_the_same_scene_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let target = baked_target(&spot_with_focal_length(dir.path(), 0.028), 1_000_000, 7);
    let mut r = request(spot_path(), target, "reflector.focal_length");
    r.budget.evaluations = Some(10);
    let text = || {
        let d = lucerna_design::design(&r, &AtomicBool::new(false), &mut |_| {}).unwrap();
        lucerna_design::output::scene_text(&d).unwrap()
    };
    let (a, b) = (text(), text());
    assert_eq!(a, b);
    // The start file's comments and labels are kept.
    assert!(a.starts_with("# A parabolic spot"), "{a}");
    assert!(a.contains("manufacturer = \"Lucerna examples\""));
}

#[test]
fn bad_input_gets_a_clear_error() {
    let dir = tempfile::tempdir().unwrap();
    let write = |name: &str, text: &str| {
        let p = dir.path().join(name);
        std::fs::write(&p, text).unwrap();
        p
    };
    let err = |r: Result<Target, DesignError>| r.unwrap_err().to_string();
    // Not a photometric file, not a spec.
    let e = err(Target::load(&write("not.ies", "hello\n"), false));
    assert!(e.contains("not a photometric file"), "{e}");
    let e = err(Target::load(&write("bad.toml", "beam = \n"), false));
    assert!(e.contains("not a valid spec"), "{e}");
    let e = err(Target::load(
        &write("unknown.toml", "beam_width = 20\n"),
        false,
    ));
    assert!(e.contains("unknown field"), "{e}");
    // Terms that contradict each other.
    let e = err(Target::load(
        &write(
            "contradiction.toml",
            "beam_angle_deg = 30\nfield_angle_max_deg = 20\n",
        ),
        false,
    ));
    assert!(e.contains("cannot be wider than the field"), "{e}");
    let e = err(Target::load(
        &write(
            "cutoff.toml",
            "beam_angle_deg = 60\ncutoff_gamma_deg = 20\ncutoff_max_fraction = 0.01\n",
        ),
        false,
    ));
    assert!(e.contains("beyond the cut-off"), "{e}");
    let e = err(Target::load(
        &write("empty.toml", "ugr_room = [4, 8]\n"),
        false,
    ));
    assert!(e.contains("states no term"), "{e}");

    // --vary naming what cannot vary.
    let scene = load_scene(&spot_path()).unwrap();
    let vary = |v: &str| {
        variables::parse(&scene, &[v.to_owned()], false)
            .unwrap_err()
            .to_string()
    };
    assert!(vary("lamp.focal_length").contains("has no part 'lamp'"));
    assert!(vary("reflector.segments_around").contains("is a count, not a continuous parameter"));
    assert!(vary("reflector.faceted").contains("is a switch"));
    assert!(vary("reflector.profile").contains("paraboloid, which has no profile"));
    assert!(vary("reflector.colour").contains("has no continuous parameter 'colour'"));
    assert!(vary("reflector").contains("PART.FIELD"));
    assert!(vary("reflector.profile[1]").contains("paraboloid, which has no profile"));

    // One profile point by its index: the same variables as the whole
    // interior names, point by point; an index beyond the ends refused.
    let revolved = load_scene(&designs_path().join("revolved_cone_start.toml")).unwrap();
    let parse = |v: &[&str]| {
        let v: Vec<String> = v.iter().map(|s| (*s).to_owned()).collect();
        variables::parse(&revolved, &v, false)
    };
    let whole = parse(&["reflector.profile"]).unwrap();
    let points = parse(&[
        "reflector.profile[1]",
        "reflector.profile[2]",
        "reflector.profile[3]",
    ])
    .unwrap();
    assert_eq!(whole, points);
    let end = parse(&["reflector.profile[4]"]).unwrap();
    assert_eq!(end.len(), 2);
    assert_eq!(end[0].name, "reflector.profile[4].r");
    assert_eq!(end[0].start, 0.04);
    let e = parse(&["reflector.profile[5]"]).unwrap_err().to_string();
    assert!(e.contains("has 5 points (profile[0] to profile[4])"), "{e}");
    let e = parse(&["reflector.profile[x]"]).unwrap_err().to_string();
    assert!(e.contains("PART.profile[INDEX]"), "{e}");
    let e = parse(&["reflector.profile", "reflector.profile[2]"])
        .unwrap_err()
        .to_string();
    assert!(e.contains("named twice"), "{e}");

    // A time of zero, a scene that does not load.
    let target = Target::Spec(Spec::parse("beam_angle_deg = 10\n").unwrap());
    let mut r = request(spot_path(), target.clone(), "reflector.focal_length");
    r.budget.time = Duration::ZERO;
    let e = lucerna_design::design(&r, &AtomicBool::new(false), &mut |_| {}).unwrap_err();
    assert!(matches!(e, DesignError::Time), "{e}");
    let broken = write("broken.toml", "format_version = 1\nname = \n");
    let r = request(broken, target, "reflector.focal_length");
    let e = lucerna_design::design(&r, &AtomicBool::new(false), &mut |_| {}).unwrap_err();
    assert!(e.to_string().contains("cannot load the scene"), "{e}");
}

/// The meridian model against the photon tracer: the revolved reflector
/// (a 5-point Catmull-Rom mirror around a 3 mm LED) and the straight
/// cone between its ends, each the model's light against its own bake.
#[test]
fn the_meridian_model_gives_the_tracers_light_of_a_revolved_mirror() {
    use lucerna_design::merit::{SMOOTH_STEP_DEG, axial};
    use lucerna_design::search::global::axial_l2;
    let dir = designs_path();
    let mut profiles = Vec::new();
    let mut baked = Vec::new();
    for name in ["revolved_reflector.toml", "revolved_cone_start.toml"] {
        let path = dir.join(name);
        let target = baked_target(&path, 2_000_000, 5);
        let start = load_scene(&path).unwrap();
        let Target::Distribution { table, .. } = &target else {
            unreachable!()
        };
        let geometry = lucerna_design::model::direct::Geometry::of(&start, 0).expect("a mirror");
        let model = geometry.model(&table.gammas_deg).expect("a model");
        profiles.push((model, geometry.profile.clone()));
        baked.push(axial(table));
    }
    let light = |k: usize| {
        profiles[k]
            .0
            .intensity(&profiles[k].1, SMOOTH_STEP_DEG)
            .unwrap()
    };
    // Each close to its own bake (the reflector's 3.2° beam: 0.044
    // against this 2 M-photon bake, 0.032 against a 30 M one; the cone's
    // broad light, where skew rays the model leaves out matter more,
    // 0.127). Before the model interpolated the shading normals and gave
    // each point of the source's diameter its own chord: 0.053 and 0.16.
    for (k, bound) in [(0, 0.05), (1, 0.14)] {
        let d = axial_l2(&light(k), &baked[k]);
        eprintln!("profile {k}: model against its bake {d:.4}");
        assert!(d < bound, "profile {k}: {d}");
    }
    // …and far from the other's, so the model tells them apart.
    assert!(axial_l2(&light(1), &baked[0]) > 0.5);
    assert!(axial_l2(&light(0), &baked[1]) > 0.5);
}
