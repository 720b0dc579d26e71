//! What a run has found so far, immutable and shared.

use std::sync::Arc;
use std::time::Duration;

use lucerna_photometry::{AxialSymmetry, CandelaTable, Figures, IntensityMap};

use crate::Luminaire;

/// Where the run stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RunState {
    Tracing,
    Paused,
    /// Stopped by its rule or by the caller; the snapshot is final.
    Finished(StopReason),
}

/// Why tracing stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StopReason {
    Photons,
    Time,
    TargetError,
    /// The caller asked (e.g. Ctrl+C, a "stop" button); the snapshot is
    /// the final export.
    Requested,
    /// The caller cancelled: tracing stopped, no final export was made.
    Cancelled,
}

/// Relative standard errors (1σ) of what the snapshot shows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Noise {
    /// Of the brightest direction (the brightest 1/64-face block, pooled
    /// over the symmetry when the photons are).
    pub peak_relative: f64,
    /// Of the escaped flux (binomial).
    pub flux_relative: f64,
}

/// What the filter did to the exported map.
#[derive(Debug, Clone, PartialEq)]
pub struct FilterSummary {
    /// The rule applied, e.g. "Poisson test (cap 1024, z 4), σ 0.75".
    pub rule: String,
    /// Whether the rule was chosen by cross-validation.
    pub automatic: bool,
    pub replaced_texels: usize,
    pub renormalisation: f64,
    /// Cross-validated RMSE per texel / mean of the exported and of the
    /// raw map, when the rule was chosen automatically.
    pub estimated_rmse: Option<(f64, f64)>,
}

/// One moment of a run. Built on the worker thread; readers share it
/// through an `Arc` and never copy the map.
#[derive(Debug, Clone)]
pub struct Snapshot {
    /// Edits of the scene (or settings) since the simulation started: a
    /// snapshot of an older generation shows a scene no longer edited.
    pub generation: u64,
    pub state: RunState,
    pub luminaire: Arc<Luminaire>,
    /// Iterations traced.
    pub iteration: u32,
    /// Photons traced (as traced, before pooling).
    pub photons: u64,
    /// Wall time of this run so far.
    pub elapsed: Duration,
    pub photons_per_second: f64,
    pub rays_per_second: f64,
    /// Surface interactions per photon.
    pub mean_bounces: f64,
    /// The backend tracing, in words, and why it was chosen.
    pub backend: String,
    pub backend_reason: String,
    /// The photon counts as traced.
    pub map: Arc<IntensityMap>,
    /// The symmetry the exported map and table are pooled over.
    pub symmetry: AxialSymmetry,
    /// Candela per texel as exported: pooled, and filtered if asked.
    pub candela: Arc<Vec<f64>>,
    pub filter: Option<FilterSummary>,
    /// The exported candela table (on the settings' grid).
    pub table: Arc<CandelaTable>,
    /// Flux, LOR, peak, beam and field angles of that table.
    pub figures: Figures,
    pub noise: Noise,
    /// What looks degenerate about the result (nothing escaped, almost
    /// nothing escaped, photons cut off by the bounce limit), in words.
    pub warnings: Vec<String>,
}

/// The warnings a map deserves once it holds photons.
pub(crate) fn degenerate_result_warnings(map: &IntensityMap, figures: &Figures) -> Vec<String> {
    let mut warnings = Vec::new();
    let emitted = map.photons_emitted;
    if emitted == 0 {
        return warnings;
    }
    let escaped = map.photons_escaped();
    if escaped == 0 {
        warnings.push(format!(
            "no photon left the luminaire: all {emitted} were absorbed or cut off (is an emitter enclosed by its parts?)"
        ));
    } else if map.light_output_ratio() < 0.01 {
        warnings.push(format!(
            "only {:.3} % of the emitted flux leaves the luminaire",
            100.0 * map.light_output_ratio()
        ));
    }
    let cut_off = map.photons_cut_off as f64 / emitted as f64;
    if cut_off > 0.001 {
        warnings.push(format!(
            "{:.2} % of the photons were still bouncing at the bounce limit and were cut off (a light trap, or raise the limit)",
            100.0 * cut_off
        ));
    }
    if !(figures.flux_lm.is_finite() && figures.peak_cd.is_finite()) {
        warnings.push("the table's flux or peak is not a finite number".to_owned());
    }
    warnings
}
