//! The menu bar (File, Edit, View, Simulation, Help: each item a
//! [`UiCommand`], whose label and shortcut live there) and, under it, the
//! notices of file handling: a drop hint, the recovery offer, the
//! unsaved-changes question, the last file error.

use egui::Ui;

use crate::command::{Command, Selection};
use crate::config::ThemeChoice;
use crate::dock::{Dock, Pane};
use crate::file_state::PendingAction;
use crate::modelling::SceneEdit;
use crate::state::EditorState;
use crate::ui_command::UiCommand;

/// What the menus open besides the editor's state: windows and the dock.
#[derive(Debug, Default)]
pub struct Windows {
    pub export: crate::export_dialog::ExportDialog,
    pub geometry: crate::geometry_dialog::GeometryDialog,
    pub shortcuts: bool,
    pub about: bool,
}

/// Carries out a menu item or shortcut.
pub fn run(command: UiCommand, state: &mut EditorState, windows: &mut Windows, dock: &mut Dock) {
    use crate::command::DialogKind;
    let selection = state.selection().cloned();
    let push = |state: &mut EditorState, c: Command| state.push(c);
    match command {
        UiCommand::New => push(state, Command::New),
        UiCommand::Open => push(state, Command::FileDialog(DialogKind::Open)),
        UiCommand::Save if state.path().is_none() => {
            push(state, Command::FileDialog(DialogKind::SaveAs));
        }
        UiCommand::Save => push(state, Command::Save),
        UiCommand::SaveAs => push(state, Command::FileDialog(DialogKind::SaveAs)),
        UiCommand::ImportObj => push(state, Command::FileDialog(DialogKind::ImportMesh)),
        UiCommand::Export => windows.export.open = true,
        UiCommand::ExportGeometry => windows.geometry.open_fresh(),
        UiCommand::Datasheet => windows.export.open_for_datasheet(),
        UiCommand::Quit => push(state, Command::Quit),
        UiCommand::Undo => push(state, Command::Undo),
        UiCommand::Redo => push(state, Command::Redo),
        UiCommand::Duplicate => match selection {
            Some(Selection::Part(i)) => push(state, Command::DuplicatePart(i)),
            Some(Selection::Emitter(i)) => {
                push(state, Command::Edit(SceneEdit::DuplicateEmitter(i)));
            }
            Some(Selection::Material(name)) => {
                push(state, Command::Edit(SceneEdit::DuplicateMaterial(name)));
            }
            None => {}
        },
        UiCommand::Delete => match selection {
            Some(Selection::Part(i)) => push(state, Command::DeletePart(i)),
            Some(Selection::Emitter(i)) => push(state, Command::Edit(SceneEdit::DeleteEmitter(i))),
            Some(Selection::Material(name)) => {
                push(state, Command::Edit(SceneEdit::DeleteMaterial(name)));
            }
            None => {}
        },
        UiCommand::PauseResume if state.run.paused => push(state, Command::Resume),
        UiCommand::PauseResume => push(state, Command::Pause),
        UiCommand::Restart => push(state, Command::Restart),
        UiCommand::ResetLayout => dock.reset(),
        UiCommand::Shortcuts => windows.shortcuts = true,
        UiCommand::About => windows.about = true,
    }
}

/// Whether the item can be chosen now.
fn enabled(command: UiCommand, state: &EditorState) -> bool {
    let dialog_free = !state.files.dialogs.is_open();
    let scene = state.scene().is_some();
    match command {
        UiCommand::Open | UiCommand::SaveAs | UiCommand::ImportObj => dialog_free,
        UiCommand::Save
        | UiCommand::Export
        | UiCommand::ExportGeometry
        | UiCommand::Datasheet
        | UiCommand::Restart
        | UiCommand::PauseResume => scene,
        UiCommand::Undo => state.can_undo(),
        UiCommand::Redo => state.can_redo(),
        UiCommand::Duplicate | UiCommand::Delete => state.selection().is_some(),
        UiCommand::New
        | UiCommand::Quit
        | UiCommand::ResetLayout
        | UiCommand::Shortcuts
        | UiCommand::About => true,
    }
}

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

/// The file's questions and messages under the menu bar, when there are
/// any.
pub fn notices_ui(ui: &mut Ui, state: &mut EditorState) {
    let mut commands = Vec::new();
    if ui.ctx().input(|i| !i.raw.hovered_files.is_empty()) {
        ui.colored_label(
            ui.visuals().hyperlink_color,
            "Drop a scene (.toml) to open it or an OBJ mesh (.obj) to import it",
        );
    }
    recovery_banner_ui(ui, state, &mut commands);
    pending_banner_ui(ui, state, &mut commands);
    if let Some(error) = &state.files.file_error {
        ui.colored_label(ui.visuals().error_fg_color, error);
    }
    if let Some(notice) = state.notice() {
        ui.label(notice);
    }
    for c in commands {
        state.push(c);
    }
}

/// Whether [`notices_ui`] has anything to show.
pub fn has_notices(ctx: &egui::Context, state: &EditorState) -> bool {
    ctx.input(|i| !i.raw.hovered_files.is_empty())
        || state.recovery_offer().is_some()
        || state.pending().is_some()
        || state.files.file_error.is_some()
        || state.notice().is_some()
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
