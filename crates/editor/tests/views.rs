#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! The photometric views against the snapshot they draw: the polar plot's
//! beam angles equal the figures panel's, the isocandela map's peak the
//! snapshot's, cd/klm scales by the lamp flux, a reference shows its RMS
//! difference (zero for the pinned result, the exact one after doubling
//! the flux); one snapshot picture per view, compared with a threshold.

mod common;

use std::path::PathBuf;
use std::time::{Duration, Instant};

use egui_kittest::Harness;
use egui_kittest::kittest::{NodeT, Queryable};
use lucerna_editor::{EditorApp, EditorState};
use lucerna_photometry::CandelaTable;
use lucerna_simulation::{RunState, SimulationSettings, StoppingRule};

fn example() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires/faceted_downlight.toml")
}

fn settings() -> SimulationSettings {
    SimulationSettings {
        resolution: 32,
        stop: StoppingRule {
            photons: Some(300_000),
            ..StoppingRule::default()
        },
        ..SimulationSettings::default()
    }
}

fn editor(app: EditorApp, size: [f32; 2]) -> Harness<'static, EditorApp> {
    Harness::builder()
        .with_size(size)
        .build_ui_state(|ui, app: &mut EditorApp| app.ui(ui), app)
}

/// Steps until the shown snapshot of generation ≥ `generation` is final.
fn wait_finished(h: &mut Harness<'_, EditorApp>, generation: u64) {
    let start = Instant::now();
    while !h
        .state()
        .state
        .snapshot()
        .is_some_and(|s| s.generation >= generation && matches!(s.state, RunState::Finished(_)))
    {
        assert!(
            start.elapsed() < Duration::from_secs(120),
            "no final snapshot"
        );
        std::thread::sleep(Duration::from_millis(20));
        h.step();
    }
    h.run_steps(3);
}

fn click(h: &mut Harness<'_, EditorApp>, label: &str) {
    h.get_by_label(label).click();
    h.run_steps(3);
}

/// The text of the label that contains `part`.
fn label_text(h: &Harness<'_, EditorApp>, part: &str) -> String {
    // A label widget keeps its text as its value.
    let node = h.get_by_label_contains(part);
    node.value()
        .or_else(|| node.accesskit_node().label())
        .unwrap_or_default()
}

#[test]
fn each_view_shows_the_current_figures() {
    let mut h = editor(
        EditorApp::new(EditorState::new(Some(example()), settings())),
        [1366.0, 900.0],
    );
    wait_finished(&mut h, 0);
    let s = h.state().state.snapshot().unwrap().clone();
    let beam = format!("{:.1}°", s.figures.beam_angle_deg[0].unwrap());
    let field = format!("{:.1}°", s.figures.field_angle_deg[1].unwrap());
    // The polar plot's label.
    let polar = label_text(&h, "Beam angle C0-C180");
    assert!(
        polar.contains(&format!("Beam angle C0-C180 {beam}")),
        "{polar}"
    );
    assert!(polar.contains(&format!("C90-C270 {field}")), "{polar}");
    // The figures panel shows the same numbers, with noise.
    click(&mut h, "Figures");
    assert!(h.query_all_by_label(&beam).next().is_some());
    assert!(h.query_all_by_label(&field).next().is_some());
    assert!(
        h.query_all_by_label(&format!("{:.1} lm", s.figures.flux_lm))
            .next()
            .is_some()
    );
    let zone = format!(
        "{:.1} lm ({:.1} %)",
        s.figures.zonal_flux_lm[0],
        100.0 * s.figures.zonal_flux_lm[0] / s.figures.flux_lm
    );
    assert!(h.query_all_by_label(&zone).next().is_some(), "{zone}");
    assert!(h.query_by_label("Copy as text").is_some());
    // The isocandela map names the peak it scales its lines to.
    click(&mut h, "Isocandela");
    let iso = label_text(&h, "Lines at");
    assert!(
        iso.contains(&format!("({:.0} cd)", s.table.peak().0)),
        "{iso}"
    );
    // cd/klm: the peak over the lamp flux in klm.
    click(&mut h, "Polar");
    click(&mut h, "Unit");
    click(&mut h, "cd/klm");
    let peak = label_text(&h, "cd/klm at C");
    let per_klm = s.figures.peak_cd * 1000.0 / s.map.emitter_flux_lm;
    assert!(
        peak.contains(&format!("Peak {per_klm:.0} cd/klm")),
        "{peak}"
    );
    // The cartesian plot and the cube map draw without a fuss.
    click(&mut h, "Cartesian");
    click(&mut h, "Log intensity");
    click(&mut h, "Cube map");
    assert!(h.query_by_label_contains("Log scale over").is_some());
}

#[test]
fn a_pinned_reference_shows_zero_then_the_exact_rms_difference_of_an_edit() {
    let mut h = editor(
        EditorApp::new(EditorState::new(Some(example()), settings())),
        [1366.0, 900.0],
    );
    wait_finished(&mut h, 0);
    click(&mut h, "Pin as reference");
    let pinned = h.state().state.snapshot().unwrap().table.clone();
    let text = label_text(&h, "RMS difference");
    assert!(
        text.contains("RMS difference 0.0 cd (0.0 % of the peak)"),
        "{text}"
    );
    // Doubling the LED's flux doubles every intensity (same seed, same
    // photons): the difference is the pinned table itself.
    click(&mut h, "Emitter LED");
    let flux = h.state().state.scene().unwrap().emitters[0].flux_lm;
    // The emitter's field, not the figures' row of the same name.
    h.get_by_role_and_label(egui::accesskit::Role::SpinButton, "Flux")
        .set_value_accesskit(2.0 * flux);
    h.run_steps(3);
    assert_eq!(
        h.state().state.scene().unwrap().emitters[0].flux_lm,
        2.0 * flux
    );
    wait_finished(&mut h, 1);
    let doubled = h.state().state.snapshot().unwrap().table.clone();
    let exact = pinned.rms_difference_cd(&CandelaTable {
        candela: vec![0.0; pinned.candela.len()],
        ..(*pinned).clone()
    });
    assert!((doubled.rms_difference_cd(&pinned) - exact).abs() < 1e-6 * exact);
    let text = label_text(&h, "RMS difference");
    assert!(
        text.contains(&format!("RMS difference {exact:.1} cd")),
        "{text}"
    );
}

#[test]
fn a_reference_file_is_overlaid_and_a_bad_one_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let mut h = editor(
        EditorApp::new(EditorState::new(Some(example()), settings())),
        [1366.0, 900.0],
    );
    wait_finished(&mut h, 0);
    let s = h.state().state.snapshot().unwrap().clone();
    // The result itself, written as IES and read back: within the file's
    // rounding of the result.
    let ies = dir.path().join("design.ies");
    let photometry = lucerna_simulation::export::photometry(
        &s,
        &lucerna_simulation::export::ExportOptions {
            symmetrise: None,
            date: "2026-12-01".to_owned(),
            seed: 1,
            scene_file: "faceted_downlight.toml".to_owned(),
            labels: None,
        },
    );
    std::fs::write(
        &ies,
        lucerna_photometry::write_ies(&photometry, lucerna_photometry::IesVersion::Lm63_2019)
            .unwrap(),
    )
    .unwrap();
    h.get_by_label("Reference file").click();
    h.get_by_label("Reference file")
        .type_text(&ies.display().to_string());
    h.run_steps(1);
    click(&mut h, "Load reference");
    let text = label_text(&h, "RMS difference");
    assert!(text.contains("Reference design.ies"), "{text}");
    let rms = s.table.rms_difference_cd(
        &lucerna_photometry::read_photometry(&std::fs::read(&ies).unwrap())
            .unwrap()
            .table,
    );
    assert!(rms < 0.01 * s.figures.peak_cd, "{rms}");
    assert!(
        text.contains(&format!("RMS difference {rms:.1} cd")),
        "{text}"
    );
    // A file that is not photometry: an error, the old reference stays.
    let bad = dir.path().join("bad.ies");
    std::fs::write(&bad, "IESNA:LM-63-2002\nTILT=NONE\n1 2 3\n").unwrap();
    h.get_by_label("Reference file").click();
    h.run_steps(1);
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::A);
    h.step();
    h.get_by_label("Reference file")
        .type_text(&bad.display().to_string());
    h.run_steps(1);
    click(&mut h, "Load reference");
    assert!(
        h.query_by_label_contains("is not a usable IES or EULUMDAT file")
            .is_some()
    );
    assert!(label_text(&h, "RMS difference").contains("design.ies"));
}

/// One picture per view of a converged example, compared with a threshold.
#[test]
fn each_view_matches_its_snapshot() {
    let mut h = common::wgpu_editor(
        EditorState::new(Some(example()), settings()),
        [1200.0, 760.0],
    );
    wait_finished(&mut h, 0);
    for (tab, name) in [
        ("Polar", "view_polar"),
        ("Cartesian", "view_cartesian"),
        ("Isocandela", "view_isocandela"),
        ("Cube map", "view_cube_map"),
        ("Figures", "view_figures"),
    ] {
        click(&mut h, tab);
        common::mask_time_dependent(&mut h);
        common::snapshot(&mut h, name);
    }
}
