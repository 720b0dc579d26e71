//! A profile polished in the meridian model alone: Levenberg–Marquardt
//! ([`super::refine`], without a tracer) on the model's light, first on
//! where the light goes (the 2-Wasserstein distance, smooth in the
//! geometry), then on its intensity (the relative L2), each interior
//! control point moving along the profile's normal. Milliseconds a
//! candidate, so many starts can be polished before the tracer judges the
//! best.

use std::sync::atomic::AtomicBool;
use std::time::Instant;

use glam::DVec2;

use crate::merit::AxialTarget;
use crate::model::meridian::MeridianModel;
use crate::search::refine::{self, Limits, Problem, Seen};

/// The finite-difference step of a control point (m).
const STEP_M: f64 = 20e-6;

/// What a polish compares.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Measure {
    /// The 2-Wasserstein distance between the γ distributions of flux.
    Wasserstein,
    /// The relative L2 difference of intensity.
    L2,
}

struct InModel<'a> {
    model: &'a MeridianModel,
    axial: &'a AxialTarget,
    measure: Measure,
    reference: Vec<[f64; 2]>,
    normals: Vec<DVec2>,
}

impl InModel<'_> {
    fn profile(&self, x: &[f64]) -> Vec<[f64; 2]> {
        let mut p = self.reference.clone();
        for (k, t) in x.iter().enumerate() {
            p[k + 1][0] += t * self.normals[k].x;
            p[k + 1][1] += t * self.normals[k].y;
        }
        p
    }

    fn residuals(&self, x: &[f64]) -> Option<Vec<f64>> {
        let light = self.model.at_nodes(&self.profile(x))?;
        match self.measure {
            Measure::Wasserstein => self.axial.quantile_residuals(&light),
            Measure::L2 => Some(self.axial.residuals(&light)),
        }
    }
}

impl Problem for InModel<'_> {
    fn dims(&self) -> usize {
        self.normals.len()
    }
    fn traced(&mut self, x: &[f64], _photons: u64) -> Option<Seen> {
        let residuals = self.residuals(x)?;
        Some(Seen {
            merit: residuals.iter().map(|r| r * r).sum::<f64>().sqrt(),
            residuals,
        })
    }
    // The model is the truth here: its own differences, plain
    // Levenberg–Marquardt (no space mapping).
    fn modelled(&self, _x: &[f64]) -> Option<Vec<f64>> {
        None
    }
    fn modelled_coordinate(&self, _k: usize) -> bool {
        false
    }
    fn step(&self, _k: usize) -> f64 {
        STEP_M
    }
}

/// Each interior point's normal (across the chord of its neighbours).
pub fn normals(profile: &[[f64; 2]]) -> Vec<DVec2> {
    (1..profile.len().saturating_sub(1))
        .map(|i| {
            let t = (DVec2::from_array(profile[i + 1]) - DVec2::from_array(profile[i - 1]))
                .normalize_or_zero();
            DVec2::new(-t.y, t.x)
        })
        .collect()
}

/// `profile` (its ends fixed) polished by each measure in turn until
/// `deadline`; the polished profile and its model L2.
pub fn polish(
    model: &MeridianModel,
    axial: &AxialTarget,
    profile: Vec<[f64; 2]>,
    measures: &[Measure],
    deadline: Instant,
    interrupt: &AtomicBool,
) -> Option<(Vec<[f64; 2]>, f64)> {
    let mut p = profile;
    for &measure in measures {
        let mut problem = InModel {
            model,
            axial,
            measure,
            normals: normals(&p),
            reference: p.clone(),
        };
        let dims = problem.dims();
        let limits = Limits {
            deadline,
            interrupt,
            photons: 1,
            max_photons: 1,
            traces: None,
        };
        if let Some(r) = refine::refine(&mut problem, vec![0.0; dims], None, limits) {
            p = problem.profile(&r.x);
        }
    }
    let light = model.at_nodes(&p)?;
    let l2 = axial.relative_l2_between(&light, &axial.intensity);
    Some((p, l2))
}
