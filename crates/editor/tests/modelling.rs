#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: tests may panic
//! The modelling side of the editor driven through its labelled widgets:
//! every shape added, the profile editor, emitters and materials, the
//! simulation's controls, and the coarse preview while dragging. CPU
//! backend, small maps and few photons keep every run short.

mod common;

use common::{choose, click, menu, set, steps, type_into};

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use egui::{Event, Modifiers, PointerButton, Pos2, vec2};
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use lucerna_editor::{EditorApp, EditorState, NewPart};
use lucerna_scene::{Emission, EmitterShape, Shape};
use lucerna_simulation::{
    BackendRequest, RunState, SimulationSettings, Snapshot, StopReason, StoppingRule,
};

const PHOTONS: u64 = 200_000;

fn example() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires/parabolic_spot.toml")
}

fn settings(resolution: u32, photons: Option<u64>) -> SimulationSettings {
    SimulationSettings {
        resolution,
        backend: BackendRequest::Cpu,
        stop: StoppingRule {
            photons,
            ..StoppingRule::default()
        },
        ..SimulationSettings::default()
    }
}

fn editor_with(settings: SimulationSettings) -> Harness<'static, EditorApp> {
    // Frames a sixtieth of a second apart, so that two clicks in
    // successive frames make a double-click.
    let mut h = Harness::builder()
        .with_size([1366.0, 1400.0])
        .with_step_dt(1.0 / 60.0)
        .build_ui_state(
            |ui, app: &mut EditorApp| app.ui(ui),
            EditorApp::new(EditorState::new(Some(example()), settings)),
        );
    h.step();
    h
}

fn editor() -> Harness<'static, EditorApp> {
    editor_with(settings(32, Some(PHOTONS)))
}

fn state<'a>(h: &'a Harness<'_, EditorApp>) -> &'a EditorState {
    &h.state().state
}

fn generation(h: &Harness<'_, EditorApp>) -> u64 {
    state(h).simulation().expect("a simulation").generation()
}

fn problems(h: &Harness<'_, EditorApp>) -> Vec<String> {
    state(h).problems().to_vec()
}

/// Steps frames until the shown snapshot satisfies `done`.
fn wait_for(
    h: &mut Harness<'_, EditorApp>,
    what: &str,
    done: impl Fn(&Snapshot) -> bool,
) -> Arc<Snapshot> {
    let deadline = Instant::now() + Duration::from_secs(90);
    loop {
        h.step();
        if let Some(s) = state(h).snapshot()
            && done(s)
        {
            return s.clone();
        }
        if let Some(sim) = state(h).simulation()
            && let Some((g, e)) = sim.published().error
            && g == sim.generation()
        {
            panic!("simulation failed while waiting for {what}: {e}");
        }
        assert!(Instant::now() < deadline, "timed out waiting for {what}");
        std::thread::sleep(Duration::from_millis(10));
    }
}

fn button(pos: Pos2, button: PointerButton, pressed: bool) -> Event {
    Event::PointerButton {
        pos,
        button,
        pressed,
        modifiers: Modifiers::NONE,
    }
}

fn add_part(h: &mut Harness<'_, EditorApp>, kind: &str) {
    click(h, "Add part");
    click(h, &format!("Add {kind}"));
}

/// The profile of part `i` (m).
fn profile(h: &Harness<'_, EditorApp>, i: usize) -> Vec<[f64; 2]> {
    match &state(h).scene().unwrap().parts[i].shape {
        Shape::Revolved(s) => s.profile.clone(),
        Shape::Extruded(s) => s.profile.clone(),
        other => panic!("part {i} has no profile: {other:?}"),
    }
}

/// Adds a revolved part (part 1 after the example's reflector), selected.
fn with_revolved_part() -> Harness<'static, EditorApp> {
    let mut h = editor();
    add_part(&mut h, "revolved");
    assert_eq!(state(&h).scene().unwrap().parts[1].shape.kind(), "revolved");
    // Its profile in the Profile pane.
    click(&mut h, "Edit the profile");
    h
}

#[test]
fn every_shape_kind_is_added_valid_and_each_add_undoes_in_one_step() {
    let mut h = editor();
    for (k, kind) in NewPart::ALL.iter().enumerate() {
        let before = generation(&h);
        add_part(&mut h, kind.kind());
        let scene = state(&h).scene().unwrap();
        assert_eq!(scene.parts.len(), k + 2, "{kind:?}");
        assert_eq!(scene.parts[k + 1].shape.kind(), kind.kind());
        assert!(problems(&h).is_empty(), "{kind:?}: {:?}", problems(&h));
        // Valid at once, so simulated at once.
        assert!(generation(&h) > before, "{kind:?} was not simulated");
        // Its parameters are shown (no "edited in the scene file").
        assert!(
            h.query_by_label_contains("edited in the scene file")
                .is_none()
        );
    }
    for expected in (1..=NewPart::ALL.len()).rev() {
        menu(&mut h, "Edit", "Undo");
        assert_eq!(state(&h).scene().unwrap().parts.len(), expected);
    }
}

#[test]
fn the_louvre_and_extrusion_parameters_are_edited_in_millimetres_and_degrees() {
    let mut h = editor();
    add_part(&mut h, "louvre");
    set(&mut h, "Blade spacing", 25.0);
    set(&mut h, "Blade tilt", 30.0);
    set(&mut h, "Cross blade count", 3.0);
    match &state(&h).scene().unwrap().parts[1].shape {
        Shape::Louvre(l) => {
            assert!((l.spacing - 0.025).abs() < 1e-12);
            assert_eq!(l.tilt_deg, 30.0);
            assert_eq!(l.cross_blade_count, 3);
            assert!(l.cross_spacing > 0.0, "cross blades need a spacing");
        }
        other => panic!("{other:?}"),
    }
    assert!(problems(&h).is_empty(), "{:?}", problems(&h));
    add_part(&mut h, "extruded");
    set(&mut h, "Length", 500.0);
    match &state(&h).scene().unwrap().parts[2].shape {
        Shape::Extruded(e) => assert!((e.length - 0.5).abs() < 1e-12),
        other => panic!("{other:?}"),
    }
    // An extrusion's x may be negative.
    click(&mut h, "Edit the profile");
    set(&mut h, "Point 1 x", -60.0);
    assert!((profile(&h, 2)[0][0] + 0.06).abs() < 1e-12);
    assert!(problems(&h).is_empty(), "{:?}", problems(&h));
    h.get_by_label("Reverse points").click();
    steps(&mut h, 2);
    assert_eq!(profile(&h, 2)[0], [0.05, -0.01]);
    assert!((profile(&h, 2)[4][0] + 0.06).abs() < 1e-12);
}

#[test]
fn dragging_a_profile_point_moves_it_in_one_undo_step() {
    let mut h = with_revolved_part();
    let original = profile(&h, 1);
    let before = generation(&h);
    let start = h.get_by_label("Profile point 2").rect().center();
    h.event(Event::PointerMoved(start));
    h.step();
    h.event(button(start, PointerButton::Primary, true));
    h.step();
    let mut pos = start;
    let mut seen = Vec::new();
    for _ in 0..6 {
        pos += vec2(8.0, 0.0);
        h.event(Event::PointerMoved(pos));
        h.step();
        seen.push(profile(&h, 1)[1]);
    }
    h.event(button(pos, PointerButton::Primary, false));
    steps(&mut h, 2);
    let dragged = profile(&h, 1);
    assert!(dragged[1][0] > original[1][0] + 1e-3, "{seen:?}");
    assert!((dragged[1][1] - original[1][1]).abs() < 1e-3, "{seen:?}");
    assert_eq!(dragged[0], original[0]);
    assert_eq!(dragged[2..], original[2..]);
    seen.dedup();
    assert!(seen.len() > 2, "the point followed the pointer: {seen:?}");
    // The reflector updated live.
    assert!(generation(&h) > before);
    menu(&mut h, "Edit", "Undo");
    assert_eq!(profile(&h, 1), original);
    menu(&mut h, "Edit", "Redo");
    assert_eq!(profile(&h, 1), dragged);
}

#[test]
fn a_point_dragged_past_the_optical_axis_stops_on_it() {
    let mut h = with_revolved_part();
    let original = profile(&h, 1);
    let start = h.get_by_label("Profile point 1").rect().center();
    h.event(Event::PointerMoved(start));
    h.step();
    h.event(button(start, PointerButton::Primary, true));
    h.step();
    let mut pos = start;
    for _ in 0..8 {
        pos += vec2(-20.0, 0.0);
        h.event(Event::PointerMoved(pos));
        h.step();
    }
    h.event(button(pos, PointerButton::Primary, false));
    steps(&mut h, 2);
    let dragged = profile(&h, 1);
    assert_eq!(dragged[0][0], 0.0, "{dragged:?}");
    assert!((dragged[0][1] - original[0][1]).abs() < 1e-3, "{dragged:?}");
    assert!(problems(&h).is_empty(), "{:?}", problems(&h));
}

#[test]
fn the_profile_table_edits_points_in_millimetres_and_refuses_a_negative_radius() {
    let mut h = with_revolved_part();
    set(&mut h, "Point 2 z", 40.0);
    assert!((profile(&h, 1)[1][1] - 0.04).abs() < 1e-12);
    set(&mut h, "Point 3 r", -5.0);
    assert_eq!(profile(&h, 1)[2][0], 0.0, "a negative radius is clamped");
    assert!(problems(&h).is_empty(), "{:?}", problems(&h));
    menu(&mut h, "Edit", "Undo");
    menu(&mut h, "Edit", "Undo");
    assert_eq!(profile(&h, 1), with_revolved_part_profile());
}

fn with_revolved_part_profile() -> Vec<[f64; 2]> {
    match NewPart::Revolved.shape() {
        Shape::Revolved(s) => s.profile,
        _ => unreachable!(),
    }
}

#[test]
fn profile_points_are_added_and_deleted_each_in_one_undo_step() {
    let mut h = with_revolved_part();
    let original = profile(&h, 1);
    // "Add point" with nothing selected splits the last segment.
    click(&mut h, "Add point");
    let added = profile(&h, 1);
    assert_eq!(added.len(), 5);
    assert_eq!(added[..3], original[..3]);
    assert_eq!(added[4], original[3]);
    // On the curve between the two, not on their chord.
    let (a, b, m) = (original[2], original[3], added[3]);
    assert!(
        m[0] > a[0] && m[0] < b[0] && m[1] < a[1] && m[1] > b[1],
        "{m:?}"
    );
    assert_ne!(m, [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])]);
    menu(&mut h, "Edit", "Undo");
    assert_eq!(profile(&h, 1), original);

    // A double-click on the curve between points 2 and 3 inserts there.
    let p2 = h.get_by_label("Profile point 2").rect().center();
    let p3 = h.get_by_label("Profile point 3").rect().center();
    let mid = p2 + 0.5 * (p3 - p2);
    h.event(Event::PointerMoved(mid));
    // Half a second after the last click, so that these two are a
    // double-click, not the end of a triple one.
    steps(&mut h, 30);
    for _ in 0..2 {
        h.event(button(mid, PointerButton::Primary, true));
        h.step();
        h.event(button(mid, PointerButton::Primary, false));
        h.step();
    }
    steps(&mut h, 2);
    let inserted = profile(&h, 1);
    assert_eq!(inserted.len(), 5, "{inserted:?}");
    assert!(
        inserted[2][0] > original[1][0] && inserted[2][0] < original[2][0],
        "{inserted:?}"
    );
    menu(&mut h, "Edit", "Undo");
    assert_eq!(profile(&h, 1), original);

    // A right-click deletes a point; so does "Delete point" on the
    // selected one.
    let p1 = h.get_by_label("Profile point 1").rect().center();
    h.event(Event::PointerMoved(p1));
    h.step();
    h.event(button(p1, PointerButton::Secondary, true));
    h.step();
    h.event(button(p1, PointerButton::Secondary, false));
    steps(&mut h, 2);
    assert_eq!(profile(&h, 1), original[1..]);
    click(&mut h, "Profile point 2");
    click(&mut h, "Delete point");
    assert_eq!(profile(&h, 1), [original[1], original[3]]);
    assert!(problems(&h).is_empty(), "{:?}", problems(&h));
    // Two points are the least a profile keeps.
    let p1 = h.get_by_label("Profile point 1").rect().center();
    h.event(Event::PointerMoved(p1));
    h.step();
    h.event(button(p1, PointerButton::Secondary, true));
    h.step();
    h.event(button(p1, PointerButton::Secondary, false));
    steps(&mut h, 2);
    assert_eq!(profile(&h, 1).len(), 2);
    let refusal = state(&h).edit_error().expect("a refusal").to_owned();
    assert!(refusal.contains("at least 2"), "{refusal}");
    // Beside the action and in the status bar.
    assert!(
        h.query_all_by_label_contains("A profile needs at least 2 control points")
            .count()
            >= 1
    );
    for expected in [original[1..].to_vec(), original.clone()] {
        menu(&mut h, "Edit", "Undo");
        assert_eq!(profile(&h, 1), expected);
    }
}

#[test]
fn a_bad_profile_edit_shows_the_validators_message_and_is_not_simulated() {
    let mut h = with_revolved_part();
    set(&mut h, "Point 1 r", 0.0);
    assert!(problems(&h).is_empty(), "{:?}", problems(&h));
    let valid = generation(&h);
    // Two consecutive points on the axis revolve into nothing.
    set(&mut h, "Point 2 r", 0.0);
    let found = problems(&h);
    assert!(
        found
            .iter()
            .any(|p| p.starts_with("part[1].shape.profile[1]") && p.contains("on the axis")),
        "{found:?}"
    );
    // Beside the action and in the status bar.
    assert!(
        h.query_all_by_label_contains("Point 2: two consecutive points on the axis")
            .count()
            >= 1
    );
    assert_eq!(generation(&h), valid, "an invalid profile was simulated");
    set(&mut h, "Point 2 r", 10.0);
    assert!(problems(&h).is_empty(), "{:?}", problems(&h));
    assert_eq!(generation(&h), valid + 1);
}

#[test]
fn renaming_a_material_renames_it_in_the_parts_in_one_undo_step() {
    let mut h = editor();
    click(&mut h, "Material polished_alu (mirror)");
    type_into(&mut h, "Material name", "anodised");
    let scene = state(&h).scene().unwrap();
    assert!(scene.materials.contains_key("anodised"));
    assert!(!scene.materials.contains_key("polished_alu"));
    assert_eq!(scene.parts[0].material, "anodised");
    assert!(problems(&h).is_empty(), "{:?}", problems(&h));
    // Beside the action and in the status bar.
    assert!(
        h.query_all_by_label_contains("Material anodised (mirror)")
            .count()
            >= 1
    );
    menu(&mut h, "Edit", "Undo");
    let scene = state(&h).scene().unwrap();
    assert!(scene.materials.contains_key("polished_alu"));
    assert_eq!(scene.parts[0].material, "polished_alu");
    assert!(!state(&h).is_dirty());

    // A name taken already is refused, and nothing changes.
    click(&mut h, "Add material");
    type_into(&mut h, "Material name", "polished_alu");
    let refusal = state(&h).edit_error().expect("a refusal").to_owned();
    assert!(refusal.contains("exists already"), "{refusal}");
    let scene = state(&h).scene().unwrap();
    assert_eq!(scene.materials.len(), 2);
    assert!(scene.materials.contains_key("material"));
}

#[test]
fn renaming_a_part_renames_the_opening_that_names_it() {
    let mut h = editor();
    click(&mut h, "Part reflector (paraboloid)");
    type_into(&mut h, "Name", "spun reflector");
    let scene = state(&h).scene().unwrap();
    assert_eq!(scene.parts[0].name, "spun reflector");
    assert_eq!(
        scene.opening,
        Some(lucerna_scene::LuminousOpening::PartAperture {
            part: "spun reflector".to_owned()
        })
    );
    assert!(problems(&h).is_empty(), "{:?}", problems(&h));
    menu(&mut h, "Edit", "Undo");
    assert_eq!(state(&h).scene().unwrap().parts[0].name, "reflector");
    assert!(!state(&h).is_dirty());
    // An empty name is refused.
    click(&mut h, "Part reflector (paraboloid)");
    type_into(&mut h, "Name", " ");
    assert!(state(&h).edit_error().is_some_and(|e| e.contains("empty")));
    assert_eq!(state(&h).scene().unwrap().parts[0].name, "reflector");
}

#[test]
fn a_material_in_use_is_not_deleted_and_one_unused_is() {
    let mut h = editor();
    click(&mut h, "Material polished_alu (mirror)");
    click(&mut h, "Delete material");
    assert!(
        state(&h)
            .scene()
            .unwrap()
            .materials
            .contains_key("polished_alu")
    );
    let refusal = state(&h).edit_error().expect("a refusal").to_owned();
    assert!(refusal.contains("part reflector"), "{refusal}");
    // Beside the action and in the status bar.
    assert!(
        h.query_all_by_label_contains("Cannot delete material polished_alu")
            .count()
            >= 1
    );
    assert!(!state(&h).is_dirty());

    click(&mut h, "Add material");
    click(&mut h, "Duplicate material");
    let names: Vec<String> = state(&h)
        .scene()
        .unwrap()
        .materials
        .keys()
        .cloned()
        .collect();
    assert_eq!(names, ["material", "material 2", "polished_alu"]);
    click(&mut h, "Delete material");
    assert_eq!(state(&h).scene().unwrap().materials.len(), 2);
    assert_eq!(state(&h).edit_error(), None);
    menu(&mut h, "Edit", "Undo");
    assert_eq!(state(&h).scene().unwrap().materials.len(), 3);
}

#[test]
fn emitters_are_added_duplicated_switched_disabled_and_deleted() {
    let mut h = editor();
    click(&mut h, "Add emitter");
    click(&mut h, "Duplicate emitter");
    let names: Vec<String> = state(&h)
        .scene()
        .unwrap()
        .emitters
        .iter()
        .map(|e| e.name.clone())
        .collect();
    assert_eq!(names, ["LED", "LED 2", "LED 3"]);
    choose(&mut h, "Emitter shape", "rectangle");
    assert_eq!(
        state(&h).scene().unwrap().emitters[2].shape,
        EmitterShape::Rectangle {
            width: 0.003,
            depth: 0.003
        }
    );
    choose(&mut h, "Emitter shape", "cylinder");
    choose(&mut h, "Emitter shape", "sphere");
    assert_eq!(
        state(&h).scene().unwrap().emitters[2].shape,
        EmitterShape::Sphere { radius: 0.0015 }
    );
    click(&mut h, "Enabled");
    assert!(!state(&h).scene().unwrap().emitters[2].enabled);
    h.get_by_label("Emitter LED 3 (off)");
    assert!(problems(&h).is_empty(), "{:?}", problems(&h));
    click(&mut h, "Delete emitter");
    assert_eq!(state(&h).scene().unwrap().emitters.len(), 2);
    // Add, duplicate, three shape switches, disable, delete: seven steps.
    for _ in 0..7 {
        menu(&mut h, "Edit", "Undo");
    }
    assert_eq!(state(&h).scene().unwrap().emitters.len(), 1);
    assert!(!state(&h).is_dirty());
}

#[test]
fn a_measured_emitter_profile_is_simulated_and_a_missing_one_is_an_error() {
    let mut h = editor();
    wait_for(&mut h, "the first run", |s| {
        matches!(s.state, RunState::Finished(_))
    });
    click(&mut h, "Emitter LED");
    choose(&mut h, "Emission", "Measured (IES/LDT file)");
    // Empty, it is an invalid scene, not a run.
    assert!(
        problems(&h).iter().any(|p| p.contains("emission")),
        "{:?}",
        problems(&h)
    );
    // The chooser lists the profiles beside the scene's folder.
    let file = "../profiles/samples/bega_50975_1995_single_h.ies";
    choose(&mut h, "Choose profile file", file);
    assert_eq!(
        state(&h).scene().unwrap().emitters[0].emission,
        Emission::Profile(file.to_owned())
    );
    assert!(problems(&h).is_empty(), "{:?}", problems(&h));
    // Beside the action and in the status bar.
    assert!(h.query_all_by_label_contains("Reads ").count() >= 1);
    let g = generation(&h);
    let measured = wait_for(&mut h, "the run with the measured profile", |s| {
        s.generation == g && matches!(s.state, RunState::Finished(_))
    });
    assert_eq!(measured.photons, PHOTONS);
    assert!(measured.figures.flux_lm > 0.0);

    type_into(&mut h, "Profile file", "../profiles/missing.ies");
    let deadline = Instant::now() + Duration::from_secs(60);
    let error = loop {
        h.step();
        if let Some(e) = state(&h).simulation_error() {
            break e.to_owned();
        }
        assert!(Instant::now() < deadline, "no error for a missing file");
        std::thread::sleep(Duration::from_millis(10));
    };
    assert!(error.contains("missing.ies"), "{error}");
    assert!(h.query_all_by_label_contains("missing.ies").count() > 0);
    // The editor keeps running: back to a real file, and it simulates.
    steps(&mut h, 5);
    type_into(&mut h, "Profile file", file);
    let g = generation(&h);
    wait_for(&mut h, "the run after the error", |s| {
        s.generation == g && matches!(s.state, RunState::Finished(_))
    });
    assert_eq!(state(&h).simulation_error(), None);
}

#[test]
fn a_manual_filter_threshold_reaches_the_snapshot() {
    let mut h = editor();
    choose(&mut h, "Filter", "Manual threshold");
    set(&mut h, "Photon threshold", 250.0);
    let sim = state(&h).simulation().unwrap();
    assert_eq!(
        sim.settings().filter,
        lucerna_simulation::FilterChoice::Threshold(250.0)
    );
    let g = sim.generation();
    // A later run (the end of a coarse preview the combo's click may
    // have started) carries the same settings; under load generation g
    // can be superseded before its first snapshot.
    let s = wait_for(&mut h, "a filtered snapshot", |s| {
        s.generation >= g && s.filter.is_some()
    });
    let rule = &s.filter.as_ref().unwrap().rule;
    assert!(rule.contains("fixed threshold 250"), "{rule}");
    // Beside the action and in the status bar.
    assert!(h.query_all_by_label_contains("fixed threshold 250").count() >= 1);
}

#[test]
fn stop_at_peak_noise_finishes_the_run_by_itself() {
    // No photon limit: only the noise target stops it.
    let mut h = editor_with(settings(16, None));
    click(&mut h, "Stop at peak noise");
    set(&mut h, "Target peak noise", 5.0);
    let sim = state(&h).simulation().unwrap();
    assert_eq!(sim.settings().stop.peak_relative_error, Some(0.05));
    let g = sim.generation();
    let s = wait_for(&mut h, "the run to meet its noise target", |s| {
        s.generation == g && matches!(s.state, RunState::Finished(_))
    });
    assert_eq!(s.state, RunState::Finished(StopReason::TargetError));
    assert!(s.noise.peak_relative <= 0.05, "{}", s.noise.peak_relative);
}

#[test]
fn backend_and_bounce_limit_reach_the_simulation() {
    let mut h = editor();
    set(&mut h, "Max bounces", 5.0);
    assert_eq!(state(&h).simulation().unwrap().settings().max_bounces, 5);
    choose(&mut h, "Backend", "Automatic");
    assert_eq!(
        state(&h).simulation().unwrap().settings().backend,
        BackendRequest::Auto
    );
    choose(&mut h, "Backend", "CPU");
    assert_eq!(
        state(&h).simulation().unwrap().settings().backend,
        BackendRequest::Cpu
    );
}

#[test]
fn a_drag_previews_at_a_coarse_resolution_then_returns_to_the_chosen_one() {
    let mut h = editor_with(settings(128, Some(PHOTONS)));
    wait_for(&mut h, "the first run", |s| s.map.layout.resolution == 128);
    click(&mut h, "Part reflector (paraboloid)");
    let start = h.get_by_label("Focal length").rect().center();
    h.event(Event::PointerMoved(start));
    h.step();
    h.event(button(start, PointerButton::Primary, true));
    h.step();
    let mut pos = start;
    for _ in 0..4 {
        pos += vec2(10.0, 0.0);
        h.event(Event::PointerMoved(pos));
        h.step();
    }
    assert!(state(&h).is_coarse_preview());
    assert_eq!(state(&h).settings().resolution, 128);
    let sim = state(&h).simulation().unwrap();
    assert_eq!(sim.settings().resolution, 64);
    let g = sim.generation();
    // The pointer is still down: the preview is coarse.
    let during = wait_for(&mut h, "a preview snapshot", |s| s.generation == g);
    assert_eq!(during.map.layout.resolution, 64);
    h.event(button(pos, PointerButton::Primary, false));
    steps(&mut h, 2);
    assert!(!state(&h).is_coarse_preview());
    let sim = state(&h).simulation().unwrap();
    assert_eq!(sim.settings().resolution, 128);
    let g = sim.generation();
    let after = wait_for(&mut h, "the snapshot after the drag", |s| s.generation == g);
    assert_eq!(after.map.layout.resolution, 128);
    // The scene of the drag is what runs at the chosen resolution.
    let f = match &state(&h).scene().unwrap().parts[0].shape {
        Shape::Paraboloid(p) => p.focal_length,
        _ => unreachable!(),
    };
    assert!(f > 0.025 + 1e-4, "{f}");
}

/// A paraboloid's section is shown read-only in the Profile pane; one
/// button makes it an editable revolved profile within 0.05 mm of it,
/// and one undo brings the paraboloid back.
#[test]
fn a_paraboloid_shows_its_section_and_converts_to_a_profile_in_one_undo_step() {
    let mut h = editor();
    click(&mut h, "Part reflector (paraboloid)");
    click(&mut h, "Show the section");
    assert!(
        h.query_by_label_contains("Section of reflector (paraboloid)")
            .is_some()
    );
    let before = state(&h).scene().unwrap().parts[0].shape.clone();
    click(&mut h, "Convert to editable profile");
    steps(&mut h, 2);
    let points = profile(&h, 0);
    assert!(points.len() >= 5, "{points:?}");
    // The ends are the paraboloid's: the vertex on the axis at f, the rim
    // at the aperture's radius in the focal plane.
    let (first, last) = (points[0], points[points.len() - 1]);
    assert!(
        first[0].abs() < 1e-12 && (first[1] - 0.025).abs() < 1e-12,
        "{first:?}"
    );
    assert!(
        (last[0] - 0.05).abs() < 1e-12 && last[1].abs() < 1e-12,
        "{last:?}"
    );
    // Every point lies on the paraboloid z = f - r²/4f.
    for p in &points {
        let z = 0.025 - p[0] * p[0] / 0.1;
        assert!((p[1] - z).abs() < 1e-9, "{p:?} off the paraboloid");
    }
    assert!(problems(&h).is_empty(), "{:?}", problems(&h));
    // Now the editable profile, and one undo restores the paraboloid.
    assert!(h.query_by_label_contains("Profile of reflector").is_some());
    menu(&mut h, "Edit", "Undo");
    assert_eq!(state(&h).scene().unwrap().parts[0].shape, before);
}

/// Any part shows its cut by a chosen C-plane in the Profile pane, with
/// the fan of rays from the emitters through the luminaire: the louvre
/// of the linear example, in C0 and then C90.
#[test]
fn a_louvre_shows_its_section_in_a_chosen_c_plane_with_the_emitters_ray_fan() {
    let path =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires/linear_louvre.toml");
    let mut h = Harness::builder()
        .with_size([1366.0, 900.0])
        .build_ui_state(
            |ui, app: &mut EditorApp| app.ui(ui),
            EditorApp::new(EditorState::new(Some(path), settings(64, Some(200_000)))),
        );
    steps(&mut h, 2);
    click(&mut h, "Part louvre (louvre)");
    click(&mut h, "Show the section");
    // The fan needs the run's first luminaire.
    let deadline = Instant::now() + Duration::from_secs(60);
    while state(&h).snapshot().is_none() {
        h.step();
        assert!(Instant::now() < deadline, "no snapshot");
        std::thread::sleep(Duration::from_millis(20));
    }
    steps(&mut h, 2);
    assert!(
        h.query_by_label_contains("Section of louvre (louvre) in C0")
            .is_some()
    );
    // The LED strip's rectangle: its centre and two edges, 15 rays each.
    assert!(h.query_by_label_contains("45 rays through them").is_some());
    set(&mut h, "Section in C-plane", 90.0);
    assert!(
        h.query_by_label_contains("Section of louvre (louvre) in C90")
            .is_some()
    );
    assert!(
        h.query_by_label_contains("The plane does not cut it here")
            .is_none()
    );
}
