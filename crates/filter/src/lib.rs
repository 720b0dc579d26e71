//! Pull-push bilateral upsampling filter for cube-map intensity maps
//! (Litemaker 2017, section 5), CPU reference.
//!
//! Pull: a pyramid of photon counts, each coarse texel the sum of its 2×2
//! children, with the exact solid angle of its region. Push: from the
//! coarsest level down, a texel with fewer photons than the threshold
//! (unstable) is replaced by a bilateral interpolation (eq. in 5.5:
//! Gaussian closeness × Gaussian similarity to the bilinear estimate) of
//! the four nearest texels of the already filtered coarser level; on levels
//! ≥ 2 the shadow-border test of Algorithm 2 keeps unstable texels next to
//! stable ones as they are.
//!
//! Where this differs from the paper, and why:
//! - neighbourhoods cross cube faces (a neighbour beyond an edge is found
//!   through its direction), so there are no seams;
//! - stability is judged on photon counts, but interpolation works on
//!   intensity per steradian, since cube-map texels differ ~5× in solid
//!   angle: an isotropic source stays flat (the paper's factor 4 is this
//!   normalisation for equal texels);
//! - a Poisson rule ([`Threshold::Poisson`]) replaces a texel only when
//!   its count is consistent with noise around the upsampled estimate, so
//!   caustics and cut-offs survive a high cap;
//! - no user threshold: [`Threshold::Automatic`] chooses the rule and the
//!   closeness σ per map by K-fold cross-validation on Poisson-thinned
//!   parts of the photons ([`choose_automatic`]); a manual threshold stays
//!   available;
//! - replaced texels are renormalised together so the filtered map keeps
//!   the traced flux; stable texels are never changed;
//! - a luminaire's symmetry about its axis ([`TexelSymmetry`]) pools the
//!   photons of every image of a texel before filtering
//!   ([`filter_symmetric`]): each texel is judged and interpolated on
//!   |group| times the photons, with no bias for a symmetric luminaire.

pub mod gpu;

use lucerna_photometry::{AxialSymmetry, CubeFace, CubeMapLayout, TexelSymmetry};
use rayon::prelude::*;

/// How unstable texels are told from stable ones.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Threshold {
    /// Photons a texel needs to be stable (the paper's user threshold).
    Fixed(f64),
    /// Per texel, from the photon statistics: a texel is replaced when its
    /// count is what Poisson noise around the upsampled estimate would
    /// give (|c − E| ≤ z·√(E + 1), E = estimate × texel solid angle),
    /// and kept when it deviates significantly (real structure: a caustic,
    /// a cut-off) or holds at least `cap` photons. Smooth regions get
    /// smoothed as much as a high threshold would, structured ones as
    /// little as a low one.
    Poisson { cap: f64, z: f64 },
    /// No user threshold: the rule is chosen per map among
    /// [`automatic_candidates`] by K-fold cross-validation on the photon
    /// counts themselves ([`choose_automatic`]).
    Automatic,
}

impl std::fmt::Display for Threshold {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Threshold::Fixed(t) if *t <= 0.0 => write!(f, "no filtering (raw)"),
            Threshold::Fixed(t) => write!(f, "fixed threshold {t:.0}"),
            Threshold::Poisson { cap, z } if *cap >= UNCAPPED => {
                write!(f, "Poisson test (no cap, z {z})")
            }
            Threshold::Poisson { cap, z } => write!(f, "Poisson test (cap {cap:.0}, z {z})"),
            Threshold::Automatic => write!(f, "automatic"),
        }
    }
}

/// z-score of the Poisson consistency test when no other is given: the
/// rule `Automatic` falls back to is `Poisson { cap: AUTO_MAX, z: AUTO_Z }`.
pub const AUTO_Z: f64 = 4.0;
/// Fewest photons a texel needs before the Poisson test believes its
/// excess over the estimate is structure rather than noise.
pub const AUTO_MIN_KEEP: f64 = 32.0;
/// A cap no texel reaches: the Poisson test alone decides which texels
/// are kept (finite, so it survives the f32 of the WGSL twin).
pub const UNCAPPED: f64 = 1e15;
/// The fallback rule's cap (relative noise ≤ 1/√256 ≈ 6 % above it).
pub const AUTO_MAX: f64 = 256.0;
/// Threshold the Poisson rule uses for Algorithm 2's border test.
pub const AUTO_BORDER: f64 = 64.0;

/// What a user reads about the settings: the rule and the two σ.
impl std::fmt::Display for FilterSettings {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}, σ closeness {}, σ range {}",
            self.threshold, self.sigma_closeness, self.sigma_range
        )
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilterSettings {
    pub threshold: Threshold,
    /// σ of the closeness Gaussian, in texels of the coarser level.
    pub sigma_closeness: f64,
    /// σ of the similarity Gaussian on the relative intensity difference
    /// |f̃ − f| / max(f̃, f).
    pub sigma_range: f64,
    /// Levels on which Algorithm 2's shadow-border test applies (the paper:
    /// all but 0 and 1).
    pub first_border_level: usize,
}

impl Default for FilterSettings {
    fn default() -> Self {
        FilterSettings {
            threshold: Threshold::Automatic,
            sigma_closeness: 0.75,
            sigma_range: 0.3,
            first_border_level: 2,
        }
    }
}

/// The filtered map and what the filter did.
#[derive(Debug, Clone, PartialEq)]
pub struct Filtered {
    /// Photons per steradian for every level-0 texel (× flux per photon =
    /// candela).
    pub photons_per_sr: Vec<f64>,
    /// Texels whose value was replaced.
    pub replaced: Vec<bool>,
    /// The threshold used (photons; the Poisson rule's cap).
    pub threshold: f64,
    /// The settings applied, with a concrete rule (what `Automatic` chose).
    pub settings: FilterSettings,
    /// For the automatic mode, the cross-validated error estimates.
    pub automatic: Option<AutomaticReport>,
    /// Factor applied to the replaced texels to keep the traced flux.
    pub renormalisation: f64,
    /// The symmetry whose images were pooled (`None`: the counts alone).
    pub symmetry: AxialSymmetry,
}

/// One pyramid level: photon counts and solid angles per texel.
struct Level {
    layout: CubeMapLayout,
    counts: Vec<f64>,
    omega: Vec<f64>,
}

/// The count below which a texel may be replaced, and the one the border
/// test uses. `Automatic` reads as its fallback rule (it is resolved by
/// [`choose_automatic`] before filtering).
pub fn thresholds(threshold: Threshold) -> (f64, f64) {
    match threshold {
        Threshold::Fixed(t) => (t, t),
        Threshold::Poisson { cap, .. } => (cap, AUTO_BORDER),
        Threshold::Automatic => thresholds(AUTOMATIC_FALLBACK),
    }
}

/// The rule `Automatic` stands for when no choice is made.
pub const AUTOMATIC_FALLBACK: Threshold = Threshold::Poisson {
    cap: AUTO_MAX,
    z: AUTO_Z,
};

/// The settings the automatic mode chooses among (σ of the range term
/// from `base` but for one candidate). Measured with `lucerna
/// filter-bench` and a wider search: smooth maps (the opal bell) do best with low thresholds at few photons
/// per texel and the Poisson test at z = 4 with the paper's closeness σ of
/// 0.75 texel, caps growing with the photons (64–128 at 10⁵, 256 at 10⁶,
/// 1024 at 10⁷ on 128² faces); maps with caustics (the faceted downlight)
/// with z = 3 and σ = 0.5, which keep more of their structure, and at few
/// photons with a range σ of 3 (the downlight at 10⁵ photons: RMSE 0.349
/// → 0.289, below the raw map's at 10⁶). With many photons per texel
/// (10⁷–10⁸ photons, or pooled over a symmetry) smooth bright regions are
/// best replaced wherever the Poisson test allows, with no cap (512²:
/// opal bell at 10⁸ RMSE 0.0385 → 0.0285, downlight pooled at 10⁸ 0.0535
/// → 0.0331). Plus the paper's fixed thresholds 100 and 250, and the raw
/// map (where every smoothing loses to the counts).
pub fn automatic_candidates(base: &FilterSettings) -> Vec<FilterSettings> {
    let with = |threshold: Threshold, sigma_closeness: f64| FilterSettings {
        threshold,
        sigma_closeness,
        ..*base
    };
    let mut v = Vec::new();
    for cap in [64.0, 128.0, 256.0, 1024.0] {
        v.push(with(Threshold::Poisson { cap, z: AUTO_Z }, 0.75));
    }
    for cap in [256.0, 1024.0, 4096.0, UNCAPPED] {
        v.push(with(Threshold::Poisson { cap, z: 3.0 }, 0.5));
    }
    v.push(with(
        Threshold::Poisson {
            cap: UNCAPPED,
            z: AUTO_Z,
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
                z: AUTO_Z,
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
/// will filter, so few folds lean to rules suited to fewer photons, and
/// each fold adds a pass per candidate. On the opal bell (128², 10⁵
/// photons) 2 and 3 folds chose a rule 6.6 % worse than the best fixed
/// threshold, 5 folds the best; on the faceted downlight at 10⁵ photons
/// 2 folds chose between rules of RMSE 0.349 and 0.412 depending on the
/// random split, 5 folds the better one.
pub const CV_FOLDS: usize = 5;

/// Splits photon counts into `folds` independent parts: each photon goes
/// to one part, uniformly at random (multinomial thinning: binomial draws
/// by inversion, a normal approximation above 256 photons), so each part
/// is a Poisson map of 1/`folds` of the flux, independent of the others.
/// Deterministic per texel.
pub fn thinned_folds(counts: &[u64], folds: usize) -> Vec<Vec<u64>> {
    let folds = folds.max(1);
    let per_texel: Vec<Vec<u64>> = counts
        .par_iter()
        .enumerate()
        .map(|(t, &c)| {
            let mut left = c;
            let mut parts = Vec::with_capacity(folds);
            for k in 0..folds - 1 {
                let p = 1.0 / (folds - k) as f64;
                let key = (t as u64).wrapping_mul(0x2545_F491_4F6C_DD1D) ^ ((k as u64) << 56);
                let n = binomial(left, p, key);
                parts.push(n);
                left -= n;
            }
            parts.push(left);
            parts
        })
        .collect();
    (0..folds)
        .map(|k| per_texel.iter().map(|p| p[k]).collect())
        .collect()
}

/// SplitMix64: the thinning's counter-based random bits.
fn splitmix64(mut x: u64) -> u64 {
    x = x.wrapping_add(0x9E37_79B9_7F4A_7C15);
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    x ^ (x >> 31)
}

/// Uniform in [0, 1) from `key`.
fn unit(key: u64) -> f64 {
    (splitmix64(key) >> 11) as f64 / (1u64 << 53) as f64
}

/// A Binomial(n, p) draw, random bits from `key`.
fn binomial(n: u64, p: f64, key: u64) -> u64 {
    let key = key ^ 0x5EED_F11E_7E12_0001;
    if n <= 256 {
        // Inversion: walk the CDF from 0 with P(k + 1) = P(k) · (n − k) /
        // (k + 1) · p / (1 − p); about n·p steps ((1 − p)ⁿ ≥ 1e-78 here).
        if p >= 1.0 {
            return n;
        }
        let u = unit(key);
        let ratio = p / (1.0 - p);
        let mut probability = (1.0 - p).powi(n as i32);
        let mut cumulative = probability;
        let mut k = 0u64;
        while u >= cumulative && k < n {
            probability *= (n - k) as f64 / (k + 1) as f64 * ratio;
            k += 1;
            cumulative += probability;
        }
        k
    } else {
        // Normal approximation (Box–Muller), clamped to [0, n].
        let u1 = unit(key) + 0.5 / (1u64 << 53) as f64;
        let u2 = unit(key ^ 0xA5A5_A5A5_A5A5);
        let z = (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos();
        let mean = n as f64 * p;
        let draw = (mean + (mean * (1.0 - p)).sqrt() * z).round();
        draw.clamp(0.0, n as f64) as u64
    }
}

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

/// Builds the pull pyramid: level k+1 sums 2×2 texels of level k;
/// `omega` holds level 0's texel solid angles.
fn pull(layout: CubeMapLayout, counts: &[u64], omega: &[f64]) -> Vec<Level> {
    let mut levels = vec![Level {
        layout,
        counts: counts.iter().map(|&c| c as f64).collect(),
        omega: omega.to_vec(),
    }];
    while levels.last().is_some_and(|l| l.layout.resolution > 1) {
        let fine = levels.last().map(|l| (l.layout, &l.counts, &l.omega));
        let Some((fine_layout, fine_counts, fine_omega)) = fine else {
            break;
        };
        let n = fine_layout.resolution;
        let coarse = CubeMapLayout::new(n.div_ceil(2));
        let mut counts = vec![0.0; coarse.texel_count()];
        let mut omega = vec![0.0; coarse.texel_count()];
        for t in 0..fine_layout.texel_count() {
            let (face, i, j) = fine_layout.texel_coordinates(t);
            let parent = coarse.texel_index(face, i / 2, j / 2);
            counts[parent] += fine_counts[t];
            omega[parent] += fine_omega[t];
        }
        levels.push(Level {
            layout: coarse,
            counts,
            omega,
        });
    }
    levels
}

/// Texel (cx, cy) of a face at `layout`, following the cube across an edge
/// when the coordinates leave the face.
fn texel_at(layout: CubeMapLayout, face: CubeFace, cx: i64, cy: i64) -> usize {
    let n = i64::from(layout.resolution);
    if (0..n).contains(&cx) && (0..n).contains(&cy) {
        return layout.texel_index(face, cx as u32, cy as u32);
    }
    // Past a cube corner there is no diagonal neighbour (three faces meet):
    // the face's own corner texel stands in. Clamping both coordinates is
    // the same choice from either edge, so the filter keeps the cube's
    // symmetries (a luminaire's quarter turns and diagonal mirrors).
    let inside = |c: i64| (0..n).contains(&c);
    if !inside(cx) && !inside(cy) {
        return layout.texel_index(face, cx.clamp(0, n - 1) as u32, cy.clamp(0, n - 1) as u32);
    }
    let step = 2.0 / n as f64;
    let a = -1.0 + (cx as f64 + 0.5) * step;
    let b = -1.0 + (cy as f64 + 0.5) * step;
    layout.texel_of_direction(face.direction(a, b))
}

fn safe_intensity(count: f64, omega: f64) -> f64 {
    if omega > 0.0 { count / omega } else { 0.0 }
}

/// Where fine texel column (or row) i falls on the coarser level: the
/// coarse cell to its lower side, the fraction beyond it, and the closeness
/// Gaussian's factors for the two coarse neighbours along this axis (the
/// 2-D closeness weight is their product).
#[derive(Debug, Clone, Copy)]
struct AxisSample {
    cell: i64,
    fraction: f64,
    near: f64,
    far: f64,
}

/// The axis samples of every fine column of a level (faces are square, so
/// rows use the same table).
fn axis_samples(fine: CubeMapLayout, coarse: CubeMapLayout, sigma: f64) -> Vec<AxisSample> {
    let ratio = f64::from(coarse.resolution) / f64::from(fine.resolution);
    let gauss = |d: f64| (-0.5 * d * d / (sigma * sigma)).exp();
    (0..fine.resolution)
        .map(|i| {
            let x = (f64::from(i) + 0.5) * ratio - 0.5;
            let x0 = x.floor();
            let fraction = x - x0;
            AxisSample {
                cell: x0 as i64,
                fraction,
                near: gauss(fraction),
                far: gauss(1.0 - fraction),
            }
        })
        .collect()
}

/// Bilateral interpolation of the coarser level's filtered intensities at
/// the centre of fine texel (face, i, j).
fn upsample(
    coarse: CubeMapLayout,
    coarse_intensity: &[f64],
    face: CubeFace,
    (sx, sy): (AxisSample, AxisSample),
    settings: &FilterSettings,
) -> f64 {
    let (fx, fy) = (sx.fraction, sy.fraction);
    let corners = [(0, 0), (1, 0), (0, 1), (1, 1)];
    let mut values = [0.0; 4];
    let mut bilinear = [0.0; 4];
    let mut closeness = [0.0; 4];
    for (k, &(dx, dy)) in corners.iter().enumerate() {
        values[k] = coarse_intensity[texel_at(coarse, face, sx.cell + dx, sy.cell + dy)];
        bilinear[k] = (if dx == 0 { 1.0 - fx } else { fx }) * (if dy == 0 { 1.0 - fy } else { fy });
        closeness[k] =
            (if dx == 0 { sx.near } else { sx.far }) * (if dy == 0 { sy.near } else { sy.far });
    }
    let estimate: f64 = values.iter().zip(&bilinear).map(|(v, w)| v * w).sum();
    let (mut num, mut den) = (0.0, 0.0);
    for k in 0..4 {
        let larger = estimate.max(values[k]);
        let delta = if larger > 0.0 {
            (estimate - values[k]).abs() / larger
        } else {
            0.0
        };
        let similarity = (-0.5 * (delta / settings.sigma_range).powi(2)).exp();
        let w = closeness[k] * similarity;
        num += values[k] * w;
        den += w;
    }
    if den > 0.0 { num / den } else { estimate }
}

/// Algorithm 2: an unstable texel is upsampled when none of its eight
/// neighbours is stable with it (f(Pᵢ) + f(P) ≥ 2·threshold) or more than
/// six are; otherwise it sits on a shadow border and keeps its value.
fn on_shadow_border(level: &Level, face: CubeFace, i: u32, j: u32, threshold: f64) -> bool {
    let own = level.counts[level.layout.texel_index(face, i, j)];
    let mut stable_neighbours = 0;
    for dy in -1i64..=1 {
        for dx in -1i64..=1 {
            if dx == 0 && dy == 0 {
                continue;
            }
            let t = texel_at(level.layout, face, i64::from(i) + dx, i64::from(j) + dy);
            if level.counts[t] + own >= 2.0 * threshold {
                stable_neighbours += 1;
            }
        }
    }
    !(stable_neighbours == 0 || stable_neighbours > 6)
}

/// Scales the replaced texels together so the map keeps the traced flux
/// (factor bounded to [0.5, 2]); returns the factor. Stable texels are not
/// touched.
pub fn renormalise(counts: &[f64], omega: &[f64], intensity: &mut [f64], replaced: &[bool]) -> f64 {
    let (mut traced, mut filtered) = (0.0, 0.0);
    for t in 0..intensity.len() {
        if replaced[t] {
            traced += counts[t];
            filtered += intensity[t] * omega[t];
        }
    }
    let factor = if filtered > 0.0 && traced > 0.0 {
        (traced / filtered).clamp(0.5, 2.0)
    } else {
        1.0
    };
    for t in 0..intensity.len() {
        if replaced[t] {
            intensity[t] *= factor;
        }
    }
    factor
}

/// Resolutions of the pyramid's levels, finest first, down to 1.
pub fn pyramid_resolutions(resolution: u32) -> Vec<u32> {
    let mut v = vec![resolution.max(1)];
    while let Some(&n) = v.last()
        && n > 1
    {
        v.push(n.div_ceil(2));
    }
    v
}

/// Solid angles of every level's texels (the pull of texel solid angles).
pub fn pyramid_solid_angles(layout: CubeMapLayout) -> Vec<Vec<f64>> {
    pull(
        layout,
        &vec![0; layout.texel_count()],
        &layout.solid_angles(),
    )
    .into_iter()
    .map(|l| l.omega)
    .collect()
}

/// Filters a map of photon counts (texel order of `layout`).
pub fn filter(layout: CubeMapLayout, counts: &[u64], settings: &FilterSettings) -> Filtered {
    filter_symmetric(counts, settings, &TexelSymmetry::none(layout))
}

/// Filters the traced counts of a luminaire with `symmetry` (its layout is
/// the map's): every texel gets the photons of all its images
/// ([`TexelSymmetry::pool`]) before the pull, so stability, the Poisson
/// test and the interpolation see |group| times the photons; the result is
/// per traced photon, as from [`filter`].
pub fn filter_symmetric(
    counts: &[u64],
    settings: &FilterSettings,
    symmetry: &TexelSymmetry,
) -> Filtered {
    let layout = symmetry.layout;
    // The texel solid angles, computed once for every candidate's passes.
    let omega = layout.solid_angles();
    let filtered = filter_pooled(&omega, counts, settings, symmetry, |c, concrete| {
        Ok::<_, std::convert::Infallible>(filter_with(layout, c, concrete, &omega))
    });
    match filtered {
        Ok(filtered) => filtered,
        Err(never) => match never {},
    }
}

/// What the CPU and GPU filters share: pools the traced counts over
/// `symmetry`, resolves `Automatic` by cross-validation
/// ([`choose_automatic`], each candidate through `pass`), runs the final
/// pass on the pooled counts and scales the result to photons per traced
/// photon (pooling counted each photon `order` times). `pass` filters
/// counts with concrete settings.
pub(crate) fn filter_pooled<E>(
    omega: &[f64],
    counts: &[u64],
    settings: &FilterSettings,
    symmetry: &TexelSymmetry,
    mut pass: impl FnMut(&[u64], &FilterSettings) -> Result<Filtered, E>,
) -> Result<Filtered, E> {
    let pooled = symmetry.pool(counts);
    let mut filtered = match settings.threshold {
        Threshold::Automatic => {
            let (best, scores) =
                choose_automatic(omega, counts, settings, symmetry, |c, candidate| {
                    Ok(pass(c, candidate)?.photons_per_sr)
                })?;
            Filtered {
                automatic: AutomaticReport::new(&best, &scores),
                ..pass(&pooled, &best)?
            }
        }
        _ => pass(&pooled, settings)?,
    };
    let order = symmetry.order() as f64;
    if order > 1.0 {
        filtered.photons_per_sr.iter_mut().for_each(|v| *v /= order);
    }
    filtered.symmetry = symmetry.symmetry;
    Ok(filtered)
}

/// Filters with concrete settings (not `Automatic`); `omega` holds the
/// texel solid angles.
fn filter_with(
    layout: CubeMapLayout,
    counts: &[u64],
    settings: &FilterSettings,
    omega: &[f64],
) -> Filtered {
    // Callers resolve `Automatic` first (`choose_automatic`).
    debug_assert!(settings.threshold != Threshold::Automatic);
    let rule = settings.threshold;
    let (threshold, border_threshold) = thresholds(rule);
    debug_assert_eq!(counts.len(), layout.texel_count());
    // The Poisson test's z, if the rule has one.
    let poisson_z = match rule {
        Threshold::Poisson { z, .. } => Some(z),
        _ => None,
    };
    let levels = pull(layout, counts, omega);
    let top = levels.len() - 1;
    let mut intensity: Vec<f64> = levels[top]
        .counts
        .iter()
        .zip(&levels[top].omega)
        .map(|(&c, &w)| safe_intensity(c, w))
        .collect();
    let mut replaced = vec![false; levels[top].layout.texel_count()];
    for k in (0..top).rev() {
        let level = &levels[k];
        let coarse = &levels[k + 1];
        let border_test = k >= settings.first_border_level;
        let samples = axis_samples(level.layout, coarse.layout, settings.sigma_closeness);
        let (next, next_replaced): (Vec<f64>, Vec<bool>) = (0..level.layout.texel_count())
            .into_par_iter()
            .map(|t| {
                let own = safe_intensity(level.counts[t], level.omega[t]);
                if level.counts[t] >= threshold {
                    return (own, false);
                }
                let (face, i, j) = level.layout.texel_coordinates(t);
                if border_test && on_shadow_border(level, face, i, j, border_threshold) {
                    return (own, false);
                }
                let estimate = upsample(
                    coarse.layout,
                    &intensity,
                    face,
                    (samples[i as usize], samples[j as usize]),
                    settings,
                );
                if let Some(z) = poisson_z {
                    let expected = estimate * level.omega[t];
                    let c = level.counts[t];
                    // Too few photons where many were expected: a shadow.
                    // Too many where few were expected: structure, once the
                    // count is large enough not to be Poisson's long tail.
                    let darker = c < expected && expected - c > z * expected.sqrt();
                    let brighter = c >= AUTO_MIN_KEEP && c - expected > z * (expected + 1.0).sqrt();
                    if darker || brighter {
                        return (own, false);
                    }
                }
                (estimate, true)
            })
            .unzip();
        intensity = next;
        replaced = next_replaced;
    }
    let renormalisation = renormalise(
        &levels[0].counts,
        &levels[0].omega,
        &mut intensity,
        &replaced,
    );
    Filtered {
        photons_per_sr: intensity,
        replaced,
        threshold,
        settings: *settings,
        automatic: None,
        renormalisation,
        symmetry: AxialSymmetry::None,
    }
}

/// Filters an intensity map of a luminaire with `symmetry` (of the map's
/// layout; [`TexelSymmetry::none`] for none); returns candela per texel and
/// the report.
pub fn filter_map(
    map: &lucerna_photometry::IntensityMap,
    settings: &FilterSettings,
    symmetry: &TexelSymmetry,
) -> (Vec<f64>, Filtered) {
    let f = filter_symmetric(&map.counts, settings, symmetry);
    let phi = map.flux_per_photon_lm();
    (f.photons_per_sr.iter().map(|v| v * phi).collect(), f)
}
