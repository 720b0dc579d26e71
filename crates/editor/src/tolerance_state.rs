//! What the editor knows of a tolerance analysis: the tolerances set in
//! the Tolerance pane (per part or emitter: its placement's σ, a
//! profile's form error, a mirror's slope error), written as the
//! tolerances file `lucerna tolerance` reads (one home for what they
//! mean), the spec of the Design pane, and a run on a thread of its own
//! whose samples arrive one by one (tolerance.rs starts it and takes its
//! news).

use std::sync::Arc;
use std::sync::atomic::AtomicBool;
use std::sync::mpsc::Receiver;
use std::time::Instant;

use lucerna_scene::Scene;
use lucerna_tolerance::analysis::{Reference, SampleRecord, Setup, Stopped};
use lucerna_tolerance::report::Report;

/// The placements a part's or emitter's tolerance may act on, as the
/// tolerances file names them, with the unit the pane edits them in.
pub const PLACEMENTS: [(&str, &str); 6] = [
    ("translate_x", "mm"),
    ("translate_y", "mm"),
    ("translate_z", "mm"),
    ("rotate_x", "°"),
    ("rotate_y", "°"),
    ("rotate_z", "°"),
];

/// One placement tolerance: a normal σ in the pane's unit (mm or °).
#[derive(Debug, Clone, PartialEq)]
pub struct PlacementTolerance {
    /// `NAME.translate_x`.
    pub at: String,
    pub sigma: f64,
}

/// A profile's form error, in millimetres.
#[derive(Debug, Clone, PartialEq)]
pub struct FormErrorForm {
    pub part: String,
    pub sigma_mm: f64,
    pub correlation_mm: f64,
}

/// A surface's slope error, in milliradians.
#[derive(Debug, Clone, PartialEq)]
pub struct SlopeErrorForm {
    pub part: String,
    pub sigma_mrad: f64,
}

/// The pane's setup.
#[derive(Debug, Clone, PartialEq)]
pub struct ToleranceSetup {
    pub placements: Vec<PlacementTolerance>,
    pub form_errors: Vec<FormErrorForm>,
    pub slope_errors: Vec<SlopeErrorForm>,
    pub samples: u32,
    pub photons: u64,
    pub seed: u32,
}

impl Default for ToleranceSetup {
    fn default() -> Self {
        ToleranceSetup {
            placements: Vec::new(),
            form_errors: Vec::new(),
            slope_errors: Vec::new(),
            samples: 200,
            photons: 200_000,
            seed: 1,
        }
    }
}

impl ToleranceSetup {
    /// The tolerances file these make (README, "Tolerance analysis").
    pub fn to_toml(&self) -> String {
        let mut t = String::new();
        for p in &self.placements {
            let metres = if p.at.contains(".translate_") {
                1e-3
            } else {
                1.0
            };
            t += &format!(
                "[[tolerance]]\nat = {:?}\nnormal = {{ sigma = {:?} }}\n\n",
                p.at,
                p.sigma * metres
            );
        }
        for f in &self.form_errors {
            t += &format!(
                "[[form_error]]\npart = {:?}\nsigma = {:?}\ncorrelation_length = {:?}\n\n",
                f.part,
                f.sigma_mm * 1e-3,
                f.correlation_mm * 1e-3
            );
        }
        for s in &self.slope_errors {
            t += &format!(
                "[[slope_error]]\npart = {:?}\nsigma_rad = {:?}\n\n",
                s.part,
                s.sigma_mrad * 1e-3
            );
        }
        t
    }

    /// The placement tolerance at `at`, if one is set.
    pub fn placement(&self, at: &str) -> Option<f64> {
        self.placements.iter().find(|p| p.at == at).map(|p| p.sigma)
    }

    /// Sets (Some) or removes (None) the placement tolerance at `at`.
    pub fn set_placement(&mut self, at: &str, sigma: Option<f64>) {
        match (self.placements.iter().position(|p| p.at == at), sigma) {
            (Some(i), Some(s)) => self.placements[i].sigma = s,
            (Some(i), None) => {
                self.placements.remove(i);
            }
            (None, Some(s)) => self.placements.push(PlacementTolerance {
                at: at.to_owned(),
                sigma: s,
            }),
            (None, None) => {}
        }
    }

    /// Drops what names a part or emitter the scene no longer has.
    pub fn keep_only_what(&mut self, scene: &Scene) {
        let has = |name: &str| {
            scene.parts.iter().any(|p| p.name == name)
                || scene.emitters.iter().any(|e| e.name == name)
        };
        self.placements
            .retain(|p| p.at.rsplit_once('.').is_some_and(|(n, _)| has(n)));
        self.form_errors.retain(|f| has(&f.part));
        self.slope_errors.retain(|s| has(&s.part));
    }
}

/// News from the analysis's thread.
pub(crate) enum Message {
    /// The nominal and its photon noise, or why the analysis cannot run.
    Reference(Result<Box<Reference>, String>),
    Sample(Box<SampleRecord>),
    Done(Stopped),
}

/// An analysis running.
pub struct ToleranceRun {
    pub(crate) interrupt: Arc<AtomicBool>,
    pub(crate) messages: Receiver<Message>,
    pub setup: Arc<Setup>,
    pub began: Instant,
    pub reference: Option<Reference>,
    pub records: Vec<SampleRecord>,
    pub stopping: bool,
}

/// A finished analysis: its samples and report, and the scene it was of.
pub struct ToleranceOutcome {
    pub setup: Arc<Setup>,
    pub reference: Reference,
    pub records: Vec<SampleRecord>,
    pub report: Report,
}

/// The editor's tolerance analysis.
#[derive(Default)]
pub struct ToleranceState {
    pub setup: ToleranceSetup,
    pub run: Option<ToleranceRun>,
    pub outcome: Option<ToleranceOutcome>,
    /// Why the last Run was refused or failed.
    pub error: Option<String>,
    /// Whether the Tolerance pane is shown (set each frame): the scene
    /// panel then shows the selected item's tolerances under its
    /// parameters.
    pub shown: bool,
}

impl std::fmt::Debug for ToleranceState {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ToleranceState")
            .field("setup", &self.setup)
            .field("running", &self.run.is_some())
            .field("outcome", &self.outcome.is_some())
            .field("error", &self.error)
            .finish()
    }
}

impl ToleranceState {
    pub fn is_running(&self) -> bool {
        self.run.is_some()
    }

    /// The samples so far (a run's) or the last run's.
    pub fn records(&self) -> &[SampleRecord] {
        match (&self.run, &self.outcome) {
            (Some(r), _) => &r.records,
            (None, Some(o)) => &o.records,
            (None, None) => &[],
        }
    }

    /// The analysis the samples are of.
    pub fn analysis(&self) -> Option<&Arc<Setup>> {
        match (&self.run, &self.outcome) {
            (Some(r), _) => Some(&r.setup),
            (None, Some(o)) => Some(&o.setup),
            (None, None) => None,
        }
    }

    /// The nominal's figures, once traced.
    pub fn reference(&self) -> Option<&Reference> {
        match (&self.run, &self.outcome) {
            (Some(r), _) => r.reference.as_ref(),
            (None, Some(o)) => Some(&o.reference),
            (None, None) => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_pane_writes_a_file_the_analysis_reads() {
        let scene = lucerna_scene::parse_scene(
            include_str!("../../../assets/luminaires/parabolic_spot.toml"),
            std::path::Path::new("spot.toml"),
        )
        .expect("the example reads");
        let mut s = ToleranceSetup::default();
        s.set_placement("LED.translate_x", Some(0.1));
        s.set_placement("reflector.rotate_y", Some(0.5));
        s.form_errors.push(FormErrorForm {
            part: "reflector".to_owned(),
            sigma_mm: 0.05,
            correlation_mm: 10.0,
        });
        s.slope_errors.push(SlopeErrorForm {
            part: "reflector".to_owned(),
            sigma_mrad: 1.0,
        });
        let t = lucerna_tolerance::tolerances::parse(&s.to_toml(), &scene).expect("reads");
        assert_eq!(t.scalars.len(), 2);
        assert!((t.scalars[0].distribution.standard_deviation() - 1e-4).abs() < 1e-15);
        assert!((t.scalars[1].distribution.standard_deviation() - 0.5).abs() < 1e-15);
        assert_eq!(t.form_errors[0].sigma_m, 0.05e-3);
        assert_eq!(t.slope_errors[0].sigma_rad, 1e-3);
        s.set_placement("LED.translate_x", None);
        assert_eq!(s.placements.len(), 1);
    }
}
