//! The design as a pipeline of phases ([`Phase`]), each a function from
//! the shared [`Context`] to its outcome:
//!
//! 1. [`start`]: the start scene traced as it is;
//! 2. [`direct`]: what the geometry can reach, and the point-source
//!    direct design between the fixed ends with as many profile points
//!    as the target needs;
//! 3. [`correction`]: that design corrected for the extended source by
//!    feedback through the tracer;
//! 4. [`refinement`]: a local refinement with the tracer in the loop;
//! 5. [`fallback`]: the meridian model's global search, where the
//!    mapping cannot represent the target;
//! 6. [`survey`]: one or two variables traced across their bounds before
//!    the refinement, and how far each term goes there.
//!
//! Phases 2, 3 and 5 apply to a revolved mirror toward a rotationally
//! symmetric distribution; every other design is a start, a survey
//! where it varies one or two numbers, and a refinement.

pub mod correction;
pub mod direct;
pub mod fallback;
pub mod refinement;
pub mod start;
pub mod survey;

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

use lucerna_scene::Scene;

use crate::history::{History, Phase, Progress};
use crate::merit::{Aim, AxialTarget};
use crate::model::direct::Geometry;
use crate::model::meridian::MeridianModel;
use crate::traced::evaluate::{Evaluator, Traced};
use crate::variables::{self, Place, Variable};
use crate::{Budget, DesignRequest, Stopped};

/// Photons of each candidate a phase traces before the refinement's
/// later stages (common random numbers: the same photons every time),
/// and of the refinement's last stage.
pub const PHASE_PHOTONS: u64 = 1_600_000;
pub const LAST_PHOTONS: u64 = 6_400_000;

/// What every phase shares.
pub struct Context<'a> {
    pub request: &'a DesignRequest,
    /// The scene the variables apply to (the start, its varied profile
    /// resampled to the design's point count where that changed).
    pub start: Scene,
    pub scene_dir: PathBuf,
    pub variables: Vec<Variable>,
    pub aim: Aim,
    pub evaluator: Evaluator,
    pub lamp_flux_lm: f64,
    pub history: History,
    pub interrupt: &'a AtomicBool,
    pub progress: &'a mut dyn FnMut(&Progress),
    /// The best traced candidate at [`PHASE_PHOTONS`] so far: values and
    /// merit.
    pub best: Option<(Vec<f64>, f64)>,
    /// What the user should know (a target designed to its mean over C).
    pub warnings: Vec<String>,
}

impl std::fmt::Debug for Context<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Context")
            .field("variables", &self.variables.len())
            .field("traced", &self.history.len())
            .finish()
    }
}

/// A traced candidate and its merit.
#[derive(Debug, Clone)]
pub struct Judged {
    pub merit: f64,
    pub traced: Traced,
}

impl Context<'_> {
    pub fn budget(&self) -> Budget {
        self.request.budget
    }

    /// When the design must end.
    pub fn deadline(&self) -> Instant {
        self.history.began() + self.request.budget.time
    }

    /// Why the design must stop now, if it must.
    pub fn spent(&self) -> Option<Stopped> {
        self.request
            .budget
            .spent(self.history.began(), self.traced(), self.interrupt)
    }

    /// Candidates traced so far.
    pub fn traced(&self) -> usize {
        self.history.traced()
    }

    /// The start's values.
    pub fn start_values(&self) -> Vec<f64> {
        self.variables.iter().map(|v| v.start).collect()
    }

    /// Whether `values` lie within the variables' bounds.
    pub fn in_bounds(&self, values: &[f64]) -> bool {
        values
            .iter()
            .zip(&self.variables)
            .all(|(&x, v)| (v.lower..=v.upper).contains(&x))
    }

    /// Traces the candidate `values` with `photons` for `phase` and
    /// records it; None where it is refused or out of bounds.
    pub fn judge(&mut self, phase: Phase, values: &[f64], photons: u64) -> Option<Judged> {
        let judged = self
            .in_bounds(values)
            .then(|| variables::apply(&self.start, &self.variables, values))
            .flatten()
            .and_then(|scene| self.evaluator.trace(&scene, photons).ok())
            .map(|traced| Judged {
                merit: self.merit_of(&traced),
                traced,
            });
        let measure = match self.aim.target() {
            crate::Target::Spec(_) => "spec",
            crate::Target::Distribution { .. } => "l2",
        };
        self.history.record(
            phase,
            photons,
            judged.as_ref().map(|j| j.merit),
            measure,
            values.to_vec(),
            self.progress,
        );
        if let Some(j) = &judged
            && photons == PHASE_PHOTONS
            && self.best.as_ref().is_none_or(|b| j.merit < b.1)
        {
            self.best = Some((values.to_vec(), j.merit));
        }
        judged
    }

    /// A traced candidate's merit.
    pub fn merit_of(&self, traced: &Traced) -> f64 {
        crate::search::optimise::merit_of(&self.aim, traced, self.lamp_flux_lm, &traced.opening)
    }
}

/// A revolved mirror's profile designed toward a rotationally symmetric
/// distribution: what the direct design, its correction and the
/// profile's refinement work with.
#[derive(Debug, Clone)]
pub struct ProfilePlan {
    pub geometry: Geometry,
    /// The meridian model (a specular mirror), tabulating on the target's
    /// γ nodes.
    pub model: Option<MeridianModel>,
    pub axial: AxialTarget,
}

impl ProfilePlan {
    /// The plan of `variables` toward the aim, where they vary exactly
    /// one revolved mirror's profile (and perhaps other numbers) of a
    /// geometry a direct design applies to; else why not.
    pub fn of(start: &Scene, variables: &[Variable], aim: &Aim) -> Result<ProfilePlan, String> {
        let axial = AxialTarget::of(aim.target())
            .filter(|_| aim.target().rotationally_symmetric())
            .ok_or("the target is not a distribution the same in every C-plane")?;
        let mut parts: Vec<usize> = variables
            .iter()
            .filter_map(|v| match v.place {
                Place::ProfilePoint { part, .. } => Some(part),
                _ => None,
            })
            .collect();
        parts.dedup();
        let [part] = parts.as_slice() else {
            return Err("the design varies no profile, or more than one".to_owned());
        };
        let geometry = Geometry::of(start, *part).map_err(|e| e.to_string())?;
        let model = geometry.model(&axial.gammas_deg);
        Ok(ProfilePlan {
            geometry,
            model,
            axial,
        })
    }

    /// The varied profile of the scene `values` make.
    pub fn profile(&self, ctx: &Context, values: &[f64]) -> Option<Vec<[f64; 2]>> {
        let scene = variables::apply(&ctx.start, &ctx.variables, values)?;
        variables::profile(&scene.parts[self.geometry.part].shape).map(<[_]>::to_vec)
    }

    /// The values of `ctx`'s variables with the varied profile set to
    /// `profile` (its point count the start's) and the other variables at
    /// `others` (the values they take otherwise).
    pub fn values(&self, ctx: &Context, profile: &[[f64; 2]], others: &[f64]) -> Vec<f64> {
        ctx.variables
            .iter()
            .zip(others)
            .map(|(v, &x)| match v.place {
                Place::ProfilePoint { part, point, coord } if part == self.geometry.part => {
                    profile.get(point).map_or(x, |p| p[coord])
                }
                _ => x,
            })
            .collect()
    }

    /// The model's residuals of a profile against the target (None: no
    /// model, or a profile it cannot sample).
    pub fn modelled(&self, profile: &[[f64; 2]]) -> Option<Vec<f64>> {
        let light = self.model.as_ref()?.at_nodes(profile)?;
        Some(self.axial.residuals(&light))
    }
}
