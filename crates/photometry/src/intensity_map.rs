//! The intensity map: escaped-photon counts per cube-map texel, with the
//! photon bookkeeping that turns them into candela.

use crate::cubemap::CubeMapLayout;
use crate::symmetry::TexelSymmetry;

/// Photon counts by escape direction. Every photon carries the same flux
/// `Φ_emitter / N_emitted` (lm), so the candela of a texel is
/// `count × Φ / N / Ω_texel`. Counts are u64: 10¹¹ photons and far beyond
/// cannot overflow.
#[derive(Debug, Clone, PartialEq)]
pub struct IntensityMap {
    pub layout: CubeMapLayout,
    /// Escaped photons per texel.
    pub counts: Vec<u64>,
    pub photons_emitted: u64,
    /// Photons absorbed by a surface (or by a dielectric's volume).
    pub photons_absorbed: u64,
    /// Photons still bouncing when the bounce limit cut them off.
    pub photons_cut_off: u64,
    /// Total flux of the emitters (lm).
    pub emitter_flux_lm: f64,
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum MergeMapError {
    #[error("cannot add maps of resolution {0} and {1}")]
    Resolution(u32, u32),
    #[error("cannot add maps of different emitter flux ({0} lm and {1} lm)")]
    Flux(f64, f64),
}

impl IntensityMap {
    pub fn new(layout: CubeMapLayout, emitter_flux_lm: f64) -> Self {
        IntensityMap {
            layout,
            counts: vec![0; layout.texel_count()],
            photons_emitted: 0,
            photons_absorbed: 0,
            photons_cut_off: 0,
            emitter_flux_lm,
        }
    }

    pub fn photons_escaped(&self) -> u64 {
        self.counts.iter().sum()
    }

    /// Whether `emitted = escaped + absorbed + cut off` holds exactly.
    pub fn is_balanced(&self) -> bool {
        self.photons_escaped() + self.photons_absorbed + self.photons_cut_off
            == self.photons_emitted
    }

    /// Flux carried by each photon (lm); zero before any photon.
    pub fn flux_per_photon_lm(&self) -> f64 {
        if self.photons_emitted == 0 {
            0.0
        } else {
            self.emitter_flux_lm / self.photons_emitted as f64
        }
    }

    /// Luminous intensity of every texel (cd).
    pub fn candela(&self) -> Vec<f64> {
        let phi = self.flux_per_photon_lm();
        let omega = self.layout.shared_solid_angles();
        self.counts
            .iter()
            .zip(omega.iter())
            .map(|(&c, &w)| c as f64 * phi / w)
            .collect()
    }

    /// Flux that left the luminaire (lm).
    pub fn escaped_flux_lm(&self) -> f64 {
        self.photons_escaped() as f64 * self.flux_per_photon_lm()
    }

    /// Light output ratio: escaped over emitted flux.
    pub fn light_output_ratio(&self) -> f64 {
        if self.photons_emitted == 0 {
            0.0
        } else {
            self.photons_escaped() as f64 / self.photons_emitted as f64
        }
    }

    /// The map of a luminaire with `symmetry`, each photon counted once in
    /// every image of its direction ([`TexelSymmetry::pool`]): as if
    /// `order` times the photons had been traced, so emitted, absorbed and
    /// cut-off photons scale by the order too and the balance stays exact;
    /// candela are the average over the images. `symmetry` must be of this
    /// map's layout.
    pub fn symmetrised(&self, symmetry: &TexelSymmetry) -> IntensityMap {
        debug_assert_eq!(symmetry.layout, self.layout);
        let order = symmetry.order() as u64;
        IntensityMap {
            layout: self.layout,
            counts: symmetry.pool(&self.counts),
            photons_emitted: self.photons_emitted * order,
            photons_absorbed: self.photons_absorbed * order,
            photons_cut_off: self.photons_cut_off * order,
            emitter_flux_lm: self.emitter_flux_lm,
        }
    }

    /// Adds an independent part of the same bake (counts add exactly).
    pub fn merge(&mut self, other: &IntensityMap) -> Result<(), MergeMapError> {
        if self.layout != other.layout {
            return Err(MergeMapError::Resolution(
                self.layout.resolution,
                other.layout.resolution,
            ));
        }
        if self.emitter_flux_lm != other.emitter_flux_lm {
            return Err(MergeMapError::Flux(
                self.emitter_flux_lm,
                other.emitter_flux_lm,
            ));
        }
        for (a, b) in self.counts.iter_mut().zip(&other.counts) {
            *a += b;
        }
        self.photons_emitted += other.photons_emitted;
        self.photons_absorbed += other.photons_absorbed;
        self.photons_cut_off += other.photons_cut_off;
        Ok(())
    }
}
