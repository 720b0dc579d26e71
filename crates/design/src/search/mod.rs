//! Searches over the design's variables: the tracer's loop (Nelder–Mead
//! or damped least squares), and the meridian model's global search with
//! its correction by the tracer.

pub mod global;
pub mod least_squares;
pub mod optimise;
pub mod polish;
pub mod refine;
