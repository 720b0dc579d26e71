//! Lucerna's luminaire editor: edit a scene and watch its light
//! distribution converge while the simulation restarts on every edit.
//!
//! The state ([`EditorState`]) knows nothing of drawing; each panel is one
//! file of `_ui` functions that edit scene fields in place and queue
//! everything else as [`Command`]s, applied once per frame.

mod app;
mod benchmark;
mod colour;
mod config;
mod dialogs;
mod export_dialog;
mod files;
mod files_bar;
mod modelling;
mod profile_editor;
mod recovery;
mod room_preview;
mod room_view;
mod scene_panel;
mod simulation_panel;
mod state;
mod viewport;
mod views;
mod widgets;

use std::path::PathBuf;

pub use app::EditorApp;
pub use config::{EditorPaths, MAX_RECENT, ThemeChoice};
pub use dialogs::DialogKind;
pub use files::{ImportMeshError, PendingAction, starter_scene};
pub use recovery::RecoveryOffer;
pub use room_preview::{
    DRAFT_SIZE, FINE_SIZE, RenderRequest, Renderer, RoomBackend, RoomPicture, RoomPreview,
    RoomSetup, TASK_TARGETS, TaskTarget, default_rooms_dir,
};
pub use state::{Command, EditorState, NewPart, SceneEdit, Selection, View};
pub use viewport::{Bounds, CubeShown, GpuTarget, OrbitCamera, StandardView, Viewport, pick};

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

/// eframe's wgpu setup, asking for the adapter's own limits: on GL (all a
/// machine without Vulkan has) egui's default is WebGL2's, with no storage
/// buffers and 2048-texel textures.
fn wgpu_configuration() -> eframe::egui_wgpu::WgpuConfiguration {
    use eframe::egui_wgpu::{WgpuSetup, WgpuSetupCreateNew};
    use eframe::wgpu;
    let mut setup = WgpuSetupCreateNew::without_display_handle();
    setup.device_descriptor =
        std::sync::Arc::new(|adapter: &wgpu::Adapter| wgpu::DeviceDescriptor {
            label: Some("Lucerna editor"),
            required_limits: adapter.limits(),
            ..wgpu::DeviceDescriptor::default()
        });
    eframe::egui_wgpu::WgpuConfiguration {
        wgpu_setup: WgpuSetup::CreateNew(setup),
        ..eframe::egui_wgpu::WgpuConfiguration::default()
    }
}

/// Opens the editor's window on `scene` (or none) and runs until it closes;
/// with `benchmark`, for that long under measurement (figures printed on
/// exit).
pub fn run(
    scene: Option<PathBuf>,
    benchmark: Option<std::time::Duration>,
) -> Result<(), RunEditorError> {
    if std::env::var_os("DISPLAY").is_none() && std::env::var_os("WAYLAND_DISPLAY").is_none() {
        return Err(RunEditorError::NoDisplay);
    }
    let options = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_inner_size([1366.0, 768.0])
            .with_min_inner_size([800.0, 500.0])
            .with_title("Lucerna editor"),
        wgpu_options: wgpu_configuration(),
        ..eframe::NativeOptions::default()
    };
    let settings = lucerna_simulation::SimulationSettings {
        resolution: 64,
        ..lucerna_simulation::SimulationSettings::default()
    };
    let state = EditorState::with_paths(scene, settings, EditorPaths::user());
    eframe::run_native(
        "Lucerna editor",
        options,
        Box::new(move |cc| {
            let app = EditorApp::from_creation(cc, state);
            Ok(Box::new(match benchmark {
                Some(d) => app.with_benchmark(d),
                None => app,
            }))
        }),
    )
    .map_err(RunEditorError::Window)
}
