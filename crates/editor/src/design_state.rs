//! The editor's design run: `lucerna design` on the scene being edited,
//! toward a target file or a spec set in the Design pane, varying the
//! parameters and profile points ticked in the scene panel and the
//! profile pane. The design runs on a thread of its own beside the
//! simulation's worker; each better candidate it finds becomes the
//! document's scene (no undo step) and goes to the live run, so the 3D
//! view, the profile and the figures follow it. The end is one undo step
//! from the start scene to the result.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, TryRecvError, channel};
use std::time::{Duration, Instant};

use lucerna_design::{
    Budget, DEFAULT_RESOLUTION, Design, DesignError, DesignRequest, Maximise, Progress, Spec,
    StartScene, Stopped, Target, Variable,
};
use lucerna_scene::Scene;

use crate::state::EditorState;

/// How often an improvement is shown at most: each one restarts the live
/// run, which shares the cores with the design.
const SHOW_EVERY: Duration = Duration::from_millis(1000);

/// Where the light wanted comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum TargetKind {
    /// An IES or EULUMDAT file's distribution.
    #[default]
    File,
    /// Figures: beam, field, cut-off, LOR, UGR, what to maximise.
    Spec,
}

/// The spec as the pane edits it: each term on or off.
#[derive(Debug, Clone, PartialEq)]
pub struct SpecForm {
    pub beam: bool,
    pub beam_angle_deg: f64,
    pub beam_tolerance_deg: f64,
    pub field: bool,
    pub field_angle_max_deg: f64,
    pub cutoff: bool,
    pub cutoff_gamma_deg: f64,
    pub cutoff_max_percent: f64,
    pub lor: bool,
    pub lor_min_percent: f64,
    pub ugr: bool,
    pub ugr_max: f64,
    pub maximise: Option<Maximise>,
    pub cone_half_angle_deg: f64,
}

impl Default for SpecForm {
    fn default() -> Self {
        SpecForm {
            beam: true,
            beam_angle_deg: 24.0,
            beam_tolerance_deg: 1.0,
            field: false,
            field_angle_max_deg: 40.0,
            cutoff: false,
            cutoff_gamma_deg: 60.0,
            cutoff_max_percent: 1.0,
            lor: false,
            lor_min_percent: 85.0,
            ugr: false,
            ugr_max: 19.0,
            maximise: None,
            cone_half_angle_deg: 30.0,
        }
    }
}

impl SpecForm {
    /// The spec file these terms make (README, "Design"): what `lucerna
    /// design --target` reads, and what the pane shows to copy.
    pub fn to_toml(&self) -> String {
        let mut t = String::new();
        if self.beam {
            t += &format!(
                "beam_angle_deg = {:?}\nbeam_tolerance_deg = {:?}\n",
                self.beam_angle_deg, self.beam_tolerance_deg
            );
        }
        if self.field {
            t += &format!("field_angle_max_deg = {:?}\n", self.field_angle_max_deg);
        }
        if self.cutoff {
            t += &format!(
                "cutoff_gamma_deg = {:?}\ncutoff_max_fraction = {:?}\n",
                self.cutoff_gamma_deg,
                self.cutoff_max_percent / 100.0
            );
        }
        if self.lor {
            t += &format!("lor_min_percent = {:?}\n", self.lor_min_percent);
        }
        if self.ugr {
            t += &format!("ugr_max = {:?}\n", self.ugr_max);
        }
        match self.maximise {
            Some(Maximise::Lor) => t += "maximise = \"lor\"\n",
            Some(Maximise::ConeFlux) => {
                t += &format!(
                    "maximise = \"cone_flux\"\ncone_half_angle_deg = {:?}\n",
                    self.cone_half_angle_deg
                );
            }
            None => {}
        }
        t
    }

    /// The spec, checked as a spec file is (contradictions refused).
    pub fn spec(&self) -> Result<Spec, String> {
        Spec::parse(&self.to_toml())
    }
}

/// What the Design pane sets up before Start.
#[derive(Debug, Clone, PartialEq)]
pub struct DesignSetup {
    pub target_kind: TargetKind,
    pub target_file: Option<PathBuf>,
    /// Match the file's candela, not only its shape.
    pub absolute: bool,
    pub spec: SpecForm,
    /// What varies, as `--vary` names it: `PART.FIELD` or
    /// `PART.profile[INDEX]`, in the order of the scene.
    pub vary: Vec<String>,
    pub time_s: f64,
    /// Stop after this many traced candidates (the same design on any
    /// machine), when set.
    pub evaluations: Option<u64>,
    pub seed: u32,
}

impl Default for DesignSetup {
    fn default() -> Self {
        DesignSetup {
            target_kind: TargetKind::File,
            target_file: None,
            absolute: false,
            spec: SpecForm::default(),
            vary: Vec::new(),
            time_s: 120.0,
            evaluations: None,
            seed: 1,
        }
    }
}

impl DesignSetup {
    pub fn is_ticked(&self, vary: &str) -> bool {
        self.vary.iter().any(|v| v == vary)
    }

    /// Ticks or unticks `vary`, keeping the scene's order (part, then a
    /// parameter before the profile's points, points in order).
    pub fn tick(&mut self, vary: &str, on: bool, scene: &Scene) {
        self.vary.retain(|v| v != vary);
        if on {
            self.vary.push(vary.to_owned());
        }
        self.vary.sort_by_key(|v| order_key(v, scene));
    }

    /// The target as the design reads it.
    pub fn target(&self) -> Result<Target, String> {
        match self.target_kind {
            TargetKind::File => {
                let path = self
                    .target_file
                    .as_ref()
                    .ok_or("choose a target file (IES or EULUMDAT) first")?;
                Target::load(path, self.absolute).map_err(|e| e.to_string())
            }
            TargetKind::Spec => self
                .spec
                .spec()
                .map(Target::Spec)
                .map_err(|e| format!("the spec: {e}")),
        }
    }

    /// The command line that runs the same design (`SCENE` where the
    /// scene has no file yet).
    pub fn command_line(&self, scene_path: Option<&std::path::Path>) -> String {
        let scene = scene_path.map_or("SCENE.toml".to_owned(), |p| p.display().to_string());
        let target = match self.target_kind {
            TargetKind::File => self
                .target_file
                .as_ref()
                .map_or("TARGET.ies".to_owned(), |p| p.display().to_string()),
            TargetKind::Spec => "SPEC.toml".to_owned(),
        };
        let mut line = format!(
            "lucerna design {scene} --target {target} --vary {} --seed {}",
            if self.vary.is_empty() {
                "PART.FIELD".to_owned()
            } else {
                self.vary.join(",")
            },
            self.seed
        );
        match self.evaluations {
            Some(n) => line += &format!(" --evaluations {n} --time {}s", self.time_s.round()),
            None => line += &format!(" --time {}s", self.time_s.round()),
        }
        if self.absolute && self.target_kind == TargetKind::File {
            line += " --absolute";
        }
        line + " --out DIR"
    }
}

/// Sorts `PART.FIELD` and `PART.profile[INDEX]` by the part's place in
/// the scene, then fields before points, then the point's index.
fn order_key(vary: &str, scene: &Scene) -> (usize, usize, usize, String) {
    let (part, field) = vary.rsplit_once('.').unwrap_or((vary, ""));
    let part_index = scene
        .parts
        .iter()
        .position(|p| p.name == part)
        .unwrap_or(usize::MAX);
    match field
        .strip_prefix("profile[")
        .and_then(|t| t.strip_suffix(']'))
        .and_then(|t| t.parse::<usize>().ok())
    {
        Some(point) => (part_index, 1, point, String::new()),
        None => (part_index, 0, 0, field.to_owned()),
    }
}

/// One traced candidate, as the merit plot draws it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MeritPoint {
    pub elapsed_s: f64,
    pub merit: f64,
    /// The best of its stage so far, and that merit's photon noise.
    pub best: f64,
    pub noise: f64,
    pub stage: usize,
    pub photons: u64,
}

/// What the design thread tells the editor.
enum Message {
    Progress(Box<Progress>),
    Done(Box<Result<Design, DesignError>>),
}

/// A design that is running.
pub struct DesignRun {
    interrupt: Arc<AtomicBool>,
    messages: Receiver<Message>,
    /// The scene when Start was pressed: each improvement is applied to
    /// it, and the end's undo step goes back to it.
    pub start: Scene,
    pub variables: Vec<Variable>,
    pub target_name: String,
    pub began: Instant,
    pub history: Vec<MeritPoint>,
    /// The newest progress report.
    pub latest: Option<Progress>,
    /// The values shown (the scene's) and when.
    shown: Option<(Vec<f64>, Instant)>,
    /// Stop was pressed.
    pub stopping: bool,
}

/// How the last design ended.
#[derive(Debug, Clone)]
pub struct DesignOutcome {
    pub stopped: Stopped,
    pub evaluations: usize,
    pub seconds: f64,
    pub start_merit: f64,
    pub merit: f64,
    pub noise: f64,
    /// Photons a candidate of the last stage traced.
    pub photons: u64,
    /// Each variable's name, start value and designed value.
    pub variables: Vec<(String, f64, f64)>,
    pub history: Vec<MeritPoint>,
    /// The designed scene, and its file's text as `lucerna design` writes
    /// it (`STEM.toml`).
    pub scene: Scene,
    pub scene_text: String,
    pub target: Target,
}

/// The Design pane's state.
#[derive(Default)]
pub struct DesignState {
    pub setup: DesignSetup,
    pub run: Option<DesignRun>,
    pub outcome: Option<DesignOutcome>,
    /// Why the last Start was refused or the design failed.
    pub error: Option<String>,
    /// The scene panel and the profile pane show their ticks (the Design
    /// pane is in front).
    pub ticks_shown: bool,
    /// Each ticked variable's bounds, for the scene they were found in.
    bounds: Vec<(String, Vec<Variable>)>,
    bounds_scene: Option<Scene>,
}

impl std::fmt::Debug for DesignState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("DesignState")
            .field("setup", &self.setup)
            .field("running", &self.run.is_some())
            .field("error", &self.error)
            .finish_non_exhaustive()
    }
}

impl DesignState {
    pub fn is_running(&self) -> bool {
        self.run.is_some()
    }

    /// Whether the scene panel and the profile pane show their ticks:
    /// while the Design pane is in front, or once something is ticked.
    pub fn ticks_visible(&self) -> bool {
        self.ticks_shown || !self.setup.vary.is_empty()
    }

    /// The bounds of a ticked variable (`PART.FIELD` or
    /// `PART.profile[INDEX]`: one per coordinate), once found.
    pub fn bounds(&self, vary: &str) -> Option<&[Variable]> {
        self.bounds
            .iter()
            .find(|(v, _)| v == vary)
            .map(|(_, b)| b.as_slice())
    }

    /// The bounds are found again at the frame's end (a tick changed).
    pub fn forget_bounds(&mut self) {
        self.bounds_scene = None;
    }

    /// Finds the ticked variables' bounds again when the scene changed
    /// (each is a walk of validations, so not while a hand drags); drops
    /// ticks whose part or field the scene no longer has.
    pub fn refresh_bounds(&mut self, scene: Option<&Scene>, dragging: bool) {
        let Some(scene) = scene else { return };
        if dragging || self.is_running() || self.bounds_scene.as_ref() == Some(scene) {
            return;
        }
        self.bounds.clear();
        let mut kept = Vec::new();
        for vary in &self.setup.vary {
            if let Ok(vars) = lucerna_design::variables::parse(scene, &[vary.clone()], true) {
                self.bounds.push((vary.clone(), vars));
                kept.push(vary.clone());
            }
        }
        self.setup.vary = kept;
        self.bounds_scene = Some(scene.clone());
    }
}

impl EditorState {
    /// Whether a design runs (the scene is its until it ends).
    pub fn is_designing(&self) -> bool {
        self.design.is_running()
    }

    /// Where the design stands, for the status bar.
    pub fn design_status(&self) -> Option<String> {
        if let Some(run) = &self.design.run {
            return Some(match &run.latest {
                Some(p) if p.photons > 0 => format!(
                    "Designing: merit {:.4} ± {:.4} (stage {})",
                    p.best_merit,
                    p.noise,
                    p.stage + 1
                ),
                _ => "Designing: looking for a start".to_owned(),
            });
        }
        let o = self.design.outcome.as_ref()?;
        (self.doc.scene.as_ref() == Some(&o.scene)).then(|| match o.target {
            Target::Distribution { .. } => {
                format!(
                    "Designed: remaining difference {:.4} ± {:.4}",
                    o.merit, o.noise
                )
            }
            Target::Spec(_) => format!("Designed: spec merit {:.4}", o.merit),
        })
    }

    /// The last design's scene file as `lucerna design` writes it
    /// (`STEM.toml`), once a design has ended.
    pub fn designed_scene_text(&self) -> Option<&str> {
        self.design.outcome.as_ref().map(|o| o.scene_text.as_str())
    }

    /// Starts a design of the current scene as the pane set it up; a
    /// refusal is shown in the pane and nothing changes.
    pub(crate) fn start_design(&mut self) {
        if self.design.is_running() {
            return;
        }
        match self.begin_design() {
            Ok(run) => {
                self.design.run = Some(run);
                self.design.error = None;
                self.design.outcome = None;
            }
            Err(why) => self.design.error = Some(why),
        }
    }

    fn begin_design(&mut self) -> Result<DesignRun, String> {
        let scene = self.doc.scene.clone().ok_or("no scene to design")?;
        if !self.doc.problems.is_empty() {
            return Err("the scene is invalid: fix it first (the scene panel lists why)".into());
        }
        if self.design.setup.vary.is_empty() {
            return Err(
                "tick what may change: a parameter in the scene panel or a point in the Profile pane"
                    .into(),
            );
        }
        if !(self.design.setup.time_s.is_finite() && self.design.setup.time_s > 0.0) {
            return Err("the time for a design must be positive".into());
        }
        let target = self.design.setup.target()?;
        let variables = lucerna_design::variables::parse(&scene, &self.design.setup.vary, false)
            .map_err(|e| e.to_string())?;
        let dir = self.scene_dir();
        let path = self.files.path.clone();
        // The file's own text where it holds this scene, so the designed
        // file keeps its comments as `lucerna design` keeps them.
        let file_text = path.as_ref().and_then(|p| {
            let text = std::fs::read_to_string(p).ok()?;
            (lucerna_scene::parse_scene(&text, p).ok()? == scene).then_some(text)
        });
        let text = match file_text {
            Some(t) => t,
            None => lucerna_scene::scene_to_toml(&scene)
                .map_err(|e| format!("the scene cannot be written as a file: {e}"))?,
        };
        let target_name = match &target {
            Target::Distribution { name, .. } => name.clone(),
            Target::Spec(_) => "the spec".to_owned(),
        };
        let request = DesignRequest {
            scene_path: path.unwrap_or_else(|| dir.join("unsaved scene.toml")),
            target,
            vary: self.design.setup.vary.clone(),
            free_ends: false,
            budget: Budget {
                time: Duration::from_secs_f64(self.design.setup.time_s),
                evaluations: self.design.setup.evaluations,
                max_photons: None,
            },
            seed: self.design.setup.seed,
            resolution: DEFAULT_RESOLUTION,
            direct: true,
            least_squares: false,
        };
        let interrupt = Arc::new(AtomicBool::new(false));
        let (send, messages) = channel();
        let start = StartScene {
            scene: scene.clone(),
            text,
            dir,
        };
        let ctx = self.ctx.clone();
        let stop = interrupt.clone();
        std::thread::Builder::new()
            .name("design".to_owned())
            .spawn(move || {
                let repaint = || {
                    if let Some(ctx) = &ctx {
                        ctx.request_repaint();
                    }
                };
                let result = lucerna_design::design_scene(start, &request, &stop, &mut |p| {
                    let _ = send.send(Message::Progress(Box::new(p.clone())));
                    repaint();
                });
                let _ = send.send(Message::Done(Box::new(result)));
                repaint();
            })
            .map_err(|e| format!("cannot start the design: {e}"))?;
        Ok(DesignRun {
            interrupt,
            messages,
            start: scene,
            variables,
            target_name,
            began: Instant::now(),
            history: Vec::new(),
            latest: None,
            shown: None,
            stopping: false,
        })
    }

    /// Stop: the design ends with the best it found so far.
    pub(crate) fn stop_design(&mut self) {
        if let Some(run) = &mut self.design.run {
            run.interrupt.store(true, Ordering::Relaxed);
            run.stopping = true;
        }
    }

    /// Takes the design thread's news (each frame, before the panels):
    /// a better candidate becomes the scene shown; the end, one undo step.
    pub(crate) fn poll_design(&mut self) {
        let Some(run) = &mut self.design.run else {
            return;
        };
        let mut done = None;
        loop {
            match run.messages.try_recv() {
                Ok(Message::Progress(p)) => {
                    if let Some(merit) = p.record.merit
                        && p.photons > 0
                    {
                        run.history.push(MeritPoint {
                            elapsed_s: p.elapsed.as_secs_f64(),
                            merit,
                            best: p.best_merit,
                            noise: p.noise,
                            stage: p.stage,
                            photons: p.photons,
                        });
                    }
                    run.latest = Some(*p);
                }
                Ok(Message::Done(result)) => {
                    done = Some(*result);
                    break;
                }
                Err(TryRecvError::Empty) => break,
                Err(TryRecvError::Disconnected) => {
                    done = Some(Err(DesignError::Output(
                        "the design stopped without an answer".to_owned(),
                    )));
                    break;
                }
            }
        }
        if let Some(result) = done {
            self.finish_design(result);
            return;
        }
        // The best so far, shown when it changed (at most every
        // SHOW_EVERY: each restarts the live run).
        let Some(latest) = &run.latest else { return };
        let values = &latest.best_values;
        let due = run
            .shown
            .as_ref()
            .is_none_or(|(v, at)| v != values && at.elapsed() >= SHOW_EVERY);
        if !due || values.len() != run.variables.len() {
            return;
        }
        let Some(scene) = lucerna_design::variables::apply(&run.start, &run.variables, values)
        else {
            return;
        };
        run.shown = Some((values.clone(), Instant::now()));
        self.doc.scene = Some(scene);
        self.scene_changed();
    }

    fn finish_design(&mut self, result: Result<Design, DesignError>) {
        let Some(run) = self.design.run.take() else {
            return;
        };
        match result {
            Ok(design) => {
                let scene_text = lucerna_design::output::scene_text(&design);
                let outcome = DesignOutcome {
                    stopped: design.found.stopped,
                    evaluations: design
                        .found
                        .history
                        .iter()
                        .filter(|r| r.photons > 0)
                        .count(),
                    seconds: run.began.elapsed().as_secs_f64(),
                    start_merit: design.start_merit,
                    merit: design.found.merit,
                    noise: design.found.noise,
                    photons: design.found.photons,
                    variables: design
                        .variables
                        .iter()
                        .zip(&design.found.values)
                        .map(|(v, &x)| (v.name.clone(), v.start, x))
                        .collect(),
                    history: run.history,
                    scene: design.scene.clone(),
                    scene_text: scene_text.unwrap_or_default(),
                    target: design.aim.target().clone(),
                };
                self.doc.replace_as_one_step(&run.start, design.scene);
                self.design.outcome = Some(outcome);
                self.files.autosave_now = true;
            }
            Err(e) => {
                // Back to the start, as if nothing ran.
                self.doc.scene = Some(run.start);
                self.design.error = Some(crate::error_text::error_chain(&e));
            }
        }
        self.scene_changed();
    }
}
