// Counter-based randomness, the WGSL twin of crates/tracer/src/rng.rs:
// PCG hash (Jarzynski & Olano 2020) seeds a PCG-RXS-M-XS stream per photon
// from (seed, iteration, photon index).

fn pcg_hash(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

var<private> rng_state: u32;

fn rng_init(seed: u32, iteration: u32, photon: u32) {
    rng_state = pcg_hash(seed ^ pcg_hash(iteration ^ pcg_hash(photon)));
}

fn rng_next_u32() -> u32 {
    rng_state = rng_state * 747796405u + 2891336453u;
    let s = rng_state;
    let word = ((s >> ((s >> 28u) + 4u)) ^ s) * 277803737u;
    return (word >> 22u) ^ word;
}

// Uniform in [0, 1) with 24 bits.
fn rng_next_f32() -> f32 {
    return f32(rng_next_u32() >> 8u) * (1.0 / 16777216.0);
}
