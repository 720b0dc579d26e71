//! Multinomial thinning of photon counts: the independent parts the
//! automatic mode's cross-validation trains and scores on, drawn from
//! counter-based random bits so a map always splits the same way.

use rand_xoshiro::SplitMix64;
use rand_xoshiro::rand_core::{RngCore, SeedableRng};
use rayon::prelude::*;

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

/// Uniform in [0, 1) from `key`: the first output of SplitMix64 (the
/// workspace's, rand_xoshiro's) seeded with it, so the thinning's random
/// bits are counter-based.
fn unit(key: u64) -> f64 {
    (SplitMix64::seed_from_u64(key).next_u64() >> 11) as f64 / (1u64 << 53) as f64
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
