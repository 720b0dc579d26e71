//! A sample of traced photons as polylines, for drawing: what engineers
//! look at first to find a stray reflection.

use glam::Vec3;

use crate::cpu::{Fate, trace_photon_recorded};
use crate::prepared::PreparedScene;
use crate::rng::PhotonRng;

/// One photon from its emitter to its end.
#[derive(Debug, Clone, PartialEq)]
pub struct PhotonPath {
    /// Where it left the emitter, then every surface point it reached (m,
    /// luminaire coordinates).
    pub points: Vec<Vec3>,
    pub fate: Fate,
    /// Surface interactions it survived.
    pub bounces: u32,
}

impl PhotonPath {
    /// The direction it left the luminaire in, if it escaped.
    pub fn escape_direction(&self) -> Option<Vec3> {
        match self.fate {
            Fate::Escaped(d) => Some(d.into()),
            _ => None,
        }
    }
}

/// The first `count` photons of a run with `seed` (iteration 0), traced
/// again with their points recorded: the very photons the run counted.
pub fn sample_photon_paths(
    scene: &PreparedScene,
    seed: u32,
    max_bounces: u32,
    count: u32,
) -> Vec<PhotonPath> {
    if scene.emitters.is_empty() {
        return Vec::new();
    }
    (0..count)
        .map(|photon| {
            let mut rng = PhotonRng::new(seed, 0, photon);
            let mut points = Vec::new();
            let (fate, bounces, _) =
                trace_photon_recorded(scene, max_bounces, &mut rng, |p| points.push(p.into()));
            PhotonPath {
                points,
                fate,
                bounces,
            }
        })
        .collect()
}

/// A photon leaving the luminaire: where it last touched a surface (or
/// left its emitter, if it escaped at once) and the way it went (m,
/// luminaire coordinates). The last interaction, not a crossing of some
/// bounding surface: it is where the light really leaves from, and needs
/// no surface of our choosing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EscapingRay {
    pub position: Vec3,
    pub direction: Vec3,
}

/// The first `wanted` photons of a run with `seed` (iteration 0, the run's
/// own first photons, then on in its stream) that leave the luminaire,
/// tracing at most `max_photons`; also returns the photons traced. Traced
/// in parallel in fixed chunks, kept in photon order: the same seed gives
/// the same rays.
pub fn escaping_rays(
    scene: &PreparedScene,
    seed: u32,
    max_bounces: u32,
    wanted: usize,
    max_photons: u32,
) -> (Vec<EscapingRay>, u32) {
    use rayon::prelude::*;
    const CHUNK: u32 = 16_384;
    let mut rays = Vec::with_capacity(wanted);
    let mut traced = 0u32;
    if scene.emitters.is_empty() {
        return (rays, 0);
    }
    while rays.len() < wanted && traced < max_photons {
        // Enough chunks for what is missing at the escape rate so far.
        let rate = if traced == 0 {
            1.0
        } else {
            (rays.len() as f64 / f64::from(traced)).max(1e-3)
        };
        let missing = ((wanted - rays.len()) as f64 / rate).ceil() as u64;
        let chunks = missing.div_ceil(u64::from(CHUNK)).clamp(1, 64) as u32;
        let start = traced;
        let batches: Vec<Vec<EscapingRay>> = (0..chunks)
            .into_par_iter()
            .map(|c| {
                let first = start.saturating_add(c * CHUNK);
                let last = first.saturating_add(CHUNK).min(max_photons);
                (first..last)
                    .filter_map(|photon| {
                        let mut rng = PhotonRng::new(seed, 0, photon);
                        let mut last_point = Vec3::ZERO;
                        let (fate, _, _) =
                            trace_photon_recorded(scene, max_bounces, &mut rng, |p| {
                                last_point = p.into();
                            });
                        match fate {
                            Fate::Escaped(d) => Some(EscapingRay {
                                position: last_point,
                                direction: d.into(),
                            }),
                            _ => None,
                        }
                    })
                    .collect()
            })
            .collect();
        traced = start.saturating_add(chunks * CHUNK).min(max_photons);
        for batch in batches {
            rays.extend(batch);
        }
    }
    rays.truncate(wanted);
    (rays, traced)
}
