//! The top bar: open, save, save as, undo and redo, and the file error.

use std::path::PathBuf;

use egui::Ui;

use crate::state::{Command, EditorState};
use crate::widgets::labelled;

pub fn files_bar_ui(ui: &mut Ui, state: &mut EditorState) {
    let mut commands = Vec::new();
    ui.horizontal_wrapped(|ui| {
        labelled(ui, "Scene file", |ui| {
            ui.add(egui::TextEdit::singleline(&mut state.open_path).desired_width(260.0))
        });
        if ui.button("Open").clicked() && !state.open_path.trim().is_empty() {
            commands.push(Command::Open(PathBuf::from(state.open_path.trim())));
        }
        ui.separator();
        if ui.button("Save").on_hover_text("Ctrl+S").clicked() {
            commands.push(Command::Save);
        }
        labelled(ui, "Save as path", |ui| {
            ui.add(egui::TextEdit::singleline(&mut state.save_as_path).desired_width(200.0))
        });
        if ui.button("Save as").clicked() && !state.save_as_path.trim().is_empty() {
            commands.push(Command::SaveAs(PathBuf::from(state.save_as_path.trim())));
        }
        ui.separator();
        if ui.button("Undo").on_hover_text("Ctrl+Z").clicked() {
            commands.push(Command::Undo);
        }
        if ui.button("Redo").on_hover_text("Ctrl+Shift+Z").clicked() {
            commands.push(Command::Redo);
        }
        ui.separator();
        ui.label(state.title());
    });
    if let Some(path) = state.pending_open.clone() {
        ui.horizontal(|ui| {
            ui.colored_label(
                ui.visuals().warn_fg_color,
                format!("Unsaved changes: open {} anyway?", path.display()),
            );
            if ui.button("Discard changes and open").clicked() {
                commands.push(Command::OpenDiscarding(path));
            }
            if ui.button("Keep editing").clicked() {
                commands.push(Command::CancelOpen);
            }
        });
    }
    if let Some(error) = &state.file_error {
        ui.colored_label(ui.visuals().error_fg_color, error);
    }
    for c in commands {
        state.push(c);
    }
}
