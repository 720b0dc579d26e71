//! The live run: the simulation of the last valid scene, its settings, the
//! coarse resolution a drag previews at, and the newest snapshot shown.

use std::path::Path;
use std::sync::Arc;

use lucerna_scene::Scene;
use lucerna_simulation::{Simulation, SimulationSettings, Snapshot};

use crate::error_text::error_chain;
use crate::pacer::RepaintPacer;

pub(crate) struct LiveRun {
    /// The last valid scene handed to the simulation.
    sent: Option<Scene>,
    sim: Option<Simulation>,
    /// The settings chosen in the simulation panel.
    pub settings: SimulationSettings,
    /// The simulation runs at [`coarse_preview`] of `settings` while a
    /// pointer drag edits the scene, and returns to them when it ends.
    coarse: bool,
    pub paused: bool,
    /// The newest snapshot, refreshed at the start of each frame.
    pub snapshot: Option<Arc<Snapshot>>,
    pub sim_error: Option<String>,
    /// Paces the repaints the simulation's snapshots ask for.
    pub pacer: Arc<RepaintPacer>,
}

impl LiveRun {
    pub fn new(settings: SimulationSettings) -> Self {
        LiveRun {
            sent: None,
            sim: None,
            settings,
            coarse: false,
            paused: false,
            snapshot: None,
            sim_error: None,
            pacer: Arc::new(RepaintPacer::default()),
        }
    }

    pub fn simulation(&self) -> Option<&Simulation> {
        self.sim.as_ref()
    }

    pub fn is_coarse_preview(&self) -> bool {
        self.coarse
    }

    /// Takes what the worker published since the last frame.
    pub fn refresh(&mut self) {
        let Some(sim) = &self.sim else { return };
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

    /// Runs the valid `scene` (relative paths from `dir`) unless the light
    /// is what already runs: labels (name, manufacturer, export keywords)
    /// are not light, and an export takes them from the edited scene. A
    /// pointer drag's edit (`dragging`) runs at the coarse preview
    /// resolution until [`Self::end_coarse_preview`].
    pub fn send(&mut self, scene: &Scene, dir: &Path, dragging: bool, ctx: Option<&egui::Context>) {
        if self.sent.as_ref().is_some_and(|s| s.same_light(scene)) {
            return;
        }
        let scene = scene.clone();
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
                sim.edit(scene, dir);
            }
            None => self.start(scene, dir, ctx),
        }
    }

    /// The scene's relative paths resolve from elsewhere now (saved in
    /// another folder): the next [`Self::send`] runs it again.
    pub fn forget_sent(&mut self) {
        self.sent = None;
    }

    /// Back to the chosen resolution once the drag that previewed at the
    /// coarse one has ended.
    pub fn end_coarse_preview(&mut self) {
        if !std::mem::take(&mut self.coarse) {
            return;
        }
        if let Some(sim) = &mut self.sim
            && let Err(e) = sim.set_settings(self.settings)
        {
            self.sim_error = Some(error_chain(&e));
        }
    }

    pub fn pause(&mut self) {
        if let Some(sim) = &self.sim {
            sim.pause();
        }
        self.paused = true;
    }

    pub fn resume(&mut self) {
        if let Some(sim) = &self.sim {
            sim.resume();
        }
        self.paused = false;
    }

    /// New chosen settings; refused ones are reported and change nothing.
    pub fn set_settings(&mut self, settings: SimulationSettings) {
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

    pub fn restart(&mut self) {
        if let Some(sim) = &mut self.sim {
            self.pacer.reset();
            sim.restart();
        }
    }

    /// A new document gets a fresh run (generation 0).
    pub fn reset(&mut self) {
        self.sim = None;
        self.coarse = false;
        self.sent = None;
        self.snapshot = None;
        self.sim_error = None;
    }

    fn start(&mut self, scene: Scene, dir: &Path, ctx: Option<&egui::Context>) {
        // A drag's coarse preview must not wait for its resolution's
        // first-time tables (250 ms in the window, measured).
        let coarse = coarse_preview(self.settings);
        let _ = std::thread::Builder::new()
            .name("lucerna-prepare".to_owned())
            .spawn(move || {
                crate::lower_this_threads_priority();
                lucerna_simulation::prepare_snapshots(&coarse);
            });
        let ctx = ctx.cloned();
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
