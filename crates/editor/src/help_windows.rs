//! The Help menu's windows: keyboard shortcuts and About.

use crate::ui_command::UiCommand;

/// The shortcuts window (Help ▸ Keyboard shortcuts, F1).
pub fn shortcuts_window_ui(ctx: &egui::Context, open: &mut bool) {
    egui::Window::new("Keyboard shortcuts")
        .open(open)
        .resizable(false)
        .show(ctx, |ui| {
            egui::Grid::new("shortcuts").striped(true).show(ui, |ui| {
                for c in UiCommand::ALL {
                    if let Some(s) = c.shortcut() {
                        ui.label(c.label().trim_end_matches('…'));
                        ui.label(ctx.format_shortcut(&s));
                        ui.end_row();
                    }
                }
                for (what, keys) in [
                    ("Zoom the window", "Ctrl+Plus, Ctrl+Minus, Ctrl+0"),
                    ("Orbit the 3D view", "drag"),
                    ("Pan the 3D view", "Shift+drag or right drag"),
                    ("Frame the luminaire", "F or double-click"),
                ] {
                    ui.label(what);
                    ui.label(keys);
                    ui.end_row();
                }
            });
        });
}

/// Help ▸ About.
pub fn about_window_ui(ctx: &egui::Context, open: &mut bool) {
    egui::Window::new("About Lucerna")
        .open(open)
        .resizable(false)
        .show(ctx, |ui| {
            ui.heading(format!("Lucerna {}", env!("CARGO_PKG_VERSION")));
            ui.label("Luminaire development: model a reflector, trace its light distribution,");
            ui.label("export IES and EULUMDAT files, see a room lit by it.");
            ui.label(format!(
                "CPU: {} threads; {}",
                rayon::current_num_threads(),
                lucerna_tracer::bvh::CpuTraversal::best().describe()
            ));
        });
}
