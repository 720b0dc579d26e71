#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: tests may panic
//! File handling driven through the editor's labels: new, the unsaved
//! changes question, recent files, autosave and recovery, OBJ import and
//! dropped files, the theme and zoom. Every editor here keeps its config
//! in a temporary directory, never the real home.

mod common;

use common::{import_obj, menu, save_as, steps};

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant};

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use lucerna_editor::{EditorApp, EditorPaths, EditorState, PendingAction, ThemeChoice};
use lucerna_scene::Shape;
use lucerna_simulation::{BackendRequest, SimulationSettings, StoppingRule};

fn assets() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets")
}

fn example() -> PathBuf {
    assets().join("luminaires/parabolic_spot.toml")
}

fn settings() -> SimulationSettings {
    SimulationSettings {
        resolution: 32,
        backend: BackendRequest::Cpu,
        stop: StoppingRule {
            photons: Some(100_000),
            ..StoppingRule::default()
        },
        ..SimulationSettings::default()
    }
}

/// An editor keeping its settings, recent files and recovery in `config`.
fn editor(open: Option<PathBuf>, config: &Path) -> Harness<'static, EditorApp> {
    let state = EditorState::with_paths(open, settings(), EditorPaths::in_dir(config));
    Harness::builder()
        .with_size([1366.0, 900.0])
        .build_ui_state(|ui, app: &mut EditorApp| app.ui(ui), EditorApp::new(state))
}

fn parts(h: &Harness<'_, EditorApp>) -> usize {
    h.state().state.scene().expect("a scene").parts.len()
}

/// The obj_cone example and its meshes copied to `dir`, keeping the
/// relative path `../meshes/cone_reflector.obj` between them.
fn copy_obj_cone(dir: &Path) -> PathBuf {
    std::fs::create_dir_all(dir.join("luminaires")).unwrap();
    std::fs::create_dir_all(dir.join("meshes")).unwrap();
    for name in ["cone_reflector.obj", "cone_reflector.mtl"] {
        std::fs::copy(
            assets().join("meshes").join(name),
            dir.join("meshes").join(name),
        )
        .unwrap();
    }
    let scene = dir.join("luminaires/obj_cone.toml");
    std::fs::copy(assets().join("luminaires/obj_cone.toml"), &scene).unwrap();
    scene
}

/// Steps until the simulation has shown a snapshot, failing on its error.
fn wait_for_snapshot(h: &mut Harness<'_, EditorApp>) {
    let deadline = Instant::now() + Duration::from_secs(60);
    loop {
        h.step();
        if h.state().state.snapshot().is_some() {
            return;
        }
        if let Some(sim) = h.state().state.simulation()
            && let Some((_, e)) = sim.published().error
        {
            panic!("simulation failed: {e}");
        }
        assert!(Instant::now() < deadline, "no snapshot in 60 s");
        std::thread::sleep(Duration::from_millis(10));
    }
}

#[test]
fn an_edit_is_autosaved_and_a_new_editor_recovers_it_with_the_original_path() {
    let work = tempfile::tempdir().unwrap();
    let config = work.path().join("config");
    let scene_path = copy_obj_cone(work.path());
    let recovery = config.join("recovery.toml");

    let mut h = editor(Some(scene_path.clone()), &config);
    steps(&mut h, 2);
    assert!(!recovery.exists(), "nothing unsaved yet");
    // A structural edit is written at once, whatever the interval.
    h.get_by_label("Add part").click();
    steps(&mut h, 2);
    h.get_by_label("Add disk").click();
    steps(&mut h, 2);
    assert_eq!(parts(&h), 2);
    assert!(recovery.exists(), "the edit was not autosaved");
    // A field edit is written once the interval has passed (zero here).
    h.state_mut().state.set_autosave_interval(Duration::ZERO);
    h.get_by_label("Part disk (disk)").click();
    steps(&mut h, 2);
    h.get_by_label("Radius").set_value_accesskit(30.0);
    steps(&mut h, 2);
    let edited = h.state().state.scene().unwrap().clone();
    assert_eq!(lucerna_scene::load_scene(&recovery).unwrap(), edited);
    // The editor "crashes": no clean exit.
    drop(h);

    let mut again = editor(None, &config);
    steps(&mut again, 2);
    let offer = again.state().state.recovery_offer().expect("an offer");
    assert_eq!(offer.scene, edited);
    again.get_by_label_contains("Recover unsaved changes to");
    again.get_by_label_contains("obj_cone.toml from");
    // Nothing is autosaved over the offer while it waits.
    assert_eq!(lucerna_scene::load_scene(&recovery).unwrap(), edited);
    again.get_by_label("Recover").click();
    steps(&mut again, 2);
    let state = &again.state().state;
    assert!(state.recovery_offer().is_none());
    assert_eq!(state.scene(), Some(&edited));
    assert!(state.is_dirty());
    assert_eq!(
        state.path().map(|p| p.canonicalize().unwrap()),
        Some(scene_path.canonicalize().unwrap())
    );
    assert!(state.problems().is_empty(), "{:?}", state.problems());
    // The mesh's relative path resolves from the original folder, not from
    // the config directory the recovery file lives in.
    wait_for_snapshot(&mut again);

    // Save writes the original file and removes the recovery file.
    again.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::S);
    steps(&mut again, 2);
    assert_eq!(again.state().state.file_error(), None);
    assert!(!again.state().state.is_dirty());
    assert_eq!(lucerna_scene::load_scene(&scene_path).unwrap(), edited);
    assert!(!recovery.exists());
    drop(again);
    let mut third = editor(None, &config);
    steps(&mut third, 2);
    assert!(third.state().state.recovery_offer().is_none());
}

#[test]
fn an_unanswered_recovery_offer_survives_quitting_and_new() {
    let work = tempfile::tempdir().unwrap();
    let config = work.path().join("config");
    let mut h = editor(Some(example()), &config);
    steps(&mut h, 2);
    h.get_by_label("Add part").click();
    steps(&mut h, 2);
    h.get_by_label("Add plate").click();
    steps(&mut h, 2);
    drop(h);
    let mut again = editor(None, &config);
    steps(&mut again, 2);
    menu(&mut again, "File", "New");
    again.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Q);
    steps(&mut again, 2);
    assert!(again.state().state.quit_requested());
    drop(again);
    let mut third = editor(None, &config);
    steps(&mut third, 2);
    assert!(third.state().state.recovery_offer().is_some());
}

#[test]
fn discarding_the_recovery_removes_it() {
    let work = tempfile::tempdir().unwrap();
    let config = work.path().join("config");
    let mut h = editor(Some(example()), &config);
    steps(&mut h, 2);
    h.get_by_label("Add part").click();
    steps(&mut h, 2);
    h.get_by_label("Add plate").click();
    steps(&mut h, 2);
    drop(h);
    let mut again = editor(None, &config);
    steps(&mut again, 2);
    again.get_by_label("Discard").click();
    steps(&mut again, 2);
    assert!(again.state().state.recovery_offer().is_none());
    assert!(again.state().state.scene().is_none());
    assert!(!config.join("recovery.toml").exists());
}

#[test]
fn new_starts_a_valid_scene_and_asks_before_dropping_unsaved_changes() {
    let config = tempfile::tempdir().unwrap();
    let mut h = editor(Some(example()), config.path());
    steps(&mut h, 2);
    h.get_by_label("Add part").click();
    steps(&mut h, 2);
    h.get_by_label("Add disk").click();
    steps(&mut h, 2);
    let edited = h.state().state.scene().unwrap().clone();
    menu(&mut h, "File", "New");
    assert_eq!(h.state().state.pending(), Some(&PendingAction::New));
    assert_eq!(h.state().state.scene(), Some(&edited));
    h.get_by_label("Keep editing").click();
    steps(&mut h, 2);
    assert_eq!(h.state().state.pending(), None);
    assert_eq!(h.state().state.scene(), Some(&edited));

    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::N);
    steps(&mut h, 2);
    assert_eq!(h.state().state.pending(), Some(&PendingAction::New));
    h.get_by_label("Discard changes and start a new scene")
        .click();
    steps(&mut h, 2);
    let state = &h.state().state;
    assert_eq!(state.scene(), Some(&lucerna_editor::starter_scene()));
    assert_eq!(state.path(), None);
    assert!(!state.is_dirty());
    assert!(state.problems().is_empty(), "{:?}", state.problems());
    assert!(
        state.title().starts_with("unsaved new scene"),
        "{}",
        state.title()
    );
    wait_for_snapshot(&mut h);
    // Unsaved and pathless: Save asks for a path.
    menu(&mut h, "File", "Save");
    h.get_by_label("Save as path");
    assert_eq!(h.state().state.path(), None);
}

#[test]
fn quitting_with_unsaved_changes_asks_first() {
    let config = tempfile::tempdir().unwrap();
    let mut h = editor(Some(example()), config.path());
    steps(&mut h, 2);
    h.get_by_label("Add part").click();
    steps(&mut h, 2);
    h.get_by_label("Add disk").click();
    steps(&mut h, 2);
    assert!(config.path().join("recovery.toml").exists());
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Q);
    steps(&mut h, 2);
    assert_eq!(h.state().state.pending(), Some(&PendingAction::Quit));
    assert!(!h.state().state.quit_requested());
    h.get_by_label("Discard changes and quit").click();
    steps(&mut h, 2);
    assert!(h.state().state.quit_requested());
    // Changes the user chose to drop are not offered again.
    assert!(!config.path().join("recovery.toml").exists());
}

/// The window manager's close button, as winit reports it.
fn close_window(h: &mut Harness<'_, EditorApp>) {
    h.input_mut()
        .viewports
        .entry(egui::ViewportId::ROOT)
        .or_default()
        .events
        .push(egui::ViewportEvent::Close);
    steps(h, 2);
}

#[test]
fn the_close_button_asks_with_unsaved_changes_and_closes_without() {
    let config = tempfile::tempdir().unwrap();
    let mut h = editor(Some(example()), config.path());
    steps(&mut h, 2);
    h.get_by_label("Add part").click();
    steps(&mut h, 2);
    h.get_by_label("Add disk").click();
    steps(&mut h, 2);
    close_window(&mut h);
    assert_eq!(h.state().state.pending(), Some(&PendingAction::Quit));
    assert!(!h.state().state.quit_requested());
    h.get_by_label("Keep editing").click();
    steps(&mut h, 2);
    menu(&mut h, "Edit", "Undo");
    assert!(!h.state().state.is_dirty());
    close_window(&mut h);
    assert_eq!(h.state().state.pending(), None);
    assert!(h.state().state.quit_requested());
}

#[test]
fn recent_files_follow_open_and_save_and_persist() {
    let work = tempfile::tempdir().unwrap();
    let config = work.path().join("config");
    let mut h = editor(Some(example()), &config);
    steps(&mut h, 2);
    let canonical_example = example().canonicalize().unwrap();
    assert_eq!(
        h.state().state.recent_files(),
        vec![(canonical_example.clone(), true)]
    );
    let saved = work.path().join("copy.toml");
    save_as(&mut h, &saved);
    assert_eq!(h.state().state.file_error(), None);
    let canonical_saved = saved.canonicalize().unwrap();
    let expected = vec![
        (canonical_saved.clone(), true),
        (canonical_example.clone(), true),
    ];
    assert_eq!(h.state().state.recent_files(), expected);
    drop(h);

    // Another editor on the same config directory lists them, and opens
    // one from the Recent menu.
    let mut again = editor(None, &config);
    steps(&mut again, 2);
    assert_eq!(again.state().state.recent_files(), expected);
    // The start page lists them too; File ▸ Open Recent opens one.
    again.get_by_label(&canonical_example.display().to_string());
    common::click(&mut again, "File");
    common::click(&mut again, "Open Recent");
    let label = canonical_example.display().to_string();
    let items: Vec<_> = again.query_all_by_label(&label).collect();
    items.last().unwrap().click();
    steps(&mut again, 2);
    assert_eq!(
        again.state().state.path(),
        Some(canonical_example.as_path())
    );
    assert_eq!(again.state().state.recent_files()[0].0, canonical_example);
    // A file that has gone is listed as missing.
    std::fs::remove_file(&saved).unwrap();
    assert_eq!(
        again.state().state.recent_files()[1],
        (canonical_saved, false)
    );
}

#[test]
fn save_as_elsewhere_keeps_relative_mesh_paths_pointing_at_the_same_file() {
    let work = tempfile::tempdir().unwrap();
    let scene_path = copy_obj_cone(work.path());
    let moved = work.path().join("elsewhere/deeper/cone.toml");
    std::fs::create_dir_all(moved.parent().unwrap()).unwrap();
    let mut h = editor(Some(scene_path), &work.path().join("config"));
    steps(&mut h, 2);
    save_as(&mut h, &moved);
    assert_eq!(h.state().state.file_error(), None);
    assert!(!h.state().state.is_dirty());
    let saved = lucerna_scene::load_scene(&moved).unwrap();
    match &saved.parts[0].shape {
        Shape::Mesh(mesh) => assert_eq!(mesh.path, "../../meshes/cone_reflector.obj"),
        other => panic!("expected a mesh, got {other:?}"),
    }
    assert_eq!(h.state().state.scene(), Some(&saved));
    // The saved file works on its own.
    let mut again = editor(Some(moved), &work.path().join("config"));
    wait_for_snapshot(&mut again);
}

fn import_through_the_field(h: &mut Harness<'_, EditorApp>, obj: &Path) {
    import_obj(h, obj);
}

#[test]
fn an_imported_obj_is_one_mesh_part_that_undo_removes() {
    let config = tempfile::tempdir().unwrap();
    let mut h = editor(Some(example()), config.path());
    steps(&mut h, 2);
    let before = h.state().state.scene().unwrap().clone();
    import_through_the_field(&mut h, &assets().join("meshes/cone_reflector.obj"));
    let state = &h.state().state;
    assert_eq!(state.file_error(), None);
    let scene = state.scene().unwrap();
    assert_eq!(scene.parts.len(), 2);
    let part = &scene.parts[1];
    assert_eq!(part.name, "cone_reflector");
    assert_eq!(part.material, "polished_alu");
    match &part.shape {
        // Relative to the scene's folder, as a hand-written scene would.
        Shape::Mesh(mesh) => assert_eq!(mesh.path, "../meshes/cone_reflector.obj"),
        other => panic!("expected a mesh, got {other:?}"),
    }
    // The file is in millimetres (60 units across).
    assert_eq!(part.transform.scale, [0.001; 3]);
    assert!(state.problems().is_empty(), "{:?}", state.problems());
    assert!(state.notice().unwrap().contains("millimetres"));
    // A second import gets a name of its own.
    import_through_the_field(&mut h, &assets().join("meshes/cone_reflector.obj"));
    assert_eq!(
        h.state().state.scene().unwrap().parts[2].name,
        "cone_reflector 2"
    );
    wait_for_snapshot(&mut h);

    menu(&mut h, "Edit", "Undo");
    assert_eq!(parts(&h), 2);
    menu(&mut h, "Edit", "Undo");
    assert_eq!(h.state().state.scene(), Some(&before));
}

#[test]
fn a_broken_obj_shows_its_error_and_changes_nothing() {
    let work = tempfile::tempdir().unwrap();
    let broken = work.path().join("broken.obj");
    std::fs::write(&broken, "v 0 0 0\nv 1 0 0\nf 1 2 7\n").unwrap();
    let mut h = editor(Some(example()), &work.path().join("config"));
    steps(&mut h, 2);
    let before = h.state().state.scene().unwrap().clone();
    import_through_the_field(&mut h, &broken);
    let error = h.state().state.file_error().expect("an error").to_owned();
    assert!(error.contains("broken.obj"), "{error}");
    // In the notices under the menu bar, and in the status bar.
    assert!(h.query_all_by_label_contains("cannot import").count() >= 1);
    assert_eq!(h.state().state.scene(), Some(&before));
    assert!(!h.state().state.is_dirty());
    // An OBJ that parses but whose triangles are unusable (zero area) is
    // caught by tessellating the part before it is added.
    let degenerate = work.path().join("degenerate.obj");
    std::fs::write(&degenerate, "v 0 0 0\nv 0 0 0\nv 0 0 0\nf 1 2 3\n").unwrap();
    import_through_the_field(&mut h, &degenerate);
    let error = h.state().state.file_error().expect("an error").to_owned();
    assert!(error.contains("degenerate.obj"), "{error}");
    assert!(error.contains("unusable mesh"), "{error}");
    assert_eq!(h.state().state.scene(), Some(&before));
    // No undo step was added either.
    menu(&mut h, "Edit", "Undo");
    assert_eq!(h.state().state.scene(), Some(&before));
}

/// A file as the window system hands it over when dropped.
#[derive(Debug)]
struct Dropped(PathBuf);

impl egui::DroppedFile for Dropped {
    fn path(&self) -> &Path {
        &self.0
    }

    fn bytes(&self) -> Result<Vec<u8>, String> {
        std::fs::read(&self.0).map_err(|e| e.to_string())
    }
}

fn drop_file(h: &mut Harness<'_, EditorApp>, path: PathBuf) {
    h.input_mut().dropped_files.push(Arc::new(Dropped(path)));
    steps(h, 2);
}

#[test]
fn a_dropped_obj_is_imported_and_a_dropped_scene_opened_through_the_question() {
    let config = tempfile::tempdir().unwrap();
    let mut h = editor(Some(example()), config.path());
    steps(&mut h, 2);
    drop_file(&mut h, assets().join("meshes/cone_reflector.obj"));
    assert_eq!(h.state().state.file_error(), None);
    assert_eq!(parts(&h), 2);
    assert!(matches!(
        h.state().state.scene().unwrap().parts[1].shape,
        Shape::Mesh(_)
    ));
    // Unsaved changes now: a dropped scene asks first.
    let other = assets().join("luminaires/opal_bell.toml");
    drop_file(&mut h, other.clone());
    assert_eq!(h.state().state.pending_open(), Some(other.as_path()));
    h.get_by_label("Discard changes and open").click();
    steps(&mut h, 2);
    assert_eq!(h.state().state.path(), Some(other.as_path()));
    // Anything else is refused with a message.
    drop_file(&mut h, config.path().join("picture.png"));
    assert!(
        h.state()
            .state
            .file_error()
            .unwrap()
            .contains("drop a scene (.toml), an OBJ mesh (.obj) or a TM-25 ray file (.tm25ray)")
    );
}

#[test]
fn the_theme_switch_changes_the_theme_and_is_remembered() {
    let config = tempfile::tempdir().unwrap();
    let mut h = editor(None, config.path());
    steps(&mut h, 2);
    for (label, theme, choice) in [
        ("Light", egui::Theme::Light, ThemeChoice::Light),
        ("Dark", egui::Theme::Dark, ThemeChoice::Dark),
        ("Light", egui::Theme::Light, ThemeChoice::Light),
    ] {
        h.get_by_label("View").click();
        steps(&mut h, 2);
        h.get_by_label(label).click();
        steps(&mut h, 2);
        assert_eq!(h.ctx.theme(), theme, "after {label}");
        assert_eq!(h.state().state.theme_choice(), choice);
        // Close the menu.
        h.key_press(egui::Key::Escape);
        steps(&mut h, 2);
    }
    drop(h);
    let mut again = editor(None, config.path());
    steps(&mut again, 2);
    assert_eq!(again.state().state.theme_choice(), ThemeChoice::Light);
    assert_eq!(again.ctx.theme(), egui::Theme::Light);
}

#[test]
fn keyboard_zoom_is_on_and_remembered() {
    let config = tempfile::tempdir().unwrap();
    let mut h = editor(Some(example()), config.path());
    steps(&mut h, 2);
    assert!(h.ctx.options(|o| o.zoom_with_keyboard));
    let before = h.ctx.zoom_factor();
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Plus);
    steps(&mut h, 2);
    assert!(h.ctx.zoom_factor() > before, "{}", h.ctx.zoom_factor());
    let zoomed = h.ctx.zoom_factor();
    drop(h);
    // The next start keeps the zoom.
    let mut again = editor(None, config.path());
    steps(&mut again, 2);
    assert_eq!(again.ctx.zoom_factor(), zoomed);
    again.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::Num0);
    steps(&mut again, 2);
    assert_eq!(again.ctx.zoom_factor(), 1.0);
    drop(again);
    let mut third = editor(None, config.path());
    steps(&mut third, 2);
    assert_eq!(third.ctx.zoom_factor(), 1.0);
}

#[test]
fn a_ray_file_is_added_as_an_emitter_showing_the_files_own_flux() {
    use common::{answer_prompt, click};
    use lucerna_scene::EmitterShape;
    let work = tempfile::tempdir().unwrap();
    // The scene and the ray file in folders of their own: the path is
    // stored relative to the scene.
    std::fs::create_dir_all(work.path().join("luminaires")).unwrap();
    std::fs::create_dir_all(work.path().join("rays")).unwrap();
    let scene_path = work.path().join("luminaires/spot.toml");
    std::fs::copy(example(), &scene_path).unwrap();
    let led = work.path().join("rays/synthetic_led.tm25ray");
    std::fs::copy(assets().join("rayfiles/synthetic_led.tm25ray"), &led).unwrap();
    let rays = lucerna_photometry::tm25::read_ray_file(&led).unwrap();
    let declared = rays.header.luminous_flux_lm.map(f64::from);
    let own = declared.unwrap_or_else(|| rays.total_luminous_flux_lm());

    let mut h = editor(Some(scene_path), &work.path().join("config"));
    steps(&mut h, 2);
    let before = h.state().state.scene().unwrap().clone();
    // Add ray-file emitter…: the prompt stands in for the native dialog.
    click(&mut h, "Add ray-file emitter…");
    steps(&mut h, 3);
    answer_prompt(&mut h, "Ray file", &led, "Add");
    let state = &h.state().state;
    assert_eq!(state.file_error(), None);
    let scene = state.scene().unwrap();
    assert_eq!(scene.emitters.len(), before.emitters.len() + 1);
    let added = scene.emitters.last().unwrap();
    assert_eq!(added.name, "synthetic_led");
    assert_eq!(
        added.shape,
        EmitterShape::RayFile {
            path: "../rays/synthetic_led.tm25ray".to_owned()
        }
    );
    assert!(
        (added.flux_lm - own).abs() < 1e-3 * own,
        "{} vs {own}",
        added.flux_lm
    );
    assert!(state.problems().is_empty(), "{:?}", state.problems());
    // Once the simulation has read it, the panel shows its own flux and
    // rays beside the Flux field.
    let deadline = Instant::now() + Duration::from_secs(60);
    let words = format!("{} rays", rays.len());
    loop {
        h.step();
        if h.query_all_by_label_contains(&words).count() > 0 {
            break;
        }
        assert!(Instant::now() < deadline, "no '{words}' shown in 60 s");
        std::thread::sleep(Duration::from_millis(10));
    }
    let summed = format!("{:.1} lm in its rays", rays.total_luminous_flux_lm());
    assert!(
        h.query_all_by_label_contains(&summed).count() > 0,
        "no '{summed}'"
    );
    // One undo step.
    menu(&mut h, "Edit", "Undo");
    assert_eq!(h.state().state.scene(), Some(&before));

    // A file that is not a ray file: its error, nothing added.
    let bogus = work.path().join("rays/bogus.tm25ray");
    std::fs::write(&bogus, b"not a ray file at all").unwrap();
    click(&mut h, "Add ray-file emitter…");
    steps(&mut h, 3);
    answer_prompt(&mut h, "Ray file", &bogus, "Add");
    let error = h.state().state.file_error().expect("an error").to_owned();
    assert!(error.contains("bogus.tm25ray"), "{error}");
    assert_eq!(h.state().state.scene(), Some(&before));
    // Dropped on the window, a ray file is added the same way.
    drop_file(&mut h, led.clone());
    let scene = h.state().state.scene().unwrap();
    assert_eq!(scene.emitters.last().unwrap().name, "synthetic_led");
}
