//! Photon maps drawn from analytic distributions, for the filter's tests.
#![allow(dead_code)] // reason: each test binary uses a part

use lucerna_photometry::CubeMapLayout;

/// xorshift64*: test randomness without a dependency.
pub struct Rng(u64);
impl Rng {
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
