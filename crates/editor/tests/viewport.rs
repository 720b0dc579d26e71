#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! The 3D view driven through its pointer: a click selects what the
//! tracer's BVH finds under it, a drag orbits, the wheel zooms; and one
//! snapshot of the main window with the view drawn by wgpu.

mod common;

use std::path::PathBuf;
use std::time::{Duration, Instant};

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use lucerna_editor::{BenchmarkOptions, EditorApp, EditorState, Selection};
use lucerna_simulation::{SimulationSettings, StoppingRule};

fn example() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires/parabolic_spot.toml")
}

fn settings(photons: u64) -> SimulationSettings {
    SimulationSettings {
        resolution: 32,
        stop: StoppingRule {
            photons: Some(photons),
            ..StoppingRule::default()
        },
        ..SimulationSettings::default()
    }
}

fn editor() -> Harness<'static, EditorApp> {
    Harness::builder()
        .with_size([1366.0, 900.0])
        .build_ui_state(
            |ui, app: &mut EditorApp| app.ui(ui),
            EditorApp::new(EditorState::new(Some(example()), settings(200_000))),
        )
}

/// Steps until a snapshot is shown (and `done` holds for it).
fn wait_for_snapshot(h: &mut Harness<'_, EditorApp>, done: impl Fn(&EditorApp) -> bool) {
    let start = Instant::now();
    while !(h.state().state.snapshot().is_some() && done(h.state())) {
        assert!(start.elapsed() < Duration::from_secs(120), "no snapshot");
        std::thread::sleep(Duration::from_millis(20));
        h.step();
    }
    h.run_steps(2);
}

fn click_at(h: &mut Harness<'_, EditorApp>, pos: egui::Pos2) {
    h.hover_at(pos);
    h.step();
    h.drag_at(pos);
    h.step();
    h.drop_at(pos);
    h.run_steps(2);
}

#[test]
fn a_click_in_the_3d_view_selects_what_lies_under_it() {
    let mut h = editor();
    wait_for_snapshot(&mut h, |_| true);
    h.get_by_label("Below").click();
    h.run_steps(2);
    let view = h.get_by_label("Luminaire in 3D").rect();
    // From below, a ray next to the axis meets the 1.5 mm LED at the
    // reflector's focus (just off the axis: the axis runs along an edge
    // of the LED's triangle fan).
    click_at(&mut h, view.center() + egui::vec2(1.5, 1.0));
    assert_eq!(h.state().state.selection(), Some(&Selection::Emitter(0)));
    // Aside from the axis it meets the reflector's inside.
    click_at(&mut h, view.center() + egui::vec2(0.2 * view.width(), 0.0));
    assert_eq!(h.state().state.selection(), Some(&Selection::Part(0)));
    // The scene panel now edits that part.
    assert!(h.query_by_label("Focal length").is_some());
    // Beside the luminaire nothing is hit: the selection clears.
    click_at(
        &mut h,
        view.left_top() + egui::vec2(10.0, 0.9 * view.height()),
    );
    assert_eq!(h.state().state.selection(), None);
}

#[test]
fn a_drag_orbits_the_camera_and_the_wheel_zooms() {
    let mut h = editor();
    wait_for_snapshot(&mut h, |_| true);
    let view = h.get_by_label("Luminaire in 3D").rect();
    let before = h.state().viewport().camera;
    let start = view.center();
    h.hover_at(start);
    h.step();
    h.drag_at(start);
    h.step();
    for k in 1..=10 {
        h.hover_at(start + egui::vec2(8.0 * k as f32, 3.0 * k as f32));
        h.step();
    }
    h.drop_at(start + egui::vec2(80.0, 30.0));
    h.run_steps(2);
    let after = h.state().viewport().camera;
    assert!(
        after.yaw_rad < before.yaw_rad - 0.3,
        "{before:?} → {after:?}"
    );
    assert!(after.pitch_rad > before.pitch_rad + 0.1);
    assert_eq!(after.distance, before.distance);
    assert_eq!(after.target, before.target);
    // Wheel forward: closer.
    h.hover_at(view.center());
    h.event(egui::Event::MouseWheel {
        unit: egui::MouseWheelUnit::Point,
        delta: egui::vec2(0.0, 120.0),
        phase: egui::TouchPhase::Move,
        source: egui::MouseWheelSource::Unknown,
        modifiers: egui::Modifiers::NONE,
    });
    h.run_steps(10);
    let zoomed = h.state().viewport().camera;
    assert!(
        zoomed.distance < 0.9 * after.distance,
        "{after:?} → {zoomed:?}"
    );
    // Frame all brings the framed distance back.
    h.get_by_label("Frame all").click();
    h.run_steps(2);
    assert!(
        (h.state().viewport().camera.distance - before.distance).abs() < 1e-4 * before.distance
    );
}

/// The main window on a converged example, drawn by egui's wgpu renderer
/// (lavapipe or llvmpipe here) with the 3D view's own pipelines, against
/// the stored picture. Figures that follow wall time (iterations,
/// photons/s) and the checkout's path are masked; the rest must match within the threshold.
#[test]
fn the_main_window_with_a_converged_example_matches_its_snapshot() {
    let mut h = common::wgpu_editor(
        EditorState::new(Some(example()), settings(400_000)),
        [1366.0, 768.0],
    );
    wait_for_snapshot(&mut h, |app| {
        app.state
            .snapshot()
            .is_some_and(|s| matches!(s.state, lucerna_simulation::RunState::Finished(_)))
    });
    h.get_by_label("Photon paths").click();
    h.run_steps(3);
    common::mask_time_dependent(&mut h);
    common::snapshot(&mut h, "main_window_converged");
}

/// The `--benchmark` mode's scripted edits restart the run, each one's
/// first preview is timed, and the nudges cancel out.
#[test]
fn the_benchmark_mode_times_each_scripted_edit() {
    let state = EditorState::new(Some(example()), settings(u64::MAX / 4));
    let mut h = Harness::builder()
        .with_size([1366.0, 900.0])
        .build_ui_state(
            |ui, app: &mut EditorApp| app.ui(ui),
            EditorApp::new(state).with_benchmark(BenchmarkOptions::Frames {
                duration: Duration::from_secs_f64(4.5),
                continuous: true,
                export_into: None,
            }),
        );
    wait_for_snapshot(&mut h, |_| true);
    let original = h.state().state.scene().unwrap().parts[0].transform.clone();
    let start = Instant::now();
    while !h.state().benchmark_report().unwrap().contains("(2 edits)")
        || h.state().state.snapshot().unwrap().generation < 2
    {
        assert!(start.elapsed() < Duration::from_secs(60), "no second edit");
        std::thread::sleep(Duration::from_millis(10));
        h.step();
    }
    let report = h.state().benchmark_report().unwrap();
    // Up then down again: the part is back where it was.
    let moved = h.state().state.scene().unwrap().parts[0].transform.clone();
    assert!((moved.translate[2] - original.translate[2]).abs() < 1e-12);
    let latencies = report
        .lines()
        .find(|l| l.starts_with("edit to first preview"))
        .unwrap();
    assert!(
        latencies.contains("over 1") || latencies.contains("over 2"),
        "{report}"
    );
    assert!(!latencies.contains("NaN"), "{report}");
}

/// Where the adapter does not multisample, the view draws straight into
/// its picture: the luminaire still shows, and nothing fails validation.
#[test]
fn the_3d_view_draws_without_multisampling_too() {
    let mut h = common::wgpu_editor_with(
        EditorState::new(Some(example()), settings(100_000)),
        [1366.0, 768.0],
        |target| lucerna_editor::GpuTarget {
            picture_samples: 1,
            ..target
        },
    );
    wait_for_snapshot(&mut h, |_| true);
    let view = h.get_by_label("Luminaire in 3D").rect();
    let image = h.render().expect("rendered");
    let ppp = image.width() as f32 / 1366.0;
    let mut colours = std::collections::HashSet::new();
    for y in (view.top() as u32 + 40..view.bottom() as u32 - 20).step_by(4) {
        for x in (view.left() as u32 + 4..view.right() as u32 - 4).step_by(4) {
            let p = image.get_pixel((x as f32 * ppp) as u32, (y as f32 * ppp) as u32);
            colours.insert(p.0);
        }
    }
    // Shaded metal, the cube's faces, the axes: many colours, not a blank.
    assert!(colours.len() > 50, "{} colours", colours.len());
}

/// The `--benchmark --export` mode exports the converged run through the
/// export dialog again and again, makes no edit, and reports the frames
/// that began while an export ran; the files are really written.
#[test]
fn the_benchmark_export_mode_exports_without_editing_and_times_those_frames() {
    let out = tempfile::tempdir().unwrap();
    let state = EditorState::new(Some(example()), settings(200_000));
    let mut h = Harness::builder()
        .with_size([1366.0, 900.0])
        .build_ui_state(
            |ui, app: &mut EditorApp| app.ui(ui),
            EditorApp::new(state).with_benchmark(BenchmarkOptions::Frames {
                duration: Duration::from_secs(600),
                continuous: true,
                export_into: Some(out.path().to_path_buf()),
            }),
        );
    wait_for_snapshot(&mut h, |_| true);
    let original = h.state().state.scene().unwrap().clone();
    let start = Instant::now();
    while !h
        .state()
        .benchmark_report()
        .unwrap()
        .contains("exports (all files, automatic filter): 2 finished")
    {
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "no second export: {}",
            h.state().benchmark_report().unwrap()
        );
        std::thread::sleep(Duration::from_millis(10));
        h.step();
    }
    let report = h.state().benchmark_report().unwrap();
    assert_eq!(h.state().state.scene().unwrap(), &original, "no edit");
    assert!(report.contains("(0 edits)"), "{report}");
    let during = report
        .lines()
        .find(|l| l.starts_with("while an export ran: frame interval"))
        .unwrap();
    assert!(
        !during.contains("NaN") && !during.contains("over 0"),
        "{report}"
    );
    let written: Vec<_> = std::fs::read_dir(out.path()).unwrap().collect();
    assert!(written.len() >= 5, "{written:?}");
}
