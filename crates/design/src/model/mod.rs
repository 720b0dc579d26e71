//! Models of a luminaire's light that are not the photon tracer: the
//! point-source direct design and the meridian model of a revolved
//! mirror. Milliseconds where the tracer takes seconds.

pub mod direct;
pub mod mapping;
pub mod meridian;
pub mod reach;
