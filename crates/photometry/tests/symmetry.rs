#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! Luminaire symmetries on the cube map: exact texel permutations, exact
//! photon bookkeeping when pooling, and the variance it saves.

use lucerna_photometry::{
    AxialIsometry, AxialSymmetry, CubeMapLayout, IntensityMap, TexelSymmetry,
};

/// Largest component difference of two unit vectors.
fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|i| (a[i] - b[i]).abs()).fold(0.0, f64::max)
}

#[test]
fn isometries_permute_texels_of_equal_solid_angle() {
    for n in [1u32, 2, 3, 5, 16] {
        let layout = CubeMapLayout::new(n);
        let omega = layout.solid_angles();
        let sym = TexelSymmetry::new(layout, AxialSymmetry::Square);
        let elements = AxialSymmetry::Square.elements();
        for (g, isometry) in elements.iter().enumerate() {
            let mut hit = vec![false; layout.texel_count()];
            for t in 0..layout.texel_count() {
                let image = sym.image(g, t);
                assert!(
                    !hit[image],
                    "N = {n}, {isometry:?}: two texels onto {image}"
                );
                hit[image] = true;
                assert!(
                    // Equal up to the rounding of the atan2 differences.
                    (omega[image] - omega[t]).abs() <= 1e-11 * omega[t],
                    "N = {n}, {isometry:?}: texel {t} → {image} changes solid angle"
                );
                // Centre onto centre: the image texel's centre is the
                // isometry applied to this one's.
                let moved = isometry.apply(layout.texel_centre_direction(t));
                assert!(distance(moved, layout.texel_centre_direction(image)) < 1e-14);
            }
        }
    }
}

#[test]
fn orbit_size_times_multiplicity_is_the_group_order() {
    let layout = CubeMapLayout::new(6);
    for s in AxialSymmetry::ALL {
        let sym = TexelSymmetry::new(layout, s);
        for t in 0..layout.texel_count() {
            let mut orbit: Vec<usize> = (0..sym.order()).map(|g| sym.image(g, t)).collect();
            orbit.sort_unstable();
            orbit.dedup();
            assert_eq!(
                orbit.len() * sym.multiplicity(t),
                sym.order(),
                "{s:?}, texel {t}"
            );
        }
    }
}

#[test]
fn identity_and_mirror_only_groups_behave() {
    let layout = CubeMapLayout::new(4);
    let counts: Vec<u64> = (0..layout.texel_count() as u64).collect();
    assert_eq!(TexelSymmetry::none(layout).pool(&counts), counts);
    // Mirror in the C0-C180 plane (y → −y) swaps the ±Y faces and keeps
    // the ±X faces as sets.
    let sym = TexelSymmetry::new(layout, AxialSymmetry::AboutC0C180);
    let pooled = sym.pool(&counts);
    let plus_y = layout.texel_index(lucerna_photometry::CubeFace::PosY, 1, 2);
    let mirrored = layout.texel_of_direction(
        AxialIsometry::MirrorC0C180.apply(layout.texel_centre_direction(plus_y)),
    );
    assert_eq!(
        layout.texel_coordinates(mirrored).0,
        lucerna_photometry::CubeFace::NegY
    );
    assert_eq!(pooled[plus_y], counts[plus_y] + counts[mirrored]);
}

#[test]
fn pooling_keeps_the_photon_balance_and_the_flux_exactly() {
    let layout = CubeMapLayout::new(8);
    let mut map = IntensityMap::new(layout, 1200.0);
    // Arbitrary asymmetric counts with a balanced bookkeeping.
    map.counts = (0..layout.texel_count() as u64)
        .map(|t| (t * 7919) % 97)
        .collect();
    map.photons_absorbed = 1234;
    map.photons_cut_off = 56;
    map.photons_emitted = map.photons_escaped() + 1234 + 56;
    for s in AxialSymmetry::ALL {
        let sym = TexelSymmetry::new(layout, s);
        let pooled = map.symmetrised(&sym);
        assert!(pooled.is_balanced(), "{s:?}");
        assert_eq!(
            pooled.photons_escaped(),
            map.photons_escaped() * s.order() as u64
        );
        let (a, b) = (map.escaped_flux_lm(), pooled.escaped_flux_lm());
        assert!((a - b).abs() <= 1e-12 * a, "{s:?}: {a} lm → {b} lm");
        // Candela are the average over the images of each texel.
        let cd = map.candela();
        let pooled_cd = pooled.candela();
        for t in (0..layout.texel_count()).step_by(17) {
            let mean =
                (0..sym.order()).map(|g| cd[sym.image(g, t)]).sum::<f64>() / sym.order() as f64;
            assert!(
                (pooled_cd[t] - mean).abs() <= 1e-12 * mean.max(1.0),
                "{s:?}"
            );
        }
    }
}

/// Poisson counts of a symmetric distribution (SplitMix-driven inversion;
/// the means are small, so inversion is exact enough).
fn poisson(mean: f64, state: &mut u64) -> u64 {
    *state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
    let mut z = *state;
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    let u = ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64;
    let (mut k, mut p) = (0u64, (-mean).exp());
    let mut cdf = p;
    while u > cdf && k < 10_000 {
        k += 1;
        p *= mean / k as f64;
        cdf += p;
    }
    k
}

#[test]
fn pooling_a_symmetric_distribution_divides_the_variance_by_the_order() {
    let layout = CubeMapLayout::new(32);
    let omega = layout.solid_angles();
    // A D4-symmetric intensity: brighter towards nadir, with four lobes.
    let truth: Vec<f64> = (0..layout.texel_count())
        .map(|t| {
            let [x, y, z] = layout.texel_centre_direction(t);
            let lobes = 1.0 + 0.5 * (x * x - y * y).powi(2);
            20.0 * (1.0 - z).powi(2) * lobes * omega[t] / omega[0]
        })
        .collect();
    let mut state = 7u64;
    let counts: Vec<u64> = truth.iter().map(|&m| poisson(m, &mut state)).collect();
    let error = |estimate: &[f64]| {
        estimate
            .iter()
            .zip(&truth)
            .map(|(e, m)| (e - m).powi(2))
            .sum::<f64>()
    };
    let raw: Vec<f64> = counts.iter().map(|&c| c as f64).collect();
    for s in [AxialSymmetry::Quadrant, AxialSymmetry::Square] {
        let sym = TexelSymmetry::new(layout, s);
        let pooled: Vec<f64> = sym
            .pool(&counts)
            .iter()
            .map(|&c| c as f64 / sym.order() as f64)
            .collect();
        let ratio = error(&raw) / error(&pooled);
        // Expected: the order, a little less where texels are their own
        // images; 6144 texels make the ratio good to a few per cent.
        let order = sym.order() as f64;
        assert!(
            ratio > 0.85 * order && ratio < 1.15 * order,
            "{s:?}: squared error down by {ratio:.2}, expected about {order}"
        );
    }
    // An asymmetric distribution pooled is biased: the test above can fail.
    let skewed: Vec<f64> = (0..layout.texel_count())
        .map(|t| {
            let [x, _, _] = layout.texel_centre_direction(t);
            50.0 * (1.0 + x)
        })
        .collect();
    let sym = TexelSymmetry::new(layout, AxialSymmetry::Square);
    let counts: Vec<u64> = skewed.iter().map(|&m| poisson(m, &mut state)).collect();
    let pooled: Vec<f64> = sym.pool(&counts).iter().map(|&c| c as f64 / 8.0).collect();
    let bias: f64 = pooled
        .iter()
        .zip(&skewed)
        .map(|(p, m)| (p - m).powi(2))
        .sum::<f64>();
    let noise: f64 = counts
        .iter()
        .zip(&skewed)
        .map(|(&c, m)| (c as f64 - m).powi(2))
        .sum::<f64>();
    assert!(
        bias > noise,
        "pooling an asymmetric map must show: {bias} vs {noise}"
    );
}
