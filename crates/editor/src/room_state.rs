//! The live preview room apart from drawing, a peer of the simulation in
//! the editor's state: which room is previewed (a room file with the
//! user's edits), its worker, the rule that picks a draft or a fine
//! picture, the task area judged, and the last picture. The Room tab
//! draws it and queues [`RoomCommand`]s; files are read and pictures
//! rendered on the worker (`room_preview.rs`).

use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use lucerna_gpu::BackendRequest;
use lucerna_room::{RoomSetup, TASK_TARGETS, TaskTarget};
use lucerna_simulation::Snapshot;

use crate::room_preview::{
    PictureQuality, RenderRequest, RoomLight, RoomPicture, RoomPreview, default_rooms_dir,
};

/// How long the table and the room must stay unchanged before the fine
/// picture is rendered.
pub const SETTLE: Duration = Duration::from_secs(1);

/// A surface of the previewed room whose reflectance an edit sets.
#[derive(Debug, Clone, PartialEq)]
pub enum RoomSurface {
    Floor,
    Walls,
    Ceiling,
    /// A named material of the room's OBJ.
    Material(String),
}

/// What the Room tab asks of the room preview.
#[derive(Debug, Clone, PartialEq)]
pub enum RoomCommand {
    /// Preview this room file (read on the worker; the current room stays
    /// until it is read, and stays if it cannot be).
    Choose(PathBuf),
    /// Render with this renderer (a fresh worker opens it).
    Renderer(BackendRequest),
    /// Judge the work plane against `TASK_TARGETS[i]`.
    Task(usize),
    /// Resize the box room (m), its layout moving with the walls.
    Resize([f64; 3]),
    Reflectance(RoomSurface, f64),
}

/// The preview room's state.
#[derive(Default)]
pub struct RoomLive {
    /// The room files offered, once the worker has listed them.
    rooms: Option<Vec<PathBuf>>,
    /// The room as edited (may be invalid while a field is changed).
    draft: Option<RoomSetup>,
    /// The draft's problems, if it is invalid.
    problems: Vec<String>,
    /// The last valid room, as rendered; `revision` counts its changes.
    room: Option<Arc<RoomSetup>>,
    revision: u64,
    /// Why the last chosen room file could not be used.
    error: Option<String>,
    /// A room file chosen, to be handed to the worker.
    chosen: Option<PathBuf>,
    /// The room file being read on the worker, with its load serial.
    loading: Option<(u64, PathBuf)>,
    backend: BackendRequest,
    preview: Option<RoomPreview>,
    refinement: Refinement,
    picture: Option<RoomPicture>,
    /// Index into [`TASK_TARGETS`]; `None` until a room suggests one.
    target: Option<usize>,
    /// The Room tab was drawn this frame: pictures are rendered only while
    /// someone looks (on the CPU they cost the tracer's cores).
    watched: bool,
}

impl std::fmt::Debug for RoomLive {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RoomLive")
            .field("room", &self.room.as_ref().map(|r| r.path.clone()))
            .field("revision", &self.revision)
            .field("preview", &self.preview)
            .finish_non_exhaustive()
    }
}

impl RoomLive {
    /// The room files offered (none before the worker has listed them).
    pub fn rooms(&self) -> &[PathBuf] {
        self.rooms.as_deref().unwrap_or_default()
    }

    /// The room being edited, if one is loaded.
    pub fn draft(&self) -> Option<&RoomSetup> {
        self.draft.as_ref()
    }

    /// The room the pictures show.
    pub fn room(&self) -> Option<&Arc<RoomSetup>> {
        self.room.as_ref()
    }

    /// The draft's problems (empty: it is the room rendered).
    pub fn problems(&self) -> &[String] {
        &self.problems
    }

    /// Why the last room file chosen could not be used, or why no room
    /// files were found.
    pub fn error(&self) -> Option<&str> {
        self.error.as_deref()
    }

    /// The room file being read, if one is.
    pub fn loading(&self) -> Option<&PathBuf> {
        self.chosen
            .as_ref()
            .or(self.loading.as_ref().map(|(_, p)| p))
    }

    pub fn renderer(&self) -> BackendRequest {
        self.backend
    }

    /// Why the worker did not start, if it did not.
    pub fn start_error(&self) -> Option<&str> {
        self.preview.as_ref().and_then(RoomPreview::start_error)
    }

    /// Whether a picture asked for has not come back yet.
    pub fn is_rendering(&self) -> bool {
        self.preview.as_ref().is_some_and(RoomPreview::is_rendering)
    }

    pub fn picture(&self) -> Option<&RoomPicture> {
        self.picture.as_ref()
    }

    /// The index into [`TASK_TARGETS`] of the task area judged.
    pub fn target_index(&self) -> usize {
        self.target.unwrap_or(0).min(TASK_TARGETS.len() - 1)
    }

    /// The Room tab is shown this frame.
    pub fn watch(&mut self) {
        self.watched = true;
    }

    pub fn apply(&mut self, command: RoomCommand) {
        match command {
            RoomCommand::Choose(path) => self.chosen = Some(path),
            RoomCommand::Renderer(backend) => {
                if backend != self.backend {
                    self.backend = backend;
                    // A fresh worker opens the chosen renderer; the old
                    // one stops after its job.
                    self.preview = None;
                    if let Some((_, path)) = self.loading.take() {
                        self.chosen.get_or_insert(path);
                    }
                }
            }
            RoomCommand::Task(i) => self.target = Some(i.min(TASK_TARGETS.len() - 1)),
            RoomCommand::Resize(size_m) => {
                if let Some(draft) = &mut self.draft {
                    draft.resize(size_m);
                }
                self.commit_draft();
            }
            RoomCommand::Reflectance(surface, value) => {
                if let Some(draft) = &mut self.draft {
                    let r = &mut draft.file.room;
                    let target = match &surface {
                        RoomSurface::Floor => Some(&mut r.floor),
                        RoomSurface::Walls => Some(&mut r.walls),
                        RoomSurface::Ceiling => Some(&mut r.ceiling),
                        RoomSurface::Material(name) => r.materials.get_mut(name),
                    };
                    if let Some(s) = target {
                        s.reflectance = value;
                    }
                }
                self.commit_draft();
            }
        }
    }

    /// The draft becomes the rendered room when it changed and is valid.
    fn commit_draft(&mut self) {
        let Some(draft) = &self.draft else { return };
        self.problems = draft.problems();
        if self.problems.is_empty() && self.room.as_ref().is_none_or(|r| r.file != draft.file) {
            self.room = Some(Arc::new(draft.clone()));
            self.revision += 1;
        }
    }

    /// Once a frame, after the commands: starts the worker on first use,
    /// takes what it finished, and asks for the picture that is due while
    /// the Room tab is shown; `dragging`: a pointer gesture is editing (a
    /// new run's picture is then a drag's).
    pub fn tick(
        &mut self,
        snapshot: Option<&Arc<Snapshot>>,
        ctx: &egui::Context,
        now: Instant,
        dragging: bool,
    ) {
        let watched = std::mem::take(&mut self.watched);
        if !watched && self.preview.is_none() {
            return;
        }
        let preview = self.preview.get_or_insert_with(|| {
            let ctx = ctx.clone();
            let mut preview = RoomPreview::start(self.backend, move || ctx.request_repaint());
            if self.rooms.is_none() {
                preview.list(default_rooms_dir());
            }
            self.refinement.reset();
            preview
        });
        if let Some(path) = self.chosen.take() {
            let serial = preview.load(path.clone());
            self.loading = Some((serial, path));
        }
        let events = preview.poll();
        if let Some(rooms) = events.listed {
            let first = rooms
                .iter()
                .find(|p| p.file_stem().is_some_and(|s| s == "office"))
                .or(rooms.first())
                .cloned();
            match first {
                Some(path)
                    if self.room.is_none() && self.loading.is_none() && self.chosen.is_none() =>
                {
                    let serial = preview.load(path.clone());
                    self.loading = Some((serial, path));
                }
                Some(_) => {}
                None => {
                    self.error = Some(format!(
                        "no room files (*.toml) in {}",
                        default_rooms_dir().display()
                    ));
                }
            }
            self.rooms = Some(rooms);
        }
        if let Some(loaded) = events.loaded
            && self
                .loading
                .as_ref()
                .is_some_and(|(serial, _)| *serial == loaded.serial)
        {
            self.loading = None;
            match loaded.result {
                Ok(setup) => {
                    self.target = Some(TaskTarget::for_room(&format!(
                        "{} {}",
                        loaded.path.display(),
                        setup.file.name
                    )));
                    self.draft = Some(setup.clone());
                    self.problems.clear();
                    self.room = Some(Arc::new(setup));
                    self.revision += 1;
                    self.error = None;
                }
                Err(e) => self.error = Some(e),
            }
        }
        if let Some(picture) = events.picture {
            self.picture = Some(picture);
        }
        if !watched {
            return;
        }
        // Ask for a picture of the newest table and room when one is due.
        if let (Some(snapshot), Some(room)) = (snapshot, &self.room) {
            if let Some(quality) = self.refinement.due(snapshot, self.revision, now, dragging) {
                preview.request(RenderRequest {
                    light: RoomLight::of(snapshot),
                    room: room.clone(),
                    room_revision: self.revision,
                    quality,
                });
            }
            if let Some(wait) = self.refinement.fine_due_in(now) {
                ctx.request_repaint_after(wait);
            }
        }
    }
}

/// Between two pictures of one converging run (no edit): the room keeps
/// up with the noise going down without rendering all the time; on the
/// CPU a picture costs 0.2-1.5 s, which would come out of the tracing.
pub const CONVERGING_REFRESH: Duration = Duration::from_secs(5);

/// When to render what: a draft at once on an edit (a new run) or a room
/// change (a drag's draft while a pointer gesture edits), the fine picture
/// once neither has changed for [`SETTLE`], and while one run converges a
/// new picture (of the quality last asked) at most every
/// [`CONVERGING_REFRESH`].
#[derive(Debug, Default)]
pub struct Refinement {
    /// The snapshot and room revision last asked for.
    shown: Option<(Arc<Snapshot>, u64)>,
    changed_at: Option<Instant>,
    requested_at: Option<Instant>,
    fine_requested: bool,
    /// The draft's quality last asked (a drag's or not).
    draft: Option<PictureQuality>,
}

impl Refinement {
    /// The picture to render now for `snapshot` and room `revision`, if
    /// one is due; `dragging`: a pointer gesture is editing.
    pub fn due(
        &mut self,
        snapshot: &Arc<Snapshot>,
        revision: u64,
        now: Instant,
        dragging: bool,
    ) -> Option<PictureQuality> {
        let Some((shown, shown_revision)) = &self.shown else {
            return Some(self.changed(snapshot, revision, now, dragging));
        };
        if *shown_revision != revision || shown.generation != snapshot.generation {
            return Some(self.changed(snapshot, revision, now, dragging));
        }
        let still = self.changed_at.is_some_and(|t| now - t >= SETTLE);
        if still && !self.fine_requested {
            self.fine_requested = true;
            self.shown = Some((snapshot.clone(), revision));
            self.requested_at = Some(now);
            return Some(PictureQuality::Fine);
        }
        let newer = !Arc::ptr_eq(shown, snapshot);
        let refresh = self
            .requested_at
            .is_none_or(|t| now - t >= CONVERGING_REFRESH);
        if newer && refresh {
            self.shown = Some((snapshot.clone(), revision));
            self.requested_at = Some(now);
            return Some(if self.fine_requested {
                PictureQuality::Fine
            } else {
                self.draft.unwrap_or(PictureQuality::Draft)
            });
        }
        None
    }

    fn changed(
        &mut self,
        snapshot: &Arc<Snapshot>,
        revision: u64,
        now: Instant,
        dragging: bool,
    ) -> PictureQuality {
        self.shown = Some((snapshot.clone(), revision));
        self.changed_at = Some(now);
        self.requested_at = Some(now);
        self.fine_requested = false;
        let quality = if dragging {
            PictureQuality::Drag
        } else {
            PictureQuality::Draft
        };
        self.draft = Some(quality);
        quality
    }

    /// How long until the next picture may be due (for a repaint then).
    pub fn fine_due_in(&self, now: Instant) -> Option<Duration> {
        if self.fine_requested {
            return self
                .requested_at
                .map(|t| CONVERGING_REFRESH.saturating_sub(now.saturating_duration_since(t)));
        }
        self.changed_at
            .map(|t| SETTLE.saturating_sub(now.saturating_duration_since(t)))
    }

    /// Forgets what was asked (a new renderer must be asked again).
    pub fn reset(&mut self) {
        *self = Refinement::default();
    }
}
