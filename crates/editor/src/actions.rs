//! What a menu item or shortcut does ([`run`]), whether it can now
//! ([`enabled`]), and the windows the menus open.

use crate::command::{Command, Selection};
use crate::dock::Dock;
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
pub(crate) fn enabled(command: UiCommand, state: &EditorState) -> bool {
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
