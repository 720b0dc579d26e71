//! Lucerna's luminaire editor: edit a scene and watch its light
//! distribution converge while the simulation restarts on every edit.
//!
//! The state ([`EditorState`]) knows nothing of drawing; each panel is one
//! file of `_ui` functions that edit scene fields in place and queue
//! everything else as [`Command`]s, applied once per frame.

mod app;
mod files_bar;
mod modelling;
mod profile_editor;
mod scene_panel;
mod simulation_panel;
mod state;
mod views;
mod widgets;

use std::path::PathBuf;

pub use app::EditorApp;
pub use state::{Command, EditorState, NewPart, SceneEdit, Selection, View};

/// Why the editor could not run.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RunEditorError {
    #[error(
        "no display (neither DISPLAY nor WAYLAND_DISPLAY is set): the editor needs a window; \
         for headless use run `lucerna bake SCENE.toml`"
    )]
    NoDisplay,
    #[error("cannot open the editor's window; for headless use run `lucerna bake SCENE.toml`")]
    Window(#[source] eframe::Error),
}

/// Opens the editor's window on `scene` (or none) and runs until it closes.
pub fn run(scene: Option<PathBuf>) -> Result<(), RunEditorError> {
    if std::env::var_os("DISPLAY").is_none() && std::env::var_os("WAYLAND_DISPLAY").is_none() {
        return Err(RunEditorError::NoDisplay);
    }
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_inner_size([1366.0, 768.0])
            .with_min_inner_size([800.0, 500.0])
            .with_title("Lucerna editor"),
        ..eframe::NativeOptions::default()
    };
    let settings = lucerna_simulation::SimulationSettings {
        resolution: 64,
        ..lucerna_simulation::SimulationSettings::default()
    };
    let state = EditorState::new(scene, settings);
    eframe::run_native(
        "Lucerna editor",
        options,
        Box::new(move |_creation| Ok(Box::new(EditorApp::new(state)))),
    )
    .map_err(RunEditorError::Window)
}
