//! The editor's state apart from any drawing: the document, its undo
//! history, the running simulation, and the commands the panels queue.
//! Panels edit scene fields in place (that is how egui widgets work) and
//! queue everything else as a [`Command`], applied once per frame.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use egui::util::undoer::{Settings as UndoSettings, Undoer};
use lucerna_scene::{Scene, load_scene, save_scene, validate};
use lucerna_simulation::{Simulation, SimulationSettings, Snapshot};

pub use crate::command::{Command, Selection};
use crate::config::EditorPaths;
use crate::files::FileState;
pub use crate::modelling::{NewPart, SceneEdit};
use crate::modelling::{new_part, unique_name};
use crate::pacer::RepaintPacer;
use crate::room_state::RoomLive;

/// Which view the central panel shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum View {
    #[default]
    Polar,
    /// I(γ) per C-plane, linear or log.
    Cartesian,
    /// The C-γ map with lines of equal intensity.
    Isocandela,
    CubeMap,
    /// Every figure with its noise, copyable as text.
    Figures,
    /// The preview room lit by the current distribution.
    Room,
}

/// Everything the editor knows; the panels draw it and queue commands.
pub struct EditorState {
    pub(crate) scene: Option<Scene>,
    pub(crate) path: Option<PathBuf>,
    /// The scene as last loaded or saved, for the unsaved-changes marker.
    saved: Option<Scene>,
    pub(crate) selection: Option<Selection>,
    /// Validation problems of the edited scene as "field: message".
    pub(crate) problems: Vec<String>,
    /// The last file error (load or save), shown until the next success.
    pub(crate) file_error: Option<String>,
    pub(crate) view: View,
    /// New, recent files, autosave and recovery, dialogs (files.rs).
    pub(crate) files: FileState,
    /// Why the last structural edit was refused, until the next one.
    pub(crate) edit_error: Option<String>,
    /// A folder chosen for the export dialog, until it takes it.
    pub(crate) chosen_export_folder: Option<PathBuf>,
    undoer: Undoer<Scene>,
    /// A pointer drag or text entry is changing the scene: one undo step.
    gesture: bool,
    /// A scripted pointer is held down (the drag benchmark and tests): the
    /// edits it makes are a drag's.
    pub(crate) scripted_pointer: bool,
    /// A pane the window should bring to the front (a panel asked).
    pub(crate) pane_request: Option<crate::dock::Pane>,
    /// The last valid scene handed to the simulation.
    sent: Option<Scene>,
    sim: Option<Simulation>,
    pub(crate) settings: SimulationSettings,
    /// The simulation runs at [`coarse_preview`] of `settings` while a
    /// pointer drag edits the scene, and returns to them when it ends.
    coarse: bool,
    pub(crate) paused: bool,
    pub(crate) snapshot: Option<Arc<Snapshot>>,
    pub(crate) sim_error: Option<String>,
    commands: Vec<Command>,
    /// The context the simulation's worker asks to repaint; known from the
    /// first frame on.
    pub(crate) ctx: Option<egui::Context>,
    /// Paces the repaints the simulation's snapshots ask for.
    pub(crate) pacer: Arc<RepaintPacer>,
    /// The preview room, lit by the snapshot's table.
    pub(crate) room: RoomLive,
    title: String,
}

impl std::fmt::Debug for EditorState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("EditorState")
            .field("path", &self.path)
            .field("selection", &self.selection)
            .field("problems", &self.problems)
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
            scene: None,
            path: None,
            saved: None,
            selection: None,
            problems: Vec::new(),
            file_error: None,
            view: View::default(),
            files: FileState::new(paths),
            edit_error: None,
            chosen_export_folder: None,
            undoer: Undoer::with_settings(UndoSettings {
                max_undos: 200,
                ..UndoSettings::default()
            }),
            gesture: false,
            scripted_pointer: false,
            pane_request: None,
            sent: None,
            sim: None,
            settings,
            coarse: false,
            paused: false,
            snapshot: None,
            sim_error: None,
            commands: Vec::new(),
            ctx: None,
            pacer: Arc::new(RepaintPacer::default()),
            room: RoomLive::default(),
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
        self.scene.as_ref()
    }

    pub fn path(&self) -> Option<&Path> {
        self.path.as_deref()
    }

    pub fn problems(&self) -> &[String] {
        &self.problems
    }

    /// What the scene panel edits and the 3D view highlights.
    pub fn selection(&self) -> Option<&Selection> {
        self.selection.as_ref()
    }

    pub fn file_error(&self) -> Option<&str> {
        self.file_error.as_deref()
    }

    /// Why the simulation of the newest scene or settings failed, if it did.
    pub fn simulation_error(&self) -> Option<&str> {
        self.sim_error.as_deref()
    }

    /// Why the last emitter, material or profile edit was refused.
    pub fn edit_error(&self) -> Option<&str> {
        self.edit_error.as_deref()
    }

    /// The settings chosen in the simulation panel (the simulation runs
    /// coarser while a drag previews an edit).
    pub fn settings(&self) -> &SimulationSettings {
        &self.settings
    }

    /// Whether the simulation runs at the coarse preview resolution of a
    /// drag.
    pub fn is_coarse_preview(&self) -> bool {
        self.coarse
    }

    pub fn simulation(&self) -> Option<&Simulation> {
        self.sim.as_ref()
    }

    /// The newest snapshot shown (refreshed each frame).
    pub fn snapshot(&self) -> Option<&Arc<Snapshot>> {
        self.snapshot.as_ref()
    }

    /// Whether there is an edit to undo.
    pub fn can_undo(&self) -> bool {
        self.scene.as_ref().is_some_and(|s| self.undoer.has_undo(s))
    }

    /// Whether there is an undone edit to redo.
    pub fn can_redo(&self) -> bool {
        self.scene.as_ref().is_some_and(|s| self.undoer.has_redo(s))
    }

    /// Unsaved changes since the last load or save.
    pub fn is_dirty(&self) -> bool {
        self.scene.is_some() && self.scene != self.saved
    }

    /// The window title: file name and an unsaved-changes marker.
    pub fn title(&self) -> String {
        let name = self.path.as_deref().and_then(Path::file_name).map_or_else(
            || match self.scene {
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
        self.path
            .as_deref()
            .and_then(Path::parent)
            .map_or_else(|| PathBuf::from("."), Path::to_path_buf)
    }

    /// Called at the start of each frame, before the panels.
    pub(crate) fn begin_frame(&mut self, ctx: &egui::Context) {
        if self.ctx.is_none() {
            self.ctx = Some(ctx.clone());
        }
        self.files_begin_frame(ctx);
        if let Some(sim) = &self.sim {
            let published = sim.published();
            // An error of an older generation is stale once a newer run
            // publishes.
            let shown = published.snapshot.as_ref().map_or(0, |s| s.generation);
            self.sim_error = published
                .error
                .filter(|(generation, _)| *generation >= shown)
                .map(|(_, e)| error_chain(&*e));
            self.snapshot = published.snapshot;
        }
    }

    /// Called after the panels with the scene as it was before them: an
    /// edit opens an undo step unless a gesture already holds one, and a
    /// valid scene goes to the simulation at once.
    pub(crate) fn end_frame(&mut self, ctx: &egui::Context, before: Option<Scene>) {
        let dragging = ctx.input(|i| i.pointer.any_down()) || self.scripted_pointer;
        let held = dragging || ctx.egui_wants_keyboard_input();
        if self.scene != before {
            if let Some(before) = &before
                && !self.gesture
            {
                self.undoer.add_undo(before);
            }
            self.gesture = held;
            self.validate_and_send(dragging);
        } else if !held {
            self.gesture = false;
        }
        if !dragging {
            self.end_coarse_preview();
        }
        self.apply_commands();
        self.room
            .tick(self.snapshot.as_ref(), ctx, std::time::Instant::now());
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
        match command {
            Command::Open(path) if self.is_dirty() => {
                self.files.pending = Some(crate::files::PendingAction::Open(path));
            }
            Command::Open(path) | Command::OpenDiscarding(path) => {
                self.files.pending = None;
                self.open(path);
            }
            Command::CancelPending => self.files.pending = None,
            Command::Save => match self.path.clone() {
                Some(path) => self.save(path),
                None => self.file_error = Some("no file to save to: use Save as".to_owned()),
            },
            Command::SaveAs(path) => self.save(path),
            Command::Undo => {
                if let Some(scene) = &self.scene
                    && let Some(previous) = self.undoer.undo(scene).cloned()
                {
                    self.scene = Some(previous);
                    self.gesture = false;
                    self.scene_changed();
                }
            }
            Command::Redo => {
                if let Some(scene) = &self.scene
                    && let Some(next) = self.undoer.redo(scene).cloned()
                {
                    self.scene = Some(next);
                    self.gesture = false;
                    self.scene_changed();
                }
            }
            Command::Select(selection) => {
                self.selection = selection;
                // A refusal is about the item it was asked of.
                self.edit_error = None;
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
                let Some(scene) = &self.scene else { return };
                match edit.refusal(scene) {
                    Some(why) => self.edit_error = Some(why),
                    None => self.structural(|scene, selection| edit.apply(scene, selection)),
                }
            }
            Command::Pause => {
                if let Some(sim) = &self.sim {
                    sim.pause();
                }
                self.paused = true;
            }
            Command::Resume => {
                if let Some(sim) = &self.sim {
                    sim.resume();
                }
                self.paused = false;
            }
            Command::SetSettings(settings) => {
                let running = if self.coarse {
                    coarse_preview(settings)
                } else {
                    settings
                };
                let result = match &mut self.sim {
                    Some(sim) => sim.set_settings(running).map(|_| ()),
                    None => settings.validate().map_err(Into::into),
                };
                match result {
                    Ok(()) => self.settings = settings,
                    Err(e) => self.sim_error = Some(error_chain(&e)),
                }
            }
            Command::SetExportFolder(path) => self.chosen_export_folder = Some(path),
            Command::ShowPane(pane) => self.pane_request = Some(pane),
            Command::Room(command) => self.room.apply(command),
            Command::Restart => {
                if let Some(sim) = &mut self.sim {
                    self.pacer.reset();
                    sim.restart();
                }
            }
            command @ (Command::New
            | Command::NewDiscarding
            | Command::Quit
            | Command::QuitDiscarding
            | Command::Recover
            | Command::DiscardRecovery
            | Command::ImportMesh(_)
            | Command::FileDialog(_)
            | Command::SetTheme(_)
            | Command::ClearRecent) => self.apply_file_command(command),
        }
    }

    /// A structural edit: its own undo step, then validation.
    pub(crate) fn structural(&mut self, edit: impl FnOnce(&mut Scene, &mut Option<Selection>)) {
        let Some(scene) = &mut self.scene else { return };
        self.undoer.add_undo(scene);
        edit(scene, &mut self.selection);
        self.edit_error = None;
        self.gesture = false;
        self.files.autosave_now = true;
        self.scene_changed();
    }

    /// Validates the edited scene; a valid one restarts the simulation, an
    /// invalid one is only reported (the last valid one keeps running).
    fn scene_changed(&mut self) {
        self.validate_and_send(false);
    }

    /// [`Self::scene_changed`], for an edit made by a pointer drag when
    /// `dragging`: the simulation then runs at the coarse preview
    /// resolution until the drag ends, so that the preview keeps up.
    fn validate_and_send(&mut self, dragging: bool) {
        let Some(scene) = &self.scene else { return };
        let problems = validate(scene);
        self.problems = problems
            .iter()
            .map(|p| format!("{}: {}", p.field, p.message))
            .collect();
        // Labels (name, manufacturer, export keywords) are not light: the
        // run goes on, and an export takes them from the edited scene.
        if !problems.is_empty() || self.sent.as_ref().is_some_and(|s| s.same_light(scene)) {
            return;
        }
        let scene = scene.clone();
        let dir = self.scene_dir();
        self.sent = Some(scene.clone());
        match &mut self.sim {
            Some(sim) => {
                let coarse = coarse_preview(self.settings);
                if dragging && !self.coarse && coarse != self.settings {
                    match sim.set_settings(coarse) {
                        Ok(_) => self.coarse = true,
                        Err(e) => self.sim_error = Some(error_chain(&e)),
                    }
                }
                self.pacer.reset();
                sim.edit(scene, &dir);
            }
            None => self.start_simulation(scene, &dir),
        }
    }

    /// Back to the chosen resolution once the drag that previewed at the
    /// coarse one has ended.
    fn end_coarse_preview(&mut self) {
        if !std::mem::take(&mut self.coarse) {
            return;
        }
        if let Some(sim) = &mut self.sim
            && let Err(e) = sim.set_settings(self.settings)
        {
            self.sim_error = Some(error_chain(&e));
        }
    }

    fn start_simulation(&mut self, scene: Scene, dir: &Path) {
        // A drag's coarse preview must not wait for its resolution's
        // first-time tables (250 ms in the window, measured).
        let coarse = coarse_preview(self.settings);
        let _ = std::thread::Builder::new()
            .name("lucerna-prepare".to_owned())
            .spawn(move || {
                crate::lower_this_threads_priority();
                lucerna_simulation::prepare_snapshots(&coarse);
            });
        let ctx = self.ctx.clone();
        let pacer = self.pacer.clone();
        let repaint = move || {
            if let Some(ctx) = &ctx {
                pacer.request(ctx);
            }
        };
        self.snapshot = None;
        match Simulation::start(scene, dir, self.settings, repaint) {
            Ok(sim) => {
                if self.paused {
                    sim.pause();
                }
                self.sim = Some(sim);
                self.sim_error = None;
            }
            Err(e) => self.sim_error = Some(error_chain(&e)),
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
            Err(e) => self.file_error = Some(error_chain(&e)),
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
        self.path = path;
        self.saved = saved;
        self.scene = Some(scene);
        self.undoer = Undoer::with_settings(UndoSettings {
            max_undos: 200,
            ..UndoSettings::default()
        });
        self.selection = None;
        self.problems.clear();
        self.file_error = None;
        self.gesture = false;
        self.edit_error = None;
        // A new document gets a fresh run (generation 0).
        self.sim = None;
        self.coarse = false;
        self.sent = None;
        self.snapshot = None;
        self.sim_error = None;
        self.scene_changed();
    }

    fn save(&mut self, path: PathBuf) {
        let Some(scene) = &self.scene else {
            self.file_error = Some("no scene to save".to_owned());
            return;
        };
        // Saved elsewhere, relative mesh and profile paths keep naming the
        // same files (files.rs).
        let rebased = crate::files::rebased_for(scene, &self.scene_dir(), &path);
        let scene = rebased.as_ref().unwrap_or(scene);
        match save_scene(scene, &path) {
            Ok(()) => {
                self.saved = Some(scene.clone());
                if let Some(rebased) = rebased {
                    self.scene = Some(rebased);
                }
                self.file_error = None;
                self.files_saved(&path);
                if self.path.as_deref() != Some(&path) {
                    self.path = Some(path);
                    // Relative paths in the scene now resolve from here.
                    self.sent = None;
                    self.scene_changed();
                }
            }
            Err(e) => self.file_error = Some(error_chain(&e)),
        }
    }
}

/// The error and its sources, one per line.
pub(crate) fn error_chain(e: &dyn std::error::Error) -> String {
    let mut text = e.to_string();
    let mut source = e.source();
    while let Some(s) = source {
        text.push_str(&format!("\n  caused by: {s}"));
        source = s.source();
    }
    text
}

/// Texels per cube-face edge of the coarsest preview.
const MIN_PREVIEW_RESOLUTION: u32 = 16;
/// Texels per cube-face edge of the finest preview: enough to see a beam
/// move, few enough (6 × 32² texels) to snapshot every frame.
const MAX_PREVIEW_RESOLUTION: u32 = 32;

/// `settings` for previewing a drag: half the chosen resolution, between
/// 16 and 32 per face, never above the chosen one.
pub(crate) fn coarse_preview(settings: SimulationSettings) -> SimulationSettings {
    let resolution = (settings.resolution / 2)
        .clamp(MIN_PREVIEW_RESOLUTION, MAX_PREVIEW_RESOLUTION)
        .min(settings.resolution);
    SimulationSettings {
        resolution,
        ..settings
    }
}
