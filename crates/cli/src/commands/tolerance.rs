//! `lucerna tolerance`: how many of the luminaires built meet the spec,
//! the figures' spread and what drives it (`lucerna_tolerance`).

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};
use indicatif::{ProgressBar, ProgressStyle};
use lucerna_tolerance::analysis::part_indices;
use lucerna_tolerance::output::{self, Manifest, PartFile};
use lucerna_tolerance::{Budget, Report, Settings, Setup, Stopped, Streams};

use super::bake::PartChoice;

#[derive(Debug, clap::Args)]
pub struct ToleranceArgs {
    /// The nominal scene (TOML).
    pub scene: PathBuf,
    /// The spec (TOML, as `lucerna design` takes: beam, field, cut-off,
    /// LOR, UGR), or a target IES/LDT file with --max-relative-l2.
    #[arg(long)]
    pub spec: PathBuf,
    /// For a target distribution: the largest relative L2 difference a
    /// built luminaire may have.
    #[arg(long)]
    pub max_relative_l2: Option<f64>,
    /// What manufacturing does (TOML: [[tolerance]], [[form_error]],
    /// [[slope_error]]; README, "Tolerance analysis").
    #[arg(long)]
    pub tolerances: PathBuf,
    #[arg(long, short)]
    pub out: PathBuf,
    /// Built luminaires to trace.
    #[arg(long)]
    pub samples: Option<u32>,
    /// Stop after this long (e.g. 60s, 5m).
    #[arg(long, value_parser = super::bake::parse_duration)]
    pub time: Option<Duration>,
    /// Stop once the yield's 95 % interval is at most ± this many points
    /// (e.g. 5).
    #[arg(long)]
    pub yield_precision: Option<f64>,
    #[arg(long, default_value_t = Settings::default().seed)]
    pub seed: u32,
    /// Photons per built luminaire.
    #[arg(long, default_value_t = Settings::default().photons)]
    pub photons: u64,
    /// Texels per cube-face edge of each sample's map.
    #[arg(long, default_value_t = Settings::default().resolution)]
    pub resolution: u32,
    /// Trace each sample with a photon stream of its own instead of the
    /// nominal's (its spread then holds the photon noise too).
    #[arg(long)]
    pub independent_streams: bool,
    /// Traces of the nominal with streams of their own, whose spread is
    /// the photon noise reported.
    #[arg(long, default_value_t = Settings::default().noise_runs)]
    pub noise_runs: u32,
    /// Trace only part K of N of the samples (every N-th from K−1) and
    /// write its part file; `auto` reads the task from Slurm or an
    /// Indexed Job (with --parts). Needs --samples.
    #[arg(long, value_parser = super::bake::parse_part)]
    pub part: Option<PartChoice>,
    /// The number of parts, for `--part auto` under Kubernetes.
    #[arg(long)]
    pub parts: Option<u32>,
    /// Merge the part files in this folder (all N of the run with the
    /// same --samples and settings) into the analysis's files.
    #[arg(long, conflicts_with = "part")]
    pub merge: Option<PathBuf>,
    /// Print the report as JSON.
    #[arg(long)]
    pub json: bool,
}

pub fn tolerance(args: &ToleranceArgs) -> Result<()> {
    if args.samples == Some(0) {
        bail!("--samples must be at least 1");
    }
    if args.time.is_some_and(|t| t.is_zero()) {
        bail!("--time must be positive");
    }
    if let Some(p) = args.yield_precision
        && !(p.is_finite() && p > 0.0 && p < 50.0)
    {
        bail!("--yield-precision is in points (e.g. 5 for ± 5 %), got {p}");
    }
    if args.samples.is_none() && args.time.is_none() && args.yield_precision.is_none() {
        bail!("say when to stop: --samples N, --time 60s or --yield-precision 5");
    }
    if (args.part.is_some() || args.merge.is_some()) && args.samples.is_none() {
        bail!("a split run needs --samples: every part and the merge must know the whole run");
    }
    if (args.part.is_some() || args.merge.is_some())
        && (args.time.is_some() || args.yield_precision.is_some())
    {
        bail!(
            "a split run is sized by --samples alone (--time and --yield-precision would make the parts differ)"
        );
    }
    if args.noise_runs < 2 {
        bail!("--noise-runs must be at least 2");
    }
    let settings = Settings {
        seed: args.seed,
        photons: args.photons,
        resolution: args.resolution,
        streams: if args.independent_streams {
            Streams::Independent
        } else {
            Streams::Common
        },
        noise_runs: args.noise_runs,
    };
    let setup = Setup::load(
        &args.scene,
        &args.spec,
        args.max_relative_l2,
        &args.tolerances,
        settings,
    )?;
    let part = match args.part {
        Some(choice) => {
            let p = choice.resolve(args.parts)?;
            Some((p.index, p.count))
        }
        None => None,
    };
    let manifest = |parts: u32| -> Result<Manifest> {
        Ok(Manifest {
            format: 1,
            inputs_sha256: output::inputs_sha256(&[&args.scene, &args.spec, &args.tolerances])?,
            samples: args.samples.unwrap_or(0),
            parts,
            settings,
            max_relative_l2: args.max_relative_l2,
        })
    };
    let interrupt = Arc::new(AtomicBool::new(false));
    {
        let flag = interrupt.clone();
        // A second handler cannot be set in one process: then Ctrl+C ends it.
        let _ = ctrlc::set_handler(move || flag.store(true, Ordering::SeqCst));
    }
    let began = Instant::now();
    if let Some((k, n)) = part {
        let manifest = manifest(n)?;
        let indices = part_indices(manifest.samples, Some((k, n)));
        let budget = Budget {
            samples: Some(indices.len() as u32),
            ..Budget::default()
        };
        let (records, stopped) = sample(&setup, indices.iter().copied(), &budget, &interrupt);
        let path = args.out.join(output::part_file_name(k, n));
        let file = PartFile {
            manifest,
            part: k,
            records,
        };
        output::write(&[(path.clone(), serde_json::to_vec(&file)?)])
            .context("nothing was written")?;
        if stopped == Stopped::Interrupted {
            eprintln!(
                "interrupted: part {k} of {n} holds {} of its {} samples; run it again before merging",
                file.records.len(),
                indices.len()
            );
        }
        println!("wrote {}", path.display());
        return Ok(());
    }
    // A merge checks its parts before it traces anything.
    let merged = match &args.merge {
        Some(dir) => Some(output::merge_parts(dir, &manifest(0)?)?),
        None => None,
    };
    eprintln!(
        "tracing the nominal and its photon noise ({} streams)",
        settings.noise_runs
    );
    let reference = setup.reference()?;
    let (records, stopped) = match merged {
        Some(records) => {
            output::check_records(&setup, reference.nominal.terms.len(), &records)?;
            (records, Stopped::Samples)
        }
        None => {
            let budget = Budget {
                samples: args.samples,
                time: args.time,
                yield_half_width: args.yield_precision.map(|p| p / 100.0),
            };
            sample(
                &setup,
                0..args.samples.unwrap_or(u32::MAX),
                &budget,
                &interrupt,
            )
        }
    };
    if records.is_empty() {
        bail!("no sample was traced: nothing written");
    }
    match stopped {
        Stopped::Interrupted => {
            eprintln!("interrupted: writing the {} samples done", records.len())
        }
        Stopped::Time => eprintln!("the time is up: writing the {} samples done", records.len()),
        Stopped::Precision => eprintln!(
            "the yield's interval is within ± {} points",
            args.yield_precision.unwrap_or(0.0)
        ),
        Stopped::Samples => {}
    }
    let report = Report::new(
        &setup,
        &reference,
        &records,
        stopped,
        began.elapsed().as_secs_f64(),
    );
    let files = output::files(&setup, &report, &records, &args.out)?;
    output::write_analysis(&files, &args.out).context("nothing was written")?;
    if args.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
        return Ok(());
    }
    print_report(&report);
    for (p, _) in &files {
        println!("wrote {}", p.display());
    }
    Ok(())
}

/// Runs the samples with a progress bar.
fn sample(
    setup: &Setup,
    indices: impl IntoIterator<Item = u32>,
    budget: &Budget,
    interrupt: &AtomicBool,
) -> (Vec<lucerna_tolerance::SampleRecord>, Stopped) {
    let bar = match budget.samples {
        Some(n) => ProgressBar::new(u64::from(n)),
        None => ProgressBar::new_spinner(),
    };
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {bar:30} {human_pos} samples ({per_sec}) {msg}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let mut progress = |p: &lucerna_tolerance::Progress, _: &lucerna_tolerance::SampleRecord| {
        if p.done.is_multiple_of(TRIM_EVERY) {
            return_freed_memory();
        }
        bar.set_position(p.done as u64);
        let y = p.yield_so_far;
        bar.set_message(format!(
            "yield {:.1} % ({:.1}–{:.1}){}",
            100.0 * y.value,
            100.0 * y.low,
            100.0 * y.high,
            if p.refused > 0 {
                format!(", {} not buildable", p.refused)
            } else {
                String::new()
            }
        ));
    };
    let out = setup.run(indices, budget, interrupt, &mut progress);
    bar.finish_and_clear();
    out
}

fn print_report(r: &Report) {
    let y = &r.overall;
    println!(
        "yield: {:.1} % ({} of {} built luminaires meet every term; 95 % interval {:.1}–{:.1} %){}",
        100.0 * y.value,
        y.passed,
        y.samples,
        100.0 * y.low,
        100.0 * y.high,
        if r.refused > 0 {
            format!("; {} could not be built and count as failed", r.refused)
        } else {
            String::new()
        }
    );
    for (index, why) in &r.refusals {
        println!("  sample {index} not buildable: {why}");
    }
    for t in &r.terms {
        println!(
            "  {:<34} wanted {:<26} nominal {:>9.3} {}   yield {:5.1} % ({:.1}–{:.1})",
            t.term,
            t.wanted,
            t.nominal,
            if t.nominal_met { "met   " } else { "MISSED" },
            100.0 * t.fraction.value,
            100.0 * t.fraction.low,
            100.0 * t.fraction.high
        );
    }
    println!(
        "{:<24} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10}",
        "figure", "nominal", "mean", "σ", "noise σ", "5 %", "50 %", "95 %"
    );
    for f in &r.figures {
        let p = &f.spread;
        println!(
            "{:<24} {:>10.4} {:>10.4} {:>10.4} {:>10.4} {:>10.4} {:>10.4} {:>10.4}",
            f.figure, f.nominal, p.mean, p.sd, f.photon_noise_sd, p.q05, p.q50, p.q95
        );
    }
    let mut drivers: Vec<&lucerna_tolerance::report::Sensitivity> = r
        .sensitivities
        .iter()
        .filter(|s| s.share.share > 3.0 * s.share.noise && s.share.share >= 0.05)
        .collect();
    drivers.sort_by(|a, b| {
        a.figure
            .cmp(b.figure)
            .then(b.share.share.total_cmp(&a.share.share))
    });
    for s in drivers {
        println!(
            "  {:<24} driven by {:<28} {:5.1} % of its variance",
            s.figure,
            s.tolerance,
            100.0 * s.share.share
        );
    }
    for w in &r.warnings {
        println!("warning: {w}");
    }
    if let Some(w) = &r.worst {
        println!("worst sample: {} ({})", w.index, w.missed.join("; "));
    }
    println!(
        "{} samples in {:.1} s ({:.2} samples/s)",
        r.samples,
        r.seconds,
        r.samples as f64 / r.seconds.max(1e-9)
    );
}

/// Samples between two [`return_freed_memory`]: each trim costs the
/// next samples their pages again (every sample: 25 % slower), so the
/// heap may hold a few dozen samples' worth.
const TRIM_EVERY: usize = 32;

/// Hands glibc's freed heap back to the system. Each sample's mesh and
/// BVH are made and freed across the tracer's threads, and glibc keeps
/// such memory in its arenas: a run of thousands of samples otherwise
/// grows by about 2.4 MB a sample (BENCHMARKS.md, "Tolerance analysis").
#[cfg(all(target_os = "linux", target_env = "gnu"))]
fn return_freed_memory() {
    #[allow(unsafe_code)]
    // SAFETY: malloc_trim walks glibc's own free lists; it takes no
    // pointer of ours and is safe to call from any thread at any time.
    unsafe {
        libc::malloc_trim(0);
    }
}

#[cfg(not(all(target_os = "linux", target_env = "gnu")))]
fn return_freed_memory() {}
