//! The top bar: new, open (field, dialog, recent), save, save as, OBJ
//! import, undo and redo, the View menu (theme, zoom), and the questions
//! and messages of file handling (unsaved changes, recovery, errors).

use std::path::PathBuf;

use egui::Ui;

use crate::config::ThemeChoice;
use crate::dialogs::DialogKind;
use crate::export_dialog::ExportDialog;
use crate::files::PendingAction;
use crate::state::{Command, EditorState};
use crate::widgets::labelled;

pub fn files_bar_ui(ui: &mut Ui, state: &mut EditorState, export: &mut ExportDialog) {
    let mut commands = Vec::new();
    let dialog_open = state.files.dialogs.is_open();
    ui.horizontal_wrapped(|ui| {
        if ui.button("New").on_hover_text("Ctrl+N").clicked() {
            commands.push(Command::New);
        }
        ui.separator();
        // Each field stays with its buttons (on narrow windows too).
        ui.horizontal(|ui| {
            labelled(ui, "Scene file", |ui| {
                ui.add(egui::TextEdit::singleline(&mut state.open_path).desired_width(240.0))
            });
            if ui.button("Open").clicked() && !state.open_path.trim().is_empty() {
                commands.push(Command::Open(PathBuf::from(state.open_path.trim())));
            }
            if ui
                .add_enabled(!dialog_open, egui::Button::new("Open…"))
                .on_hover_text("Choose a scene file in a dialog")
                .clicked()
            {
                commands.push(Command::FileDialog(DialogKind::Open));
            }
            recent_menu_ui(ui, state, &mut commands);
        });
        ui.separator();
        if ui.button("Save").on_hover_text("Ctrl+S").clicked() {
            commands.push(Command::Save);
        }
        ui.horizontal(|ui| {
            labelled(ui, "Save as path", |ui| {
                ui.add(egui::TextEdit::singleline(&mut state.save_as_path).desired_width(180.0))
            });
            if ui.button("Save as").clicked() && !state.save_as_path.trim().is_empty() {
                commands.push(Command::SaveAs(PathBuf::from(state.save_as_path.trim())));
            }
            if ui
                .add_enabled(!dialog_open, egui::Button::new("Save as…"))
                .on_hover_text("Choose where to save in a dialog")
                .clicked()
            {
                commands.push(Command::FileDialog(DialogKind::SaveAs));
            }
        });
        ui.separator();
        if ui
            .button("Export…")
            .on_hover_text("IES, EULUMDAT, EXR and PNGs of the current result")
            .clicked()
        {
            export.open = true;
        }
    });
    // A second row: on one row the bar is wider than a 1366-pixel laptop
    // screen, and egui cannot wrap a field together with its buttons.
    ui.horizontal_wrapped(|ui| {
        ui.horizontal(|ui| {
            labelled(ui, "OBJ file", |ui| {
                ui.add(
                    egui::TextEdit::singleline(&mut state.files.import_path).desired_width(160.0),
                )
            });
            if ui
                .button("Import OBJ")
                .on_hover_text("Add the OBJ file as a mesh part (or drop it on the window)")
                .clicked()
                && !state.files.import_path.trim().is_empty()
            {
                commands.push(Command::ImportMesh(PathBuf::from(
                    state.files.import_path.trim(),
                )));
            }
            if ui
                .add_enabled(!dialog_open, egui::Button::new("Import OBJ…"))
                .on_hover_text("Choose an OBJ file in a dialog")
                .clicked()
            {
                commands.push(Command::FileDialog(DialogKind::ImportMesh));
            }
        });
        ui.separator();
        if ui.button("Undo").on_hover_text("Ctrl+Z").clicked() {
            commands.push(Command::Undo);
        }
        if ui.button("Redo").on_hover_text("Ctrl+Shift+Z").clicked() {
            commands.push(Command::Redo);
        }
        ui.separator();
        view_menu_ui(ui, state, &mut commands);
        ui.separator();
        ui.label(state.title());
    });
    if ui.ctx().input(|i| !i.raw.hovered_files.is_empty()) {
        ui.colored_label(
            ui.visuals().hyperlink_color,
            "Drop a scene (.toml) to open it or an OBJ mesh (.obj) to import it",
        );
    }
    recovery_banner_ui(ui, state, &mut commands);
    pending_banner_ui(ui, state, &mut commands);
    if let Some(error) = &state.file_error {
        ui.colored_label(ui.visuals().error_fg_color, error);
    }
    if let Some(notice) = state.notice() {
        ui.label(notice);
    }
    for c in commands {
        state.push(c);
    }
}

/// The last scenes opened or saved; files that have gone are greyed.
fn recent_menu_ui(ui: &mut Ui, state: &EditorState, commands: &mut Vec<Command>) {
    let recent = state.recent_files();
    ui.add_enabled_ui(!recent.is_empty(), |ui| {
        ui.menu_button("Recent", |ui| {
            for (path, exists) in &recent {
                let text = path.display().to_string();
                let button = ui
                    .add_enabled(*exists, egui::Button::new(&text))
                    .on_disabled_hover_text("this file no longer exists");
                if button.clicked() {
                    commands.push(Command::Open(path.clone()));
                }
            }
            ui.separator();
            if ui.button("Clear recent files").clicked() {
                commands.push(Command::ClearRecent);
            }
        })
        .response
        .on_hover_text("Recently opened or saved scenes");
    });
}

/// Theme and zoom. egui's own Ctrl+Plus / Ctrl+Minus / Ctrl+0 zoom is on
/// (`Options::zoom_with_keyboard`), so a 1366×768 laptop and a 4K screen
/// both get a usable size; the menu names the keys.
fn view_menu_ui(ui: &mut Ui, state: &EditorState, commands: &mut Vec<Command>) {
    ui.menu_button("View", |ui| {
        ui.label("Theme");
        let current = state.theme_choice();
        for (choice, name) in [
            (ThemeChoice::Dark, "Dark"),
            (ThemeChoice::Light, "Light"),
            (ThemeChoice::System, "Follow the system"),
        ] {
            if ui.radio(current == choice, name).clicked() {
                commands.push(Command::SetTheme(choice));
            }
        }
        ui.separator();
        ui.label(format!(
            "Zoom {:.0} % (Ctrl+Plus, Ctrl+Minus, Ctrl+0)",
            ui.ctx().zoom_factor() * 100.0
        ));
        egui::gui_zoom::zoom_menu_buttons(ui);
    });
}

fn recovery_banner_ui(ui: &mut Ui, state: &EditorState, commands: &mut Vec<Command>) {
    let Some(offer) = state.recovery_offer() else {
        return;
    };
    let what = offer
        .original
        .as_ref()
        .map_or_else(|| "a new scene".to_owned(), |p| p.display().to_string());
    ui.horizontal_wrapped(|ui| {
        ui.colored_label(
            ui.visuals().warn_fg_color,
            format!(
                "Recover unsaved changes to {what} from {}?",
                offer.written_local()
            ),
        );
        if ui.button("Recover").clicked() {
            commands.push(Command::Recover);
        }
        if ui.button("Discard").clicked() {
            commands.push(Command::DiscardRecovery);
        }
    });
}

fn pending_banner_ui(ui: &mut Ui, state: &EditorState, commands: &mut Vec<Command>) {
    let Some(pending) = state.pending() else {
        return;
    };
    let (question, discard, command) = match pending {
        PendingAction::Open(path) => (
            format!("Unsaved changes: open {} anyway?", path.display()),
            "Discard changes and open",
            Command::OpenDiscarding(path.clone()),
        ),
        PendingAction::New => (
            "Unsaved changes: start a new scene anyway?".to_owned(),
            "Discard changes and start a new scene",
            Command::NewDiscarding,
        ),
        PendingAction::Quit => (
            "Unsaved changes: quit anyway?".to_owned(),
            "Discard changes and quit",
            Command::QuitDiscarding,
        ),
    };
    ui.horizontal_wrapped(|ui| {
        ui.colored_label(ui.visuals().warn_fg_color, question);
        if ui.button(discard).clicked() {
            commands.push(command);
        }
        if ui.button("Keep editing").clicked() {
            commands.push(Command::CancelPending);
        }
    });
}
