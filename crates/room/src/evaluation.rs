//! The near-field evaluation of Luksch et al. 2020, section 6: a 1 × 1
//! opening at heights 0.1, 1.0 and 2.5 above a ground plane, tilted so that
//! the angle between its normal and the ground's is π/2, 5π/8, 3π/4, 7π/8
//! or π, the ground seen over a 5 × 5 region centred below the light. The
//! shading rules' illuminance images are compared with the exact
//! quadrature of eq. 1 (`reference::exact_illuminance`), or with Monte Carlo
//! (MIS of area and profile sampling, `reference::mis_illuminance`); the
//! five orientations are stitched into one image per height, as in the
//! paper's Figure 10. The ground is sampled corner to corner (101 points
//! are the protocol's 5 cm apart).

use std::sync::Arc;

use glam::{DMat3, DVec3};
use rayon::prelude::*;

use crate::cubature::{CubatureRule, illuminance_with, point_illuminance};
use crate::light::{Opening, PlacedLight};
use crate::profile::ProfileGrid;
use crate::reference::exact_illuminance;
use crate::reference::{ProfileDirectionSampler, mis_illuminance, monte_carlo_illuminance};

pub const HEIGHTS: [f64; 3] = [0.1, 1.0, 2.5];
/// Angles between the opening's normal and the ground's normal (× π).
pub const ORIENTATIONS: [f64; 5] = [0.5, 0.625, 0.75, 0.875, 1.0];
/// Side of the ground region shown (units of the opening's side).
pub const REGION: f64 = 5.0;

/// The ground truth an evaluation compares with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Reference {
    /// `reference::exact_illuminance` to this relative accuracy.
    Exact { relative: f64 },
    /// MIS Monte Carlo with this many samples per technique and point.
    MonteCarlo { samples: usize },
}

/// Resolution and effort of one evaluation.
#[derive(Debug, Clone, Copy)]
pub struct NearFieldSettings {
    /// Ground samples per side of each image.
    pub pixels: usize,
    pub reference: Reference,
}

/// The 1 × 1 opening at height h, its normal at angle `orientation·π`
/// from the ground's normal (+z), tilted about x.
pub fn evaluation_light(profile: Arc<ProfileGrid>, height: f64, orientation: f64) -> PlacedLight {
    let phi = std::f64::consts::PI * (1.0 - orientation);
    PlacedLight {
        profile,
        opening: Opening::Rectangle {
            length_m: 1.0,
            width_m: 1.0,
        },
        position: DVec3::new(0.0, 0.0, height),
        rotation: DMat3::from_rotation_x(phi),
    }
}

/// The ground points, row by row (y), x fastest, corner to corner of the
/// region: 101 per side are 5 cm apart.
pub fn ground_points(pixels: usize) -> Vec<DVec3> {
    let step = REGION / (pixels.max(2) - 1) as f64;
    let mut out = Vec::with_capacity(pixels * pixels);
    for j in 0..pixels {
        for i in 0..pixels {
            out.push(DVec3::new(
                -0.5 * REGION + i as f64 * step,
                -0.5 * REGION + j as f64 * step,
                0.0,
            ));
        }
    }
    out
}

/// Illuminance images (stitched over the five orientations) of one height:
/// Monte Carlo reference, and the cubature by each rule.
#[derive(Debug, Clone)]
pub struct StitchedImages {
    pub reference: Vec<f64>,
    /// The default rule (`polar::illuminance`).
    pub polar: Vec<f64>,
    /// Distance of each point from its light's opening (m).
    pub distance_m: Vec<f64>,
    pub paper: Vec<f64>,
    pub exact_cosine: Vec<f64>,
    pub prefiltered: Vec<f64>,
    /// The far-field (point-light) baseline.
    pub point: Vec<f64>,
}

pub fn stitched_images(
    profile: &Arc<ProfileGrid>,
    height: f64,
    settings: NearFieldSettings,
) -> StitchedImages {
    let points = ground_points(settings.pixels);
    let mut images = StitchedImages {
        reference: Vec::new(),
        polar: Vec::new(),
        distance_m: Vec::new(),
        paper: Vec::new(),
        exact_cosine: Vec::new(),
        prefiltered: Vec::new(),
        point: Vec::new(),
    };
    let sampler = ProfileDirectionSampler::new(profile);
    for (k, &o) in ORIENTATIONS.iter().enumerate() {
        let light = evaluation_light(profile.clone(), height, o);
        let polygon = light.world_polygon();
        let rows: Vec<[f64; 7]> = points
            .par_iter()
            .enumerate()
            .map(|(i, &x)| {
                let seed = (k * points.len() + i) as u64;
                let reference = match (settings.reference, &sampler) {
                    (Reference::Exact { relative }, _) => {
                        exact_illuminance(&light, x, DVec3::Z, relative)
                    }
                    (Reference::MonteCarlo { samples }, Some(sampler)) => {
                        mis_illuminance(&light, sampler, x, DVec3::Z, samples, seed)
                    }
                    (Reference::MonteCarlo { samples }, None) => {
                        monte_carlo_illuminance(&light, x, DVec3::Z, samples, seed)
                    }
                };
                let nearest = crate::cubature::closest_point_on_polygon(
                    &polygon,
                    light.normal(),
                    x - light.normal() * (x - light.position).dot(light.normal()),
                );
                [
                    reference,
                    illuminance_with(&light, x, DVec3::Z, CubatureRule::Polar).lux,
                    illuminance_with(&light, x, DVec3::Z, CubatureRule::Paper).lux,
                    illuminance_with(&light, x, DVec3::Z, CubatureRule::ExactCosine).lux,
                    illuminance_with(&light, x, DVec3::Z, CubatureRule::Prefiltered).lux,
                    point_illuminance(&light, x, DVec3::Z).lux,
                    (nearest - x).length(),
                ]
            })
            .collect();
        for [r, polar, p, e, f, q, d] in rows {
            images.reference.push(r);
            images.polar.push(polar);
            images.paper.push(p);
            images.exact_cosine.push(e);
            images.prefiltered.push(f);
            images.point.push(q);
            images.distance_m.push(d);
        }
    }
    images
}

/// Root-mean-square difference normalised by the reference's RMS.
pub fn nrms(image: &[f64], reference: &[f64]) -> f64 {
    let se: f64 = image
        .iter()
        .zip(reference)
        .map(|(a, r)| (a - r) * (a - r))
        .sum();
    let sr: f64 = reference.iter().map(|r| r * r).sum();
    if sr > 0.0 { (se / sr).sqrt() } else { 0.0 }
}

/// Root-mean-square difference normalised by the reference's mean (the
/// issue's and the paper's measure; `nrms` divides by the RMS instead).
pub fn mean_normalised_rms(image: &[f64], reference: &[f64]) -> f64 {
    let n = reference.len().max(1) as f64;
    let se: f64 = image
        .iter()
        .zip(reference)
        .map(|(a, r)| (a - r) * (a - r))
        .sum();
    let mean: f64 = reference.iter().sum::<f64>() / n;
    if mean > 0.0 {
        (se / n).sqrt() / mean
    } else {
        0.0
    }
}

/// Per point |image − reference| / reference, with a floor of 1 % of the
/// reference's peak (points the light barely reaches).
pub fn relative_errors(image: &[f64], reference: &[f64]) -> Vec<f64> {
    let peak = reference.iter().copied().fold(0.0, f64::max);
    image
        .iter()
        .zip(reference)
        .map(|(a, r)| (a - r).abs() / r.max(0.01 * peak).max(1e-300))
        .collect()
}
