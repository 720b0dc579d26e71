#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: tests may panic
//! The export dialog driven by its labels: the files it writes read back
//! with the editor's flux and peak, are byte for byte what a bake with the
//! same settings writes, carry the keywords typed (saved in the scene,
//! undoable, without restarting the run), and an unwritable folder is an
//! error that writes nothing. CPU backend, 32 texels per face edge and a
//! photon limit keep each run short and deterministic.

mod common;

use common::{choose, click, steps, type_into};

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use egui::Modifiers;
use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use lucerna_editor::{EditorApp, EditorState};
use lucerna_photometry::{IesVersion, read_photometry};
use lucerna_simulation::{
    BackendRequest, ExportOptions, ExportRequest, FilterChoice, Labels, Luminaire, RunState,
    SimulationSettings, Snapshot, StoppingRule, TableGrid,
};

const PHOTONS: u64 = 40_000;

fn settings() -> SimulationSettings {
    SimulationSettings {
        resolution: 32,
        backend: BackendRequest::Cpu,
        stop: StoppingRule {
            photons: Some(PHOTONS),
            ..StoppingRule::default()
        },
        ..SimulationSettings::default()
    }
}

/// A copy of the parabolic spot in `dir` (the tests save it).
fn scene_copy(dir: &Path) -> PathBuf {
    let example =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires/parabolic_spot.toml");
    let path = dir.join("spot.toml");
    std::fs::copy(example, &path).unwrap();
    path
}

fn editor(open: &Path) -> Harness<'static, EditorApp> {
    Harness::builder()
        .with_size([1366.0, 900.0])
        .build_ui_state(
            |ui, app: &mut EditorApp| app.ui(ui),
            EditorApp::new(EditorState::new(Some(open.to_path_buf()), settings())),
        )
}

/// Steps frames until the run of the opened scene has finished.
fn finished_run(h: &mut Harness<'_, EditorApp>) -> Arc<Snapshot> {
    let deadline = Instant::now() + Duration::from_secs(120);
    loop {
        h.step();
        if let Some(s) = h.state().state.snapshot()
            && matches!(s.state, RunState::Finished(_))
        {
            return s.clone();
        }
        if let Some(sim) = h.state().state.simulation()
            && let Some((_, e)) = sim.published().error
        {
            panic!("simulation failed: {e}");
        }
        assert!(Instant::now() < deadline, "timed out waiting for the run");
        std::thread::sleep(Duration::from_millis(10));
    }
}

fn open_dialog(h: &mut Harness<'_, EditorApp>, out: &Path, base: &str) {
    common::menu(h, "File", "Export…");
    type_into(h, "Output folder", &out.display().to_string());
    type_into(h, "Base name", base);
    type_into(h, "Issue date", "2026-05-06");
}

/// What the dialog's defaults and `open_dialog`'s date give to a bake of
/// `spot.toml`.
fn dialog_options(h: &Harness<'_, EditorApp>) -> ExportOptions {
    ExportOptions {
        symmetrise: None,
        date: "2026-05-06".to_owned(),
        seed: settings().seed,
        scene_file: "spot.toml".to_owned(),
        labels: Some(Labels::of(h.state().state.scene().unwrap())),
    }
}

/// Clicks Export and steps frames until the export's thread has ended
/// (its result shown).
fn export(h: &mut Harness<'_, EditorApp>) {
    click(h, "Export");
    let deadline = Instant::now() + Duration::from_secs(60);
    while h.query_by_label_contains("Wrote ").is_none()
        && h.query_by_label_contains("Export failed").is_none()
    {
        assert!(
            Instant::now() < deadline,
            "timed out waiting for the export"
        );
        std::thread::sleep(Duration::from_millis(10));
        h.step();
    }
}

fn names_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .map(|d| {
            d.map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
                .collect()
        })
        .unwrap_or_default();
    names.sort();
    names
}

#[test]
fn exported_files_read_back_with_the_editors_figures_and_are_the_bakes_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let scene_path = scene_copy(dir.path());
    let mut h = editor(&scene_path);
    let snapshot = finished_run(&mut h);
    let out = dir.path().join("out");
    open_dialog(&mut h, &out, "spot");
    export(&mut h);
    h.get_by_label("Wrote 5 files:");
    assert_eq!(
        names_in(&out),
        [
            "spot.exr",
            "spot.ies",
            "spot.ldt",
            "spot_cube.png",
            "spot_polar.png"
        ]
    );
    let shown = &snapshot.figures;
    for name in ["spot.ies", "spot.ldt"] {
        let p = read_photometry(&std::fs::read(out.join(name)).unwrap()).unwrap();
        let f = p.figures();
        assert!(
            (f.flux_lm / shown.flux_lm - 1.0).abs() < 0.005,
            "{name}: {} lm, the editor shows {}",
            f.flux_lm,
            shown.flux_lm
        );
        assert!(
            (f.peak_cd / shown.peak_cd - 1.0).abs() < 0.005,
            "{name}: {} cd, the editor shows {}",
            f.peak_cd,
            shown.peak_cd
        );
    }

    // Another grid, the filtered map and LM-63-2002: the editor's run is
    // raw on 5° × automatic, so the export filters and tabulates afresh.
    let other = dir.path().join("other");
    type_into(&mut h, "Output folder", &other.display().to_string());
    choose(&mut h, "IES edition", "LM-63-2002");
    choose(&mut h, "Map", "Filtered");
    choose(&mut h, "C step", "15°");
    choose(&mut h, "γ step", "2.5°");
    click(&mut h, "EXR of the map");
    click(&mut h, "Cube map PNG");
    click(&mut h, "Polar diagram PNG");
    export(&mut h);
    h.get_by_label("Wrote 2 files:");
    assert_eq!(names_in(&other), ["spot.ies", "spot.ldt"]);
    assert_eq!(
        h.state().state.snapshot().unwrap().generation,
        snapshot.generation,
        "exporting restarts nothing"
    );

    // What `lucerna bake --filter auto --c-step 15 --gamma-step 2.5
    // --ies-version 2002 --date 2026-05-06` writes: its library calls.
    let grid = TableGrid {
        c_step_deg: 15.0,
        gamma_step_deg: Some(2.5),
    };
    let baked = lucerna_simulation::bake(
        Arc::new(Luminaire::load(&scene_path).unwrap()),
        SimulationSettings {
            filter: FilterChoice::Automatic,
            table: grid,
            ..settings()
        },
    )
    .unwrap();
    let options = dialog_options(&h);
    let mut request = ExportRequest::new(&baked, options, dir.path(), "spot");
    request.formats.ies = Some(IesVersion::Lm63_2002);
    let files = request.render(&baked).unwrap().files;
    for name in ["spot.ies", "spot.ldt"] {
        let bake = &files.iter().find(|(p, _)| p.ends_with(name)).unwrap().1;
        let editor = std::fs::read(other.join(name)).unwrap();
        assert!(
            editor == *bake,
            "{name}: the editor's export and the bake differ:\n{}\n---\n{}",
            String::from_utf8_lossy(&editor),
            String::from_utf8_lossy(bake)
        );
    }
}

#[test]
fn keywords_typed_in_the_dialog_are_saved_in_the_scene_undoable_and_restart_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let scene_path = scene_copy(dir.path());
    let mut h = editor(&scene_path);
    let snapshot = finished_run(&mut h);
    let out = dir.path().join("out");
    open_dialog(&mut h, &out, "spot");
    type_into(&mut h, "Catalogue number", "AC-25/100");
    type_into(&mut h, "Manufacturer", "Acme Lighting");
    type_into(&mut h, "Lamp", "LED 800 lm 3000 K");
    let state = &h.state().state;
    let scene = state.scene().unwrap();
    assert_eq!(scene.export.catalogue_number, "AC-25/100");
    assert_eq!(scene.manufacturer, "Acme Lighting");
    assert!(state.is_dirty());
    assert_eq!(
        state.simulation().unwrap().generation(),
        snapshot.generation
    );
    assert!(
        Arc::ptr_eq(state.snapshot().unwrap(), &snapshot),
        "a keyword is not light: the finished run stays"
    );

    // One undo step per field.
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::Z);
    steps(&mut h, 2);
    assert_eq!(h.state().state.scene().unwrap().export.lamp, "");
    h.key_press_modifiers(Modifiers::COMMAND | Modifiers::SHIFT, egui::Key::Z);
    steps(&mut h, 2);
    assert_eq!(
        h.state().state.scene().unwrap().export.lamp,
        "LED 800 lm 3000 K"
    );

    // The export carries them, and they are saved with the scene.
    export(&mut h);
    let ies = std::fs::read_to_string(out.join("spot.ies")).unwrap();
    for line in [
        "[LUMCAT] AC-25/100",
        "[MANUFAC] Acme Lighting",
        "[LAMP] LED 800 lm 3000 K",
    ] {
        assert!(ies.contains(line), "{line} missing:\n{ies}");
    }
    h.key_press_modifiers(Modifiers::COMMAND, egui::Key::S);
    steps(&mut h, 2);
    assert!(!h.state().state.is_dirty());
    let saved = lucerna_scene::load_scene(&scene_path).unwrap();
    assert_eq!(saved.export.catalogue_number, "AC-25/100");
    assert_eq!(saved.export.lamp, "LED 800 lm 3000 K");

    // Reopened, the dialog shows them again.
    let mut again = editor(&scene_path);
    steps(&mut again, 2);
    common::menu(&mut again, "File", "Export…");
    assert_eq!(
        again.get_by_label("Catalogue number").value().as_deref(),
        Some("AC-25/100")
    );
    assert_eq!(
        again.get_by_label("Manufacturer").value().as_deref(),
        Some("Acme Lighting")
    );
}

#[test]
fn an_export_to_an_unwritable_folder_shows_an_error_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    let scene_path = scene_copy(dir.path());
    let mut h = editor(&scene_path);
    finished_run(&mut h);
    // A folder inside a plain file can be neither made nor written (even
    // by root, whom permissions do not stop).
    let file = dir.path().join("plain.txt");
    std::fs::write(&file, b"not a folder").unwrap();
    open_dialog(&mut h, &file.join("out"), "spot");
    export(&mut h);
    h.get_by_label_contains("Export failed, nothing written");
    assert_eq!(names_in(dir.path()), ["plain.txt", "spot.toml"]);

    // A base name with a folder in it is refused the same way.
    let out = dir.path().join("out");
    type_into(&mut h, "Output folder", &out.display().to_string());
    type_into(&mut h, "Base name", "../spot");
    export(&mut h);
    h.get_by_label_contains("is not a plain file name");
    assert!(names_in(&out).is_empty());
}

#[test]
fn the_luminous_opening_chosen_in_the_dialog_is_declared_in_the_files() {
    let dir = tempfile::tempdir().unwrap();
    let scene_path = scene_copy(dir.path());
    let mut h = editor(&scene_path);
    finished_run(&mut h);
    let out = dir.path().join("out");
    open_dialog(&mut h, &out, "spot");
    choose(&mut h, "Luminous opening", "Disk");
    h.get_by_label("Opening diameter").set_value_accesskit(80.0);
    steps(&mut h, 2);
    assert_eq!(
        h.state().state.scene().unwrap().opening,
        Some(lucerna_scene::LuminousOpening::Disk {
            diameter_m: 0.08,
            height_m: 0.0
        })
    );
    // The opening is the preview room's too: the run restarts with it.
    let generation = h.state().state.simulation().unwrap().generation();
    assert!(generation >= 1);
    finished_run_of(&mut h, generation);
    export(&mut h);
    h.get_by_label("Wrote 5 files:");
    let ies = read_photometry(&std::fs::read(out.join("spot.ies")).unwrap()).unwrap();
    let area = ies.meta.luminous_area;
    assert!(
        area.circular && (area.length_m - 0.08).abs() < 1e-9,
        "{area:?}"
    );
}

/// Steps frames until the run of `generation` has finished.
fn finished_run_of(h: &mut Harness<'_, EditorApp>, generation: u64) -> Arc<Snapshot> {
    let deadline = Instant::now() + Duration::from_secs(120);
    loop {
        let s = finished_run(h);
        if s.generation >= generation {
            return s;
        }
        assert!(Instant::now() < deadline, "timed out waiting for the run");
    }
}

#[test]
fn a_folder_chosen_in_the_native_dialog_fills_the_output_folder() {
    let dir = tempfile::tempdir().unwrap();
    let scene_path = scene_copy(dir.path());
    let mut h = editor(&scene_path);
    steps(&mut h, 2);
    common::menu(&mut h, "File", "Export…");
    h.get_by_label("Choose folder…");
    // What the dialog's thread delivers when a folder is picked.
    let chosen = dir.path().join("chosen");
    h.state_mut()
        .state
        .push(lucerna_editor::Command::SetExportFolder(chosen.clone()));
    steps(&mut h, 2);
    assert_eq!(
        h.get_by_label("Output folder").value(),
        Some(chosen.display().to_string())
    );
}

/// The export runs beside the window: the frame after the click shows it
/// under way (the automatic filter choosing its rule), not a frozen wait,
/// and its result comes later.
#[test]
fn an_export_runs_on_its_own_thread_and_reports_its_stage() {
    let dir = tempfile::tempdir().unwrap();
    let scene_path = scene_copy(dir.path());
    let mut h = editor(&scene_path);
    finished_run(&mut h);
    let out = dir.path().join("out");
    open_dialog(&mut h, &out, "spot");
    choose(&mut h, "Map", "Filtered");
    h.get_by_label("Export").click();
    h.step();
    assert!(
        h.query_by_label_contains("Exporting: ").is_some()
            || h.query_by_label_contains("Wrote ").is_some(),
        "the export neither runs nor has ended"
    );
    let running_seen = h.query_by_label_contains("Exporting: ").is_some();
    let deadline = Instant::now() + Duration::from_secs(60);
    while h.query_by_label_contains("Wrote 5 files:").is_none() {
        assert!(
            Instant::now() < deadline,
            "timed out waiting for the export"
        );
        std::thread::sleep(Duration::from_millis(10));
        h.step();
    }
    assert_eq!(names_in(&out).len(), 5);
    assert!(
        running_seen,
        "the frame after the click waited for the export"
    );
}

/// File ▸ Datasheet… opens the dialog with only the datasheet ticked; its
/// three files are the bytes `lucerna report` of the same scene and
/// settings writes (both through `ExportRequest`).
#[test]
fn the_datasheet_menu_writes_the_reports_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let scene_path = scene_copy(dir.path());
    let mut h = editor(&scene_path);
    let snapshot = finished_run(&mut h);
    let out = dir.path().join("sheet");
    common::menu(&mut h, "File", "Datasheet…");
    type_into(&mut h, "Output folder", &out.display().to_string());
    type_into(&mut h, "Base name", "spot");
    type_into(&mut h, "Issue date", "2026-05-06");
    export(&mut h);
    h.get_by_label("Wrote 3 files:");
    assert_eq!(
        names_in(&out),
        [
            "spot_datasheet.html",
            "spot_datasheet.json",
            "spot_datasheet.pdf"
        ]
    );
    let options = dialog_options(&h);
    let mut request = ExportRequest::new(&snapshot, options, dir.path(), "spot");
    request.formats = lucerna_simulation::ExportFormats {
        datasheet: true,
        ..lucerna_simulation::ExportFormats::NONE
    };
    for (path, bytes) in request.render(&snapshot).unwrap().files {
        let name = path.file_name().unwrap();
        assert!(
            std::fs::read(out.join(name)).unwrap() == bytes,
            "{} differs from the report's",
            name.to_string_lossy()
        );
    }
}

#[test]
fn export_geometry_writes_the_command_lines_bytes_for_the_ticked_parts() {
    let dir = tempfile::tempdir().unwrap();
    let scene_path = scene_copy(dir.path());
    let mut h = editor(&scene_path);
    h.step();
    let out = dir.path().join("geometry");
    common::menu(&mut h, "File", "Export geometry…");
    type_into(&mut h, "Output folder", &out.display().to_string());
    type_into(&mut h, "Base name", "spot");
    // The reflector alone, as `--parts reflector`; STEP and OBJ only.
    click(&mut h, "LED (emitter)");
    click(&mut h, "STL (traced triangles)");
    click(&mut h, "Export");
    let deadline = Instant::now() + Duration::from_secs(60);
    while h.query_by_label_contains("Wrote ").is_none()
        && h.query_by_label_contains("Export failed").is_none()
    {
        assert!(
            Instant::now() < deadline,
            "timed out waiting for the export"
        );
        std::thread::sleep(Duration::from_millis(10));
        h.step();
    }
    h.get_by_label("Wrote 2 files:");
    assert_eq!(names_in(&out), ["spot.obj", "spot.step"]);
    let scene = lucerna_scene::load_scene(&scene_path).unwrap();
    let request = lucerna_cad::GeometryRequest {
        formats: vec![
            lucerna_cad::GeometryFormat::Step,
            lucerna_cad::GeometryFormat::Obj,
        ],
        parts: Some(vec!["reflector".to_owned()]),
        finish: Default::default(),
    };
    for (name, bytes) in lucerna_cad::geometry_files(&scene, dir.path(), "spot", &request).unwrap()
    {
        assert_eq!(std::fs::read(out.join(&name)).unwrap(), bytes, "{name}");
    }
}
