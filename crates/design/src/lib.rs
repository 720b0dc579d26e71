//! Design from the light you want: a luminaire's shape parameters or a
//! reflector's profile shaped toward a target distribution (an IES or
//! EULUMDAT file) or a spec of figures (beam, field, cut-off, LOR, UGR).
//!
//! Where a revolved profile is varied toward a rotationally symmetric
//! target, a direct design for a point source at the emitter gives the
//! start in milliseconds ([`direct`]); then the photon tracer in the loop
//! corrects it for the real extended source and package ([`optimise`]:
//! Nelder–Mead on common random numbers, in stages of growing photon
//! counts, pooled over the luminaire's symmetry). [`output`] writes the
//! designed scene (the start scene's file with the values replaced), its
//! bake, the design's history and its picture, all or none.

pub mod merit;
pub mod model;
pub mod outcome;
pub mod output;
pub mod picture;
pub mod search;
pub mod target;
pub mod traced;
pub mod variables;

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

use lucerna_photometry::AxialSymmetry;
use lucerna_scene::{Scene, Shape, parse_scene};
use lucerna_simulation::Luminaire;

pub use search::optimise::{Budget, Found, Progress, Record, Stopped};
pub use target::{Maximise, Spec, Target};
pub use variables::Variable;

use crate::merit::Aim;
use crate::traced::evaluate::Evaluator;

/// Why a design could not start or could not be written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DesignError {
    #[error("cannot load the scene {path}")]
    Scene {
        path: String,
        #[source]
        source: lucerna_scene::LoadSceneError,
    },
    #[error("the scene {path} cannot be traced")]
    Prepare {
        path: String,
        #[source]
        source: Box<lucerna_simulation::SimulationError>,
    },
    #[error("target {path}: {why}")]
    Target { path: String, why: String },
    #[error("--vary {what}: {why}")]
    Vary { what: String, why: String },
    #[error("the time for a design must be positive")]
    Time,
    #[error("the start scene itself cannot be traced: {0}")]
    Start(String),
    #[error("the design's files cannot be made: {0}")]
    Output(String),
    #[error("cannot write {path}")]
    Write {
        path: String,
        #[source]
        source: std::io::Error,
    },
}

/// Texels per cube-face edge of every candidate's map, unless asked
/// otherwise (`lucerna design --resolution`).
pub const DEFAULT_RESOLUTION: u32 = 256;

/// Everything a design needs.
#[derive(Debug, Clone)]
pub struct DesignRequest {
    pub scene_path: PathBuf,
    pub target: Target,
    /// `PART.FIELD` or `PART.profile`.
    pub vary: Vec<String>,
    /// Frees a profile's end points.
    pub free_ends: bool,
    pub budget: Budget,
    pub seed: u32,
    /// Texels per cube-face edge of the candidates' maps.
    pub resolution: u32,
    /// Start a varied revolved profile from the point-source direct design.
    pub direct: bool,
    /// Fit a distribution by damped least squares instead of Nelder–Mead.
    pub least_squares: bool,
}

/// A finished design.
#[derive(Debug, Clone)]
pub struct Design {
    /// The start scene, its file's text and folder.
    pub start: Scene,
    pub start_text: String,
    pub scene_dir: PathBuf,
    pub variables: Vec<Variable>,
    /// The start's merit at the first stage's photons.
    pub start_merit: f64,
    /// The direct design's values and merit, where one was made.
    pub direct: Option<(Vec<f64>, f64)>,
    /// The meridian model's global search, where one was made.
    pub model_search: Option<ModelSearch>,
    pub found: Found,
    /// The designed scene.
    pub scene: Scene,
    pub aim: Aim,
    pub symmetry: AxialSymmetry,
    pub seed: u32,
    pub resolution: u32,
    pub lamp_flux_lm: f64,
}

impl Design {
    /// Each variable's name, start value and designed value.
    pub fn changes(&self) -> Vec<(String, f64, f64)> {
        self.variables
            .iter()
            .zip(&self.found.values)
            .map(|(v, &x)| (v.name.clone(), v.start, x))
            .collect()
    }
}

/// What the meridian model's global search ([`global`]) gave.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ModelSearch {
    /// Runs finished and model candidates traced.
    pub runs: usize,
    pub evaluations: u64,
    pub seconds: f64,
    /// The best run's relative L2 difference in the model, and the
    /// tracer's merit of the best of the few it traced.
    pub model_l2: f64,
    pub traced_merit: Option<f64>,
    /// The corrected model's rounds ([`corrected`]): the basins they
    /// started from, how many rounds in all, and the tracer's merit of
    /// the best start before them and of the best after them, at
    /// [`CORRECTED_PHOTONS`].
    pub corrected_basins: usize,
    pub corrected_rounds: u64,
    pub corrected_from: Option<f64>,
    pub corrected_merit: Option<f64>,
}

/// Runs of the meridian model's global search, its share of the design's
/// time and the most time it takes, and how many of its best the tracer
/// judges.
const MODEL_RUNS: usize = 8;
/// Passes of the search over its survey's starts, before those runs.
const SURVEY_PASSES: usize = 2;
const MODEL_TIME_SHARE: u32 = 2;
const MODEL_TIME_MAX: std::time::Duration = std::time::Duration::from_secs(60);
const MODEL_TRACED: usize = 6;
/// Basins the corrected model refines, at most, and how far apart (the
/// largest distance between two profiles' control points) two
/// candidates must be to count as two. The model alone ranks
/// neighbouring basins wrongly at times (toward the second hidden
/// profile's bake its best sat at traced 0.149, where another basin's
/// walked to 0.018).
const BASINS: usize = 3;
const BASIN_APART_M: f64 = 0.001;
/// The photons of each candidate the corrected model's rounds trace, and
/// the share of the design's time those rounds may end by.
pub const CORRECTED_PHOTONS: u64 = 1_600_000;
const CORRECTED_TIME_SHARE: (u32, u32) = (15, 16);
/// The tracer's loop's first simplex after them (a share of each
/// variable's range).
const CORRECTED_STEP: f64 = 0.002;

/// Loads, checks and runs a design; `progress` hears of every traced
/// candidate, `interrupt` stops it with the best so far.
pub fn design(
    request: &DesignRequest,
    interrupt: &AtomicBool,
    progress: &mut dyn FnMut(&Progress),
) -> Result<Design, DesignError> {
    let path = &request.scene_path;
    let scene_err = |source| DesignError::Scene {
        path: path.display().to_string(),
        source,
    };
    let text = lucerna_scene::read_limited_text(path, lucerna_scene::file::MAX_SCENE_FILE_BYTES)
        .map_err(|e| scene_err(lucerna_scene::LoadSceneError::from(e)))?;
    let scene = parse_scene(&text, path).map_err(scene_err)?;
    let dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
    design_scene(
        StartScene { scene, text, dir },
        request,
        interrupt,
        progress,
    )
}

/// A design's start: the scene, the text its designed file is edited
/// from (its file's, so comments and labels stay), and the folder its
/// relative paths start from.
#[derive(Debug, Clone)]
pub struct StartScene {
    pub scene: Scene,
    pub text: String,
    pub dir: PathBuf,
}

/// Runs a design from a scene already loaded (the editor's): the same
/// design as [`design`] of its file, for the same request.
pub fn design_scene(
    start: StartScene,
    request: &DesignRequest,
    interrupt: &AtomicBool,
    progress: &mut dyn FnMut(&Progress),
) -> Result<Design, DesignError> {
    if request.budget.time.is_zero() {
        return Err(DesignError::Time);
    }
    let began = std::time::Instant::now();
    let path = &request.scene_path;
    let StartScene {
        scene: start,
        text: start_text,
        dir: scene_dir,
    } = start;
    let variables = variables::parse(&start, &request.vary, request.free_ends)?;
    let luminaire =
        Luminaire::new(start.clone(), &scene_dir).map_err(|source| DesignError::Prepare {
            path: path.display().to_string(),
            source: Box::new(source),
        })?;
    // Pooled over the start's symmetry where every varied part is a
    // surface of revolution about the axis (which varying keeps);
    // otherwise not at all.
    let keeps_symmetry = variables.iter().all(|v| {
        let part = match &v.place {
            variables::Place::Field { part, .. } | variables::Place::ProfilePoint { part, .. } => {
                &start.parts[*part]
            }
        };
        let about_axis = part.transform.translate[0] == 0.0
            && part.transform.translate[1] == 0.0
            && part.transform.rotate_deg[0] == 0.0
            && part.transform.rotate_deg[1] == 0.0;
        about_axis
            && matches!(
                part.shape,
                Shape::Paraboloid(_)
                    | Shape::Ellipsoid(_)
                    | Shape::Revolved(_)
                    | Shape::Dome(_)
                    | Shape::Cylinder(_)
                    | Shape::Disk(_)
            )
    });
    let symmetry = if keeps_symmetry {
        luminaire.find_symmetry().symmetry
    } else {
        AxialSymmetry::None
    };
    let lamp_flux_lm = luminaire.prepared.total_flux_lm;
    let aim = Aim::new(request.target.clone());
    let mut evaluator = Evaluator::new(
        &scene_dir,
        request.seed,
        request.resolution,
        symmetry,
        &variables,
        aim.grid(),
    );
    let start_values: Vec<f64> = variables.iter().map(|v| v.start).collect();
    let trace = |e: &mut Evaluator, values: &[f64]| -> Option<f64> {
        let scene = variables::apply(&start, &variables, values)?;
        let t = e
            .trace(&scene, search::optimise::FIRST_STAGE_PHOTONS)
            .ok()?;
        Some(search::optimise::merit_of(
            &aim,
            &t,
            lamp_flux_lm,
            &t.opening,
        ))
    };
    let start_merit = trace(&mut evaluator, &start_values).ok_or_else(|| {
        DesignError::Start(
            evaluator
                .check(&start)
                .err()
                .map_or("it is refused".to_owned(), |r| r.to_string()),
        )
    })?;
    // The direct design, where it applies, replaces the start if it is
    // better.
    let direct = if request.direct {
        model::direct::designs(&start, &variables, &request.target)
            .into_iter()
            .filter(|values| {
                values
                    .iter()
                    .zip(&variables)
                    .all(|(&x, v)| (v.lower..=v.upper).contains(&x))
            })
            .filter_map(|values| Some((values.clone(), trace(&mut evaluator, &values)?)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
    } else {
        None
    };
    // The meridian model's global search, where the model applies: its
    // best few traced, the best of them replaces the start if better.
    let mut model_records = Vec::new();
    let mut model_best: Option<(Vec<f64>, f64)> = None;
    let mut corrected_records = Vec::new();
    let mut corrected_best: Option<(Vec<f64>, f64)> = None;
    let model_search = match (&request.target, request.direct) {
        (Target::Distribution { table, .. }, true) => {
            model::direct::meridian_model(&start, &variables, &request.target).and_then(
                |(model, points)| {
                    let goal = merit::axial(table);
                    // With an evaluation budget (a design that must not depend
                    // on the machine's speed) every run finishes.
                    let deadline = began
                        + if request.budget.evaluations.is_some() {
                            request.budget.time
                        } else {
                            (request.budget.time / MODEL_TIME_SHARE).min(MODEL_TIME_MAX)
                        };
                    let values_of = |profile: &[[f64; 2]]| -> Vec<f64> {
                        variables
                            .iter()
                            .map(|v| match v.place {
                                variables::Place::ProfilePoint { point, coord, .. } => {
                                    profile[point][coord]
                                }
                                variables::Place::Field { .. } => v.start,
                            })
                            .collect()
                    };
                    let mut heard = 0u64;
                    let plan = search::global::Plan {
                        survey_passes: SURVEY_PASSES,
                        random_runs: MODEL_RUNS,
                    };
                    let mut finished_at = vec![
                        0.0;
                        search::global::CHORD_STARTS
                            + plan.random_runs
                            + search::global::SURVEY_STARTS
                                * plan.survey_passes
                    ];
                    let mut best_heard = f64::INFINITY;
                    let mut best_values = start_values.clone();
                    let mut on_run = |run: usize, c: &search::global::Candidate| {
                        heard += 1;
                        if let Some(t) = finished_at.get_mut(run) {
                            *t = began.elapsed().as_secs_f64();
                        }
                        let values = values_of(&c.profile);
                        if c.model_l2 < best_heard {
                            best_heard = c.model_l2;
                            best_values = values.clone();
                        }
                        progress(&Progress {
                            elapsed: began.elapsed(),
                            evaluations: heard,
                            stage: 0,
                            photons: 0,
                            best_merit: best_heard,
                            noise: 0.0,
                            best_values: best_values.clone(),
                            record: Record {
                                evaluation: run as u64,
                                elapsed_s: began.elapsed().as_secs_f64(),
                                photons: 0,
                                merit: Some(c.model_l2),
                                measure: "meridian model".to_owned(),
                                values,
                            },
                        });
                    };
                    let model_found = search::global::search(
                        &model,
                        &points,
                        &goal,
                        request.seed,
                        plan,
                        deadline,
                        interrupt,
                        &mut on_run,
                    )?;
                    // One row per run, in the order they finished.
                    let mut rows: Vec<(f64, &search::global::Candidate)> = model_found
                        .candidates
                        .iter()
                        .map(|c| (finished_at.get(c.run).copied().unwrap_or(0.0), c))
                        .collect();
                    rows.sort_by(|a, b| a.0.total_cmp(&b.0));
                    for (k, (t, c)) in rows.into_iter().enumerate() {
                        model_records.push(Record {
                            evaluation: k as u64,
                            elapsed_s: t,
                            photons: 0,
                            merit: Some(c.model_l2),
                            measure: "meridian model".to_owned(),
                            values: values_of(&c.profile),
                        });
                    }
                    let in_bounds = |values: &[f64]| {
                        values
                            .iter()
                            .zip(&variables)
                            .all(|(&x, v)| (v.lower..=v.upper).contains(&x))
                    };
                    // The best few traced; the best traced of each basin
                    // (profiles more than BASIN_APART_M apart) refined.
                    let mut traced: Vec<(Vec<f64>, f64, Vec<[f64; 2]>)> = Vec::new();
                    for c in model_found.candidates.iter().take(MODEL_TRACED) {
                        let values = values_of(&c.profile);
                        if let Some(m) = in_bounds(&values)
                            .then(|| trace(&mut evaluator, &values))
                            .flatten()
                        {
                            traced.push((values, m, c.profile.clone()));
                        }
                    }
                    traced.sort_by(|a, b| a.1.total_cmp(&b.1));
                    model_best = traced.first().map(|(v, m, _)| (v.clone(), *m));
                    let mut basins: Vec<Vec<[f64; 2]>> = Vec::new();
                    for (_, _, p) in &traced {
                        if basins.len() < BASINS
                            && basins
                                .iter()
                                .all(|b| search::global::farthest_apart_m(b, p) > BASIN_APART_M)
                        {
                            basins.push(p.clone());
                        }
                    }
                    // One round of the model corrected by the tracer from
                    // each basin (a round's far search is where a basin
                    // leads to another), then the best refined in the
                    // rounds and time left.
                    let seen = |e: &mut Evaluator, profile: &[[f64; 2]]| {
                        let values = values_of(profile);
                        if !in_bounds(&values) {
                            return None;
                        }
                        let scene = variables::apply(&start, &variables, &values)?;
                        let t = e.trace(&scene, CORRECTED_PHOTONS).ok()?;
                        Some(search::corrected::Seen {
                            merit: search::optimise::merit_of(&aim, &t, lamp_flux_lm, &t.opening),
                            axial: merit::axial(&t.table),
                        })
                    };
                    let timed = request.budget.evaluations.is_none();
                    let correction_deadline = began
                        + if timed {
                            request.budget.time * CORRECTED_TIME_SHARE.0 / CORRECTED_TIME_SHARE.1
                        } else {
                            request.budget.time
                        };
                    let mut rounds = 0u64;
                    let mut corrected_from: Option<f64> = None;
                    let basin_count = basins.len();
                    let mut on_round = |r: &search::corrected::Round| {
                        rounds += 1;
                        let values = values_of(&r.profile);
                        let record = Record {
                            evaluation: rounds,
                            elapsed_s: began.elapsed().as_secs_f64(),
                            photons: CORRECTED_PHOTONS,
                            merit: r.merit,
                            measure: "l2".to_owned(),
                            values: values.clone(),
                        };
                        progress(&Progress {
                            elapsed: began.elapsed(),
                            evaluations: rounds,
                            stage: 0,
                            photons: CORRECTED_PHOTONS,
                            best_merit: r.merit.unwrap_or(f64::INFINITY),
                            noise: 0.0,
                            best_values: values,
                            record: record.clone(),
                        });
                        corrected_records.push(record);
                    };
                    let refine =
                        |e: &mut Evaluator,
                         profile: Vec<[f64; 2]>,
                         first: search::corrected::Seen,
                         count: usize,
                         on_round: &mut dyn FnMut(&search::corrected::Round)| {
                            search::corrected::refine(
                                &model,
                                &points,
                                &goal,
                                profile,
                                first,
                                request.seed,
                                count,
                                correction_deadline,
                                interrupt,
                                &mut |p| seen(e, p),
                                on_round,
                            )
                        };
                    let mut refined: Option<(Vec<[f64; 2]>, search::corrected::Seen)> = None;
                    let mut keep = |found: (Vec<[f64; 2]>, search::corrected::Seen)| {
                        if refined
                            .as_ref()
                            .is_none_or(|(_, b)| found.1.merit < b.merit)
                        {
                            refined = Some(found);
                        }
                    };
                    for profile in basins {
                        let Some(first) = seen(&mut evaluator, &profile) else {
                            continue;
                        };
                        corrected_from =
                            Some(corrected_from.map_or(first.merit, |m| m.min(first.merit)));
                        keep(refine(&mut evaluator, profile, first, 1, &mut on_round));
                    }
                    // The best goes on (refine never returns worse than
                    // its start).
                    if let Some((profile, first)) = refined.take() {
                        refined = Some(refine(
                            &mut evaluator,
                            profile,
                            first,
                            search::corrected::ROUNDS.saturating_sub(basin_count),
                            &mut on_round,
                        ));
                    }
                    corrected_best = refined.map(|(p, s)| (values_of(&p), s.merit));
                    Some(ModelSearch {
                        runs: model_found.candidates.len(),
                        evaluations: model_found.evaluations,
                        seconds: model_found.seconds,
                        model_l2: model_found
                            .candidates
                            .first()
                            .map_or(f64::INFINITY, |c| c.model_l2),
                        traced_merit: model_best.as_ref().map(|b| b.1),
                        corrected_basins: basin_count,
                        corrected_rounds: rounds,
                        corrected_from,
                        corrected_merit: corrected_best.as_ref().map(|b| b.1),
                    })
                },
            )
        }
        _ => None,
    };
    let chosen = [
        Some((&start_values, start_merit)),
        direct.as_ref().map(|(v, m)| (v, *m)),
        model_best.as_ref().map(|(v, m)| (v, *m)),
    ]
    .into_iter()
    .flatten()
    .min_by(|a, b| a.1.total_cmp(&b.1))
    .map_or(&start_values, |(v, _)| v);
    // Where the corrected model refined the model's best, the tracer's
    // loop starts from its result with its photons and a small simplex
    // (a large one at few photons would leave its valley).
    let (chosen, first) = match (&corrected_best, &model_best) {
        (Some((values, _)), Some((model_values, _))) if chosen == model_values => (
            values,
            search::optimise::FirstStage {
                photons: CORRECTED_PHOTONS,
                step: CORRECTED_STEP,
            },
        ),
        _ => (chosen, search::optimise::FirstStage::default()),
    };
    let x0: Vec<f64> = chosen
        .iter()
        .zip(&variables)
        .map(|(&x, v)| v.fraction(x))
        .collect();
    // The tracer's loop has the time the search left.
    let before_loop = began.elapsed();
    let budget = Budget {
        time: request
            .budget
            .time
            .saturating_sub(before_loop)
            .max(std::time::Duration::from_millis(1)),
        ..request.budget
    };
    // A distribution is a sum of squares: damped least squares on its
    // residuals; a spec's terms are not, Nelder–Mead on its merit.
    let found = match &request.target {
        Target::Distribution { .. } if request.least_squares => search::least_squares::fit(
            &start,
            &variables,
            x0,
            &aim,
            &mut evaluator,
            budget,
            interrupt,
            progress,
        ),
        _ => search::optimise::optimise(
            &start,
            &variables,
            x0,
            &aim,
            &mut evaluator,
            lamp_flux_lm,
            budget,
            first,
            interrupt,
            progress,
        ),
    };
    // design.csv lists the model's runs first, then the traced
    // candidates, on one clock.
    let mut found = found;
    for (k, r) in corrected_records.iter_mut().enumerate() {
        r.evaluation = (model_records.len() + k) as u64;
    }
    model_records.append(&mut corrected_records);
    let offset = model_records.len() as u64;
    for r in &mut found.history {
        r.evaluation += offset;
        r.elapsed_s += before_loop.as_secs_f64();
    }
    model_records.append(&mut found.history);
    found.history = model_records;
    let values = output::rounded(&variables, &found.values);
    let scene = variables::apply(&start, &variables, &values)
        .ok_or_else(|| DesignError::Output("the designed values do not apply".to_owned()))?;
    Ok(Design {
        start,
        start_text,
        scene_dir,
        variables,
        start_merit,
        direct,
        model_search,
        found: Found { values, ..found },
        scene,
        aim,
        symmetry,
        seed: request.seed,
        resolution: request.resolution,
        lamp_flux_lm,
    })
}
