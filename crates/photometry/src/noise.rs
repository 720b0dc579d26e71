//! The photon statistics behind a traced map, for telling a
//! distribution's shape from its noise.

use crate::cubemap::CubeMapLayout;

/// The photon statistics behind a map's intensities, for telling shape
/// from noise: each texel's intensity is photons × `lm_per_photon` over
/// its solid angle, averaged over `pooled_images` images when the map is
/// pooled over the luminaire's symmetry (which that many times the
/// photons back).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhotonNoise {
    pub lm_per_photon: f64,
    pub pooled_images: f64,
}

impl PhotonNoise {
    /// One standard deviation (cd) of the mean intensity of a region that
    /// holds `flux_lm` over `omega_sr`: Poisson, with at least one
    /// photon's worth where the region is dark.
    pub fn sigma_cd(&self, flux_lm: f64, omega_sr: f64) -> f64 {
        if !(self.lm_per_photon > 0.0 && omega_sr > 0.0) {
            return 0.0;
        }
        let k = self.pooled_images.max(1.0);
        let photons = k * flux_lm / self.lm_per_photon;
        photons.max(1.0).sqrt() * self.lm_per_photon / (k * omega_sr)
    }

    /// The relative noise (one standard deviation) of the brightest texel
    /// of `candela_per_texel`.
    pub fn peak_texel(&self, layout: CubeMapLayout, candela_per_texel: &[f64]) -> f64 {
        let omega = layout.shared_solid_angles();
        let Some((t, &cd)) = candela_per_texel
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(b.1))
        else {
            return 0.0;
        };
        if !(cd > 0.0) {
            return 0.0;
        }
        self.sigma_cd(cd * omega[t], omega[t]) / cd
    }
}
