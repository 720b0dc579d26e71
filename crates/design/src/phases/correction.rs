//! The direct design corrected for what the model leaves out, by
//! feedback through the tracer (as Wester et al. 2014 correct a freeform
//! surface for an extended source): the design is traced, the light the
//! model aims at is multiplied, angle by angle, by how much the target
//! wants over what the tracer saw there, and the profile is polished in
//! the model toward that corrected aim. Kept while the traced difference
//! falls; it stops at the first iteration that does not lower it.

use crate::history::Phase;
use crate::search::polish::{Measure, polish};

use super::direct::DirectDesign;
use super::{Context, PHASE_PHOTONS, ProfilePlan};

/// Iterations at most.
pub const MAX_ITERATIONS: usize = 8;
/// The most one iteration changes the aim at an angle (a factor either
/// way): the ratio where the design has almost no light of its own would
/// be unbounded.
const RATIO_LIMIT: f64 = 4.0;
/// The time one polish may take, at most.
const POLISH_TIME: std::time::Duration = std::time::Duration::from_secs(5);

/// One iteration, for the report.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Iteration {
    pub merit: Option<f64>,
    pub kept: bool,
}

/// What the correction ends with: the best design (the direct design
/// where no iteration bettered it) and each iteration's merit.
#[derive(Debug, Clone)]
pub struct Corrected {
    pub values: Vec<f64>,
    pub merit: f64,
    pub iterations: Vec<Iteration>,
}

/// Corrects `first` (the best direct design) by feedback.
pub fn correction(ctx: &mut Context, plan: &ProfilePlan, first: &DirectDesign) -> Corrected {
    let mut best = (first.values.clone(), first.judged.merit);
    let mut iterations = Vec::new();
    let Some(model) = &plan.model else {
        return Corrected {
            values: best.0,
            merit: best.1,
            iterations,
        };
    };
    let others = ctx.start_values();
    let mut aim = plan.axial.intensity.clone();
    let mut seen = crate::target::axial_nodes(&first.judged.traced.table);
    let Some(mut profile) = plan.profile(ctx, &first.values) else {
        return Corrected {
            values: best.0,
            merit: best.1,
            iterations,
        };
    };
    for _ in 0..MAX_ITERATIONS {
        if ctx.spent().is_some() {
            break;
        }
        let next = corrected_aim(plan, &aim, &seen);
        let target = plan.axial.aiming_at(next.clone());
        let deadline = (std::time::Instant::now() + POLISH_TIME).min(ctx.deadline());
        let Some((polished, _)) = polish(
            model,
            &target,
            profile.clone(),
            &[Measure::L2],
            deadline,
            ctx.interrupt,
        ) else {
            break;
        };
        let values = plan.values(ctx, &polished, &others);
        let judged = ctx.judge(Phase::Correction, &values, PHASE_PHOTONS);
        let merit = judged.as_ref().map(|j| j.merit);
        match judged {
            Some(j) if j.merit < best.1 => {
                best = (values, j.merit);
                seen = crate::target::axial_nodes(&j.traced.table);
                aim = next;
                profile = polished;
                iterations.push(Iteration { merit, kept: true });
            }
            _ => {
                iterations.push(Iteration { merit, kept: false });
                break;
            }
        }
    }
    Corrected {
        values: best.0,
        merit: best.1,
        iterations,
    }
}

/// The aim times the ratio, at each node, of the target to what the
/// tracer saw (at the target's flux), limited to [`RATIO_LIMIT`] either
/// way and regularised by a hundredth of the target's peak where either
/// is dark.
pub fn corrected_aim(plan: &ProfilePlan, aim: &[f64], seen: &[f64]) -> Vec<f64> {
    let axial = &plan.axial;
    let scale = axial.scale_of(seen);
    let peak = axial.intensity.iter().copied().fold(0.0, f64::max);
    let epsilon = 0.01 * peak;
    (0..aim.len())
        .map(|j| {
            let ratio = ((axial.intensity[j] + epsilon) / (scale * seen[j] + epsilon))
                .clamp(1.0 / RATIO_LIMIT, RATIO_LIMIT);
            aim[j] * ratio
        })
        .collect()
}
