//! Every action the menus offer, each with its label, shortcut and hover
//! text written once: the menu bar, the keyboard shortcuts and the help
//! window all read them from here.

use egui::{Key, KeyboardShortcut, Modifiers};

/// An action of the window's menus.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum UiCommand {
    New,
    Open,
    Save,
    SaveAs,
    ImportObj,
    Export,
    ExportGeometry,
    Datasheet,
    Quit,
    Undo,
    Redo,
    Duplicate,
    Delete,
    PauseResume,
    Restart,
    ResetLayout,
    Shortcuts,
    About,
}

impl UiCommand {
    /// In menu order.
    pub const ALL: [UiCommand; 18] = [
        UiCommand::New,
        UiCommand::Open,
        UiCommand::Save,
        UiCommand::SaveAs,
        UiCommand::ImportObj,
        UiCommand::Export,
        UiCommand::ExportGeometry,
        UiCommand::Datasheet,
        UiCommand::Quit,
        UiCommand::Undo,
        UiCommand::Redo,
        UiCommand::Duplicate,
        UiCommand::Delete,
        UiCommand::PauseResume,
        UiCommand::Restart,
        UiCommand::ResetLayout,
        UiCommand::Shortcuts,
        UiCommand::About,
    ];

    /// The menu item's text (also its accessible name).
    pub fn label(self) -> &'static str {
        match self {
            UiCommand::New => "New",
            UiCommand::Open => "Open…",
            UiCommand::Save => "Save",
            UiCommand::SaveAs => "Save As…",
            UiCommand::ImportObj => "Import OBJ…",
            UiCommand::Export => "Export…",
            UiCommand::ExportGeometry => "Export geometry…",
            UiCommand::Datasheet => "Datasheet…",
            UiCommand::Quit => "Quit",
            UiCommand::Undo => "Undo",
            UiCommand::Redo => "Redo",
            UiCommand::Duplicate => "Duplicate",
            UiCommand::Delete => "Delete",
            UiCommand::PauseResume => "Pause / Resume",
            UiCommand::Restart => "Restart",
            UiCommand::ResetLayout => "Reset layout",
            UiCommand::Shortcuts => "Keyboard shortcuts",
            UiCommand::About => "About Lucerna",
        }
    }

    /// What it does, for its hover text.
    pub fn hover(self) -> &'static str {
        match self {
            UiCommand::New => "Start a new scene (a lamp and a reflector)",
            UiCommand::Open => "Open a scene file",
            UiCommand::Save => "Save the scene to its file",
            UiCommand::SaveAs => "Save the scene to another file",
            UiCommand::ImportObj => "Add an OBJ file as a mesh part (or drop it on the window)",
            UiCommand::Export => "IES, EULUMDAT, EXR and PNGs of the current result",
            UiCommand::ExportGeometry => {
                "The parts for CAD: STEP with exact surfaces, STL and OBJ (millimetres)"
            }
            UiCommand::Datasheet => {
                "The photometric datasheet (HTML, PDF, JSON) with the UGR table, as lucerna report writes it"
            }
            UiCommand::Quit => "Close the editor",
            UiCommand::Undo => "Undo the last edit",
            UiCommand::Redo => "Redo the edit undone last",
            UiCommand::Duplicate => "Duplicate the selected part, emitter or material",
            UiCommand::Delete => "Delete the selected part, emitter or material",
            UiCommand::PauseResume => "Pause or resume tracing",
            UiCommand::Restart => "Trace the scene again from zero photons",
            UiCommand::ResetLayout => "Put the views back where they start",
            UiCommand::Shortcuts => "Every keyboard shortcut",
            UiCommand::About => "Which Lucerna this is",
        }
    }

    /// Its keyboard shortcut, if it has one.
    pub fn shortcut(self) -> Option<KeyboardShortcut> {
        let command = |key| Some(KeyboardShortcut::new(Modifiers::COMMAND, key));
        match self {
            UiCommand::New => command(Key::N),
            UiCommand::Open => command(Key::O),
            UiCommand::Save => command(Key::S),
            UiCommand::SaveAs => Some(KeyboardShortcut::new(
                Modifiers::COMMAND | Modifiers::SHIFT,
                Key::S,
            )),
            UiCommand::Export => command(Key::E),
            UiCommand::Quit => command(Key::Q),
            UiCommand::Undo => command(Key::Z),
            UiCommand::Redo => Some(KeyboardShortcut::new(
                Modifiers::COMMAND | Modifiers::SHIFT,
                Key::Z,
            )),
            UiCommand::Duplicate => command(Key::D),
            UiCommand::PauseResume => command(Key::P),
            UiCommand::Shortcuts => Some(KeyboardShortcut::new(Modifiers::NONE, Key::F1)),
            UiCommand::ImportObj
            | UiCommand::ExportGeometry
            | UiCommand::Datasheet
            | UiCommand::Delete
            | UiCommand::Restart
            | UiCommand::ResetLayout
            | UiCommand::About => None,
        }
    }

    /// The command whose shortcut the input holds this frame, consumed.
    /// Shortcuts with more modifiers go first (Ctrl+Shift+Z is not Undo).
    pub fn pressed(ctx: &egui::Context) -> Option<UiCommand> {
        let mut with_shortcuts: Vec<(UiCommand, KeyboardShortcut)> = UiCommand::ALL
            .iter()
            .filter_map(|&c| c.shortcut().map(|s| (c, s)))
            .collect();
        with_shortcuts.sort_by_key(|(_, s)| {
            std::cmp::Reverse(
                u8::from(s.modifiers.shift)
                    + u8::from(s.modifiers.alt)
                    + u8::from(s.modifiers.command),
            )
        });
        with_shortcuts
            .into_iter()
            .find(|(_, s)| ctx.input_mut(|i| i.consume_shortcut(s)))
            .map(|(c, _)| c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_and_shortcuts_are_each_used_once() {
        let mut labels: Vec<&str> = UiCommand::ALL.iter().map(|c| c.label()).collect();
        labels.sort_unstable();
        labels.dedup();
        assert_eq!(labels.len(), UiCommand::ALL.len());
        let mut shortcuts: Vec<KeyboardShortcut> =
            UiCommand::ALL.iter().filter_map(|c| c.shortcut()).collect();
        let n = shortcuts.len();
        shortcuts.sort_by_key(|s| format!("{s:?}"));
        shortcuts.dedup();
        assert_eq!(shortcuts.len(), n);
    }
}
