//! The document being edited: the scene, its undo history, the selection
//! and what the validator says of it. Nothing here knows about files or
//! the simulation; [`crate::state::EditorState`] ties them together.

use egui::util::undoer::{Settings as UndoSettings, Undoer};
use lucerna_scene::{Scene, validate};

use crate::command::Selection;

/// Undo steps kept per document.
const MAX_UNDOS: usize = 200;

pub(crate) struct Document {
    pub scene: Option<Scene>,
    pub selection: Option<Selection>,
    /// Validation problems of the edited scene as "field: message".
    pub problems: Vec<String>,
    /// Why the last structural edit was refused, until the next one.
    pub edit_error: Option<String>,
    undoer: Undoer<Scene>,
    /// A pointer drag or text entry is changing the scene: one undo step.
    gesture: bool,
}

impl Default for Document {
    fn default() -> Self {
        Document {
            scene: None,
            selection: None,
            problems: Vec::new(),
            edit_error: None,
            undoer: fresh_undoer(),
            gesture: false,
        }
    }
}

impl Document {
    /// Whether a pointer drag or text entry is changing the scene now.
    pub fn in_gesture(&self) -> bool {
        self.gesture
    }
}

fn fresh_undoer() -> Undoer<Scene> {
    Undoer::with_settings(UndoSettings {
        max_undos: MAX_UNDOS,
        ..UndoSettings::default()
    })
}

impl Document {
    /// A new document holding `scene`, with a fresh history.
    pub fn holding(scene: Scene) -> Self {
        Document {
            scene: Some(scene),
            ..Document::default()
        }
    }

    pub fn can_undo(&self) -> bool {
        self.scene.as_ref().is_some_and(|s| self.undoer.has_undo(s))
    }

    pub fn can_redo(&self) -> bool {
        self.scene.as_ref().is_some_and(|s| self.undoer.has_redo(s))
    }

    /// Steps back one edit; whether there was one.
    pub fn undo(&mut self) -> bool {
        self.step(|undoer, scene| undoer.undo(scene).cloned())
    }

    /// Steps forward one undone edit; whether there was one.
    pub fn redo(&mut self) -> bool {
        self.step(|undoer, scene| undoer.redo(scene).cloned())
    }

    /// Replaces the scene by what `to` finds in the history (undo or
    /// redo), ending any gesture; whether it found one.
    fn step(&mut self, to: impl FnOnce(&mut Undoer<Scene>, &Scene) -> Option<Scene>) -> bool {
        let Some(scene) = &self.scene else {
            return false;
        };
        let Some(other) = to(&mut self.undoer, scene) else {
            return false;
        };
        self.scene = Some(other);
        self.gesture = false;
        true
    }

    /// After the panels edited the scene in place this frame (it was
    /// `before`): an undo step opens unless a gesture already holds one,
    /// and the gesture lasts while the pointer or keyboard is `held`.
    /// Whether the scene changed.
    pub fn note_panel_edits(&mut self, before: Option<&Scene>, held: bool) -> bool {
        if self.scene.as_ref() == before {
            if !held {
                self.gesture = false;
            }
            return false;
        }
        if let Some(before) = before
            && !self.gesture
        {
            self.undoer.add_undo(before);
        }
        self.gesture = held;
        true
    }

    /// A structural edit (add, delete, rename…): its own undo step.
    /// Whether there was a scene to edit.
    pub fn structural(&mut self, edit: impl FnOnce(&mut Scene, &mut Option<Selection>)) -> bool {
        let Some(scene) = &mut self.scene else {
            return false;
        };
        self.undoer.add_undo(scene);
        edit(scene, &mut self.selection);
        self.edit_error = None;
        self.gesture = false;
        true
    }

    /// `after` in place of the scene, one undo step back to `before` (a
    /// design's whole run: the scene it showed on the way is not a step).
    pub fn replace_as_one_step(&mut self, before: &Scene, after: Scene) {
        self.undoer.add_undo(before);
        self.scene = Some(after);
        self.edit_error = None;
        self.gesture = false;
    }

    /// Validates the scene again; the scene if it is valid.
    pub fn validated(&mut self) -> Option<&Scene> {
        let scene = self.scene.as_ref()?;
        let problems = validate(scene);
        self.problems = problems
            .iter()
            .map(|p| format!("{}: {}", p.field, p.message))
            .collect();
        problems.is_empty().then_some(scene)
    }
}
