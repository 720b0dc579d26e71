//! The preview room's worker: a thread that reads room files and renders
//! the room lit by the newest table, through `lucerna-room`'s pipeline
//! (`RoomSetup`, `RoomRenderer`), the one `lucerna render` uses. The
//! state it serves is `room_state.rs`; the drawing is `room_view.rs`.
//!
//! Only the newest request matters: a request waiting while the worker
//! renders is replaced by the next one, so a converging run never queues
//! pictures of tables already superseded.

use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, Sender, channel};
use std::sync::{Arc, Condvar, Mutex, PoisonError};
use std::time::{Duration, Instant};

use lucerna_gpu::BackendRequest;
use lucerna_photometry::CandelaTable;
use lucerna_room::scene::opening_from_dimensions;
use lucerna_room::{
    IlluminanceFigures, Opening, ProfileGrid, RoomRenderer, RoomSetup, Shading, WorkPlaneGrid,
    room_files, tone_map,
};
use lucerna_simulation::Snapshot;

/// Picture size while the distribution changes (a converging run, an
/// edit): small enough to follow a run's snapshots on two CPU cores.
pub const DRAFT_SIZE: [u32; 2] = [320, 200];
/// Picture size while a drag runs: a quarter of the draft's pixels, so
/// that on the CPU, sharing its cores with the tracer, the room keeps
/// within about a second of the hand.
pub const DRAG_SIZE: [u32; 2] = [160, 100];
/// Picture size once the distribution has been still for a second.
pub const FINE_SIZE: [u32; 2] = [640, 400];

/// Which picture: while a drag runs, while the distribution changes
/// otherwise, or once it is still.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PictureQuality {
    /// At `DRAG_SIZE` by the polar rule's draft nodes
    /// (`Shading::Draft`, about 0.7 of the ray integrals), and never given
    /// up for a newer request: the room follows the hand.
    Drag,
    /// At `DRAFT_SIZE` by the full rule.
    Draft,
    /// At `FINE_SIZE` by the full rule.
    Fine,
}

impl PictureQuality {
    pub fn size(self) -> [u32; 2] {
        match self {
            PictureQuality::Drag => DRAG_SIZE,
            PictureQuality::Draft => DRAFT_SIZE,
            PictureQuality::Fine => FINE_SIZE,
        }
    }

    pub fn shading(self) -> Shading {
        match self {
            PictureQuality::Drag => Shading::Draft,
            PictureQuality::Draft | PictureQuality::Fine => Shading::Cubature,
        }
    }
}

/// The room files shipped in `assets/rooms`: beside the working directory
/// when run from the repository or an unpacked release, else where this
/// crate was built from.
pub fn default_rooms_dir() -> PathBuf {
    let here = PathBuf::from("assets/rooms");
    if here.is_dir() {
        return here;
    }
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/rooms")
}

/// What a picture is lit by: one candela table at every luminaire of the
/// room, from its luminous opening, and the run it came from.
#[derive(Debug, Clone)]
pub struct RoomLight {
    pub table: Arc<CandelaTable>,
    pub opening: Opening,
    /// The simulation run and photons of the table (0 for a file's).
    pub generation: u64,
    pub photons: u64,
}

impl RoomLight {
    /// The snapshot's exported table from its luminaire's opening.
    pub fn of(snapshot: &Snapshot) -> RoomLight {
        RoomLight {
            table: snapshot.table.clone(),
            opening: opening_from_dimensions(snapshot.luminaire.luminous_opening),
            generation: snapshot.generation,
            photons: snapshot.photons,
        }
    }
}

/// The profile grids of one table (one per flux factor): building a
/// grid's prefiltered levels is the largest fixed cost of a picture, so
/// the fine picture and room edits reuse them.
#[derive(Default)]
struct ProfileCache {
    table: Option<Arc<CandelaTable>>,
    grids: Vec<(f64, Arc<ProfileGrid>)>,
}

impl ProfileCache {
    fn for_table(&mut self, table: &Arc<CandelaTable>) -> &mut ProfileCache {
        if !self.table.as_ref().is_some_and(|t| Arc::ptr_eq(t, table)) {
            *self = ProfileCache {
                table: Some(table.clone()),
                grids: Vec::new(),
            };
        }
        self
    }

    fn grid(&mut self, flux_factor: f64) -> Arc<ProfileGrid> {
        if let Some((_, g)) = self.grids.iter().find(|(f, _)| *f == flux_factor) {
            return g.clone();
        }
        let Some(table) = &self.table else {
            return Arc::new(ProfileGrid::from_fn(true, |_, _| 0.0));
        };
        let grid = Arc::new(if flux_factor == 1.0 {
            ProfileGrid::from_table(table)
        } else {
            ProfileGrid::from_table(&table.scaled(flux_factor))
        });
        self.grids.push((flux_factor, grid.clone()));
        grid
    }
}

/// One picture to render.
#[derive(Debug, Clone)]
pub struct RenderRequest {
    pub light: RoomLight,
    pub room: Arc<RoomSetup>,
    /// Counts the room's edits, so a picture names the room it shows.
    pub room_revision: u64,
    pub quality: PictureQuality,
}

/// A rendered preview: the view, its illuminance, the work plane and its
/// figures, and what it shows.
#[derive(Debug, Clone)]
pub struct RoomPicture {
    /// The request it answers (numbered from 1 by [`RoomPreview::request`]).
    pub serial: u64,
    /// The simulation run and photons of the table it is lit by.
    pub generation: u64,
    pub photons: u64,
    pub room_revision: u64,
    pub quality: PictureQuality,
    pub size: [u32; 2],
    /// Tone-mapped sRGB, row-major.
    pub rgb: Vec<u8>,
    /// Illuminance (lx) on the surface seen in each pixel, −1 on a
    /// luminaire's opening.
    pub illuminance_lx: Vec<f32>,
    /// The work plane, the uniform indirect estimate included.
    pub grid: WorkPlaneGrid,
    pub figures: IlluminanceFigures,
    pub indirect_lux: f64,
    /// Room (width, depth) and the luminaires' plan positions (m).
    pub room_m: (f64, f64),
    pub luminaires_m: Vec<(f64, f64)>,
    /// The renderer that made it, in words.
    pub backend: String,
    /// From taking the request to the picture (profile grids, view, work
    /// plane).
    pub render_time: Duration,
    pub requested_at: Instant,
    pub finished_at: Instant,
}

/// The room renderer the worker opened and the grids of its last table.
pub struct Renderer {
    room: RoomRenderer,
    profiles: ProfileCache,
}

impl std::fmt::Debug for Renderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.room.fmt(f)
    }
}

impl Renderer {
    /// Opens the renderer `backend` asks for, as `lucerna render` does.
    pub fn open(backend: BackendRequest) -> Renderer {
        Renderer {
            room: RoomRenderer::open(backend),
            profiles: ProfileCache::default(),
        }
    }

    pub fn description(&self) -> &str {
        self.room.description()
    }

    /// Renders one request (on the calling thread), shaded by the polar
    /// rule (its draft nodes for a drag's picture), by
    /// `lucerna render`'s pipeline; `None` if `give_up` said so between
    /// two bands of rows (a newer request that makes it stale waits).
    pub fn render(
        &mut self,
        request: &RenderRequest,
        serial: u64,
        give_up: &dyn Fn() -> bool,
    ) -> Option<RoomPicture> {
        let requested_at = Instant::now();
        let light = &request.light;
        let cache = self.profiles.for_table(&light.table);
        let scene = request.room.scene_lit_by(|f| cache.grid(f), light.opening);
        let size = request.quality.size();
        let lit = self
            .room
            .light(&scene, size, request.quality.shading(), give_up)?;
        let finished_at = Instant::now();
        Some(RoomPicture {
            serial,
            generation: light.generation,
            photons: light.photons,
            room_revision: request.room_revision,
            quality: request.quality,
            size,
            rgb: tone_map(&lit.frame),
            illuminance_lx: lit.frame.illuminance,
            grid: lit.grid,
            figures: lit.figures,
            indirect_lux: lit.indirect_lux,
            room_m: (scene.size.x, scene.size.y),
            luminaires_m: scene
                .lights
                .iter()
                .map(|l| (l.position.x, l.position.y))
                .collect(),
            backend: lit.backend,
            render_time: finished_at - requested_at,
            requested_at,
            finished_at,
        })
    }
}

/// A room file read on the worker, or why it could not be.
#[derive(Debug, Clone)]
pub struct LoadedRoom {
    /// The load it answers (numbered from 1 by [`RoomPreview::load`]).
    pub serial: u64,
    pub path: PathBuf,
    pub result: Result<RoomSetup, String>,
}

/// What the worker hands back.
#[derive(Debug)]
enum Event {
    Listed(Vec<PathBuf>),
    Loaded(LoadedRoom),
    Picture(RoomPicture),
}

/// What came back since the last [`RoomPreview::poll`]: the newest of
/// each.
#[derive(Debug, Default)]
pub struct RoomEvents {
    /// The room files of the folder asked with [`RoomPreview::list`].
    pub listed: Option<Vec<PathBuf>>,
    pub loaded: Option<LoadedRoom>,
    pub picture: Option<RoomPicture>,
}

/// The jobs waiting for the worker (at most one of each) and the close
/// flag. File jobs go first: they are quick and a picture needs a room.
#[derive(Default)]
struct Mailbox {
    list: Option<PathBuf>,
    load: Option<(PathBuf, u64)>,
    render: Option<(RenderRequest, u64)>,
    closed: bool,
}

enum Job {
    List(PathBuf),
    Load(PathBuf, u64),
    Render(RenderRequest, u64),
}

impl Mailbox {
    fn take(&mut self) -> Option<Job> {
        if let Some(dir) = self.list.take() {
            return Some(Job::List(dir));
        }
        if let Some((path, serial)) = self.load.take() {
            return Some(Job::Load(path, serial));
        }
        self.render
            .take()
            .map(|(request, serial)| Job::Render(request, serial))
    }
}

#[derive(Default)]
struct Shared {
    mailbox: Mutex<Mailbox>,
    wake: Condvar,
}

impl Shared {
    fn mailbox(&self) -> std::sync::MutexGuard<'_, Mailbox> {
        self.mailbox.lock().unwrap_or_else(PoisonError::into_inner)
    }
}

/// The room worker on its own thread: [`request`](Self::request) hands it
/// the newest table and room, [`load`](Self::load) a room file to read,
/// [`poll`](Self::poll) takes what came back. Dropping it stops the thread
/// after the job it is on.
pub struct RoomPreview {
    shared: Arc<Shared>,
    events: Receiver<Event>,
    requested: u64,
    received: u64,
    loads: u64,
    backend: BackendRequest,
    /// Why no worker runs, if it could not start.
    start_error: Option<String>,
}

impl std::fmt::Debug for RoomPreview {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RoomPreview")
            .field("requested", &self.requested)
            .field("received", &self.received)
            .finish_non_exhaustive()
    }
}

impl RoomPreview {
    /// Starts the worker; `repaint` is called after each result (the
    /// editor asks egui for a frame). The renderer opens on the worker
    /// thread, so opening a GPU never stalls the UI.
    pub fn start(backend: BackendRequest, repaint: impl Fn() + Send + 'static) -> RoomPreview {
        let shared = Arc::new(Shared::default());
        let (send, events) = channel();
        let worker = shared.clone();
        let spawned = std::thread::Builder::new()
            .name("room preview".to_owned())
            .spawn(move || {
                // At the tracer's priority: a frame never waits for it.
                crate::lower_this_threads_priority();
                worker_loop(&worker, &send, backend, repaint)
            });
        RoomPreview {
            shared,
            events,
            requested: 0,
            received: 0,
            loads: 0,
            backend,
            start_error: spawned
                .err()
                .map(|e| format!("cannot start the room renderer's thread: {e}")),
        }
    }

    pub fn backend(&self) -> BackendRequest {
        self.backend
    }

    /// Why the worker thread did not start, if it did not.
    pub fn start_error(&self) -> Option<&str> {
        self.start_error.as_deref()
    }

    fn post(&self, put: impl FnOnce(&mut Mailbox)) {
        put(&mut self.shared.mailbox());
        self.shared.wake.notify_one();
    }

    /// Asks for the room files in `dir`.
    pub fn list(&mut self, dir: PathBuf) {
        self.post(|m| m.list = Some(dir));
    }

    /// Asks for a room file to be read, replacing a load still waiting;
    /// returns its serial number.
    pub fn load(&mut self, path: PathBuf) -> u64 {
        self.loads += 1;
        let serial = self.loads;
        self.post(|m| m.load = Some((path, serial)));
        serial
    }

    /// Asks for a picture, replacing any request still waiting; returns
    /// its serial number.
    pub fn request(&mut self, request: RenderRequest) -> u64 {
        self.requested += 1;
        let serial = self.requested;
        self.post(|m| m.render = Some((request, serial)));
        serial
    }

    /// The newest listing, load and picture finished since the last call.
    pub fn poll(&mut self) -> RoomEvents {
        let mut events = RoomEvents::default();
        for event in self.events.try_iter() {
            match event {
                Event::Listed(files) => events.listed = Some(files),
                Event::Loaded(loaded) => events.loaded = Some(loaded),
                Event::Picture(picture) => {
                    self.received = picture.serial;
                    events.picture = Some(picture);
                }
            }
        }
        events
    }

    /// Whether a requested picture has not come back yet.
    pub fn is_rendering(&self) -> bool {
        self.received < self.requested
    }
}

impl Drop for RoomPreview {
    fn drop(&mut self) {
        let mut mailbox = self.shared.mailbox();
        *mailbox = Mailbox {
            closed: true,
            ..Mailbox::default()
        };
        self.shared.wake.notify_all();
    }
}

fn worker_loop(
    shared: &Shared,
    events: &Sender<Event>,
    backend: BackendRequest,
    repaint: impl Fn(),
) {
    let mut renderer: Option<Renderer> = None;
    loop {
        let job = {
            let mut mailbox = shared.mailbox();
            loop {
                if mailbox.closed {
                    return;
                }
                if let Some(job) = mailbox.take() {
                    break job;
                }
                mailbox = shared
                    .wake
                    .wait(mailbox)
                    .unwrap_or_else(PoisonError::into_inner);
            }
        };
        let event = match job {
            Job::List(dir) => Some(Event::Listed(room_files(&dir))),
            Job::Load(path, serial) => {
                let result = RoomSetup::load(&path).map_err(|e| crate::error_text::error_chain(&e));
                Some(Event::Loaded(LoadedRoom {
                    serial,
                    path,
                    result,
                }))
            }
            Job::Render(request, serial) => {
                let renderer = renderer.get_or_insert_with(|| Renderer::open(backend));
                // Given up for any newer request when fine (a draft of it
                // comes next), and a draft for one of a newer run (an
                // edit): never a draft for the next snapshot of the same
                // run, or a converging run would show nothing; never a
                // drag's picture (a drag makes a run every frame: given up
                // for each, the room would wait for the hand to stop).
                let quality = request.quality;
                let generation = request.light.generation;
                let newer_waits = || {
                    let mailbox = shared.mailbox();
                    mailbox.closed
                        || mailbox
                            .render
                            .as_ref()
                            .is_some_and(|(next, _)| match quality {
                                PictureQuality::Fine => true,
                                PictureQuality::Draft => next.light.generation != generation,
                                PictureQuality::Drag => false,
                            })
                };
                // A picture given up for a newer request is not sent: that
                // one is next.
                renderer
                    .render(&request, serial, &newer_waits)
                    .map(Event::Picture)
            }
        };
        if let Some(event) = event {
            if events.send(event).is_err() {
                return;
            }
            repaint();
        }
    }
}
