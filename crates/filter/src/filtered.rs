//! What a filter pass returns: the filtered map and what the filter did.

use lucerna_photometry::AxialSymmetry;

use crate::cross_validation::AutomaticReport;
use crate::settings::FilterSettings;

/// The filtered map and what the filter did.
#[derive(Debug, Clone, PartialEq)]
pub struct Filtered {
    /// Photons per steradian for every level-0 texel (× flux per photon =
    /// candela).
    pub photons_per_sr: Vec<f64>,
    /// Texels whose value was replaced.
    pub replaced: Vec<bool>,
    /// The threshold used (photons; the Poisson rule's cap).
    pub threshold: f64,
    /// The settings applied, with a concrete rule (what `Automatic` chose).
    pub settings: FilterSettings,
    /// For the automatic mode, the cross-validated error estimates.
    pub automatic: Option<AutomaticReport>,
    /// Factor applied to the replaced texels to keep the traced flux.
    pub renormalisation: f64,
    /// The symmetry whose images were pooled (`None`: the counts alone).
    pub symmetry: AxialSymmetry,
}
