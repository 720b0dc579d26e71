//! Lucerna's luminaire editor: edit a scene and watch its light
//! distribution converge while the simulation restarts on every edit.
//!
//! The state ([`EditorState`]) knows nothing of drawing; each panel is one
//! file of `_ui` functions that edit scene fields in place and queue
//! everything else as [`Command`]s, applied once per frame.

mod actions;
mod app;
mod benchmarks;
mod colour;
mod command;
mod config;
mod design;
mod design_pane;
mod design_state;
mod dialogs;
pub mod dock;
mod document;
mod error_text;
mod export_dialog;
mod export_job;
mod file_state;
mod files;
mod finish_fields;
mod geometry_dialog;
mod help_windows;
mod imports;
mod intensity_unit;
mod live_run;
mod menu_bar;
mod modelling;
mod notices;
mod pacer;
mod pane;
mod profile_editor;
mod profile_pane;
mod recovery;
mod reference;
mod room_preview;
mod room_state;
mod room_view;
mod scene_panel;
mod scene_paths;
mod selection;
mod simulation_panel;
mod start_page;
mod state;
mod status_bar;
mod tolerance;
mod tolerance_pane;
mod tolerance_state;
mod ui_command;
mod viewport;
mod views;
mod widgets;

use std::path::PathBuf;

pub use app::EditorApp;
pub use benchmarks::{BenchmarkOptions, DragTarget};
pub use command::DialogKind;
pub use config::{EditorPaths, MAX_RECENT, ThemeChoice};
pub use file_state::PendingAction;
pub use files::starter_scene;
pub use imports::ImportMeshError;
pub use recovery::RecoveryOffer;
pub use room_preview::{
    DRAFT_SIZE, FINE_SIZE, PictureQuality, RenderRequest, Renderer, RoomLight, RoomPicture,
    RoomPreview, default_rooms_dir,
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

/// Tracing and filtering run on rayon's global pool, its threads at nice
/// 10: against them a frame (egui's thread and, on a machine without a GPU,
/// the software rasteriser's threads) gets the CPU when it needs it, while
/// other programs still leave the tracer a fair share. On 2 cores the UI
/// otherwise got half a core against the tracer's two threads. A platform
/// that refuses keeps normal priority.
fn tracer_threads_at_low_priority() {
    let _ = rayon::ThreadPoolBuilder::new()
        .thread_name(|i| format!("lucerna-trace-{i}"))
        .start_handler(|_| lower_this_threads_priority())
        .build_global();
}

#[cfg(target_os = "linux")]
pub(crate) fn lower_this_threads_priority() {
    use thread_priority::unix::{
        NormalThreadSchedulePolicy, ThreadSchedulePolicy, set_thread_priority_and_policy,
        thread_native_id,
    };
    // The crate's 0–99 scale maps 22 to nice 10 under the normal policy.
    let Ok(priority) = thread_priority::ThreadPriorityValue::try_from(22u8) else {
        return;
    };
    let _ = set_thread_priority_and_policy(
        thread_native_id(),
        thread_priority::ThreadPriority::Crossplatform(priority),
        ThreadSchedulePolicy::Normal(NormalThreadSchedulePolicy::Other),
    );
}

#[cfg(not(target_os = "linux"))]
pub(crate) fn lower_this_threads_priority() {
    let _ = thread_priority::set_current_thread_priority(thread_priority::ThreadPriority::Min);
}

/// How the window starts.
#[derive(Debug, Clone, Default)]
pub struct RunOptions {
    pub scene: Option<PathBuf>,
    /// The photometric view shown first.
    pub view: View,
    /// Run a benchmark, then print its figures and close.
    pub benchmark: Option<BenchmarkOptions>,
}

/// Opens the editor's window and runs until it closes.
pub fn run(options: RunOptions) -> Result<(), RunEditorError> {
    if std::env::var_os("DISPLAY").is_none() && std::env::var_os("WAYLAND_DISPLAY").is_none() {
        return Err(RunEditorError::NoDisplay);
    }
    let native = eframe::NativeOptions {
        viewport: egui::ViewportBuilder::default()
            .with_inner_size([1366.0, 768.0])
            .with_min_inner_size([800.0, 500.0])
            .with_title("Lucerna editor"),
        wgpu_options: wgpu_configuration(),
        ..eframe::NativeOptions::default()
    };
    tracer_threads_at_low_priority();
    let mut state = EditorState::with_paths(
        options.scene,
        live_run::editor_settings(),
        EditorPaths::user(),
    );
    state.view = options.view;
    let benchmark = options.benchmark;
    eframe::run_native(
        "Lucerna editor",
        native,
        Box::new(move |cc| {
            let app = EditorApp::from_creation(cc, state);
            Ok(Box::new(match benchmark {
                Some(options) => app.with_benchmark(options),
                None => app,
            }))
        }),
    )
    .map_err(RunEditorError::Window)
}
