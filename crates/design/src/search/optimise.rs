//! The tracer in the loop: Nelder–Mead (argmin) on the merit of traced
//! candidates, in stages of growing photon counts. Within a stage every
//! candidate is traced with the same photons (common random numbers), so
//! two nearby candidates differ by their geometry, not by their noise; a
//! stage ends when the simplex's merits agree within the merit's photon
//! noise (measured with a second seed), and the next one starts from the
//! best with four times the photons and half the simplex.

use std::cell::RefCell;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use argmin::core::{CostFunction, Error as ArgminError, Executor};
use argmin::solver::neldermead::NelderMead;
use lucerna_photometry::Dimensions;
use lucerna_scene::Scene;

use crate::history::{Frame, Phase, Progress, Record};
use crate::merit::Aim;
use crate::traced::evaluate::{Evaluator, Refused, Traced};
use crate::variables::{Variable, apply};
use crate::{Budget, Found, Stopped};

/// Photons of the first stage, and the most any stage traces.
pub const FIRST_STAGE_PHOTONS: u64 = 100_000;
pub const LAST_STAGE_PHOTONS: u64 = 6_400_000;

/// The tracer's loop's first stage: its photons and its simplex's size
/// (a share of each variable's range).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FirstStage {
    pub photons: u64,
    pub step: f64,
}

impl Default for FirstStage {
    fn default() -> FirstStage {
        FirstStage {
            photons: FIRST_STAGE_PHOTONS,
            step: 0.15,
        }
    }
}

/// The state shared by the cost function's calls.
struct Loop<'a> {
    start: &'a Scene,
    variables: &'a [Variable],
    aim: &'a Aim,
    evaluator: RefCell<&'a mut Evaluator>,
    photons: u64,
    lamp_flux_lm: f64,
    penalty: f64,
    budget: Budget,
    began: Instant,
    interrupt: &'a AtomicBool,
    history: RefCell<&'a mut Vec<Record>>,
    best: RefCell<(f64, Vec<f64>)>,
    stage: usize,
    noise: f64,
    progress: RefCell<&'a mut dyn FnMut(&Progress)>,
    frame: std::sync::Arc<Frame>,
    halted: std::cell::Cell<Option<Stopped>>,
}

impl Loop<'_> {
    fn values(&self, x: &[f64]) -> Vec<f64> {
        crate::variables::values_at(self.variables, x)
    }

    fn halt(&self) -> Option<Stopped> {
        self.budget
            .spent(self.began, self.history.borrow().len(), self.interrupt)
    }

    /// The merit of normalised parameters `x`; a candidate outside the
    /// bounds or refused costs the penalty and its distance outside.
    fn merit(&self, x: &[f64]) -> Result<f64, Refused> {
        let outside: f64 = x.iter().map(|t| (-t).max(0.0) + (t - 1.0).max(0.0)).sum();
        if outside > 0.0 {
            return Err(Refused::Invalid(format!("{outside} outside the bounds")));
        }
        let values = self.values(x);
        let scene = apply(self.start, self.variables, &values)
            .ok_or_else(|| Refused::Invalid("the shape refuses the value".to_owned()))?;
        let traced = self.evaluator.borrow_mut().trace(&scene, self.photons)?;
        Ok(stage_merit_of(
            self.aim,
            &traced,
            self.lamp_flux_lm,
            blur_of(self.stage),
        ))
    }
}

/// A traced candidate's merit.
pub fn merit_of(aim: &Aim, traced: &Traced, lamp_flux_lm: f64, opening: &Dimensions) -> f64 {
    aim.merit(
        &traced.table,
        traced.map.light_output_ratio(),
        lamp_flux_lm,
        opening,
    )
}

/// A traced candidate's merit at a stage blurred by `sigma_deg`.
fn stage_merit_of(aim: &Aim, traced: &Traced, lamp_flux_lm: f64, sigma_deg: f64) -> f64 {
    aim.stage_merit(
        &traced.table,
        traced.map.light_output_ratio(),
        lamp_flux_lm,
        &traced.opening,
        sigma_deg,
    )
}

/// The blur of each stage's comparison (degrees of γ): the first stages
/// see where the light goes, the last its every detail.
const STAGE_BLUR_DEG: [f64; 1] = [0.0];

fn blur_of(stage: usize) -> f64 {
    STAGE_BLUR_DEG[stage.min(STAGE_BLUR_DEG.len() - 1)]
}

impl CostFunction for Loop<'_> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, x: &Vec<f64>) -> Result<f64, ArgminError> {
        // argmin unwraps the costs of its first simplex, so a halt is not
        // an error: the solver is left to run out its iterations on a
        // constant cost, tracing nothing more.
        if let Some(why) = self.halted.get().or_else(|| self.halt()) {
            self.halted.set(Some(why));
            return Ok(self.penalty * 1e3);
        }
        let merit = self.merit(x);
        let values = self.values(x);
        let evaluation = self.history.borrow().len() as u64;
        let record = Record {
            evaluation,
            elapsed_s: self.began.elapsed().as_secs_f64(),
            photons: self.photons,
            merit: merit.as_ref().ok().copied(),
            measure: match self.aim.target() {
                crate::Target::Spec(_) => "spec".to_owned(),
                crate::Target::Distribution { .. } => match blur_of(self.stage) {
                    b if b > 0.0 => format!("l2 blur {b}°"),
                    _ => "l2".to_owned(),
                },
            },
            phase: Phase::Refinement,
            values: values.clone(),
        };
        self.history.borrow_mut().push(record.clone());
        let cost = match merit {
            Ok(m) => {
                let mut best = self.best.borrow_mut();
                if m < best.0 {
                    *best = (m, x.clone());
                }
                m
            }
            Err(_) => {
                let outside: f64 = x.iter().map(|t| (-t).max(0.0) + (t - 1.0).max(0.0)).sum();
                self.penalty * (1.0 + outside)
            }
        };
        let best = self.best.borrow();
        (self.progress.borrow_mut())(&Progress {
            elapsed: self.began.elapsed(),
            phase: Phase::Refinement,
            evaluations: evaluation + 1,
            stage: self.stage,
            photons: self.photons,
            best_merit: best.0,
            noise: self.noise,
            best_values: self.values(&best.1),
            record,
            frame: self.frame.clone(),
            reach: None,
        });
        Ok(cost)
    }
}

/// Optimises `variables` of `start` toward `aim`, from normalised
/// parameters `x0`.
#[allow(clippy::too_many_arguments)]
pub fn optimise(
    start: &Scene,
    variables: &[Variable],
    x0: Vec<f64>,
    aim: &Aim,
    evaluator: &mut Evaluator,
    lamp_flux_lm: f64,
    budget: Budget,
    first: FirstStage,
    interrupt: &AtomicBool,
    progress: &mut dyn FnMut(&Progress),
    frame: std::sync::Arc<Frame>,
) -> Found {
    let began = Instant::now();
    let n = variables.len();
    let mut history: Vec<Record> = Vec::new();
    let mut best_x = x0;
    let mut photons = first.photons.min(budget.last_stage_photons());
    let mut step = first.step;
    let mut stage = 0;
    let mut best_merit;
    let mut noise = 0.0;
    let stopped = loop {
        // The stage's noise: the best candidate with a second seed.
        let values: Vec<f64> = crate::variables::values_at(variables, &best_x);
        let scene = apply(start, variables, &values);
        let mut stage_merit = f64::INFINITY;
        if let Some(scene) = &scene {
            let at = |e: &mut Evaluator| e.trace(scene, photons).ok();
            if let Some(t) = at(evaluator) {
                stage_merit = stage_merit_of(aim, &t, lamp_flux_lm, blur_of(stage));
                let seed = evaluator.seed();
                let mut other = evaluator.with_seed(seed.wrapping_add(0x9e37_79b9));
                if let Some(t2) = at(&mut other) {
                    let m2 = stage_merit_of(aim, &t2, lamp_flux_lm, blur_of(stage));
                    noise = (stage_merit - m2).abs() / std::f64::consts::SQRT_2;
                }
            }
        }
        best_merit = stage_merit;
        let penalty = (4.0 * stage_merit).max(10.0);
        // The simplex: the best and one step along each variable (inward
        // where a step would leave the bounds).
        let mut simplex = vec![best_x.clone()];
        for i in 0..n {
            let mut p = best_x.clone();
            p[i] = if p[i] + step <= 1.0 {
                p[i] + step
            } else {
                p[i] - step
            };
            simplex.push(p);
        }
        let problem = Loop {
            start,
            variables,
            aim,
            evaluator: RefCell::new(&mut *evaluator),
            photons,
            lamp_flux_lm,
            penalty,
            budget,
            began,
            interrupt,
            history: RefCell::new(&mut history),
            best: RefCell::new((stage_merit, best_x.clone())),
            stage,
            noise,
            progress: RefCell::new(&mut *progress),
            frame: frame.clone(),
            halted: std::cell::Cell::new(None),
        };
        let tolerance = noise.max(1e-6 * stage_merit.abs()).max(1e-12);
        let solver = match NelderMead::new(simplex).with_sd_tolerance(tolerance) {
            Ok(s) => s,
            Err(_) => break Stopped::Converged,
        };
        let max_iterations = 40 * (n as u64 + 1);
        let result = Executor::new(problem, solver)
            .configure(|state| state.max_iters(max_iterations))
            .run();
        // The best is read from the loop: the solver's own best may be a
        // halted run's constant.
        let from_history = |history: &[Record]| {
            best_in(history, variables, photons).unwrap_or((stage_merit, best_x.clone()))
        };
        let (m, x, halted) = match result.ok().and_then(|r| r.problem.problem) {
            Some(problem) => {
                let halted = problem.halted.get();
                let (m, x) = problem.best.into_inner();
                (m, x, halted)
            }
            None => {
                let (m, x) = from_history(&history);
                (m, x, None)
            }
        };
        // Each stage's merits are its own (photons, blur): its best is
        // the start of the next.
        best_merit = m;
        best_x = x;
        if let Some(why) = halted {
            break why;
        }
        if photons >= budget.last_stage_photons() && step <= 0.01 && blur_of(stage) == 0.0 {
            break Stopped::Converged;
        }
        photons = (photons * 4).min(budget.last_stage_photons());
        step = (step * 0.5).max(0.005);
        stage += 1;
    };
    Found {
        values: crate::variables::values_at(variables, &best_x),
        merit: best_merit,
        photons,
        noise,
        history,
        stopped,
    }
}

/// The best record at `photons` (a stage's), as merit and normalised
/// parameters.
fn best_in(history: &[Record], variables: &[Variable], photons: u64) -> Option<(f64, Vec<f64>)> {
    history
        .iter()
        .filter(|r| r.photons == photons)
        .filter_map(|r| Some((r.merit?, r)))
        .min_by(|a, b| a.0.total_cmp(&b.0))
        .map(|(m, r)| {
            (
                m,
                variables
                    .iter()
                    .zip(&r.values)
                    .map(|(v, &x)| v.fraction(x))
                    .collect(),
            )
        })
}
