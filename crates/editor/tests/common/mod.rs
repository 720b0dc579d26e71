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

/// Masks the figures that follow wall time (iterations, photons/s, the
/// status bar) or the machine (the tracer's threads), then hides the
/// cursor.
pub fn mask_time_dependent(h: &mut Harness<'_, EditorApp>) {
    // The status bar: photons and photons/s follow wall time.
    let status = h.get_by_label_contains(" M photons/s").rect();
    h.mask(egui::Rect::from_min_max(
        egui::pos2(0.0, status.min.y),
        egui::pos2(4000.0, status.max.y),
    ));
    // And the machine: the tracer's thread count in the Backend rows.
    for row in ["Iteration", "Photons/s", "Backend"] {
        let rects: Vec<egui::Rect> = h.get_all_by_label(row).map(|n| n.rect()).collect();
        for label in rects {
            let wide = egui::Rect::from_min_max(label.min, egui::pos2(4000.0, label.max.y));
            h.mask(wide);
        }
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

/// Picks `option` in the combo box (or menu button) labelled `combo`: a
/// combo box first, since a figure row of the same name may show beside
/// it once a snapshot arrives, as "Backend" does.
pub fn choose(h: &mut Harness<'_, EditorApp>, combo: &str, option: &str) {
    match h.query_by_role_and_label(egui::accesskit::Role::ComboBox, combo) {
        Some(node) => node.click(),
        None => h.get_by_label(combo).click(),
    }
    steps(h, 2);
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

/// Queues `command` as a panel or a native dialog would, then lets two
/// frames pass.
pub fn command(h: &mut Harness<'_, EditorApp>, command: lucerna_editor::Command) {
    h.state_mut().state.push(command);
    steps(h, 2);
}

/// Chooses `item` in the menu bar's `top` menu (its accessible name is
/// the label and the shortcut: "Undo Ctrl+Z").
pub fn menu(h: &mut Harness<'_, EditorApp>, top: &str, item: &str) {
    click(h, top);
    // An item with a shortcut is named "Save Ctrl+S"; "Save" alone must
    // not find "Save As… Ctrl+Shift+S".
    let found = h.query_by_label(item).or_else(|| {
        h.query_by(|n| {
            n.label().is_some_and(|l| {
                l.strip_prefix(item)
                    .and_then(|rest| rest.strip_prefix(' '))
                    .is_some_and(|keys| {
                        !keys.contains(' ')
                            && (keys.contains('+') || keys[1..].parse::<u8>().is_ok())
                    })
            })
        })
    });
    found
        .unwrap_or_else(|| panic!("no menu item {item} in {top}"))
        .click();
    // The click is taken the frame after, its command applied at that
    // frame's end, and what it opens drawn the frame after that.
    steps(h, 3);
}

/// Answers the window's path prompt (what stands in for a native file
/// dialog in tests): types `path` into its `field` and clicks `confirm`.
pub fn answer_prompt(
    h: &mut Harness<'_, EditorApp>,
    field: &str,
    path: &std::path::Path,
    confirm: &str,
) {
    h.get_by_label(field)
        .set_text_value_accesskit(&path.display().to_string());
    steps(h, 1);
    click(h, confirm);
}

/// File ▸ Save As…, answered with `path`.
pub fn save_as(h: &mut Harness<'_, EditorApp>, path: &std::path::Path) {
    menu(h, "File", "Save As…");
    answer_prompt(h, "Save as path", path, "Save");
}

/// File ▸ Open…, answered with `path`.
pub fn open(h: &mut Harness<'_, EditorApp>, path: &std::path::Path) {
    menu(h, "File", "Open…");
    answer_prompt(h, "Scene file", path, "Open");
}

/// File ▸ Import OBJ…, answered with `path`.
pub fn import_obj(h: &mut Harness<'_, EditorApp>, path: &std::path::Path) {
    menu(h, "File", "Import OBJ…");
    answer_prompt(h, "OBJ file", path, "Import");
}
