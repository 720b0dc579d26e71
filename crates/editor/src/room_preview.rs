//! The live preview room apart from drawing: the room being previewed
//! (a room file of `lucerna-room` with the user's edits), the renderer on
//! its own thread that lights it with the newest snapshot's candela table,
//! and the rule that picks a draft or a fine resolution. The UI is
//! `room_view.rs`.
//!
//! Only the newest request matters: a request waiting while the worker
//! renders is replaced by the next one, so a converging run never queues
//! pictures of tables already superseded.

use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, Sender, channel};
use std::sync::{Arc, Condvar, Mutex, PoisonError};
use std::time::{Duration, Instant};

use glam::DVec3;
use lucerna_room::gpu::{GpuRoomRenderer, UploadedRoom};
use lucerna_room::model::{RoomFile, RoomFileError, load_room, validate};
use lucerna_room::render::render_cpu_rows;
use lucerna_room::scene::{RoomMesh, load_room_mesh, opening_from_dimensions};
use lucerna_room::{
    Frame, IlluminanceFigures, Opening, PlacedLight, ProfileGrid, RoomScene, Shading,
    WorkPlaneGrid, tone_map, work_plane_cpu,
};
use lucerna_simulation::Snapshot;
use lucerna_simulation::export::luminous_opening;

/// Picture size while the distribution changes (a converging run, an
/// edit): small enough to follow a run's snapshots on two CPU cores.
pub const DRAFT_SIZE: [u32; 2] = [320, 200];
/// Picture size once the distribution has been still for [`SETTLE`].
pub const FINE_SIZE: [u32; 2] = [640, 400];
/// How long the table and the room must stay unchanged before the fine
/// picture is rendered.
pub const SETTLE: Duration = Duration::from_secs(1);

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

/// The `*.toml` room files in `dir`, sorted by name (empty if unreadable).
pub fn room_files(dir: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut files: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    files
}

/// A room file as loaded and then edited: every luminaire it places is the
/// edited luminaire (its own profile file is not read), at the file's
/// positions, rotations and arrays.
#[derive(Debug, Clone, PartialEq)]
pub struct RoomSetup {
    pub path: PathBuf,
    pub file: RoomFile,
    /// The OBJ room's triangles, loaded once with the file.
    pub mesh: Option<Arc<RoomMesh>>,
}

impl RoomSetup {
    /// Reads and validates a room file and its OBJ, if it names one.
    pub fn load(path: &Path) -> Result<RoomSetup, RoomFileError> {
        let file = load_room(path)?;
        let base = path.parent().unwrap_or(Path::new("."));
        let mesh = load_room_mesh(&file, base)?.map(Arc::new);
        Ok(RoomSetup {
            path: path.to_owned(),
            file,
            mesh,
        })
    }

    /// The edits' problems as "field: problem" (none: it can be rendered).
    pub fn problems(&self) -> Vec<String> {
        validate(&self.file)
    }

    /// Changes the box's size (m), moving the luminaires, their array
    /// spacing and the camera with the walls (each coordinate scaled by its
    /// axis' ratio) so the layout stays inside the room; the work plane
    /// keeps its height.
    pub fn resize(&mut self, size_m: [f64; 3]) {
        let r = &mut self.file.room;
        let old = [r.width_m, r.depth_m, r.height_m];
        let ratio: [f64; 3] = std::array::from_fn(|k| {
            if old[k] > 0.0 && size_m[k].is_finite() {
                size_m[k] / old[k]
            } else {
                1.0
            }
        });
        [r.width_m, r.depth_m, r.height_m] = size_m;
        let scale = |p: &mut [f64; 3]| {
            for k in 0..3 {
                p[k] *= ratio[k];
            }
        };
        for l in &mut self.file.luminaires {
            scale(&mut l.position);
            if let Some(a) = &mut l.array {
                a.spacing_m[0] *= ratio[0];
                a.spacing_m[1] *= ratio[1];
            }
        }
        scale(&mut self.file.camera.position);
        scale(&mut self.file.camera.look_at);
    }

    /// The room lit by the edited luminaire at every luminaire of the
    /// file: `profile(flux_factor)` gives the profile grid scaled by a
    /// spec's factor (one grid shared by all copies), and the opening is
    /// the edited luminaire's own, not the one the file gives its profile.
    pub fn scene(
        &self,
        mut profile: impl FnMut(f64) -> Arc<ProfileGrid>,
        opening: Opening,
    ) -> RoomScene {
        let mut shell = self.file.clone();
        shell.luminaires.clear();
        let mut scene = RoomScene::new(&shell, &[]);
        for spec in &self.file.luminaires {
            let grid = profile(spec.flux_factor);
            let rotation = PlacedLight::rotation_from_euler_deg(spec.rotation_deg);
            for p in spec.positions() {
                scene.lights.push(PlacedLight {
                    profile: grid.clone(),
                    opening,
                    position: DVec3::from_array(p),
                    rotation,
                });
            }
        }
        scene.mesh = self.mesh.as_deref().cloned();
        scene
    }
}

/// The profile grids of one snapshot's table (one per flux factor) and
/// its luminous opening: building a grid's prefiltered levels is the
/// largest fixed cost of a picture, so the fine picture and room edits
/// reuse them.
#[derive(Default)]
struct ProfileCache {
    snapshot: Option<Arc<Snapshot>>,
    grids: Vec<(f64, Arc<ProfileGrid>)>,
    opening: Option<Opening>,
}

impl ProfileCache {
    fn for_snapshot(&mut self, snapshot: &Arc<Snapshot>) -> &mut ProfileCache {
        if !self
            .snapshot
            .as_ref()
            .is_some_and(|s| Arc::ptr_eq(s, snapshot))
        {
            let l = &snapshot.luminaire;
            *self = ProfileCache {
                snapshot: Some(snapshot.clone()),
                grids: Vec::new(),
                opening: Some(opening_from_dimensions(luminous_opening(
                    &l.scene,
                    &l.tessellated,
                ))),
            };
        }
        self
    }

    fn grid(&mut self, flux_factor: f64) -> Arc<ProfileGrid> {
        if let Some((_, g)) = self.grids.iter().find(|(f, _)| *f == flux_factor) {
            return g.clone();
        }
        let table = match &self.snapshot {
            Some(s) if flux_factor == 1.0 => s.table.as_ref().clone(),
            Some(s) => s.table.scaled(flux_factor),
            None => return Arc::new(ProfileGrid::from_fn(true, |_, _| 0.0)),
        };
        let grid = Arc::new(ProfileGrid::from_table(&table));
        self.grids.push((flux_factor, grid.clone()));
        grid
    }
}

/// Which renderer the preview uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RoomBackend {
    /// A hardware GPU if one opens, else the CPU (faster than a software
    /// adapter: `lucerna render-bench`), as `lucerna render` chooses.
    #[default]
    Auto,
    Cpu,
    /// The WGSL renderer on whatever adapter opens, a software one too.
    Gpu,
}

/// One picture to render.
#[derive(Debug, Clone)]
pub struct RenderRequest {
    pub snapshot: Arc<Snapshot>,
    pub room: Arc<RoomSetup>,
    /// Counts the room's edits, so a picture names the room it shows.
    pub room_revision: u64,
    pub size: [u32; 2],
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
    /// From taking the request to the picture (table, profile grids,
    /// view, work plane).
    pub render_time: Duration,
    pub requested_at: Instant,
    pub finished_at: Instant,
}

/// The renderer the worker opened, and why that one.
pub struct Renderer {
    gpu: Option<GpuRoomRenderer>,
    description: String,
    profiles: ProfileCache,
}

impl std::fmt::Debug for Renderer {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.description)
    }
}

impl Renderer {
    /// Opens the GPU renderer where `backend` asks for one and it opens;
    /// otherwise the CPU, saying why.
    pub fn open(backend: RoomBackend) -> Renderer {
        let cpu = |why: String| Renderer {
            gpu: None,
            description: why,
            profiles: ProfileCache::default(),
        };
        if backend == RoomBackend::Cpu {
            return cpu("CPU".to_owned());
        }
        let ctx = match lucerna_gpu::open() {
            Ok(ctx) => ctx,
            Err(e) => return cpu(format!("CPU (no GPU: {e})")),
        };
        if backend == RoomBackend::Auto && ctx.is_software() {
            return cpu(format!(
                "CPU (the adapter {} is software, slower than the CPU renderer)",
                ctx.describe()
            ));
        }
        let name = ctx.describe();
        match GpuRoomRenderer::new(ctx) {
            Ok(gpu) => Renderer {
                gpu: Some(gpu),
                description: format!("GPU: {name}"),
                profiles: ProfileCache::default(),
            },
            Err(e) => cpu(format!("CPU (the GPU renderer failed on {name}: {e})")),
        }
    }

    pub fn description(&self) -> &str {
        &self.description
    }

    /// Renders one request (on the calling thread). A GPU failure falls
    /// back to the CPU for good, and the picture says so. On the CPU the
    /// view is rendered in bands of rows and given up (`None`) between two
    /// when `give_up` says so (a newer request that makes it stale waits).
    pub fn render(
        &mut self,
        request: &RenderRequest,
        serial: u64,
        give_up: &dyn Fn() -> bool,
    ) -> Option<RoomPicture> {
        let requested_at = Instant::now();
        let snapshot = &request.snapshot;
        let cache = self.profiles.for_snapshot(snapshot);
        let opening = cache.opening.unwrap_or(Opening::Point);
        let scene = request.room.scene(|f| cache.grid(f), opening);
        let [w, h] = request.size;
        let gpu_result = self.gpu.as_ref().map(|gpu| {
            let uploaded: UploadedRoom = gpu.upload(&scene)?;
            let (frame, _) = gpu.render(&scene, &uploaded, w, h, Shading::Cubature)?;
            let grid = gpu.work_plane(&scene, &uploaded, Shading::Cubature)?;
            Ok::<_, lucerna_gpu::GpuError>((frame, grid))
        });
        let (frame, mut grid) = match gpu_result {
            Some(Ok(done)) => done,
            other => {
                if let Some(Err(e)) = other {
                    self.gpu = None;
                    self.description = format!("CPU (the GPU render failed: {e})");
                }
                let band = (h / 10).max(1);
                let mut frame = Frame {
                    width: w,
                    height: h,
                    luminance: Vec::with_capacity((w * h) as usize),
                    illuminance: Vec::with_capacity((w * h) as usize),
                };
                for top in (0..h).step_by(band as usize) {
                    if give_up() {
                        return None;
                    }
                    let rows = render_cpu_rows(&scene, w, h, top..top + band, Shading::Cubature);
                    frame.luminance.extend(rows.luminance);
                    frame.illuminance.extend(rows.illuminance);
                }
                (frame, work_plane_cpu(&scene, Shading::Cubature))
            }
        };
        let indirect_lux = scene.indirect_lux();
        for e in &mut grid.lux {
            *e += indirect_lux;
        }
        let figures = grid.figures();
        let finished_at = Instant::now();
        Some(RoomPicture {
            serial,
            generation: snapshot.generation,
            photons: snapshot.photons,
            room_revision: request.room_revision,
            size: request.size,
            rgb: tone_map(&frame),
            illuminance_lx: frame.illuminance,
            grid,
            figures,
            indirect_lux,
            room_m: (scene.size.x, scene.size.y),
            luminaires_m: scene
                .lights
                .iter()
                .map(|l| (l.position.x, l.position.y))
                .collect(),
            backend: self.description.clone(),
            render_time: finished_at - requested_at,
            requested_at,
            finished_at,
        })
    }
}

/// The request waiting for the worker (at most one) and the close flag.
#[derive(Default)]
struct Mailbox {
    pending: Option<(RenderRequest, u64)>,
    closed: bool,
}

#[derive(Default)]
struct Shared {
    mailbox: Mutex<Mailbox>,
    wake: Condvar,
}

/// The room renderer on its own thread: [`request`](Self::request) hands
/// it the newest table and room, [`poll`](Self::poll) takes the newest
/// picture. Dropping it stops the thread after the picture it is on.
pub struct RoomPreview {
    shared: Arc<Shared>,
    pictures: Receiver<RoomPicture>,
    requested: u64,
    received: u64,
    backend: RoomBackend,
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
    /// Starts the worker; `repaint` is called after each picture (the
    /// editor asks egui for a frame). The renderer opens on the worker
    /// thread, so opening a GPU never stalls the UI.
    pub fn start(backend: RoomBackend, repaint: impl Fn() + Send + 'static) -> RoomPreview {
        let shared = Arc::new(Shared::default());
        let (send, pictures) = channel();
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
            pictures,
            requested: 0,
            received: 0,
            backend,
            start_error: spawned
                .err()
                .map(|e| format!("cannot start the room renderer's thread: {e}")),
        }
    }

    pub fn backend(&self) -> RoomBackend {
        self.backend
    }

    /// Why the worker thread did not start, if it did not.
    pub fn start_error(&self) -> Option<&str> {
        self.start_error.as_deref()
    }

    /// Asks for a picture, replacing any request still waiting; returns
    /// its serial number.
    pub fn request(&mut self, request: RenderRequest) -> u64 {
        self.requested += 1;
        let mut mailbox = self
            .shared
            .mailbox
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        mailbox.pending = Some((request, self.requested));
        self.shared.wake.notify_one();
        self.requested
    }

    /// The newest picture finished since the last call, if any.
    pub fn poll(&mut self) -> Option<RoomPicture> {
        let newest = self.pictures.try_iter().last()?;
        self.received = newest.serial;
        Some(newest)
    }

    /// Whether a requested picture has not come back yet.
    pub fn is_rendering(&self) -> bool {
        self.received < self.requested
    }
}

impl Drop for RoomPreview {
    fn drop(&mut self) {
        let mut mailbox = self
            .shared
            .mailbox
            .lock()
            .unwrap_or_else(PoisonError::into_inner);
        mailbox.closed = true;
        mailbox.pending = None;
        self.shared.wake.notify_all();
    }
}

fn worker_loop(
    shared: &Shared,
    pictures: &Sender<RoomPicture>,
    backend: RoomBackend,
    repaint: impl Fn(),
) {
    let mut renderer: Option<Renderer> = None;
    loop {
        let (request, serial) = {
            let mut mailbox = shared
                .mailbox
                .lock()
                .unwrap_or_else(PoisonError::into_inner);
            loop {
                if mailbox.closed {
                    return;
                }
                if let Some(next) = mailbox.pending.take() {
                    break next;
                }
                mailbox = shared
                    .wake
                    .wait(mailbox)
                    .unwrap_or_else(PoisonError::into_inner);
            }
        };
        let renderer = renderer.get_or_insert_with(|| Renderer::open(backend));
        // Given up for any newer request when fine (a draft of it comes
        // next), and a draft for one of a newer run (an edit): never a
        // draft for the next snapshot of the same run, or a converging
        // run would show nothing.
        let fine = request.size != DRAFT_SIZE;
        let generation = request.snapshot.generation;
        let newer_waits = || {
            let mailbox = shared
                .mailbox
                .lock()
                .unwrap_or_else(PoisonError::into_inner);
            mailbox.closed
                || mailbox
                    .pending
                    .as_ref()
                    .is_some_and(|(next, _)| fine || next.snapshot.generation != generation)
        };
        // A picture given up for a newer request is not sent: that one
        // is next.
        if let Some(picture) = renderer.render(&request, serial, &newer_waits) {
            if pictures.send(picture).is_err() {
                return;
            }
            repaint();
        }
    }
}

/// Between two pictures of one converging run (no edit): the room keeps
/// up with the noise going down without rendering all the time; on the
/// CPU a picture costs 0.2-1.5 s, which would come out of the tracing.
pub const CONVERGING_REFRESH: Duration = Duration::from_secs(5);

/// When to render what: a draft at once on an edit (a new run) or a room
/// change, the fine picture once neither has changed for [`SETTLE`], and
/// while one run converges a new picture (at the size last asked) at most
/// every [`CONVERGING_REFRESH`].
#[derive(Debug, Default)]
pub struct Refinement {
    /// The snapshot and room revision last asked for.
    shown: Option<(Arc<Snapshot>, u64)>,
    changed_at: Option<Instant>,
    requested_at: Option<Instant>,
    fine_requested: bool,
}

impl Refinement {
    /// The size to render now for `snapshot` and room `revision`, if a
    /// picture is due.
    pub fn due(
        &mut self,
        snapshot: &Arc<Snapshot>,
        revision: u64,
        now: Instant,
    ) -> Option<[u32; 2]> {
        let Some((shown, shown_revision)) = &self.shown else {
            return Some(self.changed(snapshot, revision, now));
        };
        if *shown_revision != revision || shown.generation != snapshot.generation {
            return Some(self.changed(snapshot, revision, now));
        }
        let still = self.changed_at.is_some_and(|t| now - t >= SETTLE);
        if still && !self.fine_requested {
            self.fine_requested = true;
            self.shown = Some((snapshot.clone(), revision));
            self.requested_at = Some(now);
            return Some(FINE_SIZE);
        }
        let newer = !Arc::ptr_eq(shown, snapshot);
        let refresh = self
            .requested_at
            .is_none_or(|t| now - t >= CONVERGING_REFRESH);
        if newer && refresh {
            self.shown = Some((snapshot.clone(), revision));
            self.requested_at = Some(now);
            return Some(if self.fine_requested {
                FINE_SIZE
            } else {
                DRAFT_SIZE
            });
        }
        None
    }

    fn changed(&mut self, snapshot: &Arc<Snapshot>, revision: u64, now: Instant) -> [u32; 2] {
        self.shown = Some((snapshot.clone(), revision));
        self.changed_at = Some(now);
        self.requested_at = Some(now);
        self.fine_requested = false;
        DRAFT_SIZE
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

/// A task area's EN 12464-1 requirement on the work plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TaskTarget {
    pub name: &'static str,
    /// Maintained illuminance Em (lx) the average must reach.
    pub e_m_lx: f64,
    /// Least uniformity U0 = Emin / Eavg.
    pub u0: f64,
}

/// EN 12464-1:2011 (Em and U0 unchanged for these in the 2021 edition),
/// as commonly quoted from its tables; reference numbers of 2011:
/// 5.1.1 circulation areas and corridors 100 lx / 0.40; 5.1.2 stairs,
/// escalators 100 lx / 0.40; 5.4.1 store and stock rooms 100 lx / 0.40;
/// 5.4.2 dispatch, packing and handling areas 300 lx / 0.60; 5.26.1
/// filing, copying 300 lx / 0.40; 5.26.2 writing, typing, reading, data
/// processing 500 lx / 0.60; 5.26.3 technical drawing 750 lx / 0.70;
/// 5.26.5 conference and meeting rooms 500 lx / 0.60; 5.26.6 reception
/// desk 300 lx / 0.60; 5.26.7 archives 200 lx / 0.40; 5.36.2 classrooms
/// 300 lx / 0.60. Em is maintained: a room file's `flux_factor` carries
/// the maintenance factor.
pub const TASK_TARGETS: [TaskTarget; 11] = [
    TaskTarget {
        name: "Corridors, circulation areas",
        e_m_lx: 100.0,
        u0: 0.40,
    },
    TaskTarget {
        name: "Stairs, escalators",
        e_m_lx: 100.0,
        u0: 0.40,
    },
    TaskTarget {
        name: "Warehouse: store and stock rooms",
        e_m_lx: 100.0,
        u0: 0.40,
    },
    TaskTarget {
        name: "Warehouse: dispatch, packing, handling",
        e_m_lx: 300.0,
        u0: 0.60,
    },
    TaskTarget {
        name: "Archives",
        e_m_lx: 200.0,
        u0: 0.40,
    },
    TaskTarget {
        name: "Offices: filing, copying",
        e_m_lx: 300.0,
        u0: 0.40,
    },
    TaskTarget {
        name: "Offices: writing, reading, data processing",
        e_m_lx: 500.0,
        u0: 0.60,
    },
    TaskTarget {
        name: "Offices: technical drawing",
        e_m_lx: 750.0,
        u0: 0.70,
    },
    TaskTarget {
        name: "Conference and meeting rooms",
        e_m_lx: 500.0,
        u0: 0.60,
    },
    TaskTarget {
        name: "Reception desk",
        e_m_lx: 300.0,
        u0: 0.60,
    },
    TaskTarget {
        name: "Classrooms",
        e_m_lx: 300.0,
        u0: 0.60,
    },
];

impl TaskTarget {
    /// Whether the work plane meets it: Eavg ≥ Em and U0 ≥ the target's.
    pub fn met_by(&self, figures: &IlluminanceFigures) -> bool {
        figures.e_avg_lx >= self.e_m_lx && figures.u0 >= self.u0
    }

    /// The target a room file's name suggests (office, corridor, meeting).
    pub fn for_room(name: &str) -> usize {
        let name = name.to_lowercase();
        let pick = |needle: &str| TASK_TARGETS.iter().position(|t| t.name.contains(needle));
        let found = if name.contains("corridor") {
            pick("Corridors")
        } else if name.contains("meeting") || name.contains("conference") {
            pick("Conference")
        } else if name.contains("warehouse") || name.contains("store") {
            pick("store and stock")
        } else {
            pick("writing")
        };
        found.unwrap_or(0)
    }
}

/// A round step (1, 2 or 5 × 10ⁿ) near `rough`.
pub fn nice_step(rough: f64) -> f64 {
    if !(rough > 0.0 && rough.is_finite()) {
        return 1.0;
    }
    let p = 10f64.powf(rough.log10().floor());
    let m = rough / p;
    let k = if m < 1.5 {
        1.0
    } else if m < 3.5 {
        2.0
    } else if m < 7.5 {
        5.0
    } else {
        10.0
    };
    k * p
}

/// The top of a linear lux scale and its tick step: a round number above
/// the 99th percentile of `lux` (negative values, luminaires, left out),
/// as `lucerna render`'s false-colour picture.
pub fn lux_scale(lux: impl Iterator<Item = f64>) -> (f64, f64) {
    let mut lit: Vec<f64> = lux.filter(|v| *v >= 0.0 && v.is_finite()).collect();
    lit.sort_by(f64::total_cmp);
    let p99 = lit
        .get(lit.len().saturating_sub(1) * 99 / 100)
        .copied()
        .unwrap_or(1.0)
        .max(1e-3);
    let step = nice_step(p99 / 5.0);
    ((p99 / step).ceil().max(1.0) * step, step)
}
