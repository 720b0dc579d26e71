//! A bake's tracing and files: a whole bake on the simulation's worker,
//! and the files of any finished bake (whole, checkpointed or merged),
//! all from a [`BakeJob`].

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use lucerna_photometry::tabulate::CPooling;
use lucerna_simulation::{
    BakeJob, Luminaire, Pace, RunState, Simulation, SimulationSettings, Snapshot, StopReason,
};

/// What the bake wrote.
#[derive(Debug)]
pub struct BakeSummary {
    pub files: Vec<PathBuf>,
    pub photons: u64,
    pub seconds: f64,
    pub interrupted: bool,
}

/// Describes what the filter did to the exported map.
pub fn describe_filter(snapshot: &Snapshot) {
    let Some(f) = &snapshot.filter else { return };
    eprintln!(
        "filtered: {}{}, {} of {} texels replaced, renormalised by {:.4}",
        f.rule,
        if f.automatic {
            " (chosen by cross-validation)"
        } else {
            ""
        },
        f.replaced_texels,
        snapshot.map.layout.texel_count(),
        f.renormalisation
    );
    if let Some((filtered, raw)) = f.estimated_rmse {
        eprintln!(
            "estimated error of the exported map (RMSE per texel / mean, cross-validated): {:.1} % filtered, {:.1} % raw",
            100.0 * filtered,
            100.0 * raw
        );
    }
}

/// Writes the files `job` asks for from a final snapshot of it (all or
/// none), after saying how the table and filter came out.
pub fn export(job: &BakeJob, snapshot: &Snapshot) -> Result<Vec<PathBuf>> {
    eprintln!("table: {}", snapshot.table_fidelity.summary());
    for warning in &snapshot.warnings {
        eprintln!("warning: {warning}");
    }
    describe_filter(snapshot);
    let out = &job.output.out_dir;
    std::fs::create_dir_all(out)
        .with_context(|| format!("cannot create output directory {}", out.display()))?;
    let today = chrono::Local::now().format("%Y-%m-%d").to_string();
    Ok(job.export_request(snapshot, &today).write(snapshot)?)
}

/// Says what symmetry the photons are pooled over.
pub fn describe_symmetry(luminaire: &Luminaire, settings: &SimulationSettings) {
    if let Some(why) = &luminaire.find_symmetry().limited_by
        && settings.pool_symmetry
    {
        eprintln!("symmetry: {why}");
    }
    let symmetry = luminaire.find_symmetry().symmetry;
    if settings.pool_symmetry && symmetry != lucerna_photometry::AxialSymmetry::None {
        eprintln!(
            "symmetry: {symmetry}: each photon counted in its {} images",
            symmetry.order()
        );
    }
    if luminaire.c_pooling(settings.pool_symmetry) == CPooling::Rotational {
        eprintln!(
            "symmetry: round about its axis (surfaces of revolution, a round Lambertian source): its table pooled over C, files declare it rotational"
        );
    }
}

/// What a ray-file emitter's photons are: how many distinct rays stand
/// behind them, and whether their directions are turned by the file's
/// kernel.
pub fn describe_ray_reuse(luminaire: &Luminaire, photons: Option<u64>) {
    let Some((rays, turned)) = luminaire.prepared.ray_file_rays() else {
        return;
    };
    let per_ray = photons.map_or(String::new(), |p| {
        format!(", {:.1} photons a ray", p as f64 / rays as f64)
    });
    for e in &luminaire.prepared.emitters {
        let lucerna_tracer::prepared::EmitterDirections::RayFile(sampler) = &e.directions else {
            continue;
        };
        let header = sampler.rays.header.luminous_flux_lm.map(f64::from);
        let whose = if Some(e.flux_lm) == header {
            "the file header's figure"
        } else if e.flux_lm == sampler.total_lm {
            "the file's rays' sum"
        } else {
            "as the scene's flux_lm states"
        };
        eprintln!("ray file: {:.1} lm, {whose}", e.flux_lm);
        for w in sampler.rays.flux_warnings() {
            eprintln!("warning: ray file: {w}");
        }
    }
    let kernel = luminaire
        .prepared
        .emitters
        .iter()
        .find_map(|e| e.ray_kernel);
    match (turned, kernel) {
        (true, Some(k)) => eprintln!(
            "ray file: {rays} distinct rays{per_ray}; each photon's direction turned by the file's kernel ({:.2}°, cross-validated on {} held-out rays), its start kept; the uncertainty counts the distinct rays",
            k.direction_deg(),
            k.held_out
        ),
        _ => eprintln!(
            "ray file: {rays} distinct rays{per_ray}, used as they are (--ray-reuse loop): more photons than rays repeat them; the uncertainty counts the distinct rays"
        ),
    }
}

/// Traces `job` (checked) on the simulation's worker to its stopping rule
/// (or Ctrl+C), with a progress bar, and writes its files.
pub fn run_whole(job: &BakeJob) -> Result<BakeSummary> {
    let settings = job.settings;
    let out = &job.output.out_dir;
    let mut luminaire = Luminaire::load(&job.scene)?;
    luminaire.prepared.set_ray_reuse(job.ray_reuse());
    describe_symmetry(&luminaire, &settings);
    describe_ray_reuse(&luminaire, settings.stop.photons);
    std::fs::create_dir_all(out)
        .with_context(|| format!("cannot create output directory {}", out.display()))?;

    let stop = Arc::new(AtomicBool::new(false));
    {
        let stop = stop.clone();
        // A second handler cannot be set (tests run bakes in one process):
        // then Ctrl+C simply ends the process.
        let _ = ctrlc::set_handler(move || stop.store(true, Ordering::SeqCst));
    }
    // The luminaire loaded above is the one traced (not prepared twice),
    // in long iterations with a snapshot a second for the progress bar.
    let simulation = Simulation::start_prepared(Arc::new(luminaire), settings, Pace::BATCH, || {})?;
    let bar = match settings.stop.photons {
        Some(n) => ProgressBar::new(n),
        None => ProgressBar::new_spinner(),
    };
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {bar:30} {human_pos} photons ({per_sec}, ETA {eta}) {msg}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let mut seen: Option<Arc<Snapshot>> = None;
    let mut told_backend = false;
    let mut asked_to_finish = false;
    let snapshot = loop {
        let published = simulation.wait_for_update(seen.as_ref(), Duration::from_millis(200));
        if let Some((_, e)) = &published.error {
            bar.abandon();
            return Err(anyhow::anyhow!("{e}")).context("tracing failed");
        }
        if stop.load(Ordering::SeqCst) && !asked_to_finish {
            simulation.finish();
            asked_to_finish = true;
        }
        let Some(s) = published.snapshot else {
            if published.gone {
                anyhow::bail!("the simulation stopped without a result");
            }
            continue;
        };
        if !told_backend {
            bar.suspend(|| eprintln!("tracing on the {} ({})", s.backend, s.backend_reason));
            told_backend = true;
        }
        bar.set_position(s.photons);
        bar.set_message(format!(
            "{:.2} M rays/s, {:.2} bounces, peak ±{:.2} %, flux ±{:.3} %",
            s.rays_per_second / 1e6,
            s.mean_bounces,
            100.0 * s.noise.peak_relative,
            100.0 * s.noise.flux_relative
        ));
        if matches!(s.state, RunState::Finished(_)) {
            break s;
        }
        seen = Some(s);
    };
    bar.finish();
    let files = export(job, &snapshot)?;
    Ok(BakeSummary {
        files,
        photons: snapshot.photons,
        // Tracing alone (the final filter and export come after).
        seconds: snapshot.photons as f64 / snapshot.photons_per_second.max(1e-9),
        interrupted: snapshot.state == RunState::Finished(StopReason::Requested),
    })
}
