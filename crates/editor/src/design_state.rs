//! What the editor knows of a design: `lucerna design` on the scene being
//! edited, toward a target file or a spec set in the Design pane, varying
//! the parameters and profile points ticked in the scene panel and the
//! profile pane. The design runs on a thread of its own beside the
//! simulation's worker (design.rs starts it and takes its news); each
//! better candidate it finds becomes the document's scene (no undo step)
//! and goes to the live run, so the 3D view, the profile and the figures
//! follow it. The end is one undo step from the start scene to the
//! result.

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::sync::mpsc::Receiver;
use std::time::{Duration, Instant};

use lucerna_design::{
    Design, DesignError, Maximise, Phase, Progress, Reachability, Spec, Stopped, Target, Variable,
};
use lucerna_scene::Scene;

/// How often an improvement is shown at most: each one restarts the live
/// run, which shares the cores with the design.
pub(crate) const SHOW_EVERY: Duration = Duration::from_millis(1000);

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
    /// Photons a candidate traced (0: judged by the meridian model).
    pub photons: u64,
    pub phase: Phase,
}

/// What the design thread tells the editor.
pub(crate) enum Message {
    Progress(Box<Progress>),
    Done(Box<Result<Design, DesignError>>),
}

/// A design that is running.
pub struct DesignRun {
    pub(crate) interrupt: Arc<AtomicBool>,
    pub(crate) messages: Receiver<Message>,
    /// The scene when Start was pressed: each improvement is applied to
    /// it, and the end's undo step goes back to it.
    pub start: Scene,
    pub variables: Vec<Variable>,
    pub target_name: String,
    pub began: Instant,
    pub history: Vec<MeritPoint>,
    /// The newest progress report.
    pub latest: Option<Progress>,
    /// What the geometry can reach, once the design has said.
    pub reach: Option<Reachability>,
    /// The values shown (the scene's) and when.
    pub(crate) shown: Option<(Vec<f64>, Instant)>,
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
    pub reach: Option<Reachability>,
    /// How far each term went across one or two surveyed variables.
    pub survey: Option<lucerna_design::Survey>,
    /// The designed profile's control points, where one was designed.
    pub points: Option<usize>,
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
            if let Ok(vars) =
                lucerna_design::variables::parse(scene, std::slice::from_ref(vary), true)
            {
                self.bounds.push((vary.clone(), vars));
                kept.push(vary.clone());
            }
        }
        self.setup.vary = kept;
        self.bounds_scene = Some(scene.clone());
    }
}
