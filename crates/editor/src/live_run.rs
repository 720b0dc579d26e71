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

/// The editor's simulation settings until the user chooses others: 64
/// texels per cube-face edge (a 4° beam to within 2 % of its peak), the
/// rest the library's defaults.
pub fn editor_settings() -> SimulationSettings {
    SimulationSettings {
        resolution: 64,
        ..SimulationSettings::default()
    }
}

/// Texels per cube-face edge of a drag's preview at most: 6 × 64² texels
/// tabulate in a few milliseconds and resolve the parabolic spot's 4°
/// beam, whose peak a 32² preview showed 73 % low and its beam twice as
/// wide.
const MAX_PREVIEW_RESOLUTION: u32 = 64;

/// `settings` for previewing a drag: the chosen resolution, at most
/// [`MAX_PREVIEW_RESOLUTION`].
pub(crate) fn coarse_preview(settings: SimulationSettings) -> SimulationSettings {
    SimulationSettings {
        resolution: settings.resolution.min(MAX_PREVIEW_RESOLUTION),
        ..settings
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lucerna_scene::Shape;
    use lucerna_simulation::{Luminaire, Run, RunState, StoppingRule, bake};

    /// The parabolic spot at f = 30 mm, as a drag passes through it.
    fn spot_at_30_mm() -> (Scene, std::path::PathBuf) {
        let path = Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../assets/luminaires/parabolic_spot.toml");
        let mut scene = lucerna_scene::load_scene(&path).expect("example");
        let Shape::Paraboloid(p) = &mut scene.parts[0].shape else {
            panic!("the spot's reflector is a paraboloid");
        };
        p.focal_length = 0.030;
        (scene, path.parent().expect("folder").to_owned())
    }

    #[test]
    fn a_drag_preview_of_a_narrow_beam_reads_its_converged_peak_and_beam() {
        let (scene, dir) = spot_at_30_mm();
        // Mid-drag: the luminaire as an edit builds it (no symmetry found
        // yet), the preview's settings, the worker's first iteration.
        let edited = Luminaire::for_edit(scene.clone(), &dir, &|| false, None)
            .expect("builds")
            .expect("not stale");
        let mut run = Run::new(Arc::new(edited), coarse_preview(editor_settings())).expect("run");
        run.set_first_iteration_photons(8192);
        run.step().expect("traces");
        let shown = run.snapshot(1, RunState::Tracing, false).figures;
        // Converged: 2 M photons at the chosen settings.
        let settings = SimulationSettings {
            stop: StoppingRule {
                photons: Some(2_000_000),
                ..StoppingRule::default()
            },
            ..editor_settings()
        };
        let luminaire = Luminaire::new(scene, &dir).expect("builds");
        let converged = bake(Arc::new(luminaire), settings).expect("bakes");
        let truth = converged.figures;
        let peak = shown.peak_cd / truth.peak_cd;
        assert!(
            (peak - 1.0).abs() < 0.15,
            "peak {} cd, converged {} cd",
            shown.peak_cd,
            truth.peak_cd
        );
        for (plane, (a, b)) in shown
            .beam_angle_deg
            .iter()
            .zip(&truth.beam_angle_deg)
            .enumerate()
        {
            let (a, b) = (a.expect("a beam"), b.expect("a beam"));
            assert!(
                (a - b).abs() < 0.5,
                "beam in plane {plane}: {a}° shown, {b}° converged"
            );
        }
    }
}
