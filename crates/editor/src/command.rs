//! What the panels ask of the editor: the commands they queue, applied
//! once a frame by [`crate::state::EditorState`]. A module of their own,
//! so that state, files, dialogs and modelling all name them without
//! naming each other.

use std::path::PathBuf;

use lucerna_simulation::SimulationSettings;

use crate::config::ThemeChoice;
use crate::modelling::{NewPart, SceneEdit};
pub use crate::selection::Selection;

/// What a dialog chooses a path for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DialogKind {
    Open,
    SaveAs,
    ImportMesh,
    /// A TM-25 ray file to add as an emitter.
    RayFileEmitter,
    /// The export dialog's output folder.
    ExportFolder,
    /// The Design pane's target: an IES or EULUMDAT file.
    DesignTarget,
}

/// A UI action, queued by a panel and applied after the panels are drawn
/// so that no panel mutates what another is still drawing.
#[derive(Debug, Clone, PartialEq)]
pub enum Command {
    /// Opens a file; with unsaved changes it asks first.
    Open(PathBuf),
    /// Opens a file, dropping unsaved changes.
    OpenDiscarding(PathBuf),
    /// Keeps the unsaved changes: the pending New, Open or Quit is dropped.
    CancelPending,
    Save,
    SaveAs(PathBuf),
    Undo,
    Redo,
    Select(Option<Selection>),
    AddPart(NewPart),
    DuplicatePart(usize),
    DeletePart(usize),
    /// An emitter, material or profile edit (one undo step), or its refusal.
    Edit(SceneEdit),
    Pause,
    Resume,
    SetSettings(SimulationSettings),
    // File handling (files.rs).
    /// Starts the starter scene; with unsaved changes it asks first.
    New,
    /// Starts the starter scene, dropping unsaved changes.
    NewDiscarding,
    /// Closes the editor; with unsaved changes it asks first.
    Quit,
    /// Closes the editor, dropping unsaved changes.
    QuitDiscarding,
    /// Takes the offered recovery file as the (unsaved) document.
    Recover,
    /// Drops the offered recovery file.
    DiscardRecovery,
    /// Adds an OBJ file as a mesh part (one undo step).
    ImportMesh(PathBuf),
    /// Adds a TM-25 ray file as an emitter (one undo step).
    AddRayFileEmitter(PathBuf),
    /// Opens a native file dialog; the chosen path comes back as a command.
    FileDialog(DialogKind),
    SetTheme(ThemeChoice),
    ClearRecent,
    /// The export dialog's output folder, chosen in a native dialog.
    SetExportFolder(PathBuf),
    /// The Design pane's target file, chosen in a native dialog.
    SetDesignTarget(PathBuf),
    /// Traces the current scene again from zero photons.
    Restart,
    /// Brings a pane of the dock to the front.
    ShowPane(crate::pane::Pane),
    /// A change to the preview room (room_state.rs).
    Room(crate::room_state::RoomCommand),
    /// Starts a design as the Design pane sets it up (design_state.rs).
    StartDesign,
    /// Stops the design with the best it found so far.
    StopDesign,
    /// Runs a tolerance analysis as the Tolerance pane sets it up
    /// (tolerance_state.rs).
    StartTolerance,
    /// Stops it, keeping the samples done.
    StopTolerance,
    /// Opens sample k of the analysis as the scene (one undo step).
    OpenToleranceSample(u32),
    /// Ticks (or unticks) what a design may vary: `PART.FIELD` or
    /// `PART.profile[INDEX]`.
    TickDesignVariable {
        vary: String,
        on: bool,
    },
}

impl Command {
    /// Whether it replaces or edits the scene (refused while a design
    /// runs: the design owns the scene until it ends).
    pub fn changes_the_scene(&self) -> bool {
        matches!(
            self,
            Command::Open(_)
                | Command::OpenDiscarding(_)
                | Command::Undo
                | Command::Redo
                | Command::AddPart(_)
                | Command::DuplicatePart(_)
                | Command::DeletePart(_)
                | Command::Edit(_)
                | Command::New
                | Command::NewDiscarding
                | Command::Recover
                | Command::ImportMesh(_)
                | Command::AddRayFileEmitter(_)
                | Command::OpenToleranceSample(_)
        )
    }
}
