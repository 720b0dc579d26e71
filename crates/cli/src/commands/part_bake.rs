//! `lucerna bake --part`, `--checkpoint` and `--resume`: a bake as a
//! well-behaved batch job. It traces a fixed range of the seed's photon
//! stream on the calling thread, writes its partial map atomically every
//! checkpoint interval and on SIGTERM or Ctrl+C, and goes on from the last
//! checkpoint when resumed, so that no photon is traced twice and a killed
//! job loses at most one interval.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use lucerna_simulation::part::{
    self, FindPartsError, PartManifest, SceneIdentity, TraceIdentity, manifest_file_name,
    new_manifest,
};
use lucerna_simulation::{BackendRequest, BakeJob, Luminaire, PartSpec, Run, RunState, StopReason};
use lucerna_tracer::Backend;

use super::bake_run::{self, BakeSummary};

/// A part stopped by a signal once its final checkpoint is written: the
/// process exits with [`Interrupted::EXIT_CODE`], which a scheduler's
/// retry rules can tell from a failure.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct Interrupted(String);

impl Interrupted {
    /// EX_TEMPFAIL of sysexits.h: try again later (from the checkpoint).
    pub const EXIT_CODE: u8 = 75;
}

/// The most photons a run can have: 2³² random-number blocks of 2³⁰.
const MAX_PHOTONS: u64 = 1 << 62;

/// How often a part's bake checkpoints unless told (`--checkpoint`).
pub const DEFAULT_CHECKPOINT_INTERVAL: Duration = Duration::from_secs(5 * 60);

/// Photons per iteration are sized to this: short enough that a
/// checkpoint comes on time, long enough to cost nothing.
const ITERATION_TIME: Duration = Duration::from_millis(500);

/// A fresh part (`--part`, `job`'s photons the whole run's) or a whole
/// bake with checkpoints (`whole`, `spec` 1/1), checkpointed every
/// `checkpoint`.
pub fn bake_part(
    job: &BakeJob,
    spec: PartSpec,
    whole: bool,
    checkpoint: Option<Duration>,
) -> Result<BakeSummary> {
    let total = job
        .settings
        .stop
        .photons
        .context("a part needs the run's photons")?;
    if total > MAX_PHOTONS {
        anyhow::bail!("--photons {total} is more than a run can trace (2^62)");
    }
    if total < u64::from(spec.count) {
        anyhow::bail!(
            "--photons {total} is fewer than the {} parts: each part traces at least one",
            spec.count
        );
    }
    let mut settings = job.settings;
    let range = spec.range(total);
    settings.stop.photons = Some(range.len());
    let out = &job.output.out_dir;
    let manifest_path = out.join(manifest_file_name(&job.output.stem, spec));
    let mut luminaire = Luminaire::load(&job.scene)?;
    luminaire.prepared.set_ray_reuse(job.ray_reuse());
    let scene = SceneIdentity::of(&job.scene, &luminaire.scene)?;
    bake_run::describe_symmetry(&luminaire, &settings);
    let trace = TraceIdentity {
        resolution: settings.resolution,
        seed: settings.seed,
        max_bounces: settings.max_bounces,
        photons_total: total,
        parts: spec.count,
        emitter_flux_lm: luminaire.prepared.total_flux_lm,
    };
    // A checkpoint is never overwritten by a fresh start, which would
    // lose its photons: the same bake goes on from it (a requeued or
    // resubmitted job), another is refused.
    if manifest_path.exists() {
        let existing = part::read_manifest(&manifest_path)?;
        let output = existing.job.output_differences(job);
        let differs = if existing.scene.sha256 != scene.sha256 {
            Some(format!(
                "the scene ({})",
                existing
                    .scene
                    .first_difference(&scene)
                    .unwrap_or_else(|| "its files differ".to_owned())
            ))
        } else if existing.trace != trace {
            Some("the photons asked for (--photons, --resolution, --seed or --max-bounces)".into())
        } else if !output.is_empty() {
            Some(format!(
                "the output settings ({})",
                output
                    .iter()
                    .map(|(what, then, now)| format!("{what} {then} then, {now} now"))
                    .collect::<Vec<_>>()
                    .join("; ")
            ))
        } else {
            None
        };
        if let Some(what) = differs {
            anyhow::bail!(
                "{} holds part {spec} of another bake: {what} differs. Remove its files to start \
                 over, or choose another --out",
                manifest_path.display()
            );
        }
        eprintln!(
            "{} holds this bake's part {spec}: going on from it",
            manifest_path.display()
        );
        return resume_checkpoint(manifest_path, existing, checkpoint);
    }
    let mut run = Run::new(Arc::new(luminaire), settings)?;
    let empty = run.session().map().clone();
    run.continue_from(range.first, empty)?;
    let manifest = new_manifest(
        scene,
        trace,
        job.clone(),
        spec,
        backend_kind(run.backend()),
        whole,
    );
    std::fs::create_dir_all(out)
        .with_context(|| format!("cannot create output directory {}", out.display()))?;
    let interval = checkpoint.unwrap_or(DEFAULT_CHECKPOINT_INTERVAL);
    drive(run, manifest, &manifest_path, interval)
}

/// `--resume DIR`: the checkpoint there (of `part`, if given) traced on
/// to its total.
pub fn resume(
    dir: &Path,
    part: Option<PartSpec>,
    checkpoint: Option<Duration>,
) -> Result<BakeSummary> {
    let (manifest_path, manifest) = part::find_checkpoint(dir, part)?;
    resume_checkpoint(manifest_path, manifest, checkpoint)
}

/// The checkpoint at `manifest_path` traced on to its total, with the
/// job it stored, after checking its scene is the same bytes.
fn resume_checkpoint(
    manifest_path: PathBuf,
    manifest: PartManifest,
    checkpoint: Option<Duration>,
) -> Result<BakeSummary> {
    let scene_path = manifest.scene.path.clone();
    let scene = lucerna_scene::load_scene(&scene_path)
        .with_context(|| format!("the scene of {} cannot be loaded", manifest_path.display()))?;
    manifest
        .scene
        .check_unchanged(&manifest_path, &scene_path, &scene)?;
    let mut settings = manifest.job.settings;
    settings.validate().with_context(|| {
        format!(
            "{}: its stored bake settings are not this Lucerna's",
            manifest_path.display()
        )
    })?;
    settings.backend = match manifest.backend_kind.as_str() {
        "gpu" => BackendRequest::Gpu,
        _ => BackendRequest::Cpu,
    };
    settings.stop.photons = Some(manifest.range.len());
    let mut luminaire = Luminaire::new(scene, scene_path.parent().unwrap_or(Path::new(".")))?;
    // The ray reuse the part began with: its photons go on alike.
    luminaire.prepared.set_ray_reuse(manifest.job.ray_reuse());
    if luminaire.prepared.total_flux_lm != manifest.trace.emitter_flux_lm {
        anyhow::bail!(
            "{}: the scene now emits {} lm, the checkpoint {} lm",
            manifest_path.display(),
            luminaire.prepared.total_flux_lm,
            manifest.trace.emitter_flux_lm
        );
    }
    let traced = part::read_part_counts(&manifest_path, &manifest)?;
    eprintln!(
        "resuming part {} of {}: {} of its {} photons traced ({}), on the {} backend",
        manifest.spec(),
        manifest_path.display(),
        manifest.photons_traced,
        manifest.range.len(),
        manifest.range,
        manifest.backend_kind
    );
    let mut run = Run::new(Arc::new(luminaire), settings).with_context(|| {
        format!(
            "{} was traced on the {} backend, which is needed to go on with it",
            manifest_path.display(),
            manifest.backend_kind
        )
    })?;
    run.continue_from(manifest.range.first, traced)?;
    let interval = checkpoint.unwrap_or(DEFAULT_CHECKPOINT_INTERVAL);
    drive(run, manifest, &manifest_path, interval)
}

fn backend_kind(backend: &Backend) -> &'static str {
    match backend {
        Backend::Cpu => "cpu",
        Backend::Gpu(_) => "gpu",
    }
}

/// Set by SIGTERM, SIGINT or SIGHUP: the bake writes a checkpoint and
/// stops.
fn stop_flag() -> Arc<AtomicBool> {
    static FLAG: std::sync::OnceLock<Arc<AtomicBool>> = std::sync::OnceLock::new();
    FLAG.get_or_init(|| {
        let flag = Arc::new(AtomicBool::new(false));
        let f = flag.clone();
        // Set once per process; if another handler came first, a signal
        // ends the process, and the last checkpoint stands.
        let _ = ctrlc::set_handler(move || f.store(true, Ordering::SeqCst));
        flag
    })
    .clone()
}

/// Traces until the part is complete, checkpointing; then, for a whole
/// bake, writes its files.
fn drive(
    mut run: Run,
    mut manifest: PartManifest,
    manifest_path: &Path,
    interval: Duration,
) -> Result<BakeSummary> {
    let stop = stop_flag();
    run.set_iteration_time(ITERATION_TIME);
    let started = Instant::now();
    let wall_before = manifest.wall_seconds;
    let traced_before = manifest.photons_traced;
    let range = manifest.range;
    eprintln!(
        "part {} of {} photons: {} on the {}, checkpoint every {}",
        manifest.spec(),
        manifest.trace.photons_total,
        range,
        run.backend().describe(),
        describe_interval(interval)
    );
    let bar = ProgressBar::new(range.len());
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {bar:30} {human_pos}/{human_len} photons ({per_sec}, ETA {eta})",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    bar.set_position(traced_before);
    bar.reset_eta();
    let checkpoint = |run: &Run, manifest: &mut PartManifest, bar: &ProgressBar| -> Result<()> {
        let t0 = Instant::now();
        let map = run.session().map();
        manifest.wall_seconds = wall_before + started.elapsed().as_secs_f64();
        let traced_here = map.photons_emitted - traced_before;
        manifest.photons_per_second = if manifest.wall_seconds > 0.0 {
            map.photons_emitted as f64 / manifest.wall_seconds
        } else {
            0.0
        };
        if manifest.backend.is_empty() || traced_here > 0 {
            manifest.backend = run.backend().describe();
        }
        part::write_part(manifest_path, manifest, map)?;
        bar.suspend(|| {
            eprintln!(
                "checkpoint: {} of {} photons of part {} in {} ({:.3} s)",
                map.photons_emitted,
                range.len(),
                manifest.spec(),
                manifest_path.display(),
                t0.elapsed().as_secs_f64()
            )
        });
        Ok(())
    };
    let mut last_checkpoint = Instant::now();
    // A signal lets the iteration in flight finish (at most
    // ITERATION_TIME; schedulers wait 30 s before SIGKILL), so its photons
    // are kept, then the loop ends with a checkpoint.
    while run.stop_reason().is_none() && !stop.load(Ordering::SeqCst) {
        let r = run.step()?;
        bar.set_position(r.photons_total);
        if last_checkpoint.elapsed() >= interval && run.stop_reason().is_none() {
            checkpoint(&run, &mut manifest, &bar)?;
            last_checkpoint = Instant::now();
        }
    }
    checkpoint(&run, &mut manifest, &bar)?;
    bar.finish_and_clear();
    if !manifest.complete {
        let part = if manifest.spec() == PartSpec::WHOLE {
            String::new()
        } else {
            format!(" --part {}", manifest.spec())
        };
        return Err(Interrupted(format!(
            "stopped by a signal: {} of {} photons are in {}; go on with `lucerna bake --resume \
             {}{part}`",
            manifest.photons_traced,
            range.len(),
            manifest_path.display(),
            manifest_path.parent().unwrap_or(Path::new(".")).display()
        ))
        .into());
    }
    let photons = manifest.photons_traced - traced_before;
    let seconds = started.elapsed().as_secs_f64();
    if !manifest.write_outputs {
        eprintln!(
            "part {} complete: {} photons; merge the parts with `lucerna merge`",
            manifest.spec(),
            manifest.photons_traced
        );
        let counts = manifest_path.with_file_name(&manifest.counts.file);
        return Ok(BakeSummary {
            files: vec![manifest_path.to_path_buf(), counts],
            photons,
            seconds,
            interrupted: false,
        });
    }
    // A whole bake: its files (where the checkpoint is: a resume may come
    // from another folder), then its checkpoint is spent.
    let snapshot = run.snapshot(0, RunState::Finished(StopReason::Photons), true);
    let mut job = manifest.job.clone();
    job.output.out_dir = manifest_path
        .parent()
        .unwrap_or(Path::new("."))
        .to_path_buf();
    let files = bake_run::export(&job, &snapshot)?;
    let counts = manifest_path.with_file_name(&manifest.counts.file);
    let _ = std::fs::remove_file(manifest_path);
    let _ = std::fs::remove_file(counts);
    Ok(BakeSummary {
        files,
        photons,
        seconds,
        interrupted: false,
    })
}

fn describe_interval(d: Duration) -> String {
    let s = d.as_secs_f64();
    if s >= 120.0 {
        format!("{:.0} min", s / 60.0)
    } else {
        format!("{s:.1} s")
    }
}

/// The manifests a merge is given: files as they are, folders for the
/// parts they hold.
pub fn expand_part_paths(paths: &[PathBuf]) -> Result<Vec<PathBuf>, FindPartsError> {
    let mut out = Vec::new();
    for p in paths {
        if p.is_dir() {
            let found = part::manifests_in(p)?;
            if found.is_empty() {
                return Err(FindPartsError::NoCheckpoint {
                    dir: p.clone(),
                    which: String::new(),
                });
            }
            out.extend(found);
        } else {
            out.push(p.clone());
        }
    }
    Ok(out)
}
