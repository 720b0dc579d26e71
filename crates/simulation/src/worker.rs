//! The simulation on its own worker thread: commands in, snapshots out.

use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, Sender, TryRecvError, channel};
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
        commands
            .send(first)
            .map_err(|_| SimulationError::WorkerGone)?;
        let thread = std::thread::Builder::new()
            .name("lucerna-simulation".to_owned())
            .spawn(move || {
                Worker::new(settings, pace, worker_shared.clone(), Box::new(on_update))
                    .serve(inbox);
                worker_shared.lock().gone = true;
                worker_shared.changed.notify_all();
            })
            .map_err(|_| SimulationError::WorkerGone)?;
        Ok(Simulation {
            commands,
            shared,
            generation: 0,
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
}

impl Worker {
    fn new(
        settings: SimulationSettings,
        pace: Pace,
        shared: Arc<Shared>,
        notify: Notify,
    ) -> Worker {
        Worker {
            settings,
            pace,
            shared,
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
            // Drain every pending command before tracing on: an edit
            // replaces the run before another stale iteration starts.
            loop {
                let command = if self.active() {
                    match inbox.try_recv() {
                        Ok(c) => c,
                        Err(TryRecvError::Empty) => break,
                        Err(TryRecvError::Disconnected) => return,
                    }
                } else {
                    match inbox.recv() {
                        Ok(c) => c,
                        Err(_) => return,
                    }
                };
                if !self.handle(command) {
                    return;
                }
            }
            self.trace_once();
        }
    }

    /// Applies a command; `false` to quit.
    fn handle(&mut self, command: Command) -> bool {
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
                match Luminaire::new(*scene, &dir) {
                    Ok(l) => {
                        self.luminaire = Some(Arc::new(l));
                        self.restart();
                    }
                    Err(e) => self.fail(e),
                }
            }
            Command::Prepared(luminaire, generation) => {
                self.generation = generation;
                self.luminaire = Some(luminaire);
                self.restart();
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
                    (Some(run), true) => {
                        run.set_stopping_rule(settings.stop);
                        self.finished = false;
                    }
                    _ => self.restart(),
                }
            }
            Command::Pause => {
                self.paused = true;
                self.publish(RunState::Paused, false);
            }
            Command::Resume => {
                self.paused = false;
            }
            Command::Finish => {
                if self.run.is_some() && !self.finished {
                    self.finished = true;
                    self.publish(RunState::Finished(StopReason::Requested), true);
                }
            }
            Command::Cancel => {
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

    fn trace_once(&mut self) {
        let Some(run) = &mut self.run else { return };
        if let Err(e) = run.step() {
            self.fail(e);
            return;
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
