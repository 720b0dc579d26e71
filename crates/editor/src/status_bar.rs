//! The status bar: where the run stands (state, photons, photons/s, peak
//! noise), whether the file is saved, and the last error.

use egui::Ui;
use lucerna_simulation::RunState;

use crate::state::EditorState;

pub fn status_bar_ui(ui: &mut Ui, state: &EditorState) {
    ui.horizontal(|ui| {
        match state.snapshot() {
            Some(s) => {
                let run = match s.state {
                    RunState::Tracing if state.is_coarse_preview() => "Previewing the drag",
                    RunState::Tracing => "Tracing",
                    RunState::Paused => "Paused",
                    RunState::Finished(_) => "Finished",
                };
                ui.label(run);
                ui.separator();
                ui.label(format!("{} photons", group_thousands(s.photons)))
                    .on_hover_text(format!(
                        "iteration {}, {} per cube face edge",
                        s.iteration, s.map.layout.resolution
                    ));
                ui.separator();
                ui.label(format!("{:.2} M photons/s", s.photons_per_second / 1e6));
                ui.separator();
                ui.label(format!(
                    "peak noise ±{:.2} %",
                    100.0 * s.noise.peak_relative
                ))
                .on_hover_text("relative standard error of the brightest direction");
            }
            None if state.scene().is_some() => {
                ui.label("Preparing the first run…");
            }
            None => {
                ui.label("No scene");
            }
        }
        ui.separator();
        let file = match (state.path(), state.is_dirty()) {
            (Some(p), dirty) => format!(
                "{}{}",
                p.file_name()
                    .map_or_else(String::new, |n| n.to_string_lossy().into_owned()),
                if dirty {
                    " (unsaved changes)"
                } else {
                    " (saved)"
                }
            ),
            (None, _) if state.scene().is_some() => "unsaved new scene".to_owned(),
            (None, _) => String::new(),
        };
        ui.label(file);
        if let Some(design) = state.design_status() {
            ui.separator();
            ui.label(design);
        }
        let error = state
            .simulation_error()
            .or(state.file_error())
            .or(state.edit_error())
            .map(|e| e.lines().next().unwrap_or_default().to_owned())
            .or_else(|| match state.problems().len() {
                0 => None,
                1 => Some("1 problem in the scene: see the scene panel".to_owned()),
                n => Some(format!("{n} problems in the scene: see the scene panel")),
            });
        if let Some(error) = error {
            ui.separator();
            ui.colored_label(ui.visuals().error_fg_color, error);
        }
    });
}

/// 1234567 → "1 234 567" (thin grouping, as the figures view).
fn group_thousands(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (k, c) in digits.chars().enumerate() {
        if k > 0 && (digits.len() - k).is_multiple_of(3) {
            out.push('\u{2009}');
        }
        out.push(c);
    }
    out
}

#[cfg(test)]
mod tests {
    #[test]
    fn thousands_are_grouped() {
        assert_eq!(super::group_thousands(0), "0");
        assert_eq!(super::group_thousands(999), "999");
        assert_eq!(super::group_thousands(1_234_567), "1\u{2009}234\u{2009}567");
    }
}
