//! What a design ends with, besides its files: the remaining difference
//! or the spec's terms, and the tables its picture draws.

use lucerna_photometry::CandelaTable;
use serde::Serialize;

use crate::merit::TermStatus;

/// What a design ends with, besides its files.
#[derive(Debug, Clone, Serialize)]
pub struct Outcome {
    /// The relative L2 difference on the sphere between the bake's table
    /// and the target distribution (distribution targets).
    pub remaining_difference: Option<f64>,
    /// The same, of the start scene baked alike.
    pub start_difference: Option<f64>,
    /// Each spec term, met or missed by how much (spec targets).
    pub terms: Vec<TermStatus>,
    /// Photons of the final bake.
    pub photons: u64,
    #[serde(skip)]
    pub table: CandelaTable,
    #[serde(skip)]
    pub start_table: CandelaTable,
}
