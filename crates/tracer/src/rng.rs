//! Counter-based randomness: every photon's stream is a hash of (seed,
//! iteration, photon index), so a bake is reproducible and splits into
//! independent parts whose counts add up. The WGSL twin is in
//! `shaders/tracer.wgsl`; both use only 32-bit integer arithmetic.

/// PCG hash (Jarzynski & Olano 2020, "Hash Functions for GPU Rendering").
#[inline]
pub fn pcg_hash(v: u32) -> u32 {
    let state = v.wrapping_mul(747_796_405).wrapping_add(2_891_336_453);
    let word = ((state >> ((state >> 28) + 4)) ^ state).wrapping_mul(277_803_737);
    (word >> 22) ^ word
}

/// A photon's random stream: a PCG-RXS-M-XS generator seeded by hashing.
#[derive(Debug, Clone)]
pub struct PhotonRng {
    state: u32,
}

impl PhotonRng {
    #[inline]
    pub fn new(seed: u32, iteration: u32, photon: u32) -> Self {
        PhotonRng {
            state: pcg_hash(seed ^ pcg_hash(iteration ^ pcg_hash(photon))),
        }
    }

    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        self.state = self
            .state
            .wrapping_mul(747_796_405)
            .wrapping_add(2_891_336_453);
        let s = self.state;
        let word = ((s >> ((s >> 28) + 4)) ^ s).wrapping_mul(277_803_737);
        (word >> 22) ^ word
    }

    /// Uniform in [0, 1) with 24 bits.
    #[inline]
    pub fn next_f32(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }
}
