#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! The evaluation's error measures against known answers: closed forms for
//! the mean-scaled RMSE, and Poisson maps drawn from a known mean for the
//! reference-noise estimate and its removal.

mod common;

use common::Rng;
use lucerna_filter::evaluation::{
    mean_scaled_rmse, raw_photons_per_sr, reference_noise_mse, rmse_without_reference_noise,
};
use lucerna_photometry::{AxialSymmetry, CubeMapLayout, TexelSymmetry};

/// An exact Poisson draw: CDF inversion in pieces of mean ≤ 100 (a sum of
/// independent Poisson draws is Poisson), so e^(−mean) cannot underflow.
fn poisson(mean: f64, rng: &mut Rng) -> u64 {
    let mut total = 0;
    let mut left = mean;
    while left > 0.0 {
        let m = left.min(100.0);
        left -= m;
        let u = rng.next();
        let mut p = (-m).exp();
        let mut cdf = p;
        let mut k = 0u64;
        while u >= cdf && p > 0.0 {
            k += 1;
            p *= m / k as f64;
            cdf += p;
        }
        total += k;
    }
    total
}

/// A lobed intensity (arbitrary units per steradian), unchanged by the
/// square's eight isometries about the z axis.
fn lobed(d: [f64; 3]) -> f64 {
    0.25 + 0.75 * d[2].max(0.0).powi(2) + 2.0 * d[0] * d[0] * d[1] * d[1]
}

/// Expected photons per texel: `lobed` at the texel's centre × its solid
/// angle, scaled to `per_texel` photons per texel on average.
fn expected_counts(layout: CubeMapLayout, per_texel: f64) -> Vec<f64> {
    let raw: Vec<f64> = (0..layout.texel_count())
        .map(|t| lobed(layout.texel_centre_direction(t)) * layout.texel_solid_angle(t))
        .collect();
    let scale = per_texel * raw.len() as f64 / raw.iter().sum::<f64>();
    raw.iter().map(|l| l * scale).collect()
}

fn draw(lambda: &[f64], rng: &mut Rng) -> Vec<u64> {
    lambda.iter().map(|&l| poisson(l, rng)).collect()
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

#[test]
fn raw_intensity_is_counts_per_steradian() {
    let layout = CubeMapLayout::new(7);
    let counts: Vec<u64> = (0..layout.texel_count() as u64).map(|t| t % 13).collect();
    let intensity = raw_photons_per_sr(layout, &counts);
    for (t, (&i, &c)) in intensity.iter().zip(&counts).enumerate() {
        let back = i * layout.texel_solid_angle(t);
        assert!(
            (back - c as f64).abs() <= 1e-12 * (c as f64).max(1.0),
            "{t}"
        );
    }
}

#[test]
fn rmse_of_identical_or_proportional_maps_is_zero() {
    let a: Vec<f64> = (0..500).map(|t| 1.0 + (t % 7) as f64).collect();
    assert_eq!(mean_scaled_rmse(&a, &a), 0.0);
    // Each map is scaled by its own mean: flux and photon count drop out.
    let b: Vec<f64> = a.iter().map(|x| 3.7 * x).collect();
    assert!(mean_scaled_rmse(&a, &b) < 1e-12);
    // No mean to scale by.
    assert_eq!(mean_scaled_rmse(&a, &vec![0.0; a.len()]), f64::INFINITY);
    assert_eq!(mean_scaled_rmse(&[], &[]), f64::INFINITY);
}

#[test]
fn rmse_of_a_constant_offset_is_the_closed_form() {
    // b = a + c: a/m − (a + c)/(m + c) = c (a − m) / (m (m + c)), so the
    // RMSE is c σ / (m (m + c)), σ the population deviation of a.
    let a: Vec<f64> = (0..1000)
        .map(|t| 2.0 + (t as f64 * 0.37).sin() + (t % 5) as f64)
        .collect();
    let m = mean(&a);
    let sigma = (a.iter().map(|x| (x - m).powi(2)).sum::<f64>() / a.len() as f64).sqrt();
    for c in [0.1, 2.5, 40.0] {
        let b: Vec<f64> = a.iter().map(|x| x + c).collect();
        let expected = c * sigma / (m * (m + c));
        let got = mean_scaled_rmse(&a, &b);
        assert!(
            (got - expected).abs() <= 1e-12 * expected,
            "{c}: {got} vs {expected}"
        );
        // Symmetric in its arguments.
        assert!((mean_scaled_rmse(&b, &a) - got).abs() <= 1e-12 * expected);
    }
}

#[test]
fn reference_noise_of_a_poisson_map_is_its_expected_variance() {
    let layout = CubeMapLayout::new(64);
    let omega = layout.solid_angles();
    let lambda = expected_counts(layout, 50.0);
    let counts = draw(&lambda, &mut Rng::new(0x5EED_0001));
    let got = reference_noise_mse(layout, &counts, &TexelSymmetry::none(layout));

    // E = mean(λ/Ω²) / mean(λ/Ω)²; its standard error from the variances
    // of numerator and denominator (Poisson: var c = λ), by the delta method.
    let t = lambda.len() as f64;
    let numerator = lambda
        .iter()
        .zip(&omega)
        .map(|(l, w)| l / (w * w))
        .sum::<f64>()
        / t;
    let truth: Vec<f64> = lambda.iter().zip(&omega).map(|(l, w)| l / w).collect();
    let m = mean(&truth);
    let expected = numerator / (m * m);
    let var_numerator = lambda
        .iter()
        .zip(&omega)
        .map(|(l, w)| l / w.powi(4))
        .sum::<f64>()
        / t
        / t;
    let var_mean = lambda
        .iter()
        .zip(&omega)
        .map(|(l, w)| l / (w * w))
        .sum::<f64>()
        / t
        / t;
    let se = expected * (var_numerator / numerator.powi(2) + 4.0 * var_mean / (m * m)).sqrt();
    eprintln!("noise MSE estimated {got:.6}, expected {expected:.6} ± {se:.6}");
    assert!(
        (got - expected).abs() < 4.0 * se,
        "estimated {got} vs expected {expected} ± {se}"
    );

    // And it is what the noise costs: the drawn map's squared mean-scaled
    // RMSE against its own mean, within its standard error
    // (var (c − λ)² = 2λ² + λ).
    let measured = mean_scaled_rmse(&raw_photons_per_sr(layout, &counts), &truth).powi(2);
    let se_measured = (lambda
        .iter()
        .zip(&omega)
        .map(|(l, w)| (2.0 * l * l + l) / w.powi(4))
        .sum::<f64>()
        .sqrt()
        / t)
        / (m * m);
    eprintln!("measured {measured:.6} ± {se_measured:.6}");
    assert!(
        (measured - expected).abs() < 4.0 * (se_measured * se_measured + se * se).sqrt(),
        "measured {measured} vs expected {expected} ± {se_measured}"
    );
}

#[test]
fn reference_noise_of_a_pooled_map_counts_each_texel_multiplicity() {
    // Pooling over the square's eight isometries counts a photon m times
    // on a texel that m of them map onto itself (2 on a mirror plane, 8 at
    // the pole), which multiplies its variance by m. Lit only on such
    // texels (odd resolution: rows and columns on the mirrors), the
    // estimate must
    // match the noise the pooled maps really have, on average over draws:
    // mean over texels of (r − E r)² / mean(E r)². (Against the truth
    // scaled by the map's own mean instead, as `mean_scaled_rmse` does,
    // the noise of the mean itself drops out, about 3 % here, where
    // 6 % of the texels hold all the photons.)
    let layout = CubeMapLayout::new(33);
    let omega = layout.solid_angles();
    let symmetry = TexelSymmetry::new(layout, AxialSymmetry::Square);
    let lambda: Vec<f64> = expected_counts(layout, 40.0)
        .iter()
        .enumerate()
        .map(|(t, &l)| if symmetry.multiplicity(t) > 1 { l } else { 0.0 })
        .collect();
    assert!(lambda.iter().filter(|&&l| l > 0.0).count() > 300);
    // The pooled map's expected intensity: each of the 8 images adds λ.
    let truth: Vec<f64> = lambda
        .iter()
        .zip(&omega)
        .map(|(l, w)| symmetry.order() as f64 * l / w)
        .collect();
    let truth_mean = mean(&truth);
    let mut rng = Rng::new(0x5EED_0002);
    let draws = 40;
    let (mut measured, mut estimated, mut ignoring) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..draws {
        let pooled = symmetry.pool(&draw(&lambda, &mut rng));
        let intensity = raw_photons_per_sr(layout, &pooled);
        let squared: Vec<f64> = intensity
            .iter()
            .zip(&truth)
            .map(|(r, f)| ((r - f) / truth_mean).powi(2))
            .collect();
        measured.push(mean(&squared));
        estimated.push(reference_noise_mse(layout, &pooled, &symmetry));
        ignoring.push(reference_noise_mse(
            layout,
            &pooled,
            &TexelSymmetry::none(layout),
        ));
    }
    let standard_error = |v: &[f64]| {
        let m = mean(v);
        (v.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (v.len() - 1) as f64 / v.len() as f64)
            .sqrt()
    };
    let se = (standard_error(&measured).powi(2) + standard_error(&estimated).powi(2)).sqrt();
    let (measured, estimated, ignoring) = (mean(&measured), mean(&estimated), mean(&ignoring));
    eprintln!(
        "pooled: measured {measured:.6}, estimated {estimated:.6} ± {se:.6}, without multiplicities {ignoring:.6}"
    );
    assert!(
        (measured - estimated).abs() < 4.0 * se,
        "measured {measured} vs estimated {estimated} ± {se}"
    );
    // The multiplicity is what makes it right here.
    assert!(
        measured - ignoring > 10.0 * se,
        "without multiplicities {ignoring} vs {measured} ± {se}"
    );
}

#[test]
fn removing_the_reference_noise_recovers_the_true_rmse() {
    // A map with a known error against the truth (a 10 % ripple), measured
    // against a noisy reference whose noise costs about as much.
    let layout = CubeMapLayout::new(64);
    let omega = layout.solid_angles();
    let lambda = expected_counts(layout, 400.0);
    let truth: Vec<f64> = lambda.iter().zip(&omega).map(|(l, w)| l / w).collect();
    let map: Vec<f64> = truth
        .iter()
        .enumerate()
        .map(|(t, &f)| {
            let d = layout.texel_centre_direction(t);
            f * (1.0 + 0.1 * (7.0 * d[0]).sin() * (5.0 * d[1]).cos())
        })
        .collect();
    let true_mse = mean_scaled_rmse(&map, &truth).powi(2);
    let reference = draw(&lambda, &mut Rng::new(0x5EED_0003));
    let measured = mean_scaled_rmse(&map, &raw_photons_per_sr(layout, &reference));
    let noise = reference_noise_mse(layout, &reference, &TexelSymmetry::none(layout));
    let corrected = rmse_without_reference_noise(measured, noise);

    // Standard error of measured² − noise: per texel, the cross term
    // 2·d·n (var 4 d² v) and the squared noise (var 2 v² + v²/λ), v the
    // texel's mean-scaled noise variance, d its mean-scaled true error;
    // doubled to cover the noise estimate's own spread and correlation.
    let t = lambda.len() as f64;
    let (m_map, m_truth) = (mean(&map), mean(&truth));
    let var_sum: f64 = (0..lambda.len())
        .map(|k| {
            let v = lambda[k] / (omega[k] * omega[k]) / (m_truth * m_truth);
            let d = map[k] / m_map - truth[k] / m_truth;
            4.0 * d * d * v + 2.0 * v * v + v * v / lambda[k]
        })
        .sum();
    let se = (2.0 * var_sum).sqrt() / t;
    eprintln!(
        "true MSE {true_mse:.6}, measured {:.6}, corrected {:.6} ± {se:.6}",
        measured * measured,
        corrected * corrected
    );
    assert!(
        measured * measured - true_mse > 10.0 * se,
        "the reference's noise should matter here: {measured}² vs {true_mse}"
    );
    assert!(
        (corrected * corrected - true_mse).abs() < 4.0 * se,
        "corrected {corrected}² vs true {true_mse} ± {se}"
    );
    // With no noise to remove, the measured RMSE is returned; with only
    // noise, zero.
    assert_eq!(rmse_without_reference_noise(0.25, 0.0), 0.25);
    assert_eq!(rmse_without_reference_noise(0.1, 0.02), 0.0);
    assert!((rmse_without_reference_noise(0.5, 0.09) - 0.4).abs() < 1e-15);
}
