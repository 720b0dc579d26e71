//! The near-field evaluation of Luksch et al. 2020, section 6: a 1 × 1
//! opening at heights 0.1, 1.0 and 2.5 above a ground plane, tilted so that
//! the angle between its normal and the ground's is π/2, 5π/8, 3π/4, 7π/8
//! or π, the ground seen over a 5 × 5 region centred below the light. The
//! cubature's illuminance images are compared with Monte Carlo integration
//! of eq. 1 (MIS of area and profile sampling, `reference::mis_illuminance`,
//! which narrow beams need); the five orientations are stitched into one image per height,
//! as in the paper's Figure 10.

use std::sync::Arc;

use glam::{DMat3, DVec3};
use rayon::prelude::*;

use crate::cubature::{CubatureRule, illuminance_with, point_illuminance};
use crate::light::{Opening, PlacedLight};
use crate::profile::ProfileGrid;
use crate::reference::{ProfileDirectionSampler, mis_illuminance, monte_carlo_illuminance};

pub const HEIGHTS: [f64; 3] = [0.1, 1.0, 2.5];
/// Angles between the opening's normal and the ground's normal (× π).
pub const ORIENTATIONS: [f64; 5] = [0.5, 0.625, 0.75, 0.875, 1.0];
/// Side of the ground region shown (units of the opening's side).
pub const REGION: f64 = 5.0;

/// Resolution and effort of one evaluation.
#[derive(Debug, Clone, Copy)]
pub struct NearFieldSettings {
    /// Ground samples per side of each image.
    pub pixels: usize,
    /// Samples per technique of the MIS reference per ground sample.
    pub reference_samples: usize,
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

fn ground_points(pixels: usize) -> Vec<DVec3> {
    let mut out = Vec::with_capacity(pixels * pixels);
    for j in 0..pixels {
        for i in 0..pixels {
            let x = ((i as f64 + 0.5) / pixels as f64 - 0.5) * REGION;
            let y = ((j as f64 + 0.5) / pixels as f64 - 0.5) * REGION;
            out.push(DVec3::new(x, y, 0.0));
        }
    }
    out
}

/// Illuminance images (stitched over the five orientations) of one height:
/// Monte Carlo reference, and the cubature by each rule.
#[derive(Debug, Clone)]
pub struct StitchedImages {
    pub reference: Vec<f64>,
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
        paper: Vec::new(),
        exact_cosine: Vec::new(),
        prefiltered: Vec::new(),
        point: Vec::new(),
    };
    let sampler = ProfileDirectionSampler::new(profile);
    for (k, &o) in ORIENTATIONS.iter().enumerate() {
        let light = evaluation_light(profile.clone(), height, o);
        let rows: Vec<(f64, f64, f64, f64, f64)> = points
            .par_iter()
            .enumerate()
            .map(|(i, &x)| {
                let seed = (k * points.len() + i) as u64;
                (
                    match &sampler {
                        Some(sampler) => mis_illuminance(
                            &light,
                            sampler,
                            x,
                            DVec3::Z,
                            settings.reference_samples,
                            seed,
                        ),
                        None => monte_carlo_illuminance(
                            &light,
                            x,
                            DVec3::Z,
                            settings.reference_samples,
                            seed,
                        ),
                    },
                    illuminance_with(&light, x, DVec3::Z, CubatureRule::Paper).lux,
                    illuminance_with(&light, x, DVec3::Z, CubatureRule::ExactCosine).lux,
                    illuminance_with(&light, x, DVec3::Z, CubatureRule::Prefiltered).lux,
                    point_illuminance(&light, x, DVec3::Z).lux,
                )
            })
            .collect();
        for (r, p, e, f, q) in rows {
            images.reference.push(r);
            images.paper.push(p);
            images.exact_cosine.push(e);
            images.prefiltered.push(f);
            images.point.push(q);
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
