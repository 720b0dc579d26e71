//! The simulation on its own worker thread: commands in, snapshots out.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::mpsc::{Receiver, RecvTimeoutError, Sender, TryRecvError, channel};
use std::sync::{Arc, Condvar, Mutex, MutexGuard, PoisonError};
use std::thread::JoinHandle;
use std::time::{Duration, Instant};

use lucerna_gpu::{BackendRequest, GpuContext};
use lucerna_scene::Scene;

use crate::run::resolve_backend;
use crate::snapshot::{RunState, Snapshot, StopReason};
use crate::{Luminaire, Run, SimulationError, SimulationSettings};

enum Command {
    Edit(Box<Scene>, PathBuf, u64),
    /// A luminaire its caller has prepared already (a bake loads it first).
    Prepared(Arc<Luminaire>, u64),
    Settings(SimulationSettings, u64),
    Pause,
    Resume,
    /// The same scene and settings from zero photons.
    Restart(u64),
    Finish,
    Cancel,
    Quit,
}

/// What the worker shares with its readers.
#[derive(Debug, Default)]
struct Shared {
    latest: Mutex<Published>,
    changed: Condvar,
}

impl Shared {
    fn lock(&self) -> MutexGuard<'_, Published> {
        self.latest.lock().unwrap_or_else(PoisonError::into_inner)
    }
}

/// The newest snapshot and failure, and whether the worker still runs.
#[derive(Debug, Default, Clone)]
pub struct Published {
    pub snapshot: Option<Arc<Snapshot>>,
    /// The last failure (a scene that cannot be prepared, a GPU error)
    /// and the generation it belongs to; cleared by the next snapshot.
    pub error: Option<(u64, Arc<SimulationError>)>,
    /// Set when the worker thread has ended.
    pub gone: bool,
    /// Edited scenes the worker has tessellated and built a BVH for: a
    /// burst of edits faster than builds is built a few times, not once
    /// per edit.
    pub scenes_built: u64,
}

type Notify = Box<dyn Fn() + Send>;

/// How a simulation paces its work: an editor wants short iterations (an
/// edit waits for at most one) and frequent snapshots; a headless bake
/// long iterations (less per-iteration overhead) and a snapshot now and
/// then for its progress bar.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Pace {
    /// Wall time one iteration aims at.
    pub iteration: Duration,
    /// Least time between two snapshots; they also take at most a fifth
    /// of the worker's time.
    pub snapshot_interval: Duration,
}

impl Pace {
    /// For an editor: 50 ms iterations, snapshots as often as they cost a
    /// fifth of the time.
    pub const INTERACTIVE: Pace = Pace {
        iteration: Duration::from_millis(50),
        snapshot_interval: Duration::from_millis(50),
    };
    /// For a bake: 250 ms iterations, a snapshot a second.
    pub const BATCH: Pace = Pace {
        iteration: Duration::from_millis(250),
        snapshot_interval: Duration::from_secs(1),
    };
}

/// A luminaire simulation running on its own thread. Every edit restarts
/// it at once (iterations of the old scene are discarded); [`latest`]
/// hands out the newest [`Snapshot`] without waiting for tracing.
///
/// [`latest`]: Simulation::latest
pub struct Simulation {
    commands: Sender<Command>,
    shared: Arc<Shared>,
    generation: u64,
    /// The newest generation sent, read by the worker to cut short an
    /// iteration that new settings or an edit have made stale.
    newest: Arc<AtomicU64>,
    /// The generation of the newest edit, read by the worker to stop
    /// building (or finding the symmetry of) a scene a newer edit has
    /// replaced. New settings or a restart do not replace the scene: a
    /// build they interrupted would never be made again.
    newest_edit: Arc<AtomicU64>,
    settings: SimulationSettings,
    thread: Option<JoinHandle<()>>,
}

impl std::fmt::Debug for Simulation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Simulation")
            .field("generation", &self.generation)
            .field("settings", &self.settings)
            .finish_non_exhaustive()
    }
}

impl Simulation {
    /// Starts simulating `scene` (its relative paths from `scene_dir`).
    /// `on_update` is called from the worker after each new snapshot or
    /// error (an editor passes its repaint request).
    pub fn start(
        scene: Scene,
        scene_dir: &Path,
        settings: SimulationSettings,
        on_update: impl Fn() + Send + 'static,
    ) -> Result<Simulation, SimulationError> {
        Simulation::spawn(
            Command::Edit(Box::new(scene), scene_dir.to_path_buf(), 0),
            settings,
            Pace::INTERACTIVE,
            on_update,
        )
    }

    /// Starts on a luminaire already prepared (not built again), paced by
    /// `pace`: what a bake does.
    pub fn start_prepared(
        luminaire: Arc<Luminaire>,
        settings: SimulationSettings,
        pace: Pace,
        on_update: impl Fn() + Send + 'static,
    ) -> Result<Simulation, SimulationError> {
        Simulation::spawn(Command::Prepared(luminaire, 0), settings, pace, on_update)
    }

    fn spawn(
        first: Command,
        settings: SimulationSettings,
        pace: Pace,
        on_update: impl Fn() + Send + 'static,
    ) -> Result<Simulation, SimulationError> {
        settings.validate()?;
        let (commands, inbox) = channel();
        let shared = Arc::new(Shared::default());
        let worker_shared = shared.clone();
        let newest = Arc::new(AtomicU64::new(0));
        let newest_edit = Arc::new(AtomicU64::new(0));
        let (worker_newest, worker_newest_edit) = (newest.clone(), newest_edit.clone());
        commands
            .send(first)
            .map_err(|_| SimulationError::WorkerGone)?;
        let thread = std::thread::Builder::new()
            .name("lucerna-simulation".to_owned())
            .spawn(move || {
                Worker::new(
                    settings,
                    pace,
                    worker_shared.clone(),
                    worker_newest,
                    worker_newest_edit,
                    Box::new(on_update),
                )
                .serve(inbox);
                worker_shared.lock().gone = true;
                worker_shared.changed.notify_all();
            })
            .map_err(|_| SimulationError::WorkerGone)?;
        Ok(Simulation {
            commands,
            shared,
            generation: 0,
            newest,
            newest_edit,
            settings,
            thread: Some(thread),
        })
    }

    fn send(&self, command: Command) {
        // A worker that has gone says so through `published().gone`.
        let _ = self.commands.send(command);
    }

    /// Restarts on an edited scene; returns the generation whose snapshots
    /// will show it.
    pub fn edit(&mut self, scene: Scene, scene_dir: &Path) -> u64 {
        self.generation += 1;
        self.newest.store(self.generation, Ordering::SeqCst);
        self.newest_edit.store(self.generation, Ordering::SeqCst);
        self.send(Command::Edit(
            Box::new(scene),
            scene_dir.to_path_buf(),
            self.generation,
        ));
        self.generation
    }

    /// New settings: a new resolution, backend, filter, symmetry or grid
    /// restarts the run; a new stopping rule alone keeps its photons.
    pub fn set_settings(&mut self, settings: SimulationSettings) -> Result<u64, SimulationError> {
        settings.validate()?;
        self.settings = settings;
        self.generation += 1;
        self.newest.store(self.generation, Ordering::SeqCst);
        self.send(Command::Settings(settings, self.generation));
        Ok(self.generation)
    }

    pub fn settings(&self) -> &SimulationSettings {
        &self.settings
    }

    /// The generation of the last edit or settings change.
    pub fn generation(&self) -> u64 {
        self.generation
    }

    pub fn pause(&self) {
        self.send(Command::Pause);
    }

    /// Starts the run again from zero photons (same scene and settings);
    /// returns the new generation.
    pub fn restart(&mut self) -> u64 {
        self.generation += 1;
        self.newest.store(self.generation, Ordering::SeqCst);
        self.send(Command::Restart(self.generation));
        self.generation
    }

    pub fn resume(&self) {
        self.send(Command::Resume);
    }

    /// Stops tracing and publishes a final snapshot (an automatic filter
    /// rule chosen afresh), as when the stopping rule is met.
    pub fn finish(&self) {
        self.send(Command::Finish);
    }

    /// Stops tracing without a final export: the last snapshot stays, marked
    /// cancelled. An edit or new settings start again.
    pub fn cancel(&self) {
        self.send(Command::Cancel);
    }

    /// The newest snapshot: an `Arc` clone under a short lock.
    pub fn latest(&self) -> Option<Arc<Snapshot>> {
        self.shared.lock().snapshot.clone()
    }

    /// The newest snapshot, the last error and whether the worker ended.
    pub fn published(&self) -> Published {
        self.shared.lock().clone()
    }

    /// Waits up to `timeout` for something newer than `seen` (a snapshot
    /// that is not `seen`, an error, or the worker's end).
    pub fn wait_for_update(&self, seen: Option<&Arc<Snapshot>>, timeout: Duration) -> Published {
        let deadline = Instant::now() + timeout;
        let mut published = self.shared.lock();
        loop {
            let newer = match (&published.snapshot, seen) {
                (Some(s), Some(old)) => !Arc::ptr_eq(s, old),
                (Some(_), None) => true,
                (None, _) => false,
            };
            if newer || published.error.is_some() || published.gone {
                return published.clone();
            }
            let now = Instant::now();
            if now >= deadline {
                return published.clone();
            }
            published = self
                .shared
                .changed
                .wait_timeout(published, deadline - now)
                .unwrap_or_else(PoisonError::into_inner)
                .0;
        }
    }

    /// Waits for the final snapshot of the current generation (the
    /// stopping rule met, or [`finish`](Simulation::finish) called), or an
    /// error of it.
    pub fn wait_until_finished(&self) -> Result<Arc<Snapshot>, Arc<SimulationError>> {
        let mut published = self.shared.lock();
        loop {
            if let Some((generation, e)) = &published.error
                && *generation >= self.generation
            {
                return Err(e.clone());
            }
            if let Some(s) = &published.snapshot
                && s.generation >= self.generation
                && matches!(s.state, RunState::Finished(_))
            {
                return Ok(s.clone());
            }
            if published.gone {
                return Err(Arc::new(SimulationError::WorkerGone));
            }
            published = self
                .shared
                .changed
                .wait(published)
                .unwrap_or_else(PoisonError::into_inner);
        }
    }
}

impl Drop for Simulation {
    fn drop(&mut self) {
        self.send(Command::Quit);
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}

/// The worker's own state.
struct Worker {
    settings: SimulationSettings,
    pace: Pace,
    shared: Arc<Shared>,
    newest: Arc<AtomicU64>,
    newest_edit: Arc<AtomicU64>,
    notify: Notify,
    generation: u64,
    luminaire: Option<Arc<Luminaire>>,
    run: Option<Run>,
    /// The backend `Auto` resolved to on the first scene, kept for edits.
    resolved: Option<(Option<GpuContext>, String)>,
    paused: bool,
    finished: bool,
    /// When and how long the last snapshot took to build.
    last_snapshot: Option<(Instant, Duration)>,
    /// Finds edited luminaires' symmetry while they are traced.
    symmetry: SymmetryFinder,
}

/// What the drain of the inbox left to do before tracing on.
#[derive(Default)]
struct Pending {
    /// The newest edit: the ones before it are dropped unbuilt.
    edit: Option<(Box<Scene>, PathBuf)>,
    /// The run must start again (new scene or settings).
    restart: bool,
}

impl Worker {
    fn new(
        settings: SimulationSettings,
        pace: Pace,
        shared: Arc<Shared>,
        newest: Arc<AtomicU64>,
        newest_edit: Arc<AtomicU64>,
        notify: Notify,
    ) -> Worker {
        Worker {
            settings,
            pace,
            shared,
            symmetry: SymmetryFinder::start(newest_edit.clone()),
            newest,
            newest_edit,
            notify,
            generation: 0,
            luminaire: None,
            run: None,
            resolved: None,
            paused: false,
            finished: false,
            last_snapshot: None,
        }
    }

    fn active(&self) -> bool {
        self.run.is_some() && !self.paused && !self.finished
    }

    fn serve(&mut self, inbox: Receiver<Command>) {
        loop {
            // Drain every pending command before tracing on, keeping only
            // the newest edit: a drag sends one a frame, and building each
            // (tessellation, BVH) would keep the worker from ever tracing
            // the newest.
            let mut pending = Pending::default();
            loop {
                let waiting = pending.edit.is_some() || pending.restart;
                let command = if self.active() || waiting {
                    match inbox.try_recv() {
                        Ok(c) => c,
                        Err(TryRecvError::Empty) => break,
                        Err(TryRecvError::Disconnected) => return,
                    }
                } else {
                    match inbox.recv_timeout(Duration::from_millis(200)) {
                        Ok(c) => c,
                        // Idle (paused, finished): the symmetry found
                        // meanwhile still reaches the shown snapshot.
                        Err(RecvTimeoutError::Timeout) => {
                            self.apply_found_symmetry(true);
                            continue;
                        }
                        Err(RecvTimeoutError::Disconnected) => return,
                    }
                };
                if !self.handle(command, &mut pending) {
                    return;
                }
            }
            if let Some((scene, dir)) = pending.edit.take() {
                let generation = self.generation;
                let newest_edit = self.newest_edit.clone();
                let stale = move || newest_edit.load(Ordering::SeqCst) > generation;
                let previous = self.luminaire.clone();
                match Luminaire::for_edit(*scene, &dir, &stale, previous.as_deref()) {
                    Ok(Some(l)) => {
                        self.shared.lock().scenes_built += 1;
                        let l = Arc::new(l);
                        self.symmetry.find(generation, l.clone());
                        self.luminaire = Some(l);
                        pending.restart = true;
                    }
                    // A newer edit is in the inbox: build that one.
                    Ok(None) => continue,
                    Err(e) => {
                        self.fail(e);
                        continue;
                    }
                }
            }
            if pending.restart {
                self.restart();
            }
            self.trace_once();
        }
    }

    /// Applies a command, or notes what it asks of the next build and
    /// restart; `false` to quit.
    fn handle(&mut self, command: Command, pending: &mut Pending) -> bool {
        if matches!(
            command,
            Command::Edit(..) | Command::Prepared(..) | Command::Settings(..)
        ) {
            // A new generation: the last one's failure no longer stands.
            self.shared.lock().error = None;
        }
        match command {
            Command::Edit(scene, dir, generation) => {
                self.generation = generation;
                self.run = None;
                pending.edit = Some((scene, dir));
            }
            Command::Prepared(luminaire, generation) => {
                self.generation = generation;
                self.run = None;
                pending.edit = None;
                self.luminaire = Some(luminaire);
                pending.restart = true;
            }
            Command::Settings(settings, generation) => {
                self.generation = generation;
                let only_stop = SimulationSettings {
                    stop: self.settings.stop,
                    ..settings
                } == self.settings;
                if settings.backend != self.settings.backend {
                    self.resolved = None;
                }
                self.settings = settings;
                match (&mut self.run, only_stop) {
                    (Some(run), true) if !pending.restart && pending.edit.is_none() => {
                        run.set_stopping_rule(settings.stop);
                        self.finished = false;
                    }
                    _ => pending.restart = true,
                }
            }
            Command::Restart(generation) => {
                self.generation = generation;
                self.shared.lock().error = None;
                pending.restart = true;
            }
            Command::Pause => {
                self.paused = true;
                self.publish(RunState::Paused, false);
            }
            Command::Resume => {
                self.paused = false;
            }
            Command::Finish => {
                self.flush(pending);
                if self.run.is_some() && !self.finished {
                    self.finished = true;
                    self.publish(RunState::Finished(StopReason::Requested), true);
                }
            }
            Command::Cancel => {
                // An edit still to be built would start the run again.
                *pending = Pending::default();
                if self.run.take().is_some() {
                    let mut published = self.shared.lock();
                    if let Some(last) = &published.snapshot {
                        published.snapshot = Some(Arc::new(Snapshot {
                            state: RunState::Finished(StopReason::Cancelled),
                            ..(**last).clone()
                        }));
                    }
                    drop(published);
                    self.shared.changed.notify_all();
                    (self.notify)();
                }
            }
            Command::Quit => return false,
        }
        true
    }

    /// Builds and restarts what `pending` holds now (before a command that
    /// acts on the run, such as Finish).
    fn flush(&mut self, pending: &mut Pending) {
        if let Some((scene, dir)) = pending.edit.take() {
            let previous = self.luminaire.clone();
            match Luminaire::for_edit(*scene, &dir, &|| false, previous.as_deref()) {
                Ok(Some(l)) => {
                    self.shared.lock().scenes_built += 1;
                    let l = Arc::new(l);
                    self.symmetry.find(self.generation, l.clone());
                    self.luminaire = Some(l);
                    pending.restart = true;
                }
                Ok(None) => {}
                Err(e) => {
                    self.fail(e);
                    pending.restart = false;
                }
            }
        }
        if std::mem::take(&mut pending.restart) {
            self.restart();
        }
    }

    /// A new run of the current luminaire and settings at zero photons.
    fn restart(&mut self) {
        self.run = None;
        self.finished = false;
        self.last_snapshot = None;
        let Some(luminaire) = self.luminaire.clone() else {
            return;
        };
        let started = (|| {
            if self.resolved.is_none() {
                self.resolved = Some(resolve_backend(
                    self.settings.backend,
                    &luminaire,
                    &self.settings,
                )?);
            }
            let (context, reason) = self
                .resolved
                .clone()
                .unwrap_or((None, "requested".to_owned()));
            let mut run = match context {
                Some(context) => Run::on_gpu(luminaire, self.settings, context, reason)?,
                None => Run::new(
                    luminaire,
                    SimulationSettings {
                        backend: BackendRequest::Cpu,
                        ..self.settings
                    },
                )
                .map(|mut r| {
                    r.set_backend_reason(reason);
                    r
                })?,
            };
            run.set_iteration_time(self.pace.iteration);
            // A small first iteration, so that the first snapshot of an
            // edit comes within milliseconds; the next ones grow to the
            // pace.
            run.set_first_iteration_photons(FIRST_ITERATION_PHOTONS);
            Ok::<_, SimulationError>(run)
        })();
        match started {
            Ok(run) => self.run = Some(run),
            Err(e) => self.fail(e),
        }
    }

    fn fail(&mut self, error: SimulationError) {
        self.run = None;
        self.shared.lock().error = Some((self.generation, Arc::new(error)));
        self.shared.changed.notify_all();
        (self.notify)();
    }

    /// The luminaire's symmetry, once found, pools the current run's
    /// photons; with `republish`, a new snapshot shows it at once.
    fn apply_found_symmetry(&mut self, republish: bool) {
        let (Some(run), Some(luminaire)) = (&mut self.run, &self.luminaire) else {
            return;
        };
        let Some(found) = luminaire.symmetry() else {
            return;
        };
        let before = run.pooled_symmetry();
        run.set_symmetry(found.symmetry);
        if republish && run.pooled_symmetry() != before {
            let state = if self.paused {
                RunState::Paused
            } else {
                RunState::Tracing
            };
            self.publish(state, false);
        }
    }

    fn trace_once(&mut self) {
        self.apply_found_symmetry(false);
        let Some(run) = &mut self.run else { return };
        // An edit or new settings make this iteration stale: it stops
        // within a chunk of photons (about a millisecond) instead of
        // running to its 50 ms. Not the first (small) one: every scene
        // built is shown once, however fast the edits come.
        let (newest, generation) = (self.newest.clone(), self.generation);
        let first = self.last_snapshot.is_none();
        match run.step_unless(&move || !first && newest.load(Ordering::SeqCst) > generation) {
            Ok(Some(_)) => {}
            Ok(None) => return,
            Err(e) => {
                self.fail(e);
                return;
            }
        }
        if let Some(reason) = run.stop_reason() {
            self.finished = true;
            self.publish(RunState::Finished(reason), true);
            return;
        }
        // Snapshots (filter, table, figures) take at most about a fifth of
        // the worker's time; the first after a restart comes at once.
        let interval = self.pace.snapshot_interval;
        let due = self
            .last_snapshot
            .is_none_or(|(at, cost)| at.elapsed() >= (cost * 4).max(interval));
        if due {
            self.publish(RunState::Tracing, false);
        }
    }

    fn publish(&mut self, state: RunState, final_export: bool) {
        if final_export && let Some(luminaire) = &self.luminaire {
            // A final result pools over the symmetry whenever the run
            // ended: found now if it was not yet.
            luminaire.find_symmetry();
            self.apply_found_symmetry(false);
        }
        let Some(run) = &mut self.run else { return };
        let start = Instant::now();
        let snapshot = run.snapshot(self.generation, state, final_export);
        self.last_snapshot = Some((start, start.elapsed()));
        {
            let mut published = self.shared.lock();
            published.snapshot = Some(Arc::new(snapshot));
            published.error = None;
        }
        self.shared.changed.notify_all();
        (self.notify)();
    }
}

/// Photons in a run's first iteration: about 2 ms on two cores.
const FIRST_ITERATION_PHOTONS: u32 = 8192;

/// How long an edited luminaire must stay the newest before its symmetry
/// is looked for: during a drag (an edit a frame) none is, and the search
/// (150 ms of the parabolic spot) would take the tracer's cores.
const SYMMETRY_SETTLE: Duration = Duration::from_millis(100);

/// A thread that finds edited luminaires' symmetry, newest request only,
/// once it has settled; the result lands in the luminaire
/// ([`Luminaire::find_symmetry`]), where the worker picks it up.
struct SymmetryFinder {
    requests: Option<Sender<(u64, Arc<Luminaire>)>>,
    thread: Option<JoinHandle<()>>,
}

impl SymmetryFinder {
    fn start(newest_edit: Arc<AtomicU64>) -> SymmetryFinder {
        let (requests, inbox) = channel::<(u64, Arc<Luminaire>)>();
        let thread = std::thread::Builder::new()
            .name("lucerna-symmetry".to_owned())
            .spawn(move || {
                while let Ok(mut request) = inbox.recv() {
                    // The newest request that stays the newest for a while.
                    loop {
                        match inbox.recv_timeout(SYMMETRY_SETTLE) {
                            Ok(newer) => request = newer,
                            Err(RecvTimeoutError::Timeout) => break,
                            Err(RecvTimeoutError::Disconnected) => return,
                        }
                    }
                    let (generation, luminaire) = request;
                    if newest_edit.load(Ordering::SeqCst) <= generation {
                        luminaire.find_symmetry();
                    }
                }
            })
            .ok();
        SymmetryFinder {
            requests: thread.as_ref().map(|_| requests),
            thread,
        }
    }

    /// Finds `luminaire`'s symmetry (of `generation`) unless a newer
    /// request comes first; found on the spot if the thread could not be
    /// started.
    fn find(&self, generation: u64, luminaire: Arc<Luminaire>) {
        if luminaire.symmetry().is_some() {
            return;
        }
        match &self.requests {
            Some(r) => {
                let _ = r.send((generation, luminaire));
            }
            None => {
                luminaire.find_symmetry();
            }
        }
    }
}

impl Drop for SymmetryFinder {
    fn drop(&mut self) {
        self.requests = None;
        if let Some(thread) = self.thread.take() {
            let _ = thread.join();
        }
    }
}
