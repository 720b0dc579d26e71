//! Photon maps drawn from analytic distributions, for the filter's tests.
#![allow(dead_code)] // reason: each test binary uses a part

use lucerna_photometry::CubeMapLayout;
use lucerna_photometry::cubemap::rectangle_solid_angle;

/// xorshift64*: test randomness without a dependency.
pub struct Rng(u64);
impl Rng {
    /// A generator from a non-zero seed.
    pub fn new(seed: u64) -> Rng {
        Rng(seed)
    }
    pub fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn direction(&mut self) -> [f64; 3] {
        let z = 1.0 - 2.0 * self.next();
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = 2.0 * std::f64::consts::PI * self.next();
        [r * phi.cos(), r * phi.sin(), z]
    }
}

/// Photons from a distribution proportional to `weight(d)` (≤ 1), by
/// rejection, counted per texel like the tracer does.
pub fn photons(
    layout: CubeMapLayout,
    n: usize,
    seed: u64,
    weight: impl Fn([f64; 3]) -> f64,
) -> Vec<u64> {
    let mut rng = Rng(seed);
    let mut counts = vec![0u64; layout.texel_count()];
    let mut kept = 0;
    while kept < n {
        let d = rng.direction();
        if rng.next() < weight(d) {
            counts[layout.texel_of_direction(d)] += 1;
            kept += 1;
        }
    }
    counts
}

/// Expected photons per steradian of every texel for `n` photons drawn from
/// `weight`: the weight integrated over 4 × 4 sub-cells of each texel.
pub fn truth(layout: CubeMapLayout, n: usize, weight: &impl Fn([f64; 3]) -> f64) -> Vec<f64> {
    let sub = 4;
    let mut mass = vec![0.0; layout.texel_count()];
    for (t, m) in mass.iter_mut().enumerate() {
        let (face, a0, b0, a1, b1) = layout.texel_bounds(t);
        let (da, db) = ((a1 - a0) / sub as f64, (b1 - b0) / sub as f64);
        for i in 0..sub {
            for j in 0..sub {
                let (x0, y0) = (a0 + i as f64 * da, b0 + j as f64 * db);
                let d = face.direction(x0 + 0.5 * da, y0 + 0.5 * db);
                let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                *m += weight([d[0] / l, d[1] / l, d[2] / l])
                    * rectangle_solid_angle(x0, y0, x0 + da, y0 + db);
            }
        }
    }
    let total: f64 = mass.iter().sum();
    mass.iter()
        .enumerate()
        .map(|(t, m)| n as f64 * m / total / layout.texel_solid_angle(t))
        .collect()
}

/// Root mean square difference.
pub fn rms(a: &[f64], b: &[f64]) -> f64 {
    (a.iter().zip(b).map(|(x, y)| (x - y).powi(2)).sum::<f64>() / a.len() as f64).sqrt()
}
