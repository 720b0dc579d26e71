//! What the editor shows with no scene open: New, the example luminaires,
//! the recent files.

use std::path::{Path, PathBuf};

use egui::Ui;

use crate::command::Command;
use crate::command::DialogKind;
use crate::state::EditorState;

/// The example luminaires beside the binary's sources or the working
/// folder (`assets/luminaires`), by name.
pub fn examples() -> Vec<PathBuf> {
    let candidates = [
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires"),
        PathBuf::from("assets/luminaires"),
    ];
    let Some(dir) = candidates.iter().find(|d| d.is_dir()) else {
        return Vec::new();
    };
    let mut found: Vec<PathBuf> = std::fs::read_dir(dir)
        .map(|entries| {
            entries
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|p| p.extension().is_some_and(|e| e == "toml"))
                .collect()
        })
        .unwrap_or_default();
    found.sort();
    found
}

pub fn start_page_ui(ui: &mut Ui, state: &mut EditorState, examples: &[PathBuf]) {
    let mut commands = Vec::new();
    ui.vertical_centered(|ui| {
        ui.add_space(40.0);
        ui.heading("Lucerna");
        ui.label("Model a reflector, watch its light distribution converge, see a room lit by it.");
        ui.add_space(20.0);
        ui.horizontal(|ui| {
            if ui
                .button("New scene")
                .on_hover_text("A lamp and a reflector to start from")
                .clicked()
            {
                commands.push(Command::New);
            }
            if ui
                .add_enabled(
                    !state.files.dialogs.is_open(),
                    egui::Button::new("Open a scene…"),
                )
                .clicked()
            {
                commands.push(Command::FileDialog(DialogKind::Open));
            }
        });
    });
    ui.add_space(20.0);
    ui.columns(2, |columns| {
        columns[0].strong("Examples");
        for path in examples {
            let name = path
                .file_stem()
                .map_or_else(String::new, |s| s.to_string_lossy().replace('_', " "));
            if columns[0]
                .button(format!("Open example {name}"))
                .on_hover_text(path.display().to_string())
                .clicked()
            {
                commands.push(Command::Open(path.clone()));
            }
        }
        columns[1].strong("Recent files");
        let recent = state.recent_files();
        if recent.is_empty() {
            columns[1].label("None yet.");
        }
        for (path, exists) in recent {
            if columns[1]
                .add_enabled(exists, egui::Button::new(path.display().to_string()))
                .on_disabled_hover_text("this file no longer exists")
                .clicked()
            {
                commands.push(Command::Open(path.clone()));
            }
        }
    });
    for c in commands {
        state.push(c);
    }
}
