#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! Filtering with a luminaire's symmetry: pooled images are worth the
//! photons they stand for, stable texels keep their pooled value, the flux
//! is kept, and the result is symmetric.

mod common;

use common::{photons, rms, truth};
use lucerna_filter::{FilterSettings, Threshold, filter, filter_symmetric};
use lucerna_photometry::{AxialSymmetry, CubeMapLayout, TexelSymmetry};

/// A downlight-like distribution with the square's symmetry: a bright
/// cone with four brighter lobes (facets) and a hard cut-off at 60°.
fn lobed(d: [f64; 3]) -> f64 {
    let [x, y, z] = d;
    if z < 0.5 {
        return 0.02;
    }
    let r2 = (x * x + y * y).max(1e-12);
    let four_fold = ((x * x - y * y) / r2).powi(2); // cos² 2C
    0.3 + 0.4 * z * z + 0.3 * four_fold
}

#[test]
fn pooling_the_images_is_worth_the_photons_they_stand_for() {
    let layout = CubeMapLayout::new(32);
    let texels = layout.texel_count();
    let sym = TexelSymmetry::new(layout, AxialSymmetry::Square);
    for per_texel in [2usize, 20] {
        let n = per_texel * texels;
        let counts = photons(layout, n, 11 + per_texel as u64, lobed);
        let many = photons(layout, 8 * n, 12 + per_texel as u64, lobed);
        let truth_n = truth(layout, n, &lobed);
        let settings = FilterSettings::default();
        let plain = filter(layout, &counts, &settings);
        let pooled = filter_symmetric(&counts, &settings, &sym);
        // The plain filter on 8× the photons, scaled back to n.
        let eight: Vec<f64> = filter(layout, &many, &settings)
            .photons_per_sr
            .iter()
            .map(|v| v / 8.0)
            .collect();
        let (e_plain, e_pooled, e_eight) = (
            rms(&plain.photons_per_sr, &truth_n),
            rms(&pooled.photons_per_sr, &truth_n),
            rms(&eight, &truth_n),
        );
        eprintln!(
            "{per_texel} photons/texel: RMS plain {e_plain:.2}, pooled over 8 images {e_pooled:.2} ({}), plain at 8× {e_eight:.2}",
            pooled.settings
        );
        assert_eq!(pooled.symmetry, AxialSymmetry::Square);
        assert!(e_pooled < 0.6 * e_plain, "{e_pooled} vs {e_plain}");
        assert!(e_pooled < 1.25 * e_eight, "{e_pooled} vs {e_eight} at 8×");
    }
}

#[test]
fn stable_texels_keep_their_pooled_value_and_the_flux_is_kept() {
    // A power of two: every pyramid level halves evenly, so the pyramid is
    // as symmetric as the map (at 24, the 3 → 2 level is not, and a
    // half turn's images differ by up to 10 % where coarse levels decide).
    let layout = CubeMapLayout::new(32);
    let omega = layout.solid_angles();
    for s in [AxialSymmetry::Quadrant, AxialSymmetry::Square] {
        let sym = TexelSymmetry::new(layout, s);
        let counts = photons(layout, 6 * layout.texel_count(), 21, lobed);
        let pooled = sym.pool(&counts);
        for threshold in [
            Threshold::Fixed(100.0),
            Threshold::Poisson { cap: 256.0, z: 4.0 },
            Threshold::Automatic,
        ] {
            let settings = FilterSettings {
                threshold,
                ..Default::default()
            };
            let f = filter_symmetric(&counts, &settings, &sym);
            let order = sym.order() as f64;
            let mut kept = 0;
            for t in 0..counts.len() {
                if !f.replaced[t] {
                    kept += 1;
                    let own = pooled[t] as f64 / omega[t] / order;
                    assert!(
                        (f.photons_per_sr[t] - own).abs() <= 1e-12 * own.max(1.0),
                        "{s:?} {threshold:?}: stable texel {t} changed"
                    );
                }
            }
            assert!(
                kept > 0 && kept < counts.len(),
                "{s:?} {threshold:?}: {kept} kept"
            );
            // Flux (photons) of the filtered map: the traced photons.
            let flux: f64 = f
                .photons_per_sr
                .iter()
                .zip(&omega)
                .map(|(v, w)| v * w)
                .sum();
            let traced = counts.iter().sum::<u64>() as f64;
            assert!(
                (flux / traced - 1.0).abs() < 1e-9,
                "{s:?} {threshold:?}: {flux} of {traced} photons"
            );
            // A symmetric input gives a symmetric result: images agree.
            for g in 1..sym.order() {
                let worst = (0..counts.len())
                    .map(|t| {
                        let (a, b) = (f.photons_per_sr[t], f.photons_per_sr[sym.image(g, t)]);
                        (a - b).abs() / a.max(b).max(1e-9)
                    })
                    .fold(0.0, f64::max);
                assert!(
                    worst < 1e-6,
                    "{s:?} {threshold:?}: image {g} differs by {worst}"
                );
            }
        }
    }
}

#[test]
fn no_symmetry_is_the_plain_filter() {
    let layout = CubeMapLayout::new(16);
    let counts = photons(layout, 10 * layout.texel_count(), 5, lobed);
    let settings = FilterSettings::default();
    assert_eq!(
        filter_symmetric(&counts, &settings, &TexelSymmetry::none(layout)),
        filter(layout, &counts, &settings)
    );
}
