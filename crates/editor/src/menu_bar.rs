//! The menu bar: File, Edit, View, Simulation, Help, each item a
//! [`UiCommand`] (whose label and shortcut live there) carried out by
//! [`crate::actions::run`].

use egui::Ui;

use crate::actions::{Windows, enabled, run};
use crate::command::Command;
use crate::config::ThemeChoice;
use crate::dock::{Dock, Pane};
use crate::state::EditorState;
use crate::ui_command::UiCommand;

/// One menu item: its label, shortcut and hover text from [`UiCommand`].
fn item_ui(ui: &mut Ui, state: &EditorState, command: UiCommand) -> Option<UiCommand> {
    let mut button = egui::Button::new(command.label());
    if let Some(s) = command.shortcut() {
        button = button.shortcut_text(ui.ctx().format_shortcut(&s));
    }
    let clicked = ui
        .add_enabled(enabled(command, state), button)
        .on_hover_text(command.hover())
        .clicked();
    clicked.then_some(command)
}

pub fn menu_bar_ui(ui: &mut Ui, state: &mut EditorState, windows: &mut Windows, dock: &mut Dock) {
    let mut chosen = None;
    let mut commands = Vec::new();
    egui::MenuBar::new().ui(ui, |ui| {
        let mut item = |ui: &mut Ui, c| {
            if let Some(c) = item_ui(ui, state, c) {
                chosen = Some(c);
                ui.close();
            }
        };
        ui.menu_button("File", |ui| {
            item(ui, UiCommand::New);
            item(ui, UiCommand::Open);
            recent_menu_ui(ui, state, &mut commands);
            ui.separator();
            item(ui, UiCommand::Save);
            item(ui, UiCommand::SaveAs);
            ui.separator();
            item(ui, UiCommand::ImportObj);
            item(ui, UiCommand::Export);
            item(ui, UiCommand::ExportGeometry);
            item(ui, UiCommand::Datasheet);
            ui.separator();
            item(ui, UiCommand::Quit);
        });
        ui.menu_button("Edit", |ui| {
            item(ui, UiCommand::Undo);
            item(ui, UiCommand::Redo);
            ui.separator();
            item(ui, UiCommand::Duplicate);
            item(ui, UiCommand::Delete);
        });
        ui.menu_button("View", |ui| {
            for pane in Pane::ALL {
                if ui
                    .button(pane.title())
                    .on_hover_text("Bring it to the front")
                    .clicked()
                {
                    dock.show(pane);
                    ui.close();
                }
            }
            ui.separator();
            item(ui, UiCommand::ResetLayout);
            ui.separator();
            theme_ui(ui, state, &mut commands);
            ui.separator();
            ui.label(format!("Zoom {:.0} %", ui.ctx().zoom_factor() * 100.0));
            egui::gui_zoom::zoom_menu_buttons(ui);
        });
        ui.menu_button("Simulation", |ui| {
            item(ui, UiCommand::PauseResume);
            item(ui, UiCommand::Restart);
            ui.separator();
            ui.label("Backend: in the simulation panel");
        });
        ui.menu_button("Help", |ui| {
            item(ui, UiCommand::Shortcuts);
            item(ui, UiCommand::About);
        });
    });
    if let Some(c) = chosen {
        run(c, state, windows, dock);
    }
    for c in commands {
        state.push(c);
    }
}

/// The last scenes opened or saved; files that have gone are greyed.
fn recent_menu_ui(ui: &mut Ui, state: &EditorState, commands: &mut Vec<Command>) {
    let recent = state.recent_files();
    ui.add_enabled_ui(!recent.is_empty(), |ui| {
        ui.menu_button("Open Recent", |ui| {
            for (path, exists) in &recent {
                let text = path.display().to_string();
                let button = ui
                    .add_enabled(*exists, egui::Button::new(&text))
                    .on_disabled_hover_text("this file no longer exists");
                if button.clicked() {
                    commands.push(Command::Open(path.clone()));
                    ui.close();
                }
            }
            ui.separator();
            if ui.button("Clear recent files").clicked() {
                commands.push(Command::ClearRecent);
                ui.close();
            }
        })
        .response
        .on_hover_text("Recently opened or saved scenes");
    });
}

/// Theme; egui's own Ctrl+Plus / Ctrl+Minus / Ctrl+0 zoom is on
/// (`Options::zoom_with_keyboard`), so a 1366×768 laptop and a 4K screen
/// both get a usable size.
fn theme_ui(ui: &mut Ui, state: &EditorState, commands: &mut Vec<Command>) {
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
}
