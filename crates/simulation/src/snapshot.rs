//! What a run has found so far, immutable and shared.

use std::sync::Arc;
use std::time::Duration;

use lucerna_photometry::tabulate::CPooling;
use lucerna_photometry::{
    AxialSymmetry, CPlaneSymmetry, CandelaTable, Figures, IntensityMap, TexelSymmetry,
};

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
    /// Of the flux in each zone of `lucerna_photometry::figures::ZONES_DEG`
    /// (binomial).
    pub zonal_relative: [f64; 5],
    /// Of the beam and field angles in the C0-C180 and C90-C270 planes
    /// (degrees, absolute): the crossings' intensity noise over the
    /// distribution's slope there.
    pub beam_angle_deg: [Option<f64>; 2],
    pub field_angle_deg: [Option<f64>; 2],
}

/// 1σ of a full spread angle `angle_deg` at `fraction` of the plane's
/// maximum in plane `c_deg`: at each crossing (γ = angle/2 in planes C and
/// C + 180°, the symmetric reading) the Poisson noise of the photons the
/// table's cell there averages, over the table's slope there; plus the
/// threshold's share of the peak's noise, which moves both crossings
/// together (so it adds through both slopes at once). With the photons
/// pooled over `symmetry` a cell's photons are those of the union of its
/// images, each once, and two crossings made of the same photons (images
/// of each other) move together too. With a filter on, this is the raw
/// photons' bound.
pub(crate) fn spread_angle_noise_deg(
    table: &CandelaTable,
    map: &IntensityMap,
    symmetry: &TexelSymmetry,
    c_deg: f64,
    fraction: f64,
    angle_deg: Option<f64>,
    peak_relative: f64,
) -> Option<f64> {
    let half = 0.5 * angle_deg?;
    // The level is a fraction of the plane's own maximum, as
    // `figures::spread_angle` measures it.
    let plane_max = (0..=360)
        .map(|k| {
            let g = f64::from(k) * 0.5;
            table
                .intensity(c_deg, g)
                .max(table.intensity(c_deg + 180.0, g))
        })
        .fold(0.0, f64::max);
    let gamma_step = local_step(&table.gammas_deg, half);
    let c_step = local_step(&table.c_planes_deg, c_deg.rem_euclid(360.0));
    let mut crossings = Vec::with_capacity(2);
    for c in [c_deg, c_deg + 180.0] {
        let (g0, g1) = ((half - 0.25).max(0.0), half + 0.25);
        let slope_per_deg = (table.intensity(c, g1) - table.intensity(c, g0)) / (g1 - g0);
        if !(slope_per_deg.abs() > 0.0) {
            return None;
        }
        let photons = cell_photons(map, symmetry, c, half, c_step, gamma_step);
        let count: u64 = photons.iter().map(|&t| map.counts[t]).sum();
        if count == 0 {
            return None;
        }
        let angle_sigma = table.intensity(c, half) / (count as f64).sqrt() / slope_per_deg.abs();
        crossings.push((angle_sigma, 1.0 / slope_per_deg.abs(), photons));
    }
    let shared = crossings[0]
        .2
        .iter()
        .any(|t| crossings[1].2.binary_search(t).is_ok());
    let intensity_part = if shared {
        crossings[0].0 + crossings[1].0
    } else {
        crossings[0].0.hypot(crossings[1].0)
    };
    let threshold_part = fraction * plane_max * peak_relative * (crossings[0].1 + crossings[1].1);
    Some(intensity_part.hypot(threshold_part))
}

/// The grid step of ascending `values` around `at` (degrees).
fn local_step(values: &[f64], at: f64) -> f64 {
    let k = values
        .partition_point(|&v| v < at)
        .clamp(1, values.len().max(2) - 1);
    match (values.get(k - 1), values.get(k)) {
        (Some(a), Some(b)) if b > a => b - a,
        _ => 5.0,
    }
}

/// The raw texels whose photons make the table cell about (C, γ): the
/// cell's texels (found by sampling directions across it, so only those
/// are visited) and their images under `symmetry`, each once, sorted.
fn cell_photons(
    map: &IntensityMap,
    symmetry: &TexelSymmetry,
    c_deg: f64,
    gamma_deg: f64,
    c_step: f64,
    gamma_step: f64,
) -> Vec<usize> {
    const SAMPLES: usize = 12;
    let mut texels = Vec::with_capacity(SAMPLES * SAMPLES * symmetry.order());
    for i in 0..SAMPLES {
        for j in 0..SAMPLES {
            let c = c_deg + c_step * ((i as f64 + 0.5) / SAMPLES as f64 - 0.5);
            let g = (gamma_deg + gamma_step * ((j as f64 + 0.5) / SAMPLES as f64 - 0.5))
                .clamp(0.0, 180.0);
            let d = lucerna_photometry::table::direction(c.to_radians(), g.to_radians());
            let t = map.layout.texel_of_direction(d);
            texels.extend((0..symmetry.order()).map(|k| symmetry.image(k, t)));
        }
    }
    texels.sort_unstable();
    texels.dedup();
    texels
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
    /// The table of the pooled but unfiltered map (the same `Arc` as
    /// `table` when no filter is asked for).
    pub raw_table: Arc<CandelaTable>,
    /// Flux, LOR, peak, beam and field angles of that table.
    pub figures: Figures,
    /// The table's γ grid and how faithfully it carries the map (its
    /// shortfalls are among `warnings`).
    pub table_fidelity: lucerna_photometry::fidelity::TableFidelity,
    pub noise: Noise,
    /// What looks degenerate about the result (nothing escaped, almost
    /// nothing escaped, photons cut off by the bounce limit), in words.
    pub warnings: Vec<String>,
    /// The settings of the run (its filter and table grid decide whether
    /// an export can reuse `table`).
    pub settings: crate::SimulationSettings,
}

impl Snapshot {
    /// The C-plane symmetry its photons were pooled over, as files
    /// declare it: rotational for a round luminaire (its table pooled over
    /// C), else the axial symmetry found in its geometry.
    pub fn pooled_file_symmetry(&self) -> CPlaneSymmetry {
        match self.luminaire.c_pooling(self.settings.pool_symmetry) {
            CPooling::Rotational => CPlaneSymmetry::Rotational,
            CPooling::Separate => self.symmetry.file_symmetry(),
        }
    }
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
