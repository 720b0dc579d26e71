//! The progressive session: one API for the editor and the CLI. Photons
//! accumulate iteration by iteration into an intensity map that can be
//! read at any time; any scene change restarts it.

use std::time::{Duration, Instant};

use lucerna_photometry::IntensityMap;

use crate::cpu::{TraceSettings, trace_batch};
use crate::prepared::PreparedScene;

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
}

impl Session {
    pub fn start(scene: PreparedScene, settings: TraceSettings) -> Session {
        let map = IntensityMap::new(settings.layout, scene.total_flux_lm);
        Session {
            scene,
            settings,
            map,
            iteration: 0,
            photons_per_iteration: 65_536,
            target_iteration_time: Duration::from_millis(200),
            bounces: 0,
            rays: 0,
            tracing_time: Duration::ZERO,
        }
    }

    /// Drops everything traced and starts over on a changed scene.
    pub fn restart(&mut self, scene: PreparedScene) {
        let target = self.target_iteration_time;
        *self = Session::start(scene, self.settings);
        self.target_iteration_time = target;
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
    pub fn iterate_at_most(&mut self, limit: u64) -> IterationReport {
        let photons = u64::from(self.photons_per_iteration).min(limit).max(1) as u32;
        let start = Instant::now();
        let tally = trace_batch(&self.scene, &self.settings, self.iteration, 0, photons);
        let elapsed = start.elapsed();
        self.tracing_time += elapsed;
        for (a, &b) in self.map.counts.iter_mut().zip(&tally.counts) {
            *a += u64::from(b);
        }
        self.map.photons_emitted += tally.emitted;
        self.map.photons_absorbed += tally.absorbed;
        self.map.photons_cut_off += tally.cut_off;
        self.bounces += tally.bounces;
        self.rays += tally.rays;
        self.iteration += 1;
        // Aim the next iteration at the time budget, changing by at most 4×.
        let seconds = elapsed.as_secs_f64().max(1e-4);
        let scale = (self.target_iteration_time.as_secs_f64() / seconds).clamp(0.25, 4.0);
        self.photons_per_iteration =
            (f64::from(photons) * scale).clamp(1024.0, f64::from(1u32 << 30)) as u32;
        self.report(photons.into(), elapsed)
    }

    /// Traces one iteration sized to the time budget.
    pub fn iterate(&mut self) -> IterationReport {
        self.iterate_at_most(u64::MAX)
    }

    fn report(&self, photons: u64, elapsed: Duration) -> IterationReport {
        let total = self.map.photons_emitted;
        let seconds = self.tracing_time.as_secs_f64().max(1e-9);
        IterationReport {
            iteration: self.iteration,
            photons,
            elapsed,
            photons_total: total,
            photons_per_second: total as f64 / seconds,
            rays_per_second: self.rays as f64 / seconds,
            mean_bounces: self.bounces as f64 / total.max(1) as f64,
            flux_relative_error: flux_relative_error(&self.map),
            peak_relative_error: peak_relative_error(&self.map),
        }
    }
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

/// Poisson error 1/√n of the brightest block of texels (blocks of 1/8 of a
/// face edge, solid-angle weighted), relative.
pub fn peak_relative_error(map: &IntensityMap) -> f64 {
    let n = map.layout.resolution as usize;
    let b = (n / 8).max(1);
    let blocks = n.div_ceil(b);
    let mut best_intensity = 0.0;
    let mut best_count = 0u64;
    for face in 0..6 {
        for by in 0..blocks {
            for bx in 0..blocks {
                let (mut count, mut omega) = (0u64, 0.0);
                for y in by * b..((by + 1) * b).min(n) {
                    for x in bx * b..((bx + 1) * b).min(n) {
                        let t = face * n * n + y * n + x;
                        count += map.counts[t];
                        omega += map.layout.texel_solid_angle(t);
                    }
                }
                let intensity = count as f64 / omega;
                if intensity > best_intensity {
                    best_intensity = intensity;
                    best_count = count;
                }
            }
        }
    }
    if best_count == 0 {
        f64::INFINITY
    } else {
        1.0 / (best_count as f64).sqrt()
    }
}
