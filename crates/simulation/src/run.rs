//! One progressive run of one luminaire with one set of settings,
//! synchronous: the worker thread drives it, and so can a bench.

use std::sync::Arc;
use std::time::{Duration, Instant};

use lucerna_gpu::{BackendRequest, GpuContext};
use lucerna_photometry::fidelity::FidelityTargets;
use lucerna_photometry::figures::ZONES_DEG;
use lucerna_photometry::gamma_grid::PhotonNoise;
use lucerna_photometry::table::uniform_c_planes;
use lucerna_photometry::tabulate::{CPooling, GammaGrid, ResampledTable, TableResampler};
use lucerna_photometry::{AxialSymmetry, CubeMapLayout, IntensityMap, TexelSymmetry, figures};
use lucerna_tracer::gpu::GpuTracer;
use lucerna_tracer::session::{
    flux_relative_error, peak_relative_error, zone_flux_relative_errors,
};
use lucerna_tracer::{Backend, IterationReport, Session, TraceSettings, choose_backend};

use crate::snapshot::{
    FilterSummary, Noise, RunState, Snapshot, StopReason, spread_angle_noise_deg,
};
use crate::{FilterChoice, LiveFilter, Luminaire, SimulationError, SimulationSettings, TableGrid};

/// A progressive run: the tracing session and what turns its map into a
/// snapshot (the pooling symmetry, the cached table binning, the live
/// filter).
#[derive(Debug)]
pub struct Run {
    luminaire: Arc<Luminaire>,
    settings: SimulationSettings,
    session: Session,
    backend_reason: String,
    symmetry: TexelSymmetry,
    resampler: TableResampler,
    filter: LiveFilter,
    started: Instant,
    last: Option<IterationReport>,
}

impl Run {
    /// Opens the backend the settings ask for and starts at zero photons.
    pub fn new(
        luminaire: Arc<Luminaire>,
        settings: SimulationSettings,
    ) -> Result<Run, SimulationError> {
        settings.validate()?;
        let trace = trace_settings(&settings);
        let (backend, choice) = choose_backend(settings.backend, &luminaire.prepared, &trace)?;
        Ok(Run::with_backend(
            luminaire,
            settings,
            backend,
            choice.reason,
        ))
    }

    /// Starts on a GPU context already open (the worker keeps one across
    /// edits, since opening an adapter costs far more than new buffers).
    pub fn on_gpu(
        luminaire: Arc<Luminaire>,
        settings: SimulationSettings,
        context: GpuContext,
        reason: String,
    ) -> Result<Run, SimulationError> {
        settings.validate()?;
        let tracer = GpuTracer::new(context, &luminaire.prepared, trace_settings(&settings))?;
        Ok(Run::with_backend(
            luminaire,
            settings,
            Backend::Gpu(Box::new(tracer)),
            reason,
        ))
    }

    fn with_backend(
        luminaire: Arc<Luminaire>,
        settings: SimulationSettings,
        backend: Backend,
        backend_reason: String,
    ) -> Run {
        let trace = trace_settings(&settings);
        // Pooled over the symmetry once it is known (an edit's is found
        // while the run goes on: `set_symmetry`).
        let axial = match luminaire.symmetry() {
            Some(s) if settings.pool_symmetry => s.symmetry,
            _ => AxialSymmetry::None,
        };
        let symmetry = TexelSymmetry::new(trace.layout, axial);
        let mut session = Session::with_backend(luminaire.prepared.clone(), trace, backend);
        session.pool_over(axial);
        Run {
            luminaire,
            settings,
            session,
            backend_reason,
            symmetry,
            resampler: TableResampler::new(),
            filter: LiveFilter::new(),
            started: Instant::now(),
            last: None,
        }
    }

    pub fn settings(&self) -> &SimulationSettings {
        &self.settings
    }

    /// The symmetry the snapshots pool the photons over.
    pub fn pooled_symmetry(&self) -> AxialSymmetry {
        self.symmetry.symmetry
    }

    /// Photons in the next iteration (later ones are sized to the time
    /// budget from its rate).
    pub fn set_first_iteration_photons(&mut self, photons: u32) {
        self.session.set_next_iteration_photons(photons);
    }

    /// Pools the photons over the luminaire's symmetry from now on, if the
    /// settings ask for pooling (found after the run started; the counts
    /// are pooled when a snapshot is taken, so none is lost).
    pub fn set_symmetry(&mut self, symmetry: AxialSymmetry) {
        if !self.settings.pool_symmetry || symmetry == self.symmetry.symmetry {
            return;
        }
        self.symmetry = TexelSymmetry::new(self.session.settings().layout, symmetry);
        self.session.pool_over(symmetry);
        // The live filter's last choice was made for the other pooling.
        self.filter = LiveFilter::new();
    }

    pub(crate) fn set_backend_reason(&mut self, reason: String) {
        self.backend_reason = reason;
    }

    /// The ray files' distinct rays, where the light comes from one.
    fn distinct_rays(&self) -> Option<u64> {
        self.luminaire
            .prepared
            .ray_file_rays()
            .map(|(rays, _)| rays)
    }

    pub fn luminaire(&self) -> &Arc<Luminaire> {
        &self.luminaire
    }

    pub fn backend(&self) -> &Backend {
        self.session.backend()
    }

    pub fn session(&self) -> &Session {
        &self.session
    }

    /// Sets how long an iteration should take (an editor wants short ones).
    pub fn set_iteration_time(&mut self, target: Duration) {
        self.session.target_iteration_time = target;
    }

    /// Changes only when the run stops; the photons so far are kept.
    pub fn set_stopping_rule(&mut self, stop: crate::StoppingRule) {
        self.settings.stop = stop;
    }

    /// Continues the seed's photon stream at `first_photon +
    /// traced.photons_emitted`, with `traced` as the map so far: a part of
    /// a split bake starts at its range's first photon, a resumed
    /// checkpoint with the photons it held. The photon limit of the
    /// stopping rule counts `traced`'s photons. Before the first step only.
    pub fn continue_from(
        &mut self,
        first_photon: u64,
        traced: IntensityMap,
    ) -> Result<(), SimulationError> {
        self.session.continue_from(first_photon, traced)?;
        Ok(())
    }

    /// [`Run::step`], given up when `stop` says so (`Ok(None)`: nothing
    /// traced counts).
    pub fn step_unless(
        &mut self,
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Result<Option<IterationReport>, SimulationError> {
        let done = self.session.map().photons_emitted;
        let left = self
            .settings
            .stop
            .photons
            .map_or(u64::MAX, |p| p.saturating_sub(done));
        let report = self.session.iterate_at_most_unless(left.max(1), stop)?;
        if report.is_some() {
            self.last = report;
        }
        Ok(report)
    }

    /// Traces one iteration (never past the photon limit).
    pub fn step(&mut self) -> Result<IterationReport, SimulationError> {
        let done = self.session.map().photons_emitted;
        let left = self
            .settings
            .stop
            .photons
            .map_or(u64::MAX, |p| p.saturating_sub(done));
        let report = self.session.iterate_at_most(left.max(1))?;
        self.last = Some(report);
        Ok(report)
    }

    /// Why the run should stop now, if its rule says so.
    pub fn stop_reason(&self) -> Option<StopReason> {
        let stop = &self.settings.stop;
        if stop
            .photons
            .is_some_and(|p| self.session.map().photons_emitted >= p)
        {
            return Some(StopReason::Photons);
        }
        if stop.time.is_some_and(|t| self.started.elapsed() >= t) {
            return Some(StopReason::Time);
        }
        if let (Some(target), Some(last)) = (stop.peak_relative_error, self.last)
            && last.peak_relative_error <= target
        {
            return Some(StopReason::TargetError);
        }
        None
    }

    /// The map as it stands, pooled, filtered and tabulated. `final_export`
    /// chooses an automatic filter rule afresh (a live snapshot may reuse
    /// the last choice until the photons double).
    pub fn snapshot(&mut self, generation: u64, state: RunState, final_export: bool) -> Snapshot {
        let map = self.session.snapshot();
        let (candela, filter) = exported_candela(
            &mut self.filter,
            &map,
            self.settings.filter,
            &self.symmetry,
            !final_export,
        );
        let grid = self.settings.table;
        let pooling = self.luminaire.c_pooling(self.settings.pool_symmetry);
        let distinct_rays = self.distinct_rays();
        let ResampledTable {
            table,
            fidelity: table_fidelity,
        } = tabulate(
            &mut self.resampler,
            &map,
            &candela,
            self.symmetry.order(),
            grid,
            pooling,
            distinct_rays,
        );
        let table = Arc::new(table);
        // The unfiltered table beside the exported one, so views can show
        // both.
        let raw_table = if filter.is_some() {
            let raw = map.symmetrised(&self.symmetry).candela();
            Arc::new(
                tabulate(
                    &mut self.resampler,
                    &map,
                    &raw,
                    self.symmetry.order(),
                    grid,
                    pooling,
                    distinct_rays,
                )
                .table,
            )
        } else {
            table.clone()
        };
        let figures = figures(&table, Some(map.emitter_flux_lm));
        let mut warnings = crate::snapshot::degenerate_result_warnings(&map, &figures);
        // A grid the user fixed is warned about; the automatic one says
        // how close it came in its summary.
        if map.photons_escaped() > 0 && !table_fidelity.automatic {
            warnings.extend(table_fidelity.shortfalls());
        }
        let report = self.last;
        // A ray file's photons are no more certain than its distinct
        // rays: each relative error grows by √(photons / effective).
        let distinct =
            lucerna_tracer::ray_kernel::noise_inflation(map.photons_emitted as f64, distinct_rays);
        let peak_relative = distinct
            * report.map_or_else(
                || peak_relative_error(&map, &self.symmetry),
                |r| r.peak_relative_error,
            );
        let zonal: Vec<f64> = zone_flux_relative_errors(&map, &ZONES_DEG)
            .into_iter()
            .map(|z| distinct * z)
            .collect();
        let angle_noise = |angles: [Option<f64>; 2], fraction: f64| {
            [0.0, 90.0].map(|c| {
                let angle = angles[if c == 0.0 { 0 } else { 1 }];
                spread_angle_noise_deg(
                    &table,
                    &map,
                    &self.symmetry,
                    c,
                    fraction,
                    angle,
                    peak_relative,
                )
            })
        };
        let noise = Noise {
            peak_relative,
            flux_relative: distinct * flux_relative_error(&map),
            zonal_relative: std::array::from_fn(|k| zonal.get(k).copied().unwrap_or(f64::INFINITY)),
            beam_angle_deg: angle_noise(figures.beam_angle_deg, 0.5),
            field_angle_deg: angle_noise(figures.field_angle_deg, 0.1),
        };
        Snapshot {
            generation,
            state,
            luminaire: self.luminaire.clone(),
            iteration: report.map_or(0, |r| r.iteration),
            photons: map.photons_emitted,
            elapsed: self.started.elapsed(),
            photons_per_second: report.map_or(0.0, |r| r.photons_per_second),
            rays_per_second: report.map_or(0.0, |r| r.rays_per_second),
            mean_bounces: report.map_or(0.0, |r| r.mean_bounces),
            backend: self.session.backend().describe(),
            backend_reason: self.backend_reason.clone(),
            map: Arc::new(map),
            symmetry: self.symmetry.symmetry,
            candela: Arc::new(candela),
            filter,
            table,
            raw_table,
            figures,
            table_fidelity,
            noise,
            warnings,
            settings: self.settings,
        }
    }
}

/// Candela per texel of `map` as exported with `filter`: pooled over
/// `symmetry`, and filtered if asked (with `live`, an automatic rule may
/// be the last one chosen; without, it is chosen now, as a final export
/// does), and what the filter did.
pub(crate) fn exported_candela(
    live_filter: &mut LiveFilter,
    map: &IntensityMap,
    filter: FilterChoice,
    symmetry: &TexelSymmetry,
    live: bool,
) -> (Vec<f64>, Option<FilterSummary>) {
    match filter.threshold() {
        Some(threshold) => {
            let (candela, report) = live_filter.filter(map, threshold, symmetry, live);
            let summary = FilterSummary {
                rule: report.settings.to_string(),
                automatic: report.automatic.is_some(),
                replaced_texels: report.replaced.iter().filter(|&&r| r).count(),
                renormalisation: report.renormalisation,
                estimated_rmse: report
                    .automatic
                    .map(|a| (a.estimated_rmse, a.raw_estimated_rmse)),
            };
            (candela, Some(summary))
        }
        None => (map.symmetrised(symmetry).candela(), None),
    }
}

/// The candela table of `candela` (per texel of `map`) on `grid`, its
/// C-planes pooled as `pooling` says, and
/// how faithfully it carries the map: the automatic γ grid is the coarsest
/// that holds the map's flux, cone fluxes, beam and field angles and peak
/// within [`FidelityTargets`]. A run's snapshots and an export on another
/// grid both tabulate here, so they agree to the bit.
pub(crate) fn tabulate(
    resampler: &mut TableResampler,
    map: &IntensityMap,
    candela: &[f64],
    pooled_images: usize,
    grid: TableGrid,
    pooling: CPooling,
    distinct_rays: Option<u64>,
) -> ResampledTable {
    let targets = FidelityTargets::default();
    let gammas = match grid.gamma_step_deg {
        Some(step) => GammaGrid::Step(step, targets),
        None => GammaGrid::Automatic(targets),
    };
    // The photons behind the map, so the automatic grid tells the
    // distribution's shape from their noise; a ray file's photons count
    // as many as the distinct rays allow (its rays are themselves a
    // sample, looped or interpolated).
    let noise = (map.photons_emitted > 0).then(|| {
        let photons = map.photons_emitted as f64;
        let inflation = lucerna_tracer::ray_kernel::noise_inflation(photons, distinct_rays);
        PhotonNoise {
            lm_per_photon: map.emitter_flux_lm / photons * inflation * inflation,
            pooled_images: pooled_images as f64,
        }
    });
    resampler.table(
        map.layout,
        candela,
        &uniform_c_planes(grid.c_step_deg),
        gammas,
        noise,
        pooling,
    )
}

/// Builds what the first snapshot at `settings`' resolution and grid
/// builds once per process (texel solid angles, the table's binning:
/// 60–250 ms), so that a switch to it — an editor's coarse preview when a
/// drag starts — does not wait for them.
pub fn prepare_snapshots(settings: &SimulationSettings) {
    let layout = CubeMapLayout::new(settings.resolution);
    let mut map = IntensityMap::new(layout, 1.0);
    map.counts.fill(1);
    map.photons_emitted = layout.texel_count() as u64;
    let candela = map.candela();
    let _ = tabulate(
        &mut TableResampler::new(),
        &map,
        &candela,
        1,
        settings.table,
        CPooling::Separate,
        None,
    );
}

fn trace_settings(settings: &SimulationSettings) -> TraceSettings {
    TraceSettings {
        seed: settings.seed,
        max_bounces: settings.max_bounces,
        layout: CubeMapLayout::new(settings.resolution),
    }
}

/// Opens the backend a request names once, for a worker that re-creates
/// runs on every edit: `Auto` is resolved by measuring on the first scene
/// and then kept.
pub(crate) fn resolve_backend(
    request: BackendRequest,
    luminaire: &Luminaire,
    settings: &SimulationSettings,
) -> Result<(Option<GpuContext>, String), SimulationError> {
    let trace = trace_settings(settings);
    let (backend, choice) = choose_backend(request, &luminaire.prepared, &trace)?;
    Ok(match backend {
        Backend::Gpu(g) => (Some(g.context().clone()), choice.reason),
        Backend::Cpu => (None, choice.reason),
    })
}

/// The final snapshot of a map traced elsewhere (the merged parts of a
/// split bake): pooled, filtered and tabulated exactly as [`bake`]'s own
/// final snapshot of the same counts, so its files are the same bytes.
pub fn snapshot_of_map(
    luminaire: Arc<Luminaire>,
    settings: SimulationSettings,
    map: IntensityMap,
) -> Result<Snapshot, SimulationError> {
    // Nothing is traced: the CPU backend costs nothing to open.
    let settings = SimulationSettings {
        backend: BackendRequest::Cpu,
        ..settings
    };
    let mut run = Run::new(luminaire, settings)?;
    run.continue_from(0, map)?;
    Ok(run.snapshot(0, RunState::Finished(StopReason::Photons), true))
}

/// Traces `luminaire` on the calling thread until the settings' stopping
/// rule is met (a photon limit, say) and returns the final snapshot.
pub fn bake(
    luminaire: Arc<Luminaire>,
    settings: SimulationSettings,
) -> Result<Snapshot, SimulationError> {
    if settings.stop == crate::StoppingRule::default() {
        return Err(crate::SettingsError::Photons.into());
    }
    let mut run = Run::new(luminaire, settings)?;
    loop {
        run.step()?;
        if let Some(reason) = run.stop_reason() {
            return Ok(run.snapshot(0, RunState::Finished(reason), true));
        }
    }
}
