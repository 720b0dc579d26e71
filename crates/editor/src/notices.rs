//! The notices of file handling under the menu bar: a drop hint, the
//! recovery offer, the unsaved-changes question, the last file error.

use egui::Ui;

use crate::command::Command;
use crate::file_state::PendingAction;
use crate::state::EditorState;

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
