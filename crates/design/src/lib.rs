//! Design from the light you want: a luminaire's shape parameters, a
//! reflector's profile or a part's placement shaped toward a target
//! distribution (an IES or EULUMDAT file) or a spec of figures (beam,
//! field, cut-off, LOR, UGR).
//!
//! A design is a pipeline of phases ([`phases`]): the start traced; for a
//! revolved mirror toward a rotationally symmetric target, what its fixed
//! parts make impossible ([`Reachability`]), the point-source direct
//! design by energy balance between the fixed ends, its correction for
//! the extended source by feedback through the tracer, and a local
//! refinement with the tracer in the loop; the meridian model's global
//! search only where the mapping cannot represent the target; for every
//! other design, the tracer's loop. [`output`] writes the designed scene
//! (the start scene's file with the values replaced), its bake, the
//! design's history and its picture, all or none.

pub mod error;
pub mod history;
pub mod merit;
pub mod model;
pub mod outcome;
pub mod output;
pub mod phases;
pub mod picture;
pub mod search;
pub mod target;
pub mod traced;
pub mod variables;

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use lucerna_photometry::AxialSymmetry;
use lucerna_scene::{Scene, Shape, parse_scene};
use lucerna_simulation::Luminaire;

pub use error::DesignError;
pub use history::{Phase, Progress, Record};
pub use model::reach::Reachability;
pub use phases::correction::Iteration;
pub use phases::direct::{MAX_POINTS, MIN_POINTS};
pub use phases::fallback::{FallbackSettings, ModelSearch};
pub use phases::survey::{Survey, SurveyAxis, TermRange};
pub use phases::{LAST_PHOTONS, PHASE_PHOTONS};
pub use target::{Maximise, Spec, Target};
pub use variables::Variable;

use crate::history::History;
use crate::merit::Aim;
use crate::phases::{Context, ProfilePlan};
use crate::search::optimise::{FIRST_STAGE_PHOTONS, LAST_STAGE_PHOTONS};
use crate::traced::evaluate::Evaluator;
use crate::variables::{Owner, Place};

/// Texels per cube-face edge of every candidate's map, unless asked
/// otherwise (`lucerna design --resolution`).
pub const DEFAULT_RESOLUTION: u32 = 256;

/// How far a target's C-planes may differ (the root mean square of each
/// angle's spread across C, over the peak) before a design that assumes
/// rotation refuses it; above [`target::SYMMETRIC_ENOUGH`] it designs to
/// the mean over C with a warning.
pub const ASYMMETRY_LIMIT: f64 = 0.10;

/// Everything a design needs.
#[derive(Debug, Clone)]
pub struct DesignRequest {
    pub scene_path: PathBuf,
    pub target: Target,
    /// `PART.FIELD`, `PART.profile`, `PART.profile[INDEX]`,
    /// `NAME.translate_z` (a part or an emitter).
    pub vary: Vec<String>,
    /// Frees a profile's end points.
    pub free_ends: bool,
    pub budget: Budget,
    pub seed: u32,
    /// Texels per cube-face edge of the candidates' maps.
    pub resolution: u32,
    /// Run the direct design of a revolved profile (and the fallback
    /// search), or the survey of one or two numbers; without it the
    /// refinement starts from the scene as it is.
    pub direct: bool,
    /// Fit a distribution by damped least squares instead of Nelder–Mead
    /// (designs other than a profile's).
    pub least_squares: bool,
    /// The designed profile's control points (None: as many as the
    /// target's detail needs, from [`MIN_POINTS`] to [`MAX_POINTS`]).
    pub points: Option<usize>,
    pub fallback: FallbackSettings,
}

/// When a design stops.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Budget {
    pub time: Duration,
    /// Traced candidates at most (a budget that does not depend on the
    /// machine's speed: the same seed and budget give the same design).
    pub evaluations: Option<u64>,
    /// Photons of the last stage (default [`LAST_STAGE_PHOTONS`]).
    pub max_photons: Option<u64>,
}

impl Budget {
    /// Why a design that began at `began` and has traced `traced`
    /// candidates must stop now, if it must.
    pub fn spent(&self, began: Instant, traced: usize, interrupt: &AtomicBool) -> Option<Stopped> {
        if interrupt.load(Ordering::Relaxed) {
            return Some(Stopped::Interrupted);
        }
        if began.elapsed() >= self.time {
            return Some(Stopped::Time);
        }
        if self.evaluations.is_some_and(|n| traced as u64 >= n) {
            return Some(Stopped::Evaluations);
        }
        None
    }

    /// The photons of the last stage.
    pub fn last_stage_photons(&self) -> u64 {
        self.max_photons
            .unwrap_or(LAST_STAGE_PHOTONS)
            .max(FIRST_STAGE_PHOTONS)
    }
}

/// Why a design stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Stopped {
    /// The last stage's simplex agrees within the merit's noise.
    Converged,
    Time,
    Evaluations,
    /// Interrupted (Ctrl+C, or Stop in the editor): the best so far.
    Interrupted,
}

/// What the loop found.
#[derive(Debug, Clone)]
pub struct Found {
    pub values: Vec<f64>,
    pub merit: f64,
    pub photons: u64,
    pub noise: f64,
    pub history: Vec<Record>,
    pub stopped: Stopped,
}

/// A finished design.
#[derive(Debug, Clone)]
pub struct Design {
    /// The start scene, its file's text and folder.
    pub start: Scene,
    pub start_text: String,
    pub scene_dir: PathBuf,
    /// The variables (of the start with its profile resampled to the
    /// designed point count, where that changed).
    pub variables: Vec<Variable>,
    /// The start's merit at [`PHASE_PHOTONS`].
    pub start_merit: f64,
    /// What the geometry can reach, where a direct design applied.
    pub reach: Option<Reachability>,
    /// How far each term went across one or two variables' bounds, where
    /// they were surveyed.
    pub survey: Option<Survey>,
    /// The profile's control points, where a profile was designed.
    pub points: Option<usize>,
    /// The best direct design's values and merit, and each correction
    /// iteration.
    pub direct: Option<(Vec<f64>, f64)>,
    pub corrections: Vec<Iteration>,
    /// The fallback's global search, where it ran.
    pub model_search: Option<ModelSearch>,
    pub found: Found,
    /// The designed scene.
    pub scene: Scene,
    pub aim: Aim,
    pub symmetry: AxialSymmetry,
    pub seed: u32,
    pub resolution: u32,
    pub lamp_flux_lm: f64,
    /// What the user should know (a target designed to its mean over C).
    pub warnings: Vec<String>,
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

/// Loads, checks and runs a design; `progress` hears of every judged
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
    let began = Instant::now();
    let StartScene {
        scene: start,
        text: start_text,
        dir: scene_dir,
    } = start;
    let variables = variables::parse(&start, &request.vary, request.free_ends)?;
    check_request(&start, &variables, request)?;
    let luminaire =
        Luminaire::new(start.clone(), &scene_dir).map_err(|source| DesignError::Prepare {
            path: request.scene_path.display().to_string(),
            source: Box::new(source),
        })?;
    let symmetry = if keeps_symmetry(&start, &variables) {
        luminaire.find_symmetry().symmetry
    } else {
        AxialSymmetry::None
    };
    let mut warnings = Vec::new();
    let round = keeps_symmetry(&start, &variables) && start.rotationally_symmetric();
    let target = aimed_target(request, round, &mut warnings)?;
    let lamp_flux_lm = luminaire.prepared.total_flux_lm;
    let aim = Aim::new(target);
    let evaluator = Evaluator::new(
        &scene_dir,
        request.seed,
        request.resolution,
        symmetry,
        &variables,
        aim.grid(),
    );
    let plan = ProfilePlan::of(&start, &variables, &aim).ok();
    let frame = history::Frame {
        start: start.clone(),
        variables: variables.clone(),
    };
    let mut ctx = Context {
        request,
        start: start.clone(),
        scene_dir: scene_dir.clone(),
        variables,
        aim,
        evaluator,
        lamp_flux_lm,
        history: History::new(began, frame),
        interrupt,
        progress,
        best: None,
        warnings,
    };
    let outcome = run(&mut ctx, plan.as_ref())?;
    let Context {
        variables,
        aim,
        history,
        start: working_start,
        warnings,
        ..
    } = ctx;
    let mut found = outcome.found;
    found.history = history.into_records();
    let values = output::rounded(&variables, &found.values);
    let scene = variables::apply(&working_start, &variables, &values)
        .ok_or_else(|| DesignError::Output("the designed values do not apply".to_owned()))?;
    Ok(Design {
        start,
        start_text,
        scene_dir,
        variables,
        start_merit: outcome.start_merit,
        reach: outcome.reach,
        survey: outcome.survey,
        points: outcome.points,
        direct: outcome.direct,
        corrections: outcome.corrections,
        model_search: outcome.model_search,
        found: Found { values, ..found },
        scene,
        aim,
        symmetry,
        seed: request.seed,
        resolution: request.resolution,
        lamp_flux_lm,
        warnings,
    })
}

/// What the phases give the design.
struct Outcome {
    start_merit: f64,
    reach: Option<Reachability>,
    survey: Option<Survey>,
    points: Option<usize>,
    direct: Option<(Vec<f64>, f64)>,
    corrections: Vec<Iteration>,
    model_search: Option<ModelSearch>,
    found: Found,
}

/// The phases in order.
fn run(ctx: &mut Context, plan: Option<&ProfilePlan>) -> Result<Outcome, DesignError> {
    // The direct design's preparation first: it decides the profile's
    // point count, which every candidate then has (the start too).
    let prepared = plan
        .filter(|_| ctx.request.direct)
        .and_then(|p| phases::direct::prepare(ctx, p, ctx.request.points));
    if let Some(p) = &prepared {
        ctx.history.set_reach(p.reach.clone());
    }
    let points = match (plan, &prepared) {
        (Some(p), Some(prep)) => {
            phases::direct::resample(ctx, p, prep.points)?;
            Some(prep.points)
        }
        (Some(p), None) => {
            if let Some(n) = ctx.request.points {
                phases::direct::resample(ctx, p, n)?;
            }
            variables::profile(&ctx.start.parts[p.geometry.part].shape).map(<[_]>::len)
        }
        _ => None,
    };
    let (start_values, start_merit) = phases::start::start(ctx)?;
    let mut out = Outcome {
        start_merit,
        reach: prepared.as_ref().map(|p| p.reach.clone()),
        survey: None,
        points,
        direct: None,
        corrections: Vec::new(),
        model_search: None,
        found: Found {
            values: start_values.clone(),
            merit: start_merit,
            photons: PHASE_PHOTONS,
            noise: 0.0,
            history: Vec::new(),
            stopped: Stopped::Converged,
        },
    };
    let mut best = (start_values, start_merit);
    if let (Some(plan), Some(prepared)) = (plan, &prepared) {
        let designs = phases::direct::direct(ctx, plan, prepared);
        if let Some(first) = designs.first() {
            out.direct = Some((first.values.clone(), first.judged.merit));
            if first.judged.merit < best.1 {
                best = (first.values.clone(), first.judged.merit);
            }
            let corrected = phases::correction::correction(ctx, plan, first);
            out.corrections = corrected.iterations;
            if corrected.merit < best.1 {
                best = (corrected.values, corrected.merit);
            }
        }
    }
    let Some(plan) = plan else {
        // One or two numbers: their whole range traced first, the
        // refinement from the best of it.
        if ctx.request.direct
            && ctx.spent().is_none()
            && let Some(survey) = phases::survey::survey(ctx)
        {
            if survey.best_merit < best.1 {
                best = (survey.best_values.clone(), survey.best_merit);
            }
            out.survey = Some(survey);
        }
        out.found = match ctx.spent() {
            Some(why) => stopped_at(best, why, out.found),
            None => phases::refinement::refine_generic(ctx, &best.0),
        };
        return Ok(out);
    };
    // Where the direct design, corrected, stays far from what the
    // geometry allows, the fallback's global search for another basin;
    // the refinement then goes on from the best of them.
    // A mirror may reach into the direct cone: the bound of every mirror
    // is the lesser.
    let bound = out.reach.as_ref().map_or(0.0, |r| r.bound.min(r.with_cap));
    let time_left = ctx.deadline().saturating_duration_since(Instant::now());
    if ctx.request.direct
        && best.1 > FALLBACK_ABOVE.max(2.0 * bound)
        && time_left > ctx.budget().time.mul_f64(FALLBACK_TIME_LEFT)
        && ctx.spent().is_none()
        && let Some((search, found)) = phases::fallback::fallback(ctx, plan, ctx.request.fallback)
    {
        out.model_search = Some(search);
        if let Some(f) = found.filter(|f| f.1 < best.1) {
            best = f;
        }
    }
    out.found = match ctx.spent() {
        Some(why) => stopped_at(best, why, out.found),
        None => phases::refinement::refine_profile(ctx, plan, best.0, best.1, None),
    };
    Ok(out)
}

/// A design stopped before its refinement: the best so far.
fn stopped_at(best: (Vec<f64>, f64), why: Stopped, found: Found) -> Found {
    Found {
        values: best.0,
        merit: best.1,
        stopped: why,
        ..found
    }
}

/// Where a profile's direct design, corrected, is above this (or above
/// twice the bound, if higher), the fallback's global search runs: 0.02
/// is what a design of a reachable target should come within. It runs
/// only with this share of the design's time left.
const FALLBACK_ABOVE: f64 = 0.02;
const FALLBACK_TIME_LEFT: f64 = 0.3;

/// Refuses what cannot be designed as asked: a point count out of range
/// or on no profile, free ends on no profile.
fn check_request(
    start: &Scene,
    variables: &[Variable],
    request: &DesignRequest,
) -> Result<(), DesignError> {
    let varies_profile = variables
        .iter()
        .any(|v| matches!(v.place, Place::ProfilePoint { .. }));
    if let Some(points) = request.points {
        if !(MIN_POINTS..=MAX_POINTS).contains(&points) {
            return Err(DesignError::Points {
                points,
                why: format!("a designed profile has {MIN_POINTS} to {MAX_POINTS} control points"),
            });
        }
        if !varies_profile {
            return Err(DesignError::Points {
                points,
                why: "the design varies no profile (--vary PART.profile)".to_owned(),
            });
        }
    }
    if request.free_ends && !varies_profile {
        let shapes: Vec<&str> = variables
            .iter()
            .filter_map(|v| v.place.part())
            .map(|p| start.parts[p].shape.kind())
            .collect();
        return Err(DesignError::FreeEnds(format!(
            "only a profile has ends to free, and the design varies none ({})",
            if shapes.is_empty() {
                "no part's shape".to_owned()
            } else {
                shapes.join(", ")
            }
        )));
    }
    Ok(())
}

/// Whether every variable keeps the luminaire's symmetry about the axis:
/// a surface of revolution about it changed, or a placement along it.
fn keeps_symmetry(start: &Scene, variables: &[Variable]) -> bool {
    variables.iter().all(|v| match &v.place {
        Place::Transform { owner, axis, .. } => {
            let t = match owner {
                Owner::Part(i) => &start.parts[*i].transform,
                Owner::Emitter(i) => &start.emitters[*i].transform,
            };
            *axis == 2 && t.translate[0] == 0.0 && t.translate[1] == 0.0
        }
        place => {
            let Some(p) = place.part() else {
                return false;
            };
            let part = &start.parts[p];
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
        }
    })
}

/// The target as the design aims at it: a distribution whose C-planes
/// differ, toward a luminaire round about its axis, is designed to its
/// mean over C with a warning, or refused past [`ASYMMETRY_LIMIT`].
fn aimed_target(
    request: &DesignRequest,
    round: bool,
    warnings: &mut Vec<String>,
) -> Result<Target, DesignError> {
    let Target::Distribution {
        table,
        absolute,
        name,
    } = &request.target
    else {
        return Ok(request.target.clone());
    };
    if !round || request.target.rotationally_symmetric() {
        return Ok(request.target.clone());
    }
    let asymmetry = target::rotational_asymmetry(table);
    if asymmetry > ASYMMETRY_LIMIT {
        return Err(DesignError::Target {
            path: name.clone(),
            why: format!(
                "its C-planes differ by {:.1} % of its peak (root mean square over γ), more than the {:.0} % a design of a luminaire round about its axis accepts: a round luminaire cannot make it",
                100.0 * asymmetry,
                100.0 * ASYMMETRY_LIMIT
            ),
        });
    }
    warnings.push(format!(
        "the target's C-planes differ by {:.1} % of its peak: designed to their mean over C",
        100.0 * asymmetry
    ));
    Ok(Target::Distribution {
        table: target::c_mean(table),
        absolute: *absolute,
        name: name.clone(),
    })
}
