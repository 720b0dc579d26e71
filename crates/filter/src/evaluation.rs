//! The error measures the filter is evaluated by (`lucerna filter-bench`,
//! the protocol of Litemaker 2017, Figure 8a): the RMSE between maps each
//! scaled by its mean, and the share of it that a high-photon reference's
//! own Poisson noise contributes, so that it can be taken out.

use lucerna_photometry::{CubeMapLayout, TexelSymmetry};

/// Photons per steradian of raw counts (texel order of `layout`): the
/// unfiltered map's estimate of the intensity (× flux per photon =
/// candela).
pub fn raw_photons_per_sr(layout: CubeMapLayout, counts: &[u64]) -> Vec<f64> {
    counts
        .iter()
        .enumerate()
        .map(|(t, &c)| c as f64 / layout.texel_solid_angle(t))
        .collect()
}

/// RMSE over texels between two maps, each divided by its own mean (the
/// paper's measure): it compares the shapes of two distributions whatever
/// the flux or photons behind each. Infinite when a map is empty or its
/// mean is not positive.
pub fn mean_scaled_rmse(a: &[f64], b: &[f64]) -> f64 {
    debug_assert_eq!(a.len(), b.len());
    if a.is_empty() {
        return f64::INFINITY;
    }
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let (ma, mb) = (mean(a), mean(b));
    if ma <= 0.0 || mb <= 0.0 {
        return f64::INFINITY;
    }
    (a.iter()
        .zip(b)
        .map(|(x, y)| (x / ma - y / mb).powi(2))
        .sum::<f64>()
        / a.len() as f64)
        .sqrt()
}

/// What a reference's own Poisson noise adds, in expectation, to the
/// squared [`mean_scaled_rmse`] of a map against it: the mean over texels
/// of var(r_t) / mean(r)², r_t = c_t / Ω_t its raw intensity, with
/// var(r_t) estimated without bias by m_t · c_t / Ω_t². `counts` may be
/// pooled over `symmetry` ([`TexelSymmetry::pool`]): a pooled count is
/// m_t times a sum of independent counts, m_t the texel's multiplicity (1
/// for [`TexelSymmetry::none`]). A map whose errors are independent of the
/// reference's noise measures its true squared error plus this (less a
/// term of order 1/photons: scaling by the reference's own mean takes out
/// the noise of that mean).
pub fn reference_noise_mse(layout: CubeMapLayout, counts: &[u64], symmetry: &TexelSymmetry) -> f64 {
    if counts.is_empty() {
        return 0.0;
    }
    let intensity = raw_photons_per_sr(layout, counts);
    let mean = intensity.iter().sum::<f64>() / intensity.len() as f64;
    if mean <= 0.0 {
        return 0.0;
    }
    counts
        .iter()
        .enumerate()
        .map(|(t, &c)| {
            symmetry.multiplicity(t) as f64 * c as f64 / layout.texel_solid_angle(t).powi(2)
        })
        .sum::<f64>()
        / counts.len() as f64
        / (mean * mean)
}

/// The mean-scaled RMSE against the truth estimated from one measured
/// against a noisy reference: √(rmse² − [`reference_noise_mse`]), 0 when
/// the measured error is all reference noise.
pub fn rmse_without_reference_noise(measured_rmse: f64, reference_noise_mse: f64) -> f64 {
    (measured_rmse * measured_rmse - reference_noise_mse)
        .max(0.0)
        .sqrt()
}
