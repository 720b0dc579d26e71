//! Candidates traced by the photon tracer with common random numbers.

pub mod evaluate;
