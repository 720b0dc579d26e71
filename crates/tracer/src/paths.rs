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
