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
//! - the threshold can be chosen from the photon statistics
//!   ([`Threshold::Automatic`]);
//! - replaced texels are renormalised together so the filtered map keeps
//!   the traced flux; stable texels are never changed.

pub mod gpu;

use lucerna_photometry::{CubeFace, CubeMapLayout};
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
    /// a cut-off) or holds more than [`AUTO_MAX`] photons (on levels ≥ 2,
    /// more than [`automatic_coarse_cap`]). No user
    /// threshold; smooth regions get smoothed as much as a high threshold
    /// would, structured ones as little as a low one.
    Automatic,
}

/// z-score of the automatic mode's Poisson consistency test. 4 rather
/// than 3: on the opal bell (128², 2·10⁸-photon reference) the error at
/// 10⁶ photons falls from +27 % to +13 % of the best fixed threshold and
/// 10⁷ filtered photons beat 10⁸ raw ones; the traced cut-off's edge
/// stays within 2 texels (2.74 at 10⁵ photons); 5 widens it to 5.1.
pub const AUTO_Z: f64 = 4.0;
/// Fewest photons a texel needs before the automatic mode believes its
/// deviation from the estimate is structure rather than noise.
pub const AUTO_MIN_KEEP: f64 = 32.0;
/// Counts above which the automatic mode never replaces a texel (its
/// relative noise is then ≤ 1/√AUTO_MAX ≈ 6 %; tuned with
/// `lucerna filter-bench`).
pub const AUTO_MAX: f64 = 256.0;
/// Threshold the automatic mode uses for Algorithm 2's border test.
pub const AUTO_BORDER: f64 = 64.0;

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
    /// The threshold used (photons).
    pub threshold: f64,
    /// Factor applied to the replaced texels to keep the traced flux.
    pub renormalisation: f64,
}

/// One pyramid level: photon counts and solid angles per texel.
struct Level {
    layout: CubeMapLayout,
    counts: Vec<f64>,
    omega: Vec<f64>,
}

/// The count below which a texel may be replaced, and the one the border
/// test uses.
pub fn thresholds(threshold: Threshold) -> (f64, f64) {
    match threshold {
        Threshold::Fixed(t) => (t, t),
        Threshold::Automatic => (AUTO_MAX, AUTO_BORDER),
    }
}

/// The automatic mode's cap on levels ≥ 2: it grows slowly with the photons
/// per lit texel m (64 at m ≤ 1, up to [`AUTO_MAX`]), as the best fixed
/// threshold does (100 at 1 photon per texel, 250 at 10 in
/// `lucerna filter-bench`).
pub fn automatic_coarse_cap(counts: &[u64]) -> f64 {
    let (lit, sum) = counts
        .iter()
        .filter(|&&c| c > 0)
        .fold((0u64, 0u64), |(n, s), &c| (n + 1, s + c));
    let m = if lit > 0 {
        sum as f64 / lit as f64
    } else {
        0.0
    };
    (64.0 * m.max(1.0).powf(0.4)).clamp(64.0, AUTO_MAX)
}

/// Builds the pull pyramid: level k+1 sums 2×2 texels of level k.
fn pull(layout: CubeMapLayout, counts: &[u64]) -> Vec<Level> {
    let mut levels = vec![Level {
        layout,
        counts: counts.iter().map(|&c| c as f64).collect(),
        omega: layout.solid_angles(),
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
    // Past a cube corner there is no diagonal neighbour: step across one
    // edge only, so the lookup never hangs on a tie between two faces.
    let cy = if (0..n).contains(&cx) {
        cy
    } else {
        cy.clamp(0, n - 1)
    };
    let step = 2.0 / n as f64;
    let a = -1.0 + (cx as f64 + 0.5) * step;
    let b = -1.0 + (cy as f64 + 0.5) * step;
    layout.texel_of_direction(face.direction(a, b))
}

fn safe_intensity(count: f64, omega: f64) -> f64 {
    if omega > 0.0 { count / omega } else { 0.0 }
}

/// Bilateral interpolation of the coarser level's filtered intensities at
/// the centre of fine texel (face, i, j).
fn upsample(
    fine: CubeMapLayout,
    coarse: CubeMapLayout,
    coarse_intensity: &[f64],
    face: CubeFace,
    i: u32,
    j: u32,
    settings: &FilterSettings,
) -> f64 {
    let ratio = f64::from(coarse.resolution) / f64::from(fine.resolution);
    let x = (f64::from(i) + 0.5) * ratio - 0.5;
    let y = (f64::from(j) + 0.5) * ratio - 0.5;
    let (x0, y0) = (x.floor(), y.floor());
    let (fx, fy) = (x - x0, y - y0);
    let corners = [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0)];
    let mut values = [0.0; 4];
    let mut bilinear = [0.0; 4];
    let mut closeness = [0.0; 4];
    for (k, &(dx, dy)) in corners.iter().enumerate() {
        let (cx, cy) = (x0 + dx, y0 + dy);
        values[k] = coarse_intensity[texel_at(coarse, face, cx as i64, cy as i64)];
        bilinear[k] =
            (if dx == 0.0 { 1.0 - fx } else { fx }) * (if dy == 0.0 { 1.0 - fy } else { fy });
        let d2 = (x - cx).powi(2) + (y - cy).powi(2);
        closeness[k] = (-0.5 * d2 / (settings.sigma_closeness * settings.sigma_closeness)).exp();
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
    pull(layout, &vec![0; layout.texel_count()])
        .into_iter()
        .map(|l| l.omega)
        .collect()
}

/// Filters a map of photon counts (texel order of `layout`).
pub fn filter(layout: CubeMapLayout, counts: &[u64], settings: &FilterSettings) -> Filtered {
    let (threshold, border_threshold) = thresholds(settings.threshold);
    debug_assert_eq!(counts.len(), layout.texel_count());
    let automatic = settings.threshold == Threshold::Automatic;
    let coarse_cap = automatic_coarse_cap(counts);
    let levels = pull(layout, counts);
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
        let (next, next_replaced): (Vec<f64>, Vec<bool>) = (0..level.layout.texel_count())
            .into_par_iter()
            .map(|t| {
                let own = safe_intensity(level.counts[t], level.omega[t]);
                // The automatic mode caps the count only on the two finest
                // levels; above them the border test and the Poisson test
                // decide alone.
                let cap = if automatic && k >= settings.first_border_level {
                    coarse_cap
                } else {
                    threshold
                };
                if level.counts[t] >= cap {
                    return (own, false);
                }
                let (face, i, j) = level.layout.texel_coordinates(t);
                if border_test && on_shadow_border(level, face, i, j, border_threshold) {
                    return (own, false);
                }
                let estimate = upsample(
                    level.layout,
                    coarse.layout,
                    &intensity,
                    face,
                    i,
                    j,
                    settings,
                );
                if automatic {
                    let expected = estimate * level.omega[t];
                    let c = level.counts[t];
                    // Too few photons where many were expected: a shadow.
                    // Too many where few were expected: structure, once the
                    // count is large enough not to be Poisson's long tail.
                    let darker = c < expected && expected - c > AUTO_Z * expected.sqrt();
                    let brighter =
                        c >= AUTO_MIN_KEEP && c - expected > AUTO_Z * (expected + 1.0).sqrt();
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
        renormalisation,
    }
}

/// Filters an intensity map; returns candela per texel and the report.
pub fn filter_map(
    map: &lucerna_photometry::IntensityMap,
    settings: &FilterSettings,
) -> (Vec<f64>, Filtered) {
    let f = filter(map.layout, &map.counts, settings);
    let phi = map.flux_per_photon_lm();
    (f.photons_per_sr.iter().map(|v| v * phi).collect(), f)
}
