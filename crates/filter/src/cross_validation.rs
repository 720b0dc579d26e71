//! The automatic mode: K-fold cross-validation on thinned parts of the
//! photons chooses the rule and the σ per map among a fixed set of
//! candidates, and estimates the chosen map's error from the photons alone.

use lucerna_photometry::TexelSymmetry;

use crate::intensity::safe_intensity;
use crate::settings::{AUTOMATIC_FALLBACK, FilterSettings, POISSON_Z, Threshold, UNCAPPED};
use crate::thinning::thinned_folds;

/// The settings the automatic mode chooses among (σ of the range term
/// from `base` but for one candidate), picked with `lucerna filter-bench`
/// and a wider search (the numbers: `BENCHMARKS.md`, "Filter"). Smooth
/// maps do best with low thresholds at few photons per texel and with the
/// Poisson test at z = 4 and the paper's closeness σ of 0.75 texel, its
/// cap growing with the photons per texel; maps with caustics with z = 3
/// and σ = 0.5, which keep more of their structure, and at few photons
/// with a range σ of 3; with many photons per texel (many photons, or
/// pooled over a symmetry) smooth bright regions are best replaced
/// wherever the Poisson test allows, with no cap. Plus the paper's fixed
/// thresholds 100 and 250, and the raw map (where every smoothing loses
/// to the counts).
pub fn automatic_candidates(base: &FilterSettings) -> Vec<FilterSettings> {
    let with = |threshold: Threshold, sigma_closeness: f64| FilterSettings {
        threshold,
        sigma_closeness,
        ..*base
    };
    let mut v = Vec::new();
    for cap in [64.0, 128.0, 256.0, 1024.0] {
        v.push(with(Threshold::Poisson { cap, z: POISSON_Z }, 0.75));
    }
    for cap in [256.0, 1024.0, 4096.0, UNCAPPED] {
        v.push(with(Threshold::Poisson { cap, z: 3.0 }, 0.5));
    }
    v.push(with(
        Threshold::Poisson {
            cap: UNCAPPED,
            z: POISSON_Z,
        },
        0.75,
    ));
    // Sharp interpolation with almost no range weighting: caustics at few
    // photons per texel, where the range term follows the noise.
    v.push(FilterSettings {
        sigma_range: 3.0,
        ..with(
            Threshold::Poisson {
                cap: 256.0,
                z: POISSON_Z,
            },
            0.5,
        )
    });
    for t in [100.0, 250.0, 0.0] {
        v.push(with(Threshold::Fixed(t), 0.75));
    }
    v
}

/// Folds of the automatic mode's cross-validation. Each candidate is
/// judged by its error at (K − 1)/K of the photons, slightly fewer than it
/// will filter, so few folds lean to rules suited to fewer photons and let
/// the random split sway the choice, and each fold adds a pass per
/// candidate: in `lucerna filter-bench` 5 folds chose the best rule where
/// 2 and 3 did not (`BENCHMARKS.md`, "Filter").
pub const CV_FOLDS: usize = 5;

/// The automatic mode's choice for `counts` and every candidate's score.
///
/// K-fold cross-validation by Poisson thinning ([`CV_FOLDS`]): the photons
/// are split into K independent parts ([`thinned_folds`]); each candidate
/// ([`automatic_candidates`]) filters all photons but part k and is scored
/// by the squared difference, summed over texels (intensity per steradian,
/// the paper's RMSE measure up to a constant), between its result / (K − 1)
/// and part k's raw intensity, for every k. The held-out part is an
/// unbiased estimate of the same distribution, independent of the filtered
/// one, so the score's expectation is the candidate's mean squared error at
/// (K − 1)/K of the photons plus a constant: the winner is the candidate
/// that would be closest to the truth, judged from the photons alone.
/// `run` filters counts with concrete settings and returns photons per
/// steradian; `omega` holds the texel solid angles. With a symmetry the
/// photons are split first and each part pooled after
/// ([`TexelSymmetry::pool`]), so training and held-out parts stay
/// independent; `counts` are the traced (unpooled) counts and `run` gets
/// pooled ones.
pub fn choose_automatic<E>(
    omega: &[f64],
    counts: &[u64],
    base: &FilterSettings,
    symmetry: &TexelSymmetry,
    mut run: impl FnMut(&[u64], &FilterSettings) -> Result<Vec<f64>, E>,
) -> Result<(FilterSettings, Vec<CandidateScore>), E> {
    let folds = CV_FOLDS.max(2);
    let parts = thinned_folds(counts, folds);
    // Training set of fold k: every photon not in part k, (K − 1)/K of them.
    let training: Vec<Vec<u64>> = parts
        .iter()
        .map(|part| {
            let rest: Vec<u64> = counts.iter().zip(part).map(|(&c, &p)| c - p).collect();
            symmetry.pool(&rest)
        })
        .collect();
    let parts: Vec<Vec<u64>> = parts.iter().map(|part| symmetry.pool(part)).collect();
    let held_out: Vec<Vec<f64>> = parts
        .iter()
        .map(|part| {
            part.iter()
                .zip(omega)
                .map(|(&c, &w)| safe_intensity(c as f64, w))
                .collect()
        })
        .collect();
    // The held-out intensities' own variance, Σ m·c / Ω² per part (an
    // unbiased estimate of Σ var(c / Ω); m is the texel's multiplicity
    // under the symmetry, 1 without), and the training maps' mean
    // intensity, for the error estimate.
    let multiplicity: Vec<f64> = (0..counts.len())
        .map(|t| symmetry.multiplicity(t) as f64)
        .collect();
    let held_out_noise: Vec<f64> = parts
        .iter()
        .map(|part| {
            part.iter()
                .zip(omega)
                .zip(&multiplicity)
                .map(|((&c, &w), &m)| if w > 0.0 { m * c as f64 / (w * w) } else { 0.0 })
                .sum()
        })
        .collect();
    let training_mean: Vec<f64> = training
        .iter()
        .map(|c| {
            c.iter()
                .zip(omega)
                .map(|(&c, &w)| safe_intensity(c as f64, w))
                .sum::<f64>()
                / c.len().max(1) as f64
        })
        .collect();
    // The filtered training map estimates K − 1 times what a held-out
    // part's raw intensity estimates.
    let scale = 1.0 / (folds - 1) as f64;
    let texels = counts.len().max(1) as f64;
    let mut scores = Vec::new();
    for candidate in automatic_candidates(base) {
        let mut score = 0.0f64;
        let mut relative_mse = 0.0f64;
        for k in 0..folds {
            let f = run(&training[k], &candidate)?;
            let squared = f
                .iter()
                .zip(&held_out[k])
                .map(|(x, y)| (x * scale - y).powi(2))
                .sum::<f64>();
            score += squared;
            // E[squared] = scale² · Σ (f − truth)² + Σ var(held out).
            let mse = (squared - held_out_noise[k]).max(0.0) / (scale * scale) / texels;
            if training_mean[k] > 0.0 {
                relative_mse += mse / (training_mean[k] * training_mean[k]);
            }
        }
        scores.push(CandidateScore {
            settings: candidate,
            score,
            estimated_rmse: (relative_mse / folds as f64).sqrt(),
        });
    }
    let best = scores
        .iter()
        .min_by(|x, y| x.score.total_cmp(&y.score))
        .map_or(
            FilterSettings {
                threshold: AUTOMATIC_FALLBACK,
                ..*base
            },
            |s| s.settings,
        );
    Ok((best, scores))
}

/// One candidate of the automatic mode, as cross-validation judged it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CandidateScore {
    pub settings: FilterSettings,
    /// Sum of squared differences to the held-out parts (lower is better).
    pub score: f64,
    /// The candidate's RMSE against the true distribution, each map
    /// scaled by its mean (the paper's measure), estimated from the same
    /// folds: at (K − 1)/K of the photons, so a little above the error at
    /// all of them.
    pub estimated_rmse: f64,
}

/// What the automatic mode found: the chosen candidate's and the raw map's
/// estimated errors.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AutomaticReport {
    /// Estimated mean-scaled RMSE of the chosen rule ([`CandidateScore`]).
    pub estimated_rmse: f64,
    /// The same for the unfiltered map.
    pub raw_estimated_rmse: f64,
}

impl AutomaticReport {
    /// The report on a cross-validation's scores for its chosen settings.
    pub fn new(chosen: &FilterSettings, scores: &[CandidateScore]) -> Option<AutomaticReport> {
        let of = |pick: &dyn Fn(&CandidateScore) -> bool| {
            scores.iter().find(|s| pick(s)).map(|s| s.estimated_rmse)
        };
        Some(AutomaticReport {
            estimated_rmse: of(&|s| s.settings == *chosen)?,
            raw_estimated_rmse: of(&|s| s.settings.threshold == Threshold::Fixed(0.0))?,
        })
    }
}
