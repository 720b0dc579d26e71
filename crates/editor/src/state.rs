//! The editor's state apart from any drawing, three peers and the room:
//! the document ([`Document`]: scene, undo, selection, problems), the live
//! run ([`LiveRun`]: simulation, coarse preview, snapshot) and the files
//! ([`FileState`]: path, saved copy, autosave, recovery, dialogs), tied
//! together by the commands the panels queue. Panels edit scene fields in
//! place (that is how egui widgets work) and queue everything else as a
//! [`Command`], applied once per frame.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use lucerna_scene::{Scene, load_scene, save_scene};
use lucerna_simulation::{Simulation, SimulationSettings, Snapshot};

pub use crate::command::{Command, Selection};
use crate::config::EditorPaths;
use crate::document::Document;
use crate::error_text::error_chain;
use crate::file_state::FileState;
use crate::live_run::LiveRun;
pub use crate::modelling::{NewPart, SceneEdit};
use crate::modelling::{new_part, unique_name};
pub use crate::pane::View;
use crate::room_state::RoomLive;

/// Everything the editor knows; the panels draw it and queue commands.
pub struct EditorState {
    pub(crate) doc: Document,
    pub(crate) run: LiveRun,
    /// Path, saved copy, recent files, autosave and recovery, dialogs
    /// (files.rs).
    pub(crate) files: FileState,
    /// The preview room, lit by the snapshot's table.
    pub(crate) room: RoomLive,
    /// The Design pane's setup, run and outcome (design_state.rs).
    pub(crate) design: crate::design_state::DesignState,
    /// The Tolerance pane's setup, run and outcome (tolerance_state.rs).
    pub(crate) tolerance: crate::tolerance_state::ToleranceState,
    pub(crate) view: View,
    /// A folder chosen for the export dialog, until it takes it.
    pub(crate) chosen_export_folder: Option<PathBuf>,
    /// A scripted pointer is held down (the drag benchmark and tests): the
    /// edits it makes are a drag's.
    pub(crate) scripted_pointer: bool,
    /// A pane the window should bring to the front (a panel asked).
    pub(crate) pane_request: Option<crate::pane::Pane>,
    commands: Vec<Command>,
    /// The context the simulation's worker asks to repaint; known from the
    /// first frame on.
    pub(crate) ctx: Option<egui::Context>,
    title: String,
}

impl std::fmt::Debug for EditorState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("EditorState")
            .field("path", &self.files.path)
            .field("selection", &self.doc.selection)
            .field("problems", &self.doc.problems)
            .finish_non_exhaustive()
    }
}

impl EditorState {
    /// An editor with no scene that remembers nothing (no config
    /// directory); `open` is loaded in the first frame.
    pub fn new(open: Option<PathBuf>, settings: SimulationSettings) -> Self {
        Self::with_paths(open, settings, EditorPaths::default())
    }

    /// An editor that keeps its recent files, theme and recovery file in
    /// `paths` ([`EditorPaths::user`] for the real one).
    pub fn with_paths(
        open: Option<PathBuf>,
        settings: SimulationSettings,
        paths: EditorPaths,
    ) -> Self {
        let mut state = EditorState {
            doc: Document::default(),
            run: LiveRun::new(settings),
            files: FileState::new(paths),
            room: RoomLive::default(),
            design: crate::design_state::DesignState::default(),
            tolerance: crate::tolerance_state::ToleranceState::default(),
            view: View::default(),
            chosen_export_folder: None,
            scripted_pointer: false,
            pane_request: None,
            commands: Vec::new(),
            ctx: None,
            title: String::new(),
        };
        if let Some(path) = open {
            state.push(Command::Open(path));
        }
        state
    }

    /// Queues a command for the end of this frame.
    pub fn push(&mut self, command: Command) {
        self.commands.push(command);
    }

    pub fn scene(&self) -> Option<&Scene> {
        self.doc.scene.as_ref()
    }

    pub fn path(&self) -> Option<&Path> {
        self.files.path.as_deref()
    }

    pub fn problems(&self) -> &[String] {
        &self.doc.problems
    }

    /// What the scene panel edits and the 3D view highlights.
    pub fn selection(&self) -> Option<&Selection> {
        self.doc.selection.as_ref()
    }

    pub fn file_error(&self) -> Option<&str> {
        self.files.file_error.as_deref()
    }

    /// Why the simulation of the newest scene or settings failed, if it did.
    pub fn simulation_error(&self) -> Option<&str> {
        self.run.sim_error.as_deref()
    }

    /// Why the last emitter, material or profile edit was refused.
    pub fn edit_error(&self) -> Option<&str> {
        self.doc.edit_error.as_deref()
    }

    /// The settings chosen in the simulation panel (the simulation runs
    /// coarser while a drag previews an edit).
    pub fn settings(&self) -> &SimulationSettings {
        &self.run.settings
    }

    /// Whether the simulation runs at the coarse preview resolution of a
    /// drag.
    pub fn is_coarse_preview(&self) -> bool {
        self.run.is_coarse_preview()
    }

    pub fn simulation(&self) -> Option<&Simulation> {
        self.run.simulation()
    }

    /// The newest snapshot shown (refreshed each frame).
    pub fn snapshot(&self) -> Option<&Arc<Snapshot>> {
        self.run.snapshot.as_ref()
    }

    /// Whether there is an edit to undo.
    pub fn can_undo(&self) -> bool {
        self.doc.can_undo()
    }

    /// Whether there is an undone edit to redo.
    pub fn can_redo(&self) -> bool {
        self.doc.can_redo()
    }

    /// Unsaved changes since the last load or save.
    pub fn is_dirty(&self) -> bool {
        self.doc.scene.is_some() && self.doc.scene != self.files.saved
    }

    /// The window title: file name and an unsaved-changes marker.
    pub fn title(&self) -> String {
        let name = self.path().and_then(Path::file_name).map_or_else(
            || match self.doc.scene {
                Some(_) => "unsaved new scene".to_owned(),
                None => "no scene".to_owned(),
            },
            |n| n.to_string_lossy().into_owned(),
        );
        let marker = if self.is_dirty() { " •" } else { "" };
        format!("{name}{marker} — Lucerna editor")
    }

    /// The folder the scene's relative paths (profiles, OBJ files) start from.
    pub(crate) fn scene_dir(&self) -> PathBuf {
        self.path()
            .and_then(Path::parent)
            .map_or_else(|| PathBuf::from("."), Path::to_path_buf)
    }

    /// Called at the start of each frame, before the panels.
    pub(crate) fn begin_frame(&mut self, ctx: &egui::Context) {
        if self.ctx.is_none() {
            self.ctx = Some(ctx.clone());
        }
        self.files_begin_frame(ctx);
        self.poll_design();
        self.poll_tolerance();
        self.run.refresh();
    }

    /// Called after the panels with the scene as it was before them: an
    /// edit opens an undo step unless a gesture already holds one, and a
    /// valid scene goes to the simulation at once.
    pub(crate) fn end_frame(&mut self, ctx: &egui::Context, before: Option<Scene>) {
        let dragging = ctx.input(|i| i.pointer.any_down()) || self.scripted_pointer;
        let held = dragging || ctx.egui_wants_keyboard_input();
        if self.doc.note_panel_edits(before.as_ref(), held) {
            self.validate_and_send(dragging);
        }
        if !dragging {
            self.run.end_coarse_preview();
        }
        self.apply_commands();
        self.design
            .refresh_bounds(self.doc.scene.as_ref(), dragging);
        self.room.tick(
            self.run.snapshot.as_ref(),
            ctx,
            std::time::Instant::now(),
            dragging,
        );
        self.autosave(ctx);
        let title = self.title();
        if title != self.title {
            ctx.send_viewport_cmd(egui::ViewportCommand::Title(title.clone()));
            self.title = title;
        }
    }

    fn apply_commands(&mut self) {
        for command in std::mem::take(&mut self.commands) {
            self.apply(command);
        }
    }

    fn apply(&mut self, command: Command) {
        if self.design.is_running() && command.changes_the_scene() {
            self.doc.edit_error =
                Some("a design is running: Stop it in the Design pane first".to_owned());
            return;
        }
        match command {
            Command::Open(path) if self.is_dirty() => {
                self.files.pending = Some(crate::file_state::PendingAction::Open(path));
            }
            Command::Open(path) | Command::OpenDiscarding(path) => {
                self.files.pending = None;
                self.open(path);
            }
            Command::CancelPending => self.files.pending = None,
            Command::Save => match self.files.path.clone() {
                Some(path) => self.save(path),
                None => {
                    self.files.file_error = Some("no file to save to: use Save as".to_owned());
                }
            },
            Command::SaveAs(path) => self.save(path),
            Command::Undo => {
                if self.doc.undo() {
                    self.scene_changed();
                }
            }
            Command::Redo => {
                if self.doc.redo() {
                    self.scene_changed();
                }
            }
            Command::Select(selection) => {
                self.doc.selection = selection;
                // A refusal is about the item it was asked of.
                self.doc.edit_error = None;
            }
            Command::AddPart(kind) => self.structural(|scene, selection| {
                let part = new_part(scene, kind);
                scene.parts.push(part);
                *selection = Some(Selection::Part(scene.parts.len() - 1));
            }),
            Command::DuplicatePart(i) => self.structural(|scene, selection| {
                if let Some(part) = scene.parts.get(i) {
                    let mut copy = part.clone();
                    copy.name =
                        unique_name(&part.name, |n| scene.parts.iter().any(|p| p.name == n));
                    scene.parts.insert(i + 1, copy);
                    *selection = Some(Selection::Part(i + 1));
                }
            }),
            Command::DeletePart(i) => self.structural(|scene, selection| {
                if i < scene.parts.len() {
                    scene.parts.remove(i);
                    *selection = None;
                }
            }),
            Command::Edit(edit) => {
                let Some(scene) = &self.doc.scene else { return };
                match edit.refusal(scene) {
                    Some(why) => self.doc.edit_error = Some(why),
                    None => self.structural(|scene, selection| edit.apply(scene, selection)),
                }
            }
            Command::Pause => self.run.pause(),
            Command::Resume => self.run.resume(),
            Command::SetSettings(settings) => self.run.set_settings(settings),
            Command::SetExportFolder(path) => self.chosen_export_folder = Some(path),
            Command::SetDesignTarget(path) => {
                self.design.setup.target_file = Some(path);
                self.design.setup.target_kind = crate::design_state::TargetKind::File;
                self.design.error = None;
            }
            Command::ShowPane(pane) => self.pane_request = Some(pane),
            Command::Room(command) => self.room.apply(command),
            Command::Restart => self.run.restart(),
            Command::StartDesign => self.start_design(),
            Command::StopDesign => self.stop_design(),
            Command::StartTolerance => self.start_tolerance(),
            Command::StopTolerance => self.stop_tolerance(),
            Command::OpenToleranceSample(index) => self.open_tolerance_sample(index),
            Command::TickDesignVariable { vary, on } => {
                if let Some(scene) = &self.doc.scene {
                    self.design.setup.tick(&vary, on, scene);
                    self.design.forget_bounds();
                }
            }
            command @ (Command::New
            | Command::NewDiscarding
            | Command::Quit
            | Command::QuitDiscarding
            | Command::Recover
            | Command::DiscardRecovery
            | Command::ImportMesh(_)
            | Command::AddRayFileEmitter(_)
            | Command::FileDialog(_)
            | Command::SetTheme(_)
            | Command::ClearRecent) => self.apply_file_command(command),
        }
    }

    /// A structural edit: its own undo step, then validation.
    pub(crate) fn structural(&mut self, edit: impl FnOnce(&mut Scene, &mut Option<Selection>)) {
        if self.doc.structural(edit) {
            self.files.autosave_now = true;
            self.scene_changed();
        }
    }

    /// Validates the edited scene; a valid one restarts the simulation, an
    /// invalid one is only reported (the last valid one keeps running).
    pub(crate) fn scene_changed(&mut self) {
        self.validate_and_send(false);
    }

    /// [`Self::scene_changed`], for an edit made by a pointer drag when
    /// `dragging`: the simulation then runs at the coarse preview
    /// resolution until the drag ends, so that the preview keeps up.
    fn validate_and_send(&mut self, dragging: bool) {
        let dir = self.scene_dir();
        if let Some(scene) = self.doc.validated() {
            self.run.send(scene, &dir, dragging, self.ctx.as_ref());
        }
    }

    /// Loads a scene file; on failure the current scene stays and the
    /// error (file, line, field) is shown.
    fn open(&mut self, path: PathBuf) {
        match load_scene(&path) {
            Ok(scene) => {
                self.files_opened(&path);
                self.replace_document(scene.clone(), Some(path), Some(scene));
            }
            Err(e) => self.files.file_error = Some(error_chain(&e)),
        }
    }

    /// A new document (opened, new or recovered): fresh undo history and a
    /// fresh run (generation 0) if it is valid. `saved` is what is on disk,
    /// for the unsaved-changes marker.
    pub(crate) fn replace_document(
        &mut self,
        scene: Scene,
        path: Option<PathBuf>,
        saved: Option<Scene>,
    ) {
        self.files.path = path;
        self.files.saved = saved;
        self.files.file_error = None;
        self.doc = Document::holding(scene);
        self.run.reset();
        self.scene_changed();
    }

    fn save(&mut self, path: PathBuf) {
        let Some(scene) = &self.doc.scene else {
            self.files.file_error = Some("no scene to save".to_owned());
            return;
        };
        // Saved elsewhere, relative mesh and profile paths keep naming the
        // same files (files.rs).
        let rebased = crate::scene_paths::rebased_for(scene, &self.scene_dir(), &path);
        let scene = rebased.as_ref().unwrap_or(scene);
        match save_scene(scene, &path) {
            Ok(()) => {
                self.files.saved = Some(scene.clone());
                if let Some(rebased) = rebased {
                    self.doc.scene = Some(rebased);
                }
                self.files.file_error = None;
                self.files_saved(&path);
                if self.files.path.as_deref() != Some(&path) {
                    self.files.path = Some(path);
                    // Relative paths in the scene now resolve from here.
                    self.run.forget_sent();
                    self.scene_changed();
                }
            }
            Err(e) => self.files.file_error = Some(error_chain(&e)),
        }
    }
}
