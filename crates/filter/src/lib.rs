//! Pull-push bilateral upsampling filter for cube-map intensity maps
//! (Litemaker 2017, section 5), CPU reference.
//!
//! Pull: a pyramid of photon counts, each coarse texel the sum of its 2×2
//! children, with the exact solid angle of its region. Push: from the
//! coarsest level down, a texel with fewer photons than the threshold
//! (unstable) is replaced by a bilateral interpolation (eq. in 5.5:
//! Gaussian closeness × Gaussian similarity to the bilinear estimate) of
//! the four nearest texels of the already filtered coarser level; on levels
//! ≥ 2 the shadow-border test of Algorithm 2 keeps unstable texels next to
//! stable ones as they are.
//!
//! Where this differs from the paper, and why:
//! - neighbourhoods cross cube faces (a neighbour beyond an edge is found
//!   through its direction), so there are no seams;
//! - stability is judged on photon counts, but interpolation works on
//!   intensity per steradian, since cube-map texels differ ~5× in solid
//!   angle: an isotropic source stays flat (the paper's factor 4 is this
//!   normalisation for equal texels);
//! - a Poisson rule ([`Threshold::Poisson`]) replaces a texel only when
//!   its count is consistent with noise around the upsampled estimate, so
//!   caustics and cut-offs survive a high cap;
//! - no user threshold: [`Threshold::Automatic`] chooses the rule and the
//!   closeness σ per map by K-fold cross-validation on Poisson-thinned
//!   parts of the photons ([`choose_automatic`]); a manual threshold stays
//!   available;
//! - replaced texels are renormalised together so the filtered map keeps
//!   the traced flux; stable texels are never changed;
//! - a luminaire's symmetry about its axis
//!   ([`TexelSymmetry`](lucerna_photometry::TexelSymmetry)) pools the
//!   photons of every image of a texel before filtering
//!   ([`filter_symmetric`]): each texel is judged and interpolated on
//!   |group| times the photons, with no bias for a symmetric luminaire.
//!
//! Modules, one job each: `settings` (the rules and σ), `thinning` (the
//! photons split into independent parts), `cross_validation` (the
//! automatic mode), `pyramid` (one pull-push pass), `driver` (pooling,
//! the choice and the final pass, shared by CPU and GPU), [`evaluation`]
//! (the error measures of `lucerna filter-bench`), [`gpu`] (the WGSL
//! driver).

mod cross_validation;
mod driver;
pub mod evaluation;
mod filtered;
pub mod gpu;
mod intensity;
mod pyramid;
mod settings;
mod thinning;

pub use cross_validation::{
    AutomaticReport, CV_FOLDS, CandidateScore, automatic_candidates, choose_automatic,
};
pub use driver::{filter, filter_map, filter_symmetric};
pub use filtered::Filtered;
pub use settings::{
    AUTOMATIC_FALLBACK, FilterSettings, POISSON_BORDER_THRESHOLD_PHOTONS,
    POISSON_FALLBACK_CAP_PHOTONS, POISSON_MIN_KEEP_PHOTONS, POISSON_Z, Threshold, UNCAPPED,
};
pub use thinning::thinned_folds;
