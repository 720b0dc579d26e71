//! A local refinement with the tracer in the loop, from the best design
//! so far.
//!
//! A revolved mirror's profile toward a rotationally symmetric target is
//! refined by Levenberg–Marquardt on the traced light's residuals
//! ([`crate::search::refine`]): each interior control point moves along
//! the profile's normal there (a move along the curve barely changes
//! it), the ends in r and z where they are free, every other variable by
//! a share of its range; the meridian model gives the profile's
//! derivatives, the tracer's differences on common random numbers the
//! others'. Every other design is refined by the tracer's loop of
//! [`crate::search::optimise`] (Nelder–Mead) or, asked for,
//! [`crate::search::least_squares`].

use glam::DVec2;

use crate::history::Phase;
use crate::search::refine::{self, Limits, Problem, Seen};
use crate::variables::Place;
use crate::{Found, Stopped, Target};

use super::{Context, LAST_PHOTONS, PHASE_PHOTONS, ProfilePlan};

/// The model's finite-difference step of a control point (m), and the
/// tracer's of any other variable (a share of its range).
const PROFILE_STEP_M: f64 = 20e-6;
const OTHER_STEP: f64 = 0.02;
/// Up to this many coordinates the tracer's own differences make the
/// Jacobian (a few traces a step; where the model is 0.02-0.03 from the
/// tracer, its derivatives mislead the last steps), with this step (m).
const TRACED_DIMS: usize = 10;
const TRACED_STEP_M: f64 = 20e-6;

/// Up to this many control points, each moves in r and z.
const FEW_POINTS: usize = 5;

/// What one coordinate of the refinement moves.
#[derive(Debug, Clone, Copy)]
enum Coordinate {
    /// An interior control point along the profile's normal there (m).
    Normal { point: usize, normal: DVec2 },
    /// A free end's r or z (m).
    End { point: usize, coord: usize },
    /// Another variable, by shares of its range.
    Other { variable: usize, range: f64 },
}

/// Where the refinement's coordinates start from.
struct Frame {
    /// The profile at the refinement's start, and every variable's value.
    reference: Vec<[f64; 2]>,
    start: Vec<f64>,
    coordinates: Vec<Coordinate>,
}

impl Frame {
    fn profile(&self, x: &[f64]) -> Vec<[f64; 2]> {
        let mut p = self.reference.clone();
        for (c, &t) in self.coordinates.iter().zip(x) {
            match *c {
                Coordinate::Normal { point, normal } => {
                    p[point][0] += t * normal.x;
                    p[point][1] += t * normal.y;
                }
                Coordinate::End { point, coord } => p[point][coord] += t,
                Coordinate::Other { .. } => {}
            }
        }
        p
    }

    fn values(&self, ctx: &Context, plan: &ProfilePlan, x: &[f64]) -> Vec<f64> {
        let mut others = self.start.clone();
        for (c, &t) in self.coordinates.iter().zip(x) {
            if let Coordinate::Other { variable, range } = *c {
                others[variable] += t * range;
            }
        }
        plan.values(ctx, &self.profile(x), &others)
    }
}

struct ProfileProblem<'c, 'a> {
    ctx: &'c mut Context<'a>,
    plan: &'c ProfilePlan,
    frame: &'c Frame,
}

impl Problem for ProfileProblem<'_, '_> {
    fn dims(&self) -> usize {
        self.frame.coordinates.len()
    }

    fn traced(&mut self, x: &[f64], photons: u64) -> Option<Seen> {
        let values = self.frame.values(self.ctx, self.plan, x);
        let judged = self.ctx.judge(Phase::Refinement, &values, photons)?;
        let light = crate::target::axial_nodes(&judged.traced.table);
        Some(Seen {
            merit: judged.merit,
            residuals: self.plan.axial.residuals(&light),
        })
    }

    fn modelled(&self, x: &[f64]) -> Option<Vec<f64>> {
        self.plan.modelled(&self.frame.profile(x))
    }

    fn modelled_coordinate(&self, k: usize) -> bool {
        self.plan.model.is_some()
            && self.frame.coordinates.len() > TRACED_DIMS
            && !matches!(self.frame.coordinates[k], Coordinate::Other { .. })
    }

    fn step(&self, k: usize) -> f64 {
        match self.frame.coordinates[k] {
            Coordinate::Other { .. } => OTHER_STEP,
            _ if !self.modelled_coordinate(k) => TRACED_STEP_M,
            _ => PROFILE_STEP_M,
        }
    }
}

/// The profile's coordinates at `values`: each interior point's normal
/// (from the Catmull-Rom tangent through its neighbours), the free ends,
/// the other variables.
fn coordinates(ctx: &Context, plan: &ProfilePlan, profile: &[[f64; 2]]) -> Vec<Coordinate> {
    let part = plan.geometry.part;
    let n = profile.len();
    let mut out = Vec::new();
    for (variable, v) in ctx.variables.iter().enumerate() {
        match v.place {
            Place::ProfilePoint {
                part: p,
                point,
                coord,
            } if p == part => {
                // Few points: both coordinates (with three interior points
                // where they sit along the curve shapes it as much as
                // across); many: across the curve only.
                if point == 0 || point + 1 == n || n <= FEW_POINTS {
                    out.push(Coordinate::End { point, coord });
                } else if coord == 0 {
                    let tangent = (DVec2::from_array(profile[point + 1])
                        - DVec2::from_array(profile[point - 1]))
                    .normalize_or_zero();
                    out.push(Coordinate::Normal {
                        point,
                        normal: DVec2::new(-tangent.y, tangent.x),
                    });
                }
            }
            _ => out.push(Coordinate::Other {
                variable,
                range: v.upper - v.lower,
            }),
        }
    }
    out
}

/// Refines a profile design from `values` (merit `merit` at
/// [`PHASE_PHOTONS`]), through every stage's photons or, with
/// `max_photons`, up to those.
pub fn refine_profile(
    ctx: &mut Context,
    plan: &ProfilePlan,
    values: Vec<f64>,
    merit: f64,
    max_photons: Option<u64>,
) -> Found {
    let Some(reference) = plan.profile(ctx, &values) else {
        return unrefined(values, merit);
    };
    let frame = Frame {
        coordinates: coordinates(ctx, plan, &reference),
        reference,
        start: values.clone(),
    };
    let limits = Limits {
        deadline: ctx.deadline(),
        interrupt: ctx.interrupt,
        photons: PHASE_PHOTONS,
        max_photons: max_photons
            .or(ctx.budget().max_photons)
            .unwrap_or(LAST_PHOTONS)
            .max(PHASE_PHOTONS),
        traces: ctx
            .budget()
            .evaluations
            .map(|n| n.saturating_sub(ctx.traced() as u64)),
    };
    let dims = frame.coordinates.len();
    let mut problem = ProfileProblem {
        ctx,
        plan,
        frame: &frame,
    };
    let refined = refine::refine(&mut problem, vec![0.0; dims], None, limits);
    let Some(r) = refined else {
        return unrefined(values, merit);
    };
    let values = frame.values(ctx, plan, &r.x);
    let noise = if max_photons.is_some() {
        0.0
    } else {
        noise_of(ctx, &values, r.photons, r.seen.merit)
    };
    Found {
        values,
        merit: r.seen.merit,
        photons: r.photons,
        noise,
        history: Vec::new(),
        stopped: if r.converged {
            Stopped::Converged
        } else {
            ctx.spent().unwrap_or(Stopped::Time)
        },
    }
}

/// A design left as it was found.
fn unrefined(values: Vec<f64>, merit: f64) -> Found {
    Found {
        values,
        merit,
        photons: PHASE_PHOTONS,
        noise: 0.0,
        history: Vec::new(),
        stopped: Stopped::Converged,
    }
}

/// The merit's photon noise at `values`: the same candidate traced with
/// a second seed (one standard deviation of the difference).
fn noise_of(ctx: &mut Context, values: &[f64], photons: u64, merit: f64) -> f64 {
    if ctx.spent().is_some() {
        return 0.0;
    }
    let Some(scene) = crate::variables::apply(&ctx.start, &ctx.variables, values) else {
        return 0.0;
    };
    let mut other = ctx
        .evaluator
        .with_seed(ctx.evaluator.seed().wrapping_add(0x9e37_79b9));
    match other.trace(&scene, photons) {
        Ok(t) => (ctx.merit_of(&t) - merit).abs() / std::f64::consts::SQRT_2,
        Err(_) => 0.0,
    }
}

/// Refines any other design with the tracer's loop from `values`.
pub fn refine_generic(ctx: &mut Context, values: &[f64]) -> Found {
    let x0: Vec<f64> = values
        .iter()
        .zip(&ctx.variables)
        .map(|(&x, v)| v.fraction(x))
        .collect();
    let before = ctx.history.elapsed();
    let budget = crate::Budget {
        time: ctx
            .budget()
            .time
            .saturating_sub(before)
            .max(std::time::Duration::from_millis(1)),
        evaluations: ctx
            .budget()
            .evaluations
            .map(|n| n.saturating_sub(ctx.traced() as u64).max(1)),
        ..ctx.budget()
    };
    let found = match ctx.aim.target() {
        Target::Distribution { .. } if ctx.request.least_squares => {
            crate::search::least_squares::fit(
                &ctx.start,
                &ctx.variables,
                x0,
                &ctx.aim,
                &mut ctx.evaluator,
                budget,
                ctx.interrupt,
                ctx.progress,
                ctx.history.frame(),
            )
        }
        _ => crate::search::optimise::optimise(
            &ctx.start,
            &ctx.variables,
            x0,
            &ctx.aim,
            &mut ctx.evaluator,
            ctx.lamp_flux_lm,
            budget,
            crate::search::optimise::FirstStage::default(),
            ctx.interrupt,
            ctx.progress,
            ctx.history.frame(),
        ),
    };
    let mut found = found;
    ctx.history
        .absorb(std::mem::take(&mut found.history), before);
    found
}
