//! The meridian model's global search, for targets the mapping cannot
//! represent (a direct design the refinement could not bring near what
//! the geometry allows): the model's surveys and CMA-ES runs
//! ([`crate::search::global`]), its best few traced; the refinement then
//! goes on from the best. Its settings are one struct, its defaults
//! justified on a held-out set (BENCHMARKS.md, "Design").

use std::time::{Duration, Instant};

use serde::Serialize;

use crate::history::Phase;
use crate::merit::axial;
use crate::search::global;

use super::direct::resampled;
use super::{Context, PHASE_PHOTONS, ProfilePlan};

/// The fallback's settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FallbackSettings {
    /// Passes of the model search over its survey's starts, then runs
    /// from random starts.
    pub survey_passes: usize,
    pub random_runs: usize,
    /// The model search's share of the time left, and the most it takes.
    pub model_time_share: f64,
    pub model_time_max: Duration,
    /// How many of the model's best the tracer judges.
    pub traced: usize,
}

impl Default for FallbackSettings {
    fn default() -> FallbackSettings {
        FallbackSettings {
            survey_passes: 2,
            random_runs: 8,
            model_time_share: 0.5,
            model_time_max: Duration::from_secs(60),
            traced: 6,
        }
    }
}

/// What the fallback did.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModelSearch {
    /// Runs finished and model candidates traced.
    pub runs: usize,
    pub evaluations: u64,
    pub seconds: f64,
    /// The best run's relative L2 difference in the model, and the
    /// tracer's merit of the best of the few it traced.
    pub model_l2: f64,
    pub traced_merit: Option<f64>,
}

/// A traced design: its values and merit.
type Best = (Vec<f64>, f64);

/// Runs the fallback from the context's start profile; its record and
/// the best design it traced (values, merit at [`PHASE_PHOTONS`]).
pub fn fallback(
    ctx: &mut Context,
    plan: &ProfilePlan,
    settings: FallbackSettings,
) -> Option<(ModelSearch, Option<Best>)> {
    let model = plan.model.clone()?;
    let crate::Target::Distribution { table, .. } = ctx.aim.target() else {
        return None;
    };
    let goal = axial(table);
    // The search's own point count is the start file's (its survey's
    // grids grow with it); each candidate is resampled to the design's.
    let working = plan.profile(ctx, &ctx.start_values())?;
    let count = working.len();
    let points = resampled(&working, plan, plan.geometry.profile.len());
    let others = ctx.start_values();
    let values_of = |ctx: &Context, profile: &[[f64; 2]]| {
        plan.values(ctx, &resampled(profile, plan, count), &others)
    };
    let now = Instant::now();
    let left = ctx.deadline().saturating_duration_since(now);
    // With an evaluation budget (a design that must not depend on the
    // machine's speed) every run finishes.
    let deadline = if ctx.budget().evaluations.is_some() {
        ctx.deadline()
    } else {
        now + left
            .mul_f64(settings.model_time_share)
            .min(settings.model_time_max)
    };
    let plan_runs = global::Plan {
        survey_passes: settings.survey_passes,
        random_runs: settings.random_runs,
    };
    let mut best_heard = f64::INFINITY;
    let interrupt = ctx.interrupt;
    let seed = ctx.request.seed;
    let found = {
        let mut on_run = |_run: usize, c: &global::Candidate| {
            let values = values_of(ctx, &c.profile);
            best_heard = best_heard.min(c.model_l2);
            ctx.history.record(
                Phase::Fallback,
                0,
                Some(c.model_l2),
                "meridian model",
                values,
                ctx.progress,
            );
        };
        global::search(
            &model,
            &points,
            &goal,
            seed,
            plan_runs,
            deadline,
            interrupt,
            &mut on_run,
        )?
    };
    // The best few traced; the best traced of each basin refined.
    let mut traced: Vec<(Vec<f64>, f64, Vec<[f64; 2]>)> = Vec::new();
    for c in found.candidates.iter().take(settings.traced) {
        let values = values_of(ctx, &c.profile);
        if let Some(j) = ctx.judge(Phase::Fallback, &values, PHASE_PHOTONS) {
            traced.push((values, j.merit, c.profile.clone()));
        }
    }
    traced.sort_by(|a, b| a.1.total_cmp(&b.1));
    let model_best = traced.first().map(|(v, m, _)| (v.clone(), *m));
    let best = model_best.clone();
    Some((
        ModelSearch {
            runs: found.candidates.len(),
            evaluations: found.evaluations,
            seconds: found.seconds,
            model_l2: found
                .candidates
                .first()
                .map_or(f64::INFINITY, |c| c.model_l2),
            traced_merit: model_best.map(|b| b.1),
        },
        best,
    ))
}
