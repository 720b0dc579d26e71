//! The analysis: the nominal luminaire and its photon noise, then the
//! built luminaires one by one, each traced with the same photons as the
//! nominal (common random numbers: photon k of the seed's stream is the
//! same photon whatever the geometry), so the spread between samples is
//! the geometry's, not the photons'.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use lucerna_design::Target;
use lucerna_design::traced::evaluate::{Evaluator, merit_grid};
use lucerna_design::variables::{Place, Variable};
use lucerna_photometry::AxialSymmetry;
use lucerna_scene::Scene;
use serde::{Deserialize, Serialize};

use crate::error::ToleranceError;
use crate::figures::{Figure, Judge, Measured};
use crate::sampling::{Draw, Model};
use crate::statistics::Fraction;
use crate::tolerances::{At, Tolerances};

/// Whether every sample is traced with the nominal's photons.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Streams {
    /// Common random numbers: the spread is the geometry's.
    Common,
    /// A photon stream of its own per sample: the spread holds each
    /// sample's photon noise too (for comparison).
    Independent,
}

/// How each sample is traced.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Settings {
    pub seed: u32,
    /// Photons per sample.
    pub photons: u64,
    /// Texels per cube-face edge.
    pub resolution: u32,
    pub streams: Streams,
    /// Traces of the nominal with streams of their own, whose spread is
    /// the figures' photon noise.
    pub noise_runs: u32,
}

impl Default for Settings {
    fn default() -> Settings {
        Settings {
            seed: 1,
            // Under a tenth of the manufacturing spread on the benchmark
            // (BENCHMARKS.md, "Tolerance analysis"); the report warns
            // where a term's figure is noisier than a third of it.
            photons: 200_000,
            resolution: 256,
            streams: Streams::Common,
            noise_runs: 6,
        }
    }
}

/// When sampling stops (whichever comes first; at least one is given).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Budget {
    pub samples: Option<u32>,
    pub time: Option<Duration>,
    /// Stop once the yield's 95 % interval is at most ± this (a
    /// fraction: 0.05 is ± 5 points).
    pub yield_half_width: Option<f64>,
}

/// Why sampling stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Stopped {
    Samples,
    Time,
    Precision,
    Interrupted,
}

/// One built luminaire's outcome.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SampleRecord {
    pub index: u32,
    /// Its figures and terms; None where it could not be built.
    pub measured: Option<Measured>,
    /// Why it could not be built (a profile crossing itself, a part
    /// through the LED): a failed sample.
    pub refused: Option<String>,
}

impl SampleRecord {
    /// Whether it meets every term.
    pub fn passes(&self) -> bool {
        self.measured
            .as_ref()
            .is_some_and(|m| m.terms.iter().all(|t| t.met))
    }
}

/// How far sampling has come.
#[derive(Debug, Clone, Copy)]
pub struct Progress {
    pub done: usize,
    pub total: Option<usize>,
    pub refused: usize,
    pub elapsed: Duration,
    pub yield_so_far: Fraction,
}

/// The nominal luminaire's figures and their photon noise.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Reference {
    pub nominal: Measured,
    /// The nominal with its surfaces' slope errors (where any).
    pub as_built: Option<Measured>,
    /// Each figure's standard deviation over independent photon streams
    /// of the nominal, at the samples' photons.
    pub noise_sd: Vec<f64>,
}

/// A loaded analysis: the scene, its tolerances and what it is judged by.
#[derive(Debug, Clone)]
pub struct Setup {
    pub scene_dir: PathBuf,
    pub model: Model,
    pub judge: Judge,
    pub figures: Vec<Figure>,
    pub settings: Settings,
    /// The evaluator's variables (what the checks of a built scene look
    /// at: the parts that move, whether an emitter does).
    variables: Vec<Variable>,
}

impl Setup {
    /// Loads the scene, the spec or target and the tolerances.
    pub fn load(
        scene_path: &Path,
        spec_path: &Path,
        max_relative_l2: Option<f64>,
        tolerances_path: &Path,
        settings: Settings,
    ) -> Result<Setup, ToleranceError> {
        let scene =
            lucerna_scene::load_scene(scene_path).map_err(|source| ToleranceError::Scene {
                path: scene_path.display().to_string(),
                source,
            })?;
        let target = Target::load(spec_path, false).map_err(|e| ToleranceError::Spec {
            path: spec_path.display().to_string(),
            why: match e {
                lucerna_design::DesignError::Target { why, .. } => why,
                other => other.to_string(),
            },
        })?;
        let tolerances = crate::tolerances::load(tolerances_path, &scene)?;
        let scene_dir = scene_path
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."))
            .to_path_buf();
        Setup::new(
            scene,
            &scene_dir,
            target,
            max_relative_l2,
            tolerances,
            settings,
        )
        .map_err(|e| match e {
            ToleranceError::Spec { why, .. } => ToleranceError::Spec {
                path: spec_path.display().to_string(),
                why,
            },
            ToleranceError::File {
                line, field, why, ..
            } => ToleranceError::File {
                path: tolerances_path.display().to_string(),
                line,
                field,
                why,
            },
            other => other,
        })
    }

    /// An analysis of a scene already loaded.
    pub fn new(
        scene: Scene,
        scene_dir: &Path,
        target: Target,
        max_relative_l2: Option<f64>,
        tolerances: Tolerances,
        settings: Settings,
    ) -> Result<Setup, ToleranceError> {
        if settings.photons == 0 {
            return Err(ToleranceError::Settings(
                "photons per sample must be at least 1".to_owned(),
            ));
        }
        if !(8..=1024).contains(&settings.resolution) {
            return Err(ToleranceError::Settings(format!(
                "the resolution must be between 8 and 1024, got {}",
                settings.resolution
            )));
        }
        let judge = Judge::new(target, max_relative_l2).map_err(|why| ToleranceError::Spec {
            path: String::new(),
            why,
        })?;
        let mut variables: Vec<Variable> = Vec::new();
        for s in &tolerances.scalars {
            if let At::Variable(place) = &s.at {
                variables.push(Variable {
                    name: s.name.clone(),
                    place: place.clone(),
                    start: s.nominal,
                    lower: s.nominal,
                    upper: s.nominal,
                });
            }
        }
        for f in &tolerances.form_errors {
            variables.push(Variable {
                name: format!("{}.profile", f.part_name),
                place: Place::ProfilePoint {
                    part: f.part,
                    point: 0,
                    coord: 0,
                },
                start: 0.0,
                lower: 0.0,
                upper: 0.0,
            });
        }
        let model =
            Model::new(scene, tolerances, settings.seed).map_err(|why| ToleranceError::File {
                path: String::new(),
                line: 0,
                field: String::new(),
                why,
            })?;
        let figures = judge.figures();
        Ok(Setup {
            scene_dir: scene_dir.to_path_buf(),
            model,
            judge,
            figures,
            settings,
            variables,
        })
    }

    /// An evaluator with the seed's stream.
    pub fn evaluator(&self, seed: u32) -> Evaluator {
        let grid = match self.judge.aim.target() {
            Target::Spec(_) => merit_grid(),
            Target::Distribution { .. } => self.judge.aim.grid(),
        };
        Evaluator::new(
            &self.scene_dir,
            seed,
            self.settings.resolution,
            AxialSymmetry::None,
            &self.variables,
            grid,
        )
    }

    /// Traces `scene` and measures it.
    pub fn measure(&self, evaluator: &mut Evaluator, scene: &Scene) -> Result<Measured, String> {
        let traced = evaluator
            .trace(scene, self.settings.photons)
            .map_err(|r| r.to_string())?;
        Ok(self.judge.measure(&traced))
    }

    /// Sample `draw` built, traced and measured.
    pub fn sample(&self, evaluator: &mut Evaluator, draw: &Draw) -> SampleRecord {
        let outcome = self
            .model
            .scene(draw)
            .and_then(|scene| match self.settings.streams {
                Streams::Common => self.measure(evaluator, &scene),
                Streams::Independent => {
                    let seed = self
                        .settings
                        .seed
                        .wrapping_add(0x1000)
                        .wrapping_add(draw.index);
                    self.measure(&mut evaluator.with_seed(seed), &scene)
                }
            });
        match outcome {
            Ok(m) => SampleRecord {
                index: draw.index,
                measured: Some(m),
                refused: None,
            },
            Err(why) => SampleRecord {
                index: draw.index,
                measured: None,
                refused: Some(why),
            },
        }
    }

    /// The nominal's figures (with the seed's photons: the samples'
    /// reference), the as-built nominal's, and the photon noise.
    pub fn reference(&self) -> Result<Reference, ToleranceError> {
        let mut evaluator = self.evaluator(self.settings.seed);
        let nominal = self
            .measure(&mut evaluator, &self.model.nominal)
            .map_err(ToleranceError::Nominal)?;
        let as_built = if self.model.tolerances.slope_errors.is_empty() {
            None
        } else {
            Some(
                self.measure(&mut evaluator, &self.model.as_built_nominal())
                    .map_err(ToleranceError::Nominal)?,
            )
        };
        let base = as_built.clone().unwrap_or_else(|| nominal.clone());
        let mut runs = vec![base.values.clone()];
        let scene = self.model.as_built_nominal();
        for k in 1..self.settings.noise_runs.max(2) {
            let mut other = evaluator.with_seed(self.settings.seed.wrapping_add(0x7000_0000 + k));
            runs.push(
                self.measure(&mut other, &scene)
                    .map_err(ToleranceError::Nominal)?
                    .values,
            );
        }
        let noise_sd = (0..self.figures.len())
            .map(|f| {
                let column: Vec<f64> = runs.iter().map(|r| r[f]).collect();
                crate::statistics::Spread::of(&column).sd
            })
            .collect();
        Ok(Reference {
            nominal,
            as_built,
            noise_sd,
        })
    }

    /// Samples `indices` in order until the budget is spent or
    /// `interrupt` is set; what was done is kept. `progress` hears of each
    /// sample as it is done. (Two samples at once, one building while
    /// the other traces, were no faster on 2 cores: BENCHMARKS.md.)
    pub fn run(
        &self,
        indices: impl IntoIterator<Item = u32>,
        budget: &Budget,
        interrupt: &AtomicBool,
        progress: &mut dyn FnMut(&Progress, &SampleRecord),
    ) -> (Vec<SampleRecord>, Stopped) {
        let began = Instant::now();
        let mut evaluator = self.evaluator(self.settings.seed);
        let mut records: Vec<SampleRecord> = Vec::new();
        let total = budget.samples.map(|n| n as usize);
        let mut passed = 0;
        let mut refused = 0;
        for index in indices {
            if let Some(n) = total
                && records.len() >= n
            {
                return (records, Stopped::Samples);
            }
            if interrupt.load(Ordering::Relaxed) {
                return (records, Stopped::Interrupted);
            }
            if let Some(t) = budget.time
                && began.elapsed() >= t
            {
                return (records, Stopped::Time);
            }
            let record = self.sample(&mut evaluator, &self.model.draw(index));
            passed += usize::from(record.passes());
            refused += usize::from(record.refused.is_some());
            let yield_so_far = Fraction::wilson(passed, records.len() + 1);
            progress(
                &Progress {
                    done: records.len() + 1,
                    total,
                    refused,
                    elapsed: began.elapsed(),
                    yield_so_far,
                },
                &record,
            );
            records.push(record);
            if let Some(w) = budget.yield_half_width
                && records.len() >= MIN_SAMPLES_FOR_PRECISION
                && yield_so_far.half_width() <= w
            {
                return (records, Stopped::Precision);
            }
        }
        (records, Stopped::Samples)
    }
}

/// A yield's interval is trusted for stopping only from this many
/// samples on (Wilson's interval of a handful is wide anyway).
pub const MIN_SAMPLES_FOR_PRECISION: usize = 30;

/// The sample numbers of part `k` of `n` (1-based) of a run of `samples`:
/// every n-th, so each part's share of the Sobol points is spread evenly.
pub fn part_indices(samples: u32, part: Option<(u32, u32)>) -> Vec<u32> {
    match part {
        None => (0..samples).collect(),
        Some((k, n)) => (0..samples).filter(|i| i % n == k - 1).collect(),
    }
}
