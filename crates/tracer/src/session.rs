//! The progressive session: one API for the editor and the CLI. Photons
//! accumulate iteration by iteration into an intensity map that can be
//! read at any time; any scene change restarts it.

use std::time::{Duration, Instant};

use lucerna_gpu::{GpuContext, GpuError};
use lucerna_photometry::cubemap::rectangle_solid_angle;
use lucerna_photometry::{AxialSymmetry, CubeFace, IntensityMap, TexelSymmetry};

use crate::cpu::{BatchTotals, CountBuffers, Tally, TraceSettings, trace_batch_into_unless};
use crate::gpu::GpuTracer;
use crate::prepared::PreparedScene;

/// Which tracer a session runs.
#[derive(Debug)]
pub enum Backend {
    /// The native CPU tracer (rayon).
    Cpu,
    /// The WGSL kernel on a GPU adapter (hardware or software).
    Gpu(Box<GpuTracer>),
}

impl Backend {
    pub fn describe(&self) -> String {
        match self {
            Backend::Cpu => format!("CPU tracer ({} threads)", rayon::current_num_threads()),
            Backend::Gpu(g) => format!("WGSL kernel on {}", g.context().describe()),
        }
    }

    /// Traces photons `first .. first + count` of random-number block
    /// `block`.
    pub fn trace(
        &self,
        scene: &PreparedScene,
        settings: &TraceSettings,
        block: u32,
        first: u32,
        count: u32,
    ) -> Result<Tally, GpuError> {
        match self {
            Backend::Cpu => Ok(crate::cpu::trace_batch(
                scene, settings, block, first, count,
            )),
            Backend::Gpu(g) => g.trace_batch(block, first, count),
        }
    }

    /// [`Backend::trace`], adding the counts to `counts` (one per texel);
    /// the CPU tracer reuses the count buffers in `buffers`, and gives up
    /// (`Ok(None)`, nothing added) when `stop` says so. A GPU dispatch is
    /// not stopped.
    pub fn trace_into(
        &self,
        scene: &PreparedScene,
        settings: &TraceSettings,
        block: u32,
        first: u32,
        count: u32,
        buffers: &CountBuffers,
        counts: &mut [u64],
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Result<Option<BatchTotals>, GpuError> {
        match self {
            Backend::Cpu => Ok(trace_batch_into_unless(
                scene, settings, block, first, count, buffers, counts, stop,
            )),
            Backend::Gpu(g) => {
                let tally = g.trace_batch(block, first, count)?;
                for (total, &c) in counts.iter_mut().zip(&tally.counts) {
                    *total += u64::from(c);
                }
                Ok(Some(BatchTotals {
                    emitted: tally.emitted,
                    absorbed: tally.absorbed,
                    cut_off: tally.cut_off,
                    bounces: tally.bounces,
                    rays: tally.rays,
                }))
            }
        }
    }
}

pub use lucerna_gpu::BackendRequest;

/// Photons/s of each candidate, and why the choice fell as it did.
#[derive(Debug, Clone)]
pub struct BackendChoice {
    pub reason: String,
}

/// Opens the backend a request names. `Auto` never fails for want of an
/// adapter: it falls back to the CPU tracer.
pub fn choose_backend(
    request: BackendRequest,
    scene: &PreparedScene,
    settings: &TraceSettings,
) -> Result<(Backend, BackendChoice), GpuError> {
    let gpu =
        |ctx: GpuContext| GpuTracer::new(ctx, scene, *settings).map(|g| Backend::Gpu(Box::new(g)));
    match request {
        BackendRequest::Cpu => Ok((
            Backend::Cpu,
            BackendChoice {
                reason: "requested".to_owned(),
            },
        )),
        BackendRequest::Gpu => {
            let backend = gpu(lucerna_gpu::open()?)?;
            Ok((
                backend,
                BackendChoice {
                    reason: "requested".to_owned(),
                },
            ))
        }
        BackendRequest::Auto => {
            let ctx = match lucerna_gpu::open() {
                Ok(ctx) => ctx,
                Err(e) => {
                    return Ok((
                        Backend::Cpu,
                        BackendChoice {
                            reason: format!("no usable GPU adapter ({e})"),
                        },
                    ));
                }
            };
            let name = ctx.describe();
            if ctx.is_software() {
                // A software adapter computes on the CPU's own cores, where
                // the native tracer does the same work about 5x more
                // efficiently (GPU-ON-CPU-MACHINES.md). A probe comparing
                // the two was biased by whatever else ran: an editor's
                // tracer threads run at a lower priority than the
                // adapter's, and under load it picked the kernel at a fifth
                // of the CPU's rate. `--backend gpu` still runs the kernel.
                return Ok((
                    Backend::Cpu,
                    BackendChoice {
                        reason: format!(
                            "only a software adapter ({name}), which runs on these same cores"
                        ),
                    },
                ));
            }
            // An adapter that cannot run the kernel is no adapter to Auto.
            match gpu(ctx) {
                Ok(backend) => Ok((
                    backend,
                    BackendChoice {
                        reason: format!("hardware adapter {name}"),
                    },
                )),
                Err(e) => Ok((
                    Backend::Cpu,
                    BackendChoice {
                        reason: format!("the adapter {name} cannot run the tracer ({e})"),
                    },
                )),
            }
        }
    }
}

/// Why a map cannot be continued by a session.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ContinueError {
    #[error("the session has already traced photons")]
    AlreadyTracing,
    #[error("the map has {map} texels per face edge, the run {run}")]
    Resolution { map: u32, run: u32 },
    #[error("the map is of {map} lm of emitters, the scene has {run} lm")]
    Flux { map: f64, run: f64 },
    #[error("the map's photons do not add up (emitted ≠ escaped + absorbed + cut off)")]
    Unbalanced,
}

/// Photons per random-number block (the tracers' `iteration` argument).
const PHOTONS_PER_BLOCK: u64 = 1 << 30;

/// What one iteration did, and where the bake stands.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IterationReport {
    pub iteration: u32,
    pub photons: u64,
    pub elapsed: Duration,
    pub photons_total: u64,
    pub photons_per_second: f64,
    pub rays_per_second: f64,
    /// Mean surface interactions per photon, over the whole bake.
    pub mean_bounces: f64,
    /// Relative standard error of the escaped flux.
    pub flux_relative_error: f64,
    /// Relative standard error of the brightest direction (counts of the
    /// brightest 1/64-face block).
    pub peak_relative_error: f64,
}

#[derive(Debug)]
pub struct Session {
    backend: Backend,
    scene: PreparedScene,
    settings: TraceSettings,
    map: IntensityMap,
    iteration: u32,
    photons_per_iteration: u32,
    /// Wall time an iteration should take, so an interactive caller stays
    /// responsive.
    pub target_iteration_time: Duration,
    bounces: u64,
    rays: u64,
    tracing_time: Duration,
    /// The symmetry the map's photons will be pooled over: the reported
    /// peak error is that of the pooled map.
    symmetry: TexelSymmetry,
    /// The CPU tracer's per-thread count buffers, kept between iterations.
    buffers: CountBuffers,
    /// The number of the map's first photon in the seed's stream: a part
    /// of a split bake traces a range that need not start at zero.
    first_photon: u64,
    /// Photons the map held before this session traced any (a resumed
    /// checkpoint's), left out of the rates.
    restored_photons: u64,
}

impl Session {
    /// A session on the CPU tracer.
    pub fn start(scene: PreparedScene, settings: TraceSettings) -> Session {
        Session::with_backend(scene, settings, Backend::Cpu)
    }

    /// A session on `backend`. Iterations aim at 40 ms on a hardware GPU
    /// (an editor stays responsive) and 100 ms elsewhere.
    pub fn with_backend(
        scene: PreparedScene,
        settings: TraceSettings,
        backend: Backend,
    ) -> Session {
        let map = IntensityMap::new(settings.layout, scene.total_flux_lm);
        let target_iteration_time = match &backend {
            Backend::Gpu(g) if !g.context().is_software() => Duration::from_millis(40),
            _ => Duration::from_millis(100),
        };
        Session {
            backend,
            scene,
            settings,
            map,
            iteration: 0,
            photons_per_iteration: 65_536,
            target_iteration_time,
            bounces: 0,
            rays: 0,
            tracing_time: Duration::ZERO,
            symmetry: TexelSymmetry::none(settings.layout),
            buffers: CountBuffers::default(),
            first_photon: 0,
            restored_photons: 0,
        }
    }

    /// Continues the stream at photon `first_photon + traced.photons_emitted`
    /// with `traced` as the map so far: a part of a split bake starts at
    /// its range's first photon with an empty map; a resumed checkpoint
    /// brings the photons it had traced. Before the first iteration only.
    pub fn continue_from(
        &mut self,
        first_photon: u64,
        traced: IntensityMap,
    ) -> Result<(), ContinueError> {
        if self.iteration != 0 || self.map.photons_emitted != 0 {
            return Err(ContinueError::AlreadyTracing);
        }
        if traced.layout != self.settings.layout {
            return Err(ContinueError::Resolution {
                map: traced.layout.resolution,
                run: self.settings.layout.resolution,
            });
        }
        if traced.emitter_flux_lm != self.scene.total_flux_lm {
            return Err(ContinueError::Flux {
                map: traced.emitter_flux_lm,
                run: self.scene.total_flux_lm,
            });
        }
        if !traced.is_balanced() {
            return Err(ContinueError::Unbalanced);
        }
        self.first_photon = first_photon;
        self.restored_photons = traced.photons_emitted;
        self.map = traced;
        Ok(())
    }

    /// The number, in the seed's stream, of the next photon to trace.
    pub fn next_photon(&self) -> u64 {
        self.first_photon + self.map.photons_emitted
    }

    /// Reports the peak error of the map pooled over the luminaire's
    /// `symmetry` (what an export with pooling holds). A restart forgets
    /// it: a changed scene may have another symmetry.
    pub fn pool_over(&mut self, symmetry: AxialSymmetry) {
        self.symmetry = TexelSymmetry::new(self.settings.layout, symmetry);
    }

    /// Drops everything traced and starts over on a changed scene (on the
    /// CPU tracer; a GPU backend must be re-created for the new buffers).
    pub fn restart(&mut self, scene: PreparedScene) {
        let target = self.target_iteration_time;
        *self = Session::start(scene, self.settings);
        self.target_iteration_time = target;
    }

    pub fn backend(&self) -> &Backend {
        &self.backend
    }

    /// Photons the next iteration traces (at least 1024); the ones after
    /// are sized to the time budget from its rate.
    pub fn set_next_iteration_photons(&mut self, photons: u32) {
        self.photons_per_iteration = photons.max(1024);
    }

    pub fn scene(&self) -> &PreparedScene {
        &self.scene
    }

    pub fn settings(&self) -> &TraceSettings {
        &self.settings
    }

    /// A copy of the map as it stands (tracing does not wait for readers).
    pub fn snapshot(&self) -> IntensityMap {
        self.map.clone()
    }

    pub fn map(&self) -> &IntensityMap {
        &self.map
    }

    /// Traces one iteration of at most `limit` photons, sized to the time
    /// budget.
    pub fn iterate_at_most(&mut self, limit: u64) -> Result<IterationReport, GpuError> {
        let report = self.iterate_at_most_unless(limit, &|| false)?;
        Ok(report.unwrap_or_else(|| self.report(0, Duration::ZERO)))
    }

    /// [`Session::iterate_at_most`], given up when `stop` says so (then
    /// `Ok(None)` and the map is as it was).
    pub fn iterate_at_most_unless(
        &mut self,
        limit: u64,
        stop: &(dyn Fn() -> bool + Sync),
    ) -> Result<Option<IterationReport>, GpuError> {
        // Photon k of the session is photon k mod 2³⁰ of random-number
        // block k / 2³⁰, however iterations split the photons: a seed and a
        // photon count give the same counts on one backend, whatever the
        // timing.
        let emitted = self.next_photon();
        let (block, first) = (emitted / PHOTONS_PER_BLOCK, emitted % PHOTONS_PER_BLOCK);
        let photons = u64::from(self.photons_per_iteration)
            .min(limit)
            .min(PHOTONS_PER_BLOCK - first)
            .max(1) as u32;
        let start = Instant::now();
        let tally = self.backend.trace_into(
            &self.scene,
            &self.settings,
            block as u32,
            first as u32,
            photons,
            &self.buffers,
            &mut self.map.counts,
            stop,
        )?;
        let Some(tally) = tally else {
            return Ok(None);
        };
        let elapsed = start.elapsed();
        self.tracing_time += elapsed;
        self.map.photons_emitted += tally.emitted;
        self.map.photons_absorbed += tally.absorbed;
        self.map.photons_cut_off += tally.cut_off;
        self.bounces += tally.bounces;
        self.rays += tally.rays;
        self.iteration += 1;
        self.photons_per_iteration =
            next_iteration_size(photons, elapsed, self.target_iteration_time);
        Ok(Some(self.report(photons.into(), elapsed)))
    }

    /// Traces one iteration sized to the time budget.
    pub fn iterate(&mut self) -> Result<IterationReport, GpuError> {
        self.iterate_at_most(u64::MAX)
    }

    fn report(&self, photons: u64, elapsed: Duration) -> IterationReport {
        let total = self.map.photons_emitted;
        let traced_here = total - self.restored_photons;
        let seconds = self.tracing_time.as_secs_f64().max(1e-9);
        IterationReport {
            iteration: self.iteration,
            photons,
            elapsed,
            photons_total: total,
            photons_per_second: traced_here as f64 / seconds,
            rays_per_second: self.rays as f64 / seconds,
            mean_bounces: self.bounces as f64 / traced_here.max(1) as f64,
            flux_relative_error: flux_relative_error(&self.map),
            peak_relative_error: peak_relative_error(&self.map, &self.symmetry),
        }
    }
}

/// Photons for the next iteration: aimed at the time budget from the last
/// one's rate, changing by at most 4× per step, within [1024, 2³⁰].
pub fn next_iteration_size(photons: u32, elapsed: Duration, target: Duration) -> u32 {
    let seconds = elapsed.as_secs_f64().max(1e-4);
    let scale = (target.as_secs_f64() / seconds).clamp(0.25, 4.0);
    (f64::from(photons) * scale).clamp(1024.0, f64::from(1u32 << 30)) as u32
}

/// Binomial standard error of the escaped fraction, relative.
pub fn flux_relative_error(map: &IntensityMap) -> f64 {
    let n = map.photons_emitted as f64;
    let k = map.photons_escaped() as f64;
    if k == 0.0 {
        return f64::INFINITY;
    }
    let p = k / n;
    ((1.0 - p) / (n * p)).sqrt()
}

/// Binomial standard errors of the flux escaping into each γ zone
/// (degrees, texels counted by their centres), relative; one pass over the
/// map comparing cos γ (γ = 0 at the nadir), no trigonometry per texel.
pub fn zone_flux_relative_errors(map: &IntensityMap, zones_deg: &[(f64, f64)]) -> Vec<f64> {
    let cos_bounds: Vec<(f64, f64)> = zones_deg
        .iter()
        .map(|&(g0, g1)| (g0.to_radians().cos(), g1.to_radians().cos()))
        .collect();
    let mut counts = vec![0u64; zones_deg.len()];
    for t in 0..map.layout.texel_count() {
        let c = map.counts[t];
        if c == 0 {
            continue;
        }
        let [x, y, z] = map.layout.texel_centre_direction(t);
        let cos_gamma = -z / (x * x + y * y + z * z).sqrt();
        for (k, &(cos0, cos1)) in cos_bounds.iter().enumerate() {
            if cos_gamma <= cos0 && cos_gamma > cos1 {
                counts[k] += c;
            }
        }
    }
    let n = map.photons_emitted as f64;
    counts
        .into_iter()
        .map(|k| {
            if k == 0 {
                return f64::INFINITY;
            }
            let p = k as f64 / n;
            ((1.0 - p) / (n * p)).sqrt()
        })
        .collect()
}

/// Poisson error 1/√n of the brightest block of texels (blocks of 1/8 of a
/// face edge, compared per steradian), relative. A block's solid angle is
/// the exact solid angle of its face rectangle, so this costs a few hundred
/// `atan2` per iteration rather than one per texel. With a symmetry, the
/// block's estimate pools the photons of all its images: n counts each
/// texel of their union once.
pub fn peak_relative_error(map: &IntensityMap, symmetry: &TexelSymmetry) -> f64 {
    let n = map.layout.resolution as usize;
    let layout = map.layout;
    let texel = move |face: usize, x: usize, y: usize| {
        layout.texel_index(CubeFace::from_index(face), x as u32, y as u32)
    };
    let b = (n / 8).max(1);
    let blocks = n.div_ceil(b);
    let step = 2.0 / n as f64;
    let mut best_intensity = 0.0;
    let mut best_count = 0u64;
    let mut best_block = (0, 0, 0);
    for face in 0..6 {
        for by in 0..blocks {
            for bx in 0..blocks {
                let (x1, y1) = (((bx + 1) * b).min(n), ((by + 1) * b).min(n));
                let mut count = 0u64;
                for y in by * b..y1 {
                    for x in bx * b..x1 {
                        count += map.counts[texel(face, x, y)];
                    }
                }
                let omega = rectangle_solid_angle(
                    -1.0 + (bx * b) as f64 * step,
                    -1.0 + (by * b) as f64 * step,
                    -1.0 + x1 as f64 * step,
                    -1.0 + y1 as f64 * step,
                );
                let intensity = count as f64 / omega;
                if intensity > best_intensity {
                    best_intensity = intensity;
                    best_count = count;
                    best_block = (face, bx, by);
                }
            }
        }
    }
    if symmetry.order() > 1 && best_count > 0 {
        let (face, bx, by) = best_block;
        let mut union: Vec<usize> = (by * b..((by + 1) * b).min(n))
            .flat_map(|y| (bx * b..((bx + 1) * b).min(n)).map(move |x| texel(face, x, y)))
            .flat_map(|t| (0..symmetry.order()).map(move |g| (g, t)))
            .map(|(g, t)| symmetry.image(g, t))
            .collect();
        union.sort_unstable();
        union.dedup();
        best_count = union.iter().map(|&t| map.counts[t]).sum();
    }
    if best_count == 0 {
        f64::INFINITY
    } else {
        1.0 / (best_count as f64).sqrt()
    }
}
