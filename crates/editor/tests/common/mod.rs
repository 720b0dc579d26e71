//! What the editor's kittest tests share: stepping, clicking, typing and
//! choosing by label; an editor drawn by egui's wgpu renderer (the
//! software adapter here) for pictures, and the masks over what follows
//! wall time.

#![allow(dead_code)] // reason: each test file uses a part of it

use egui_kittest::Harness;
use egui_kittest::kittest::Queryable;
use lucerna_editor::{EditorApp, EditorState, GpuTarget};

/// An editor whose 3D view and plots are rendered for snapshots.
pub fn wgpu_editor(state: EditorState, size: [f32; 2]) -> Harness<'static, EditorApp> {
    wgpu_editor_with(state, size, |target| target)
}

/// [`wgpu_editor`] with the 3D view's target adjusted (e.g. no MSAA, as a
/// GL driver may only allow).
pub fn wgpu_editor_with(
    state: EditorState,
    size: [f32; 2],
    adjust: impl FnOnce(GpuTarget) -> GpuTarget,
) -> Harness<'static, EditorApp> {
    let render_state = egui_kittest::wgpu::create_render_state(
        egui_kittest::wgpu::default_wgpu_setup(),
        eframe::egui_wgpu::RendererOptions::PREDICTABLE,
    );
    let target = adjust(GpuTarget::new(
        &render_state.adapter,
        render_state.target_format,
    ));
    Harness::builder()
        .with_size(size)
        .renderer(egui_kittest::wgpu::WgpuTestRenderer::from_render_state(
            render_state,
        ))
        .build_ui_state(
            |ui, app: &mut EditorApp| app.ui(ui),
            EditorApp::with_gpu_target(state, Some(target)),
        )
}

/// Masks the checkout's path and the figures that follow wall time
/// (iterations, photons/s), then hides the cursor.
pub fn mask_time_dependent(h: &mut Harness<'_, EditorApp>) {
    h.mask(h.get_by_label("Scene file").rect());
    for row in ["Iteration", "Photons/s"] {
        let label = h.get_by_label(row).rect();
        let wide = egui::Rect::from_min_max(label.min, egui::pos2(4000.0, label.max.y));
        h.mask(wide);
    }
    h.remove_cursor();
    h.run_steps(2);
}

/// A snapshot compared with a threshold, never exact pixels.
pub fn snapshot(h: &mut Harness<'_, EditorApp>, name: &str) {
    h.snapshot_options(
        name,
        &egui_kittest::SnapshotOptions::new()
            .threshold(1.5)
            .max_failed_pixels(2500),
    );
}

/// Steps `n` frames.
pub fn steps(h: &mut Harness<'_, EditorApp>, n: usize) {
    for _ in 0..n {
        h.step();
    }
}

/// Clicks the widget labelled `label`, then lets two frames pass.
pub fn click(h: &mut Harness<'_, EditorApp>, label: &str) {
    h.get_by_label(label).click();
    steps(h, 2);
}

/// Picks `option` in the combo box labelled `combo`.
pub fn choose(h: &mut Harness<'_, EditorApp>, combo: &str, option: &str) {
    click(h, combo);
    click(h, option);
}

/// Replaces the text of the field labelled `label` and presses Enter.
pub fn type_into(h: &mut Harness<'_, EditorApp>, label: &str, text: &str) {
    click(h, label);
    h.key_press_modifiers(egui::Modifiers::COMMAND, egui::Key::A);
    h.step();
    h.get_by_label(label).type_text(text);
    h.step();
    h.key_press(egui::Key::Enter);
    steps(h, 2);
}

/// Sets the numeric field labelled `label` through accessibility.
pub fn set(h: &mut Harness<'_, EditorApp>, label: &str, value: f64) {
    h.get_by_label(label).set_value_accesskit(value);
    steps(h, 2);
}
