//! What every filter call goes through, on the CPU and the GPU alike: pool
//! the traced counts over the luminaire's symmetry, resolve `Automatic` by
//! cross-validation, run the final pass, scale the result per traced
//! photon.

use lucerna_photometry::{CubeMapLayout, IntensityMap, TexelSymmetry};

use crate::cross_validation::{AutomaticReport, choose_automatic};
use crate::filtered::Filtered;
use crate::pyramid::pull_push;
use crate::settings::{FilterSettings, Threshold};

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
    // The texel solid angles, shared by every call on this layout.
    let omega = layout.shared_solid_angles();
    let filtered = filter_pooled(&omega, counts, settings, symmetry, |c, concrete| {
        Ok::<_, std::convert::Infallible>(pull_push(layout, c, concrete, &omega))
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

/// Filters an intensity map of a luminaire with `symmetry` (of the map's
/// layout; [`TexelSymmetry::none`] for none); returns candela per texel and
/// the report.
pub fn filter_map(
    map: &IntensityMap,
    settings: &FilterSettings,
    symmetry: &TexelSymmetry,
) -> (Vec<f64>, Filtered) {
    let f = filter_symmetric(&map.counts, settings, symmetry);
    let phi = map.flux_per_photon_lm();
    (f.photons_per_sr.iter().map(|v| v * phi).collect(), f)
}
