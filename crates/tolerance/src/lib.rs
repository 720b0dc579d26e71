//! Tolerance analysis: will the luminaire that is built meet its spec?
//!
//! A tolerances file says what manufacturing does (placements, shape
//! parameters, flux with their distributions; a profile's form error as a
//! Gaussian process along its arc; a surface's slope error). Each built
//! luminaire is drawn from a Sobol sequence, traced with the nominal's
//! photons (common random numbers) and measured by the figures a
//! datasheet gives; the report is the yield against the spec with its
//! 95 % interval, each term's, each figure's spread beside its photon
//! noise, which tolerance drives which figure, and the worst sample.

pub mod analysis;
pub mod distribution;
pub mod error;
pub mod figures;
pub mod form_error;
mod numbers;
pub mod output;
pub mod picture;
pub mod report;
pub mod sampling;
pub mod statistics;
pub mod tolerances;

pub use analysis::{Budget, Progress, SampleRecord, Settings, Setup, Stopped, Streams};
pub use error::ToleranceError;
pub use report::Report;
pub use tolerances::Tolerances;
