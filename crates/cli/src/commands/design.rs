//! `lucerna design`: a scene shaped toward a target distribution or spec,
//! with the tracer in the loop (`lucerna_design`).

use std::path::PathBuf;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use anyhow::{Context, Result, bail};
use lucerna_design::output::Outcome;
use lucerna_design::{Budget, DesignRequest, Progress, Stopped, Target};
use serde::Serialize;

#[derive(Debug, clap::Args)]
pub struct DesignArgs {
    /// The start scene (TOML).
    pub scene: PathBuf,
    /// The light wanted: an IES or EULUMDAT file (its distribution), or a
    /// spec (TOML: beam, field, cut-off, LOR, UGR, what to maximise;
    /// README, "Design").
    #[arg(long)]
    pub target: PathBuf,
    /// What may change: PART.FIELD (a continuous shape parameter, e.g.
    /// reflector.focal_length) or PART.profile (a revolved or extruded
    /// part's control points); repeat or separate with commas.
    #[arg(long, required = true, value_delimiter = ',')]
    pub vary: Vec<String>,
    #[arg(long, short)]
    pub out: PathBuf,
    /// How long the design may run (e.g. 120s, 5m).
    #[arg(long, default_value = "120s", value_parser = super::bake::parse_duration)]
    pub time: Duration,
    /// At most this many traced candidates: a budget that does not depend
    /// on the machine, so the same seed gives the same design anywhere.
    #[arg(long)]
    pub evaluations: Option<u64>,
    #[arg(long, default_value_t = 1)]
    pub seed: u32,
    /// Match the target's candela, not only its shape (both scaled to the
    /// same flux by default).
    #[arg(long)]
    pub absolute: bool,
    /// Let a varied profile's end points move too (by default they stay:
    /// the package around the LED and the aperture).
    #[arg(long)]
    pub free_ends: bool,
    /// Skip the point-source direct design of a revolved profile, its
    /// correction and the fallback search (or the survey of one or two
    /// numbers across their bounds), and refine the scene as it is.
    #[arg(long)]
    pub no_direct: bool,
    /// The designed profile's control points (3 to 33; by default as many
    /// as the target's detail needs).
    #[arg(long)]
    pub points: Option<usize>,
    /// For designs other than a revolved profile's: fit a distribution by
    /// damped least squares (Levenberg–Marquardt) instead of Nelder–Mead.
    #[arg(long)]
    pub least_squares: bool,
    /// Texels per cube-face edge of every candidate's map.
    #[arg(long, default_value_t = lucerna_design::DEFAULT_RESOLUTION)]
    pub resolution: u32,
    /// Photons of the designed scene's final bake (and the start's, for
    /// the comparison).
    #[arg(long, default_value_t = 10_000_000)]
    pub photons: u64,
    /// The base name of the files (default: the scene file's).
    #[arg(long)]
    pub name: Option<String>,
    /// ISO date of the bake's files (the same date makes them
    /// reproducible to the byte).
    #[arg(long)]
    pub date: Option<String>,
    /// Print the outcome as JSON.
    #[arg(long)]
    pub json: bool,
}

/// The outcome as `--json` prints it.
#[derive(Debug, Serialize)]
struct Report<'a> {
    scene: String,
    stopped: Stopped,
    evaluations: usize,
    variables: Vec<(String, f64, f64)>,
    start_merit: f64,
    reachability: Option<&'a lucerna_design::Reachability>,
    survey: Option<&'a lucerna_design::Survey>,
    advice: Vec<String>,
    points: Option<usize>,
    direct_design_merit: Option<f64>,
    corrections: &'a [lucerna_design::Iteration],
    meridian_model_search: Option<lucerna_design::ModelSearch>,
    warnings: &'a [String],
    merit: f64,
    merit_noise: f64,
    outcome: &'a Outcome,
    files: Vec<String>,
}

pub fn design(args: &DesignArgs) -> Result<()> {
    if args.time.is_zero() {
        bail!("--time must be positive");
    }
    if args.photons == 0 {
        bail!("--photons must be at least 1");
    }
    if !(8..=1024).contains(&args.resolution) {
        bail!(
            "--resolution must be between 8 and 1024, got {}",
            args.resolution
        );
    }
    if args.evaluations == Some(0) {
        bail!("--evaluations must be at least 1");
    }
    let target = Target::load(&args.target, args.absolute)?;
    let stem = args.name.clone().unwrap_or_else(|| {
        args.scene
            .file_stem()
            .map_or("design".to_owned(), |s| s.to_string_lossy().into_owned())
    });
    let date = args
        .date
        .clone()
        .unwrap_or_else(|| chrono::Local::now().format("%Y-%m-%d").to_string());
    let request = DesignRequest {
        scene_path: args.scene.clone(),
        target,
        vary: args.vary.clone(),
        free_ends: args.free_ends,
        budget: Budget {
            time: args.time,
            evaluations: args.evaluations,
            max_photons: None,
        },
        seed: args.seed,
        resolution: args.resolution,
        direct: !args.no_direct,
        least_squares: args.least_squares,
        points: args.points,
        fallback: Default::default(),
    };
    let interrupt = Arc::new(AtomicBool::new(false));
    {
        let flag = interrupt.clone();
        // A second handler cannot be set in one process: then Ctrl+C ends it.
        let _ = ctrlc::set_handler(move || flag.store(true, Ordering::SeqCst));
    }
    let mut last_line = std::time::Instant::now() - Duration::from_secs(1);
    let mut last_phase = None;
    let mut progress = |p: &Progress| {
        let new_phase = last_phase != Some(p.phase);
        if !new_phase && last_line.elapsed() < Duration::from_millis(500) {
            return;
        }
        last_phase = Some(p.phase);
        last_line = std::time::Instant::now();
        let measured = if p.photons == 0 {
            format!("model {:.4}", p.record.merit.unwrap_or(f64::NAN))
        } else {
            format!(
                "{:.2} M photons  merit {}",
                p.photons as f64 / 1e6,
                p.record
                    .merit
                    .map_or("refused".to_owned(), |m| format!("{m:.5}"))
            )
        };
        eprintln!(
            "{:6.1} s  {:<10}  {:5} candidates  {measured}  best {:.5}",
            p.elapsed.as_secs_f64(),
            p.phase.name(),
            p.evaluations,
            p.best_merit,
        );
    };
    let design = lucerna_design::design(&request, &interrupt, &mut progress)
        .with_context(|| format!("design of {}", args.scene.display()))?;
    for w in &design.warnings {
        eprintln!("warning: {w}");
    }
    match design.found.stopped {
        Stopped::Interrupted => eprintln!("interrupted: writing the best design so far"),
        Stopped::Time => eprintln!("the time is up: writing the best design found"),
        Stopped::Evaluations => {
            eprintln!("the evaluation budget is spent: writing the best design found")
        }
        Stopped::Converged => eprintln!("converged"),
    }
    eprintln!(
        "baking the design and the start with {} photons each",
        args.photons
    );
    let files = lucerna_design::output::files(&design, &args.out, &stem, &date, args.photons)
        .context("the design's files")?;
    lucerna_design::output::write(&files.files).context("nothing was written")?;
    let outcome = &files.outcome;
    let names: Vec<String> = files
        .files
        .iter()
        .map(|(p, _)| p.display().to_string())
        .collect();
    if args.json {
        let report = Report {
            scene: args.scene.display().to_string(),
            stopped: design.found.stopped,
            evaluations: design.found.history.len(),
            variables: design.changes(),
            start_merit: design.start_merit,
            reachability: design.reach.as_ref(),
            survey: design.survey.as_ref(),
            advice: advice(&design, outcome),
            points: design.points,
            direct_design_merit: design.direct.as_ref().map(|d| d.1),
            corrections: &design.corrections,
            meridian_model_search: design.model_search.clone(),
            warnings: &design.warnings,
            merit: design.found.merit,
            merit_noise: design.found.noise,
            outcome,
            files: names,
        };
        println!("{}", serde_json::to_string_pretty(&report)?);
        return Ok(());
    }
    if let Some(r) = &design.reach {
        print_reach(r);
    }
    if let Some(s) = &design.survey {
        print_survey(s);
    }
    if let Some((_, m)) = &design.direct {
        println!(
            "direct design (point source, {} control points): {m:.4} (the start: {:.4})",
            design.points.unwrap_or(0),
            design.start_merit
        );
    }
    if !design.corrections.is_empty() {
        let merits: Vec<String> = design
            .corrections
            .iter()
            .map(|i| {
                let m = i.merit.map_or("refused".to_owned(), |m| format!("{m:.4}"));
                if i.kept { m } else { format!("{m} (not kept)") }
            })
            .collect();
        println!("extended-source correction: {}", merits.join(" -> "));
    }
    if let Some(m) = &design.model_search {
        println!(
            "fallback: meridian model search, {} runs, {} model candidates in {:.1} s, best model L2 {:.4}; traced: {}",
            m.runs,
            m.evaluations,
            m.seconds,
            m.model_l2,
            m.traced_merit
                .map_or("refused".to_owned(), |t| format!("{t:.4}")),
        );
    }
    println!(
        "refined with the tracer: {:.4} ± {:.4} ({} M photons)",
        design.found.merit,
        design.found.noise,
        design.found.photons as f64 / 1e6
    );
    for (v, &x) in design.variables.iter().zip(&design.found.values) {
        println!(
            "{:<28} {:>14.6} -> {:>14.6}   (bounds {:.6} … {:.6})",
            v.name, v.start, x, v.lower, v.upper
        );
    }
    if let (Some(d), Some(s)) = (outcome.remaining_difference, outcome.start_difference) {
        println!(
            "remaining difference (relative L2 on the sphere, {} photons): {d:.4} (the start: {s:.4})",
            outcome.photons
        );
    }
    for t in &outcome.terms {
        if t.term.ends_with("(aim)") {
            continue;
        }
        let state = if t.missed_by > 0.0 {
            format!("MISSED by {:.3}", t.missed_by)
        } else {
            "met".to_owned()
        };
        println!(
            "{:<34} {:>9.3}   wanted {:<24} {state}",
            t.term, t.value, t.wanted
        );
    }
    for a in advice(&design, outcome) {
        println!("what would help: {a}");
    }
    for n in &names {
        println!("wrote {n}");
    }
    Ok(())
}

/// What the fixed parts make impossible, in a few lines.
fn print_reach(r: &lucerna_design::Reachability) {
    println!(
        "reachability: the LED's direct light leaves through a {:.1}° cone: at least {:.1} % of any design's light is there, the target has {:.1} % there",
        r.direct_cone_deg,
        100.0 * r.design_cone_share_min,
        100.0 * r.target_cone_share
    );
    println!(
        "reachability: the LED sends {:.1} % of its flux out directly; the mirror can send out at most {:.1} %",
        100.0 * r.direct_share,
        100.0 * r.mirror_share_max
    );
    println!(
        "reachability: no mirror between these ends that stays out of that cone can come closer than {:.4} (relative L2); one reaching into it shades the LED's direct light, and could come down to {:.4}",
        r.bound, r.with_cap
    );
}

/// How far each term went across the surveyed range.
fn print_survey(s: &lucerna_design::Survey) {
    println!(
        "survey: {} candidates across {}: merit {:.4} … {:.4}",
        s.traced,
        s.across(),
        s.merit_range[0],
        s.merit_range[1]
    );
    for t in &s.terms {
        println!(
            "survey: {:<28} {:>9.3} … {:<9.3} wanted {:<20} met by {} of {}",
            t.term, t.lowest, t.highest, t.wanted, t.met_by, s.traced
        );
    }
    for f in s.findings() {
        println!("survey: {f}");
    }
}

/// What would help the design reach further: where the result is well
/// above the bound, more control points; where the bound itself is
/// high, what frees it.
fn advice(design: &lucerna_design::Design, outcome: &Outcome) -> Vec<String> {
    let Some(r) = &design.reach else {
        return Vec::new();
    };
    let result = outcome.remaining_difference.unwrap_or(design.found.merit);
    let mut out = r.advice(result.min(0.02));
    if let Some(n) = design.points
        && n < lucerna_design::MAX_POINTS
        && result > 2.0 * r.bound + 0.01
    {
        out.push(format!(
            "more profile points (--points {}): the result is {result:.3}, the bound {:.3}",
            (2 * n - 1).min(lucerna_design::MAX_POINTS),
            r.bound
        ));
    }
    out
}
