//! One pull-push pass with concrete settings: the pull pyramid of photon
//! counts and solid angles, the bilateral upsampling across cube faces,
//! Algorithm 2's shadow-border test, the Poisson test, and the flux
//! renormalisation of the replaced texels.

use lucerna_photometry::{AxialSymmetry, CubeFace, CubeMapLayout};
use rayon::prelude::*;

use crate::filtered::Filtered;
use crate::intensity::safe_intensity;
use crate::settings::{FilterSettings, POISSON_MIN_KEEP_PHOTONS, Threshold};

/// One pyramid level: photon counts and solid angles per texel.
struct Level {
    layout: CubeMapLayout,
    counts: Vec<f64>,
    omega: Vec<f64>,
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
pub(crate) fn renormalise(
    counts: &[f64],
    omega: &[f64],
    intensity: &mut [f64],
    replaced: &[bool],
) -> f64 {
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
pub(crate) fn pyramid_resolutions(resolution: u32) -> Vec<u32> {
    let mut v = vec![resolution.max(1)];
    while let Some(&n) = v.last()
        && n > 1
    {
        v.push(n.div_ceil(2));
    }
    v
}

/// Solid angles of every level's texels (the pull of texel solid angles).
pub(crate) fn pyramid_solid_angles(layout: CubeMapLayout) -> Vec<Vec<f64>> {
    pull(
        layout,
        &vec![0; layout.texel_count()],
        &layout.solid_angles(),
    )
    .into_iter()
    .map(|l| l.omega)
    .collect()
}

/// One pull-push pass with concrete settings (not `Automatic`); `omega`
/// holds the level-0 texel solid angles.
pub(crate) fn pull_push(
    layout: CubeMapLayout,
    counts: &[u64],
    settings: &FilterSettings,
    omega: &[f64],
) -> Filtered {
    // Callers resolve `Automatic` first (`choose_automatic`).
    debug_assert!(settings.threshold != Threshold::Automatic);
    let thresholds = settings.threshold.photon_thresholds();
    debug_assert_eq!(counts.len(), layout.texel_count());
    let poisson_z = settings.threshold.poisson_z();
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
                if level.counts[t] >= thresholds.stable {
                    return (own, false);
                }
                let (face, i, j) = level.layout.texel_coordinates(t);
                if border_test && on_shadow_border(level, face, i, j, thresholds.border) {
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
                    let brighter =
                        c >= POISSON_MIN_KEEP_PHOTONS && c - expected > z * (expected + 1.0).sqrt();
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
        threshold: thresholds.stable,
        settings: *settings,
        automatic: None,
        renormalisation,
        symmetry: AxialSymmetry::None,
    }
}
