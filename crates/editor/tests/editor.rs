#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: tests may panic
//! The editor driven through its labelled widgets, as a user would: open,
//! edit, watch the simulation restart, undo, save, reopen, and a broken
//! file. CPU backend, small maps and a photon limit keep every run short
//! and its figures deterministic (a seed and a photon count fix the map).

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

mod common;

use common::{command, menu};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use lucerna_editor::{EditorApp, EditorState};
use lucerna_scene::Shape;
use lucerna_simulation::{BackendRequest, RunState, SimulationSettings, Snapshot, StoppingRule};

/// Photons per run: enough for a stable beam angle at this resolution.
const PHOTONS: u64 = 1_000_000;

fn example() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires/parabolic_spot.toml")
}

fn settings(resolution: u32) -> SimulationSettings {
    SimulationSettings {
        resolution,
        backend: BackendRequest::Cpu,
        stop: StoppingRule {
            photons: Some(PHOTONS),
            ..StoppingRule::default()
        },
        ..SimulationSettings::default()
    }
}

fn editor(open: Option<PathBuf>) -> Harness<'static, EditorApp> {
    editor_at(open, 64)
}

/// An editor whose runs use `resolution` texels per cube-face edge.
fn editor_at(open: Option<PathBuf>, resolution: u32) -> Harness<'static, EditorApp> {
    Harness::builder()
        .with_size([1366.0, 900.0])
        .build_ui_state(
            |ui, app: &mut EditorApp| app.ui(ui),
            EditorApp::new(EditorState::new(open, settings(resolution))),
        )
}

/// Steps frames until the shown snapshot satisfies `done`.
fn wait_for(
    h: &mut Harness<'_, EditorApp>,
    what: &str,
    done: impl Fn(&Snapshot) -> bool,
) -> Arc<Snapshot> {
    let deadline = Instant::now() + Duration::from_secs(60);
    loop {
        h.step();
        if let Some(s) = h.state().state.snapshot()
            && done(s)
        {
            return s.clone();
        }
        if let Some(sim) = h.state().state.simulation()
            && let Some((_, e)) = sim.published().error
        {
            panic!("simulation failed while waiting for {what}: {e}");
        }
        assert!(Instant::now() < deadline, "timed out waiting for {what}");
        std::thread::sleep(Duration::from_millis(10));
    }
}

fn finished(generation: u64) -> impl Fn(&Snapshot) -> bool {
    move |s| s.generation == generation && matches!(s.state, RunState::Finished(_))
}

fn focal_length(h: &Harness<'_, EditorApp>) -> f64 {
    match &h.state().state.scene().expect("a scene").parts[0].shape {
        Shape::Paraboloid(p) => p.focal_length,
        other => panic!("expected the paraboloid, got {other:?}"),
    }
}

fn select_reflector(h: &mut Harness<'_, EditorApp>) {
    h.get_by_label("Part reflector (paraboloid)").click();
    h.step();
    h.step();
}

#[test]
fn a_longer_focal_length_restarts_the_run_and_narrows_the_beam_and_undo_restores_it() {
    // Texels of 0.45° at the nadir: fine enough for a beam of a few degrees.
    let mut h = editor_at(Some(example()), 256);
    let before = wait_for(&mut h, "the first run", finished(0));
    assert_eq!(before.photons, PHOTONS);
    let beam_before = before.figures.beam_angle_deg[0].expect("a beam angle");

    select_reflector(&mut h);
    h.get_by_label("Focal length").set_value_accesskit(50.0);
    h.step();
    h.step();
    assert!(
        (focal_length(&h) - 0.05).abs() < 1e-12,
        "{}",
        focal_length(&h)
    );
    assert!(
        h.state().state.problems().is_empty(),
        "{:?}",
        h.state().state.problems()
    );
    assert_eq!(h.state().state.simulation().unwrap().generation(), 1);
    assert!(h.state().state.is_dirty());
    assert!(h.state().state.title().contains('•'));

    // The edited run counts its photons from zero: it stops at the same
    // limit, not at twice it.
    let after = wait_for(&mut h, "the edited run", finished(1));
    assert_eq!(after.photons, PHOTONS);
    let beam_after = after.figures.beam_angle_deg[0].expect("a beam angle");
    // The LED's angular size seen from the reflector shrinks with the
    // distance to it: 25-50 mm at f = 25 mm, 50-62.5 mm at f = 50 mm
    // (measured here: 3.20° → 2.72°, deterministic for this seed and count).
    assert!(
        beam_after < 0.9 * beam_before,
        "beam {beam_before:.2}° at f = 25 mm, {beam_after:.2}° at f = 50 mm"
    );

    menu(&mut h, "Edit", "Undo");
    assert!(
        (focal_length(&h) - 0.025).abs() < 1e-12,
        "{}",
        focal_length(&h)
    );
    assert!(!h.state().state.is_dirty());
    assert_eq!(h.state().state.simulation().unwrap().generation(), 2);
    let undone = wait_for(&mut h, "the undone run", finished(2));
    assert_eq!(undone.figures.beam_angle_deg, before.figures.beam_angle_deg);

    menu(&mut h, "Edit", "Redo");
    assert!((focal_length(&h) - 0.05).abs() < 1e-12);
}

#[test]
fn an_invalid_edit_is_shown_and_not_simulated() {
    let mut h = editor(Some(example()));
    wait_for(&mut h, "the first run", |s| s.generation == 0);
    select_reflector(&mut h);
    h.get_by_label("Focal length").set_value_accesskit(0.0);
    h.step();
    h.step();
    let problems = h.state().state.problems().to_vec();
    assert!(
        problems
            .iter()
            .any(|p| p.contains("part[0].shape.focal_length")),
        "{problems:?}"
    );
    assert_eq!(h.state().state.simulation().unwrap().generation(), 0);
    h.get_by_label_contains("part[0].shape.focal_length");
    // Fixing it sends the fixed scene.
    h.get_by_label("Focal length").set_value_accesskit(30.0);
    h.step();
    assert!(h.state().state.problems().is_empty());
    assert_eq!(h.state().state.simulation().unwrap().generation(), 1);
}

#[test]
fn save_as_and_reopen_gives_the_same_scene() {
    let dir = tempfile::tempdir().unwrap();
    let saved = dir.path().join("spot.toml");
    let mut h = editor(Some(example()));
    h.step();
    select_reflector(&mut h);
    h.get_by_label("Focal length").set_value_accesskit(40.0);
    h.step();
    // What the Save As dialog delivers.
    command(&mut h, lucerna_editor::Command::SaveAs(saved.clone()));
    assert_eq!(h.state().state.file_error(), None);
    assert!(!h.state().state.is_dirty());
    let edited = h.state().state.scene().unwrap().clone();
    assert_eq!(lucerna_scene::load_scene(&saved).unwrap(), edited);

    // Reopen from the file in a fresh editor, then through the Open field.
    let mut again = editor(Some(saved.clone()));
    again.step();
    again.step();
    assert_eq!(again.state().state.scene(), Some(&edited));
    assert!(!again.state().state.is_dirty());
    assert_eq!(again.state().state.path(), Some(saved.as_path()));
}

#[test]
fn ctrl_s_saves_to_the_open_file() {
    let dir = tempfile::tempdir().unwrap();
    let copy = dir.path().join("spot.toml");
    std::fs::copy(example(), &copy).unwrap();
    let mut h = editor(Some(copy.clone()));
    h.step();
    select_reflector(&mut h);
    h.get_by_label("Aperture diameter")
        .set_value_accesskit(120.0);
    h.step();
    assert!(h.state().state.is_dirty());
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::S);
    h.step();
    h.step();
    assert!(!h.state().state.is_dirty());
    let on_disk = lucerna_scene::load_scene(&copy).unwrap();
    assert_eq!(Some(&on_disk), h.state().state.scene());
}

#[test]
fn a_broken_scene_file_shows_its_error_and_the_editor_keeps_running() {
    let dir = tempfile::tempdir().unwrap();
    let broken = dir.path().join("broken.toml");
    std::fs::write(
        &broken,
        "format_version = 1\nname = \"broken\"\n[[part]]\nname = \"r\"\nmaterial = \"nothing\"\n\
         shape = { type = \"paraboloid\", focal_length = -0.02, aperture_diameter = 0.1 }\n",
    )
    .unwrap();
    let mut h = editor(Some(example()));
    h.step();
    let original = h.state().state.scene().unwrap().clone();
    // What the Open dialog delivers.
    command(&mut h, lucerna_editor::Command::Open(broken.clone()));
    let error = h.state().state.file_error().expect("an error").to_owned();
    assert!(error.contains("broken.toml"), "{error}");
    assert!(error.contains("line 6"), "{error}");
    assert!(error.contains("focal_length"), "{error}");
    h.get_by_label_contains("focal_length");
    // The scene that was open stays open and simulated.
    assert_eq!(h.state().state.scene(), Some(&original));
    for _ in 0..5 {
        h.step();
    }
    assert!(h.state().state.simulation().is_some());

    // A file that is not TOML at all.
    std::fs::write(&broken, "this is = = not toml").unwrap();
    command(&mut h, lucerna_editor::Command::Open(broken.clone()));
    let error = h.state().state.file_error().expect("an error").to_owned();
    assert!(error.contains("broken.toml:1"), "{error}");
}

#[test]
fn parts_are_added_duplicated_and_deleted_each_as_one_undo_step() {
    let mut h = editor(Some(example()));
    h.step();
    h.get_by_label("Add part").click();
    h.step();
    h.step();
    h.get_by_label("Add disk").click();
    h.step();
    h.step();
    let parts = |h: &Harness<'_, EditorApp>| h.state().state.scene().unwrap().parts.len();
    assert_eq!(parts(&h), 2);
    assert!(
        h.state().state.problems().is_empty(),
        "{:?}",
        h.state().state.problems()
    );
    h.get_by_label("Duplicate part").click();
    h.step();
    h.step();
    assert_eq!(parts(&h), 3);
    let names: Vec<String> = h
        .state()
        .state
        .scene()
        .unwrap()
        .parts
        .iter()
        .map(|p| p.name.clone())
        .collect();
    assert_eq!(names, ["reflector", "disk", "disk 2"]);
    h.get_by_label("Delete part").click();
    h.step();
    assert_eq!(parts(&h), 2);
    for expected in [3, 2, 1] {
        menu(&mut h, "Edit", "Undo");
        assert_eq!(parts(&h), expected);
    }
}

#[test]
fn the_views_show_the_polar_diagram_and_the_cube_map() {
    let mut h = editor(Some(example()));
    wait_for(&mut h, "a snapshot", |_| true);
    h.step();
    h.get_by_label("Polar");
    h.get_by_label("Cube map").click();
    h.step();
    h.step();
    h.get_by_label_contains("Log scale over 3 decades");
    h.get_by_label_contains("Beam C0-C180");
}

#[test]
fn opening_over_unsaved_changes_asks_first() {
    let mut h = editor(Some(example()));
    h.step();
    select_reflector(&mut h);
    h.get_by_label("Focal length").set_value_accesskit(30.0);
    h.step();
    command(&mut h, lucerna_editor::Command::Open(example()));
    assert!(h.state().state.pending_open().is_some());
    h.get_by_label("Keep editing").click();
    h.step();
    assert!(h.state().state.pending_open().is_none());
    assert!((focal_length(&h) - 0.03).abs() < 1e-12);
    command(&mut h, lucerna_editor::Command::Open(example()));
    h.get_by_label("Discard changes and open").click();
    h.step();
    h.step();
    assert!((focal_length(&h) - 0.025).abs() < 1e-12);
    assert!(!h.state().state.is_dirty());
}

/// Every item of every example shows its properties with labelled fields,
/// and merely looking at them changes nothing.
#[test]
fn every_item_of_every_example_can_be_inspected_without_changing_it() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires");
    let mut examples: Vec<PathBuf> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|x| x == "toml"))
        .collect();
    examples.sort();
    assert!(examples.len() >= 5);
    for path in examples {
        let mut h = editor(Some(path.clone()));
        h.step();
        let scene = h.state().state.scene().expect("loads").clone();
        let mut items: Vec<String> = scene
            .emitters
            .iter()
            .map(|e| format!("Emitter {}", e.name))
            .collect();
        items.extend(
            scene
                .parts
                .iter()
                .map(|p| format!("Part {} ({}", p.name, p.shape.generator().kind())),
        );
        items.extend(scene.materials.keys().map(|m| format!("Material {m} (")));
        for item in items {
            h.get_by_label_contains(&item).click();
            h.step();
            h.step();
        }
        assert_eq!(h.state().state.scene(), Some(&scene), "{}", path.display());
        assert!(!h.state().state.is_dirty(), "{}", path.display());
    }
}

/// A whole drag of a field is one undo step, however many frames it
/// changed the scene in.
#[test]
fn a_drag_is_one_undo_step() {
    let mut h = editor(Some(example()));
    h.step();
    select_reflector(&mut h);
    let start = h.get_by_label("Focal length").rect().center();
    let button = |pos, pressed| egui::Event::PointerButton {
        pos,
        button: egui::PointerButton::Primary,
        pressed,
        modifiers: egui::Modifiers::NONE,
    };
    h.event(egui::Event::PointerMoved(start));
    h.step();
    h.event(button(start, true));
    h.step();
    let mut pos = start;
    let mut seen = Vec::new();
    for _ in 0..6 {
        pos.x += 10.0;
        h.event(egui::Event::PointerMoved(pos));
        h.step();
        seen.push(focal_length(&h));
    }
    h.event(button(pos, false));
    h.step();
    h.step();
    let dragged = focal_length(&h);
    assert!(dragged > 0.025 + 1e-4, "{seen:?}");
    // The scene changed in several frames of the drag…
    seen.dedup();
    assert!(seen.len() > 2, "{seen:?}");
    // …and one undo goes back to before it.
    menu(&mut h, "Edit", "Undo");
    assert!(
        (focal_length(&h) - 0.025).abs() < 1e-12,
        "{}",
        focal_length(&h)
    );
    menu(&mut h, "Edit", "Redo");
    assert!((focal_length(&h) - dragged).abs() < 1e-12);
}

/// The core gesture: while a drag changes the focal length frame after
/// frame (over a second, as a hand does), the views keep showing newer
/// previews of it, not one frozen snapshot, and after the release they end
/// on the released value at the chosen resolution.
#[test]
fn a_drag_previews_live_and_ends_on_the_released_value() {
    // Chosen finer than the preview, so that the drag switches to it.
    let mut h = editor_at(Some(example()), 128);
    wait_for(&mut h, "the first run", |s| {
        s.generation == 0 && s.photons > 0
    });
    select_reflector(&mut h);
    let before_drag = h.state().state.simulation().unwrap().generation();
    let start = h.get_by_label("Focal length").rect().center();
    let button = |pos, pressed| egui::Event::PointerButton {
        pos,
        button: egui::PointerButton::Primary,
        pressed,
        modifiers: egui::Modifiers::NONE,
    };
    h.event(egui::Event::PointerMoved(start));
    h.step();
    h.event(button(start, true));
    h.step();
    let mut pos = start;
    let mut shown = Vec::new();
    let previews = |shown: &[u64]| -> Vec<u64> {
        let mut g: Vec<u64> = shown.iter().copied().filter(|&g| g > before_drag).collect();
        g.dedup();
        g
    };
    // A second of dragging, then to and fro (every frame still an edit)
    // until three previews have shown or 400 frames have passed: a loaded
    // machine may take more than the second for its first preview.
    for frame in 0..400 {
        pos.x += if frame < 50 || frame % 2 == 0 {
            2.0
        } else {
            -2.0
        };
        h.event(egui::Event::PointerMoved(pos));
        h.step();
        if let Some(s) = h.state().state.snapshot() {
            shown.push(s.generation);
        }
        if frame >= 50 && previews(&shown).len() >= 3 {
            break;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let during = previews(&shown);
    assert!(
        during.len() >= 3,
        "the previews froze during the drag: generations shown {shown:?}"
    );
    assert!(
        h.state().state.is_coarse_preview(),
        "a drag previews at the coarse resolution"
    );
    h.event(button(pos, false));
    h.step();
    let released = h.state().state.scene().cloned().expect("a scene");
    let last = wait_for(&mut h, "the released value at full resolution", |s| {
        s.map.layout.resolution == 128 && s.luminaire.scene == released && s.photons > 0
    });
    assert!(last.generation > *during.last().unwrap());
    assert!(!h.state().state.is_coarse_preview());
}

#[test]
fn settings_restart_the_run_and_pause_pauses_it() {
    let mut h = editor(Some(example()));
    wait_for(&mut h, "the first run", |s| s.generation == 0);
    h.get_by_label("Symmetry pooling").click();
    h.step();
    h.step();
    let sim = h.state().state.simulation().unwrap();
    assert!(!sim.settings().pool_symmetry);
    assert_eq!(sim.generation(), 1);
    h.get_by_label("Filter").click();
    h.step();
    h.step();
    h.get_by_label("Automatic").click();
    h.step();
    h.step();
    let sim = h.state().state.simulation().unwrap();
    assert_eq!(
        sim.settings().filter,
        lucerna_simulation::FilterChoice::Automatic
    );
    assert_eq!(sim.generation(), 2);
    wait_for(&mut h, "the filtered run", |s| s.generation == 2);
    for (button, then) in [("Pause", "Resume"), ("Resume", "Pause")] {
        h.get_by_label(button).hover();
        h.step();
        h.get_by_label(button).click();
        h.step();
        h.step();
        assert!(
            h.query_by_label(then).is_some(),
            "{button} did not turn into {then}"
        );
    }
}

/// The Design pane, driven as a user would: tick the focal length in
/// the scene panel, set a spec in the pane, Start; while it runs the
/// scene is the design's (an Undo is refused); at the end the scene is
/// the design's result, its file the same bytes as `lucerna design`
/// writes for the same target, variables, seed and budget, and one
/// "Undo design" goes back to the start.
#[test]
fn a_design_run_in_the_pane_gives_the_command_lines_scene_and_undoes_in_one_step() {
    let dir = tempfile::tempdir().unwrap();
    let scene_path = dir.path().join("spot.toml");
    std::fs::copy(example(), &scene_path).unwrap();
    let mut h = editor_at(Some(scene_path.clone()), 32);
    h.state_mut().show_pane(lucerna_editor::dock::Pane::Design);
    common::steps(&mut h, 3);
    select_reflector(&mut h);
    common::click(&mut h, "Vary Focal length");
    // The tick shows the bounds the design keeps the focal length in.
    h.get_by_label_contains("reflector.focal_length: 25.000 mm (");
    common::click(&mut h, "Spec");
    common::set(&mut h, "Beam angle (°)", 6.0);
    common::set(&mut h, "Beam tolerance (°)", 0.5);
    common::click(&mut h, "Stop after");
    common::set(&mut h, "Candidates at most", 8.0);
    h.get_by_label_contains("--vary reflector.focal_length --seed 1 --evaluations 8");
    common::click(&mut h, "Start design");
    assert!(h.state().state.is_designing(), "{:?}", h.state().state);
    // The design owns the scene while it runs.
    command(&mut h, lucerna_editor::Command::Undo);
    assert!(
        h.state()
            .state
            .edit_error()
            .is_some_and(|e| e.contains("a design is running")),
        "{:?}",
        h.state().state.edit_error()
    );
    let deadline = Instant::now() + Duration::from_secs(300);
    while h.state().state.is_designing() {
        h.step();
        assert!(Instant::now() < deadline, "the design did not end");
        std::thread::sleep(Duration::from_millis(20));
    }
    common::steps(&mut h, 2);
    h.get_by_label_contains("Design ended, it traced the candidates it was given");
    let designed = h
        .state()
        .state
        .designed_scene_text()
        .expect("a designed scene")
        .to_owned();

    // The command line's design: the same request `lucerna design SCENE
    // --target SPEC --vary reflector.focal_length --seed 1 --evaluations 8
    // --time 120s` makes, and the file it writes.
    let request = lucerna_design::DesignRequest {
        scene_path: scene_path.clone(),
        target: lucerna_design::Target::Spec(
            lucerna_design::Spec::parse("beam_angle_deg = 6.0\nbeam_tolerance_deg = 0.5\n")
                .unwrap(),
        ),
        vary: vec!["reflector.focal_length".to_owned()],
        free_ends: false,
        budget: lucerna_design::Budget {
            time: Duration::from_secs(120),
            evaluations: Some(8),
            max_photons: None,
        },
        seed: 1,
        resolution: lucerna_design::DEFAULT_RESOLUTION,
        direct: true,
        least_squares: false,
        points: None,
        fallback: Default::default(),
    };
    let cli = lucerna_design::design(
        &request,
        &std::sync::atomic::AtomicBool::new(false),
        &mut |_| {},
    )
    .unwrap();
    let cli_text = lucerna_design::output::scene_text(&cli).unwrap();
    assert_eq!(designed, cli_text);
    let designed_f = focal_length(&h);
    assert!(
        (designed_f - 0.025).abs() > 1e-4,
        "the design moved nothing: {designed_f}"
    );
    assert_eq!(Some(h.state().state.scene().unwrap()), Some(&cli.scene));

    // One undo step for the whole run.
    common::click(&mut h, "Undo design");
    assert_eq!(focal_length(&h), 0.025);
    assert!(!h.state().state.can_undo());
}

/// The Design pane refuses what cannot start, saying why, and changes
/// nothing: nothing ticked, no target file, a spec with no term, a target
/// file that is not photometry.
#[test]
fn the_design_pane_refuses_what_cannot_start_and_says_why() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = editor(Some(example()));
    h.state_mut().show_pane(lucerna_editor::dock::Pane::Design);
    common::steps(&mut h, 3);
    let before = h.state().state.scene().cloned();
    let start = |h: &mut Harness<'_, EditorApp>| {
        common::click(h, "Start design");
        assert!(!h.state().state.is_designing());
        assert_eq!(h.state().state.scene().cloned(), before);
    };
    start(&mut h);
    h.get_by_label_contains("tick what may change");
    select_reflector(&mut h);
    common::click(&mut h, "Vary Focal length");
    start(&mut h);
    h.get_by_label_contains("choose a target file (IES or EULUMDAT) first");
    let not_photometry = dir.path().join("notes.ies");
    std::fs::write(&not_photometry, "hello\n").unwrap();
    command(
        &mut h,
        lucerna_editor::Command::SetDesignTarget(not_photometry),
    );
    start(&mut h);
    h.get_by_label_contains("not a photometric file");
    common::click(&mut h, "Spec");
    common::click(&mut h, "Beam angle");
    start(&mut h);
    // Said twice: under the spec as it is edited, and as Start's refusal.
    assert_eq!(h.get_all_by_label_contains("states no term").count(), 2);
}

/// A design toward a file's shape draws the file at the design's flux:
/// a target of a tenth of the scene's flux would be a tenth of its size,
/// invisible beside the design, although its shape is what is matched.
/// The polar view's label gives the plotted peak; "Match absolute
/// candela" draws it in its own candela.
#[test]
fn the_design_target_is_drawn_at_the_designs_flux_in_shape_mode() {
    let dir = tempfile::tempdir().unwrap();
    let scene_path = dir.path().join("cone.toml");
    std::fs::copy(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/designs/revolved_cone_start.toml"),
        &scene_path,
    )
    .unwrap();
    // A 10° Gaussian beam of about 60 lm, absolute photometry.
    let target = dir.path().join("narrow.ies");
    let gammas: Vec<String> = (0..=180).map(|g| g.to_string()).collect();
    let candela: Vec<String> = (0..=180)
        .map(|g| {
            format!(
                "{:.3}",
                800.0 * (-0.5 * (f64::from(g) / 4.25).powi(2)).exp()
            )
        })
        .collect();
    std::fs::write(
        &target,
        format!(
            "IESNA:LM-63-2002\n[TEST] synthetic 10 degree beam\nTILT=NONE\n1 -1 1 181 1 1 2 0.08 0.08 0\n1 1 0\n{}\n0\n{}\n",
            gammas.join(" "),
            candela.join(" ")
        ),
    )
    .unwrap();
    let reference = lucerna_photometry::read_photometry(&std::fs::read(&target).unwrap())
        .unwrap()
        .table;
    let mut h = editor_at(Some(scene_path), 32);
    h.state_mut().show_pane(lucerna_editor::dock::Pane::Design);
    common::steps(&mut h, 3);
    command(&mut h, lucerna_editor::Command::SetDesignTarget(target));
    common::click(&mut h, "Vary the interior points of reflector");
    common::click(&mut h, "Stop after");
    common::set(&mut h, "Candidates at most", 2.0);
    common::click(&mut h, "Start design");
    let deadline = Instant::now() + Duration::from_secs(300);
    while h.state().state.is_designing() {
        h.step();
        assert!(Instant::now() < deadline, "the design did not end");
        std::thread::sleep(Duration::from_millis(20));
    }
    h.state_mut().show_pane(lucerna_editor::dock::Pane::View(
        lucerna_editor::View::Polar,
    ));
    common::steps(&mut h, 3);
    let plotted = |h: &Harness<'_, EditorApp>| -> (f64, f64) {
        let node = h.get_by_label_contains("Reference peak");
        let text = node.value().unwrap_or_default();
        let number: f64 = text
            .split_whitespace()
            .nth(2)
            .and_then(|v| v.parse().ok())
            .unwrap_or_else(|| panic!("no peak in {text}"));
        let shown = h.state().state.snapshot().unwrap().table.flux_lm();
        (number, shown)
    };
    h.step();
    let (peak, shown_flux) = plotted(&h);
    let expected = reference.peak().0 * shown_flux / reference.flux_lm();
    assert!(
        (peak - expected).abs() <= 0.01 * expected + 1.0,
        "plotted {peak} cd, the target's shape at {shown_flux:.0} lm is {expected:.0} cd"
    );
    // Far from the file's own candela: what the design matches is its
    // shape at the design's flux.
    assert!(peak > 5.0 * reference.peak().0, "{peak}");
    h.get_by_label_contains("as the design matches it");
}

/// The Tolerance pane, driven as a user would: the LED's placement
/// tolerance set beside its parameters, the Design pane's spec, Run; the
/// samples arrive and the yield is shown; the samples are those `lucerna
/// tolerance` traces for the same tolerances, spec and seed; a sample
/// opened from its bar is one undo step.
#[test]
fn a_tolerance_analysis_in_the_pane_gives_the_command_lines_samples() {
    let mut h = editor_at(Some(example()), 32);
    h.state_mut()
        .show_pane(lucerna_editor::dock::Pane::Tolerance);
    common::steps(&mut h, 3);
    common::click(&mut h, "Run tolerance analysis");
    h.get_by_label_contains("set a tolerance first");
    h.get_by_label("Emitter LED").click();
    common::steps(&mut h, 2);
    common::click(&mut h, "translate_x");
    common::set(&mut h, "σ translate_x", 0.3);
    h.get_by_label_contains("LED.translate_x: σ 0.3 mm");
    common::set(&mut h, "Samples", 6.0);
    common::set(&mut h, "Photons per sample", 20_000.0);
    let before = h.state().state.scene().cloned().unwrap();
    common::click(&mut h, "Run tolerance analysis");
    assert!(h.state().state.is_analysing_tolerances());
    let deadline = Instant::now() + Duration::from_secs(300);
    while h.state().state.is_analysing_tolerances() {
        h.step();
        assert!(Instant::now() < deadline, "the analysis did not end");
        std::thread::sleep(Duration::from_millis(20));
    }
    common::steps(&mut h, 2);
    h.get_by_label_contains("of 6 built luminaires");
    let (samples, passed) = h.state().state.tolerance_samples();
    assert_eq!(samples, 6);

    // The library's run of the same tolerances, spec and seed.
    let tolerances = lucerna_tolerance::tolerances::parse(
        "[[tolerance]]\nat = \"LED.translate_x\"\nnormal = { sigma = 0.0003 }\n",
        &before,
    )
    .unwrap();
    let setup = lucerna_tolerance::Setup::new(
        before.clone(),
        example().parent().unwrap(),
        lucerna_design::Target::Spec(
            lucerna_design::Spec::parse("beam_angle_deg = 24.0\nbeam_tolerance_deg = 1.0\n")
                .unwrap(),
        ),
        None,
        tolerances,
        lucerna_tolerance::Settings {
            photons: 20_000,
            noise_runs: 4,
            ..lucerna_tolerance::Settings::default()
        },
    )
    .unwrap();
    let (records, _) = setup.run(
        0..6,
        &lucerna_tolerance::Budget {
            samples: Some(6),
            ..Default::default()
        },
        &std::sync::atomic::AtomicBool::new(false),
        &mut |_, _| {},
    );
    assert_eq!(records.iter().filter(|r| r.passes()).count(), passed);

    // Sample 2 as the scene, and back in one step.
    command(&mut h, lucerna_editor::Command::OpenToleranceSample(2));
    let moved = h.state().state.scene().unwrap().emitters[0]
        .transform
        .translate[0];
    let want = setup.model.scene(&setup.model.draw(2)).unwrap().emitters[0]
        .transform
        .translate[0];
    assert_eq!(moved, want);
    assert!(moved != 0.0);
    command(&mut h, lucerna_editor::Command::Undo);
    assert_eq!(h.state().state.scene(), Some(&before));
}

#[test]
fn a_finish_is_set_in_a_toolmakers_numbers_and_the_light_follows() {
    use egui::accesskit::Role;
    use lucerna_scene::finish::Finish;
    let mut h = editor_at(Some(example()), 64);
    let smooth = wait_for(&mut h, "the first run", finished(0));
    select_reflector(&mut h);
    h.get_by_role_and_label(Role::ComboBox, "Finish").click();
    h.step();
    h.step();
    h.get_by_label("dimples").click();
    h.step();
    h.step();
    let depth = |h: &Harness<'_, EditorApp>| match &h.state().state.scene().unwrap().parts[0].finish
    {
        Some(Finish::Dimples { depth, .. }) => *depth,
        other => panic!("expected dimples, got {other:?}"),
    };
    // A toolmaker's default: 0.15 mm deep on 2 mm.
    assert!((depth(&h) - 0.15e-3).abs() < 1e-12, "{}", depth(&h));
    let hammered = wait_for(&mut h, "the hammered run", finished(1));
    // The dimples spread nine tenths of the light out of the beam: the
    // peak falls, the flux stays (a mirror's 0.9 either way).
    assert!(
        hammered.figures.peak_cd < 0.5 * smooth.figures.peak_cd,
        "{} vs {}",
        hammered.figures.peak_cd,
        smooth.figures.peak_cd
    );
    // Shallower dimples leave more land: the peak comes back part way.
    h.get_by_label("Dimple depth").set_value_accesskit(0.07);
    h.step();
    h.step();
    assert!((depth(&h) - 0.07e-3).abs() < 1e-9, "{}", depth(&h));
    let shallow = wait_for(&mut h, "the shallower run", finished(2));
    assert!(shallow.figures.peak_cd > 1.5 * hammered.figures.peak_cd);
    // A depth the punch cannot make on this pitch is refused, naming
    // the field, and the last valid run goes on.
    h.get_by_label("Dimple depth").set_value_accesskit(0.5);
    h.step();
    h.step();
    let problems = h.state().state.problems().join("\n");
    assert!(problems.contains("finish.pitch"), "{problems}");
    assert_eq!(h.state().state.simulation().unwrap().generation(), 2);
}
