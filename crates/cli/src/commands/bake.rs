//! `lucerna bake`: trace a luminaire headlessly and write its photometry.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use anyhow::{Context, Result};
use indicatif::{ProgressBar, ProgressStyle};
use lucerna_photometry::{CPlaneSymmetry, IesVersion};
use lucerna_simulation::{
    BackendRequest, ExportFormats, ExportOptions, ExportRequest, FilterChoice, Luminaire, Pace,
    PartSpec, RunState, SettingsError, Simulation, SimulationSettings, Snapshot, StopReason,
    StoppingRule, TableGrid,
};

/// The C-plane symmetry the files declare (the table is averaged over it,
/// so it holds exactly).
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SymmetryArg {
    /// What the photons were pooled over (found in the geometry), where
    /// the formats can say it; else none.
    Auto,
    /// None: C0-C360 written.
    None,
    Rotational,
    /// Both mirror planes, C0-C180 and C90-C270.
    Quadrant,
    C0C180,
    C90C270,
}

impl SymmetryArg {
    /// The symmetry imposed, `None` for the automatic one.
    pub fn imposed(self) -> Option<CPlaneSymmetry> {
        match self {
            SymmetryArg::Auto => None,
            SymmetryArg::None => Some(CPlaneSymmetry::None),
            SymmetryArg::Rotational => Some(CPlaneSymmetry::Rotational),
            SymmetryArg::Quadrant => Some(CPlaneSymmetry::Quadrant),
            SymmetryArg::C0C180 => Some(CPlaneSymmetry::AboutC0C180),
            SymmetryArg::C90C270 => Some(CPlaneSymmetry::AboutC90C270),
        }
    }
}

/// The LM-63 edition of the IES file.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum IesVersionArg {
    #[value(name = "2019")]
    Lm63_2019,
    #[value(name = "2002")]
    Lm63_2002,
}

/// One of the files a bake writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum FileFormat {
    /// STEM.ies
    Ies,
    /// STEM.ldt (EULUMDAT)
    Ldt,
    /// STEM.exr, the raw map with its photon counts
    Exr,
    /// STEM_cube.png, the false-colour cube map
    Cube,
    /// STEM_polar.png, the polar diagram
    Polar,
    /// STEM_datasheet.html, .pdf and .json: the photometric datasheet
    /// with the UGR table (`lucerna report` writes the same)
    Datasheet,
    /// STEM.tm25ray, `--rays` rays leaving the luminaire (IES TM-25)
    Tm25,
}

/// Whether photons are pooled over the luminaire's symmetry.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum PoolSymmetry {
    /// The symmetry found in the luminaire's geometry.
    Auto,
    /// No pooling.
    None,
}

/// `--part`: a part number, or the scheduler's task.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PartChoice {
    /// From `SLURM_ARRAY_TASK_ID` (with `SLURM_ARRAY_TASK_COUNT` or
    /// `_MIN`/`_MAX`) or `JOB_COMPLETION_INDEX` (with `--parts`).
    Auto,
    Part(PartSpec),
}

fn parse_part(s: &str) -> Result<PartChoice, String> {
    if s.trim() == "auto" {
        return Ok(PartChoice::Auto);
    }
    s.parse::<PartSpec>()
        .map(PartChoice::Part)
        .map_err(|e| e.to_string())
}

impl PartChoice {
    /// The part this choice is, the scheduler's read from the environment.
    pub fn resolve(self, parts: Option<u32>) -> Result<PartSpec> {
        match self {
            PartChoice::Part(spec) => {
                if let Some(n) = parts
                    && n != spec.count
                {
                    anyhow::bail!("--parts {n} disagrees with --part {spec}");
                }
                Ok(spec)
            }
            PartChoice::Auto => PartSpec::from_scheduler(&|name| std::env::var(name).ok(), parts)
                .map_err(|e| anyhow::anyhow!("--part auto: {e}")),
        }
    }
}

#[derive(Debug, clap::Args)]
pub struct BakeArgs {
    /// The luminaire scene (TOML).
    #[arg(required_unless_present = "resume")]
    pub scene: Option<PathBuf>,
    /// Stop after this many photons (default 10 000 000 when no other
    /// limit is given).
    #[arg(long)]
    pub photons: Option<u64>,
    /// Stop after this long, e.g. 30s, 2m, 500ms.
    #[arg(long, value_parser = parse_duration)]
    pub time: Option<Duration>,
    /// Stop once the relative standard error of the peak intensity is
    /// below this (e.g. 0.01).
    #[arg(long)]
    pub rel_error: Option<f64>,
    /// Texels per cube-face edge.
    #[arg(long, default_value_t = 256)]
    pub resolution: u32,
    #[arg(long, default_value_t = 1)]
    pub seed: u32,
    /// cpu, gpu, or auto (a hardware GPU if there is one, else the CPU
    /// tracer: a software adapter runs on the same cores, 5x slower).
    #[arg(long, default_value = "auto")]
    pub backend: BackendRequest,
    /// Surface interactions after which a photon is cut off.
    #[arg(long, default_value_t = 64)]
    pub max_bounces: u32,
    /// C-plane spacing of the exported table (degrees).
    #[arg(long, default_value_t = 5.0)]
    pub c_step: f64,
    /// γ spacing of the exported table (degrees); by default the coarsest
    /// of 2.5°, 1.25° … 0.078125° whose table holds the map's flux
    /// (0.05 %), cone fluxes at 2/5/10/30° (0.3 %), beam and field angles
    /// (0.05°) and peak (0.5 %). A fixed step that loses the beam is
    /// written, with a warning that gives the numbers.
    #[arg(long)]
    pub gamma_step: Option<f64>,
    /// The C-plane symmetry the files declare, the table averaged over it
    /// (even one the geometry lacks, such as rotational): `auto` declares
    /// what the photons were pooled over (`--symmetry`), quadrant or one
    /// mirror plane, where the formats can say it; `none` writes C0-C360.
    #[arg(long, value_enum, default_value_t = SymmetryArg::Auto)]
    pub symmetrise: SymmetryArg,
    /// Pool the photons of every image of a direction under the
    /// luminaire's own symmetry about its axis (quarter turns, mirror
    /// planes), found from its geometry: `auto` (worth up to 8× the
    /// photons, unbiased) or `none` (the counts as traced).
    #[arg(long, value_enum, default_value_t = PoolSymmetry::Auto)]
    pub symmetry: PoolSymmetry,
    /// Export the map filtered by the pull-push bilateral filter: `auto`
    /// (rule chosen per map by cross-validation on the photons), a photon
    /// threshold such as 100, or `none` for the raw map.
    #[arg(long, default_value = "none")]
    pub filter: FilterChoice,
    /// Output directory (created if needed).
    #[arg(long, required_unless_present = "resume")]
    pub out: Option<PathBuf>,
    /// The files to write, comma-separated.
    #[arg(long, value_enum, value_delimiter = ',', default_values_t = [FileFormat::Ies, FileFormat::Ldt, FileFormat::Exr, FileFormat::Cube, FileFormat::Polar])]
    pub formats: Vec<FileFormat>,
    /// The LM-63 edition of the IES file.
    #[arg(long, value_enum, default_value_t = IesVersionArg::Lm63_2019)]
    pub ies_version: IesVersionArg,
    /// Rays in the TM-25 file (`--formats tm25`): the run's first photons
    /// that leave the luminaire.
    #[arg(long, default_value_t = lucerna_simulation::DEFAULT_TM25_RAYS, value_parser = clap::value_parser!(u32).range(1..=50_000_000))]
    pub rays: u32,
    /// The files' base name (STEM.ies, STEM_polar.png, …); by default the
    /// scene file's name without its extension.
    #[arg(long)]
    pub name: Option<String>,
    /// The issue date the files state, e.g. 2026-01-31 (today by
    /// default): the same date makes a bake reproducible to the byte.
    #[arg(long)]
    pub date: Option<String>,
    /// The datasheet's UGR spacings and outdoor rating (`--formats datasheet`).
    #[command(flatten)]
    pub sheet: super::report::DatasheetArgs,
    /// Trace only part K of N of the run's `--photons` (e.g. 3/8), as a
    /// partial map (STEM.part-K-of-N.json and its counts) for `lucerna
    /// merge`; `auto` takes K and N from the scheduler (a Slurm job
    /// array's task, or a Kubernetes Indexed Job's JOB_COMPLETION_INDEX
    /// with --parts).
    #[arg(long, value_parser = parse_part)]
    pub part: Option<PartChoice>,
    /// The number of parts, for `--part auto` in a Kubernetes Indexed Job
    /// (its `completions`).
    #[arg(long)]
    pub parts: Option<u32>,
    /// Write the photons traced so far every this long (e.g. 5m), so that
    /// a killed job loses at most that much: `--resume` goes on from the
    /// last. A part's bake checkpoints every 5m unless told.
    #[arg(long, value_parser = parse_duration)]
    pub checkpoint: Option<Duration>,
    /// Continue the checkpointed bake in this folder to its total (every
    /// setting is the checkpoint's; with --part, that part's checkpoint).
    #[arg(long, conflicts_with_all = [
        "scene", "photons", "time", "rel_error", "resolution", "seed", "backend",
        "max_bounces", "c_step", "gamma_step", "symmetrise", "symmetry", "filter",
        "out", "formats", "ies_version", "rays", "name", "date", "ugr_spacing", "outdoor",
    ])]
    pub resume: Option<PathBuf>,
}

/// `lucerna bake`'s arguments on their own: to take their defaults, or
/// to rebuild a checkpoint's bake from the flags it stored.
#[derive(Debug, clap::Parser)]
#[command(name = "bake")]
struct BakeCommand {
    #[command(flatten)]
    bake: BakeArgs,
}

/// Parses `lucerna bake`'s flags (`argv` without the program name).
pub fn parse_bake_args<I, T>(argv: I) -> Result<BakeArgs>
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    use clap::Parser;
    let argv =
        std::iter::once(std::ffi::OsString::from("bake")).chain(argv.into_iter().map(Into::into));
    BakeCommand::try_parse_from(argv)
        .map(|c| c.bake)
        .map_err(|e| anyhow::anyhow!("{e}"))
}

/// A clap value's own name (`quadrant`, `2019`).
fn value_name<T: clap::ValueEnum>(value: &T) -> String {
    value
        .to_possible_value()
        .map_or_else(String::new, |v| v.get_name().to_owned())
}

/// "30s", "2m", "1.5h", "500ms", or plain seconds.
pub fn parse_duration(s: &str) -> Result<Duration, String> {
    let s = s.trim();
    let (number, unit) = s
        .find(|c: char| c.is_ascii_alphabetic())
        .map_or((s, "s"), |i| (&s[..i], &s[i..]));
    let v: f64 = number
        .trim()
        .parse()
        .map_err(|_| format!("'{s}' is not a duration like 30s, 2m or 500ms"))?;
    let seconds = match unit {
        "ms" => v / 1000.0,
        "s" => v,
        "m" | "min" => v * 60.0,
        "h" => v * 3600.0,
        _ => return Err(format!("unknown unit '{unit}' in '{s}' (ms, s, m, h)")),
    };
    if !(seconds.is_finite() && seconds > 0.0 && seconds < 1e7) {
        return Err(format!("'{s}' is not a positive duration"));
    }
    Ok(Duration::from_secs_f64(seconds))
}

/// What the bake wrote.
#[derive(Debug)]
pub struct BakeSummary {
    pub files: Vec<PathBuf>,
    pub photons: u64,
    pub seconds: f64,
    pub interrupted: bool,
}

impl BakeArgs {
    /// The simulation these arguments ask for.
    pub fn settings(&self) -> SimulationSettings {
        let photons = match (self.photons, self.time, self.rel_error) {
            (None, None, None) => Some(10_000_000),
            (p, _, _) => p,
        };
        SimulationSettings {
            resolution: self.resolution,
            seed: self.seed,
            max_bounces: self.max_bounces,
            backend: self.backend,
            filter: self.filter,
            pool_symmetry: self.symmetry == PoolSymmetry::Auto,
            stop: StoppingRule {
                photons,
                time: self.time,
                peak_relative_error: self.rel_error,
            },
            table: TableGrid {
                c_step_deg: self.c_step,
                gamma_step_deg: self.gamma_step,
            },
        }
    }
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

/// Writes the files `args` ask for from a final snapshot (all or none),
/// after saying how the table and filter came out.
pub fn export(args: &BakeArgs, snapshot: &Snapshot) -> Result<Vec<PathBuf>> {
    eprintln!("table: {}", snapshot.table_fidelity.summary());
    for warning in &snapshot.warnings {
        eprintln!("warning: {warning}");
    }
    describe_filter(snapshot);
    let scene_file = args
        .scene
        .as_deref()
        .and_then(Path::file_name)
        .map_or(String::new(), |s| s.to_string_lossy().into_owned());
    let options = ExportOptions {
        symmetrise: args.symmetrise.imposed(),
        date: args
            .date
            .clone()
            .unwrap_or_else(|| chrono::Local::now().format("%Y-%m-%d").to_string()),
        seed: args.seed,
        scene_file: scene_file.clone(),
        // The scene's name, manufacturer and [export] keywords.
        labels: None,
    };
    let out = args.out_dir()?;
    std::fs::create_dir_all(out)
        .with_context(|| format!("cannot create output directory {}", out.display()))?;
    let mut request = ExportRequest::new(snapshot, options, out, &args.stem());
    request.formats = formats(&args.formats, args.ies_version, args.rays);
    request.datasheet = args.sheet.options(scene_file);
    Ok(request.write(snapshot)?)
}

/// The files `--formats` and `--ies-version` ask for.
pub fn formats(formats: &[FileFormat], version: IesVersionArg, rays: u32) -> ExportFormats {
    ExportFormats {
        ies: formats.contains(&FileFormat::Ies).then_some(match version {
            IesVersionArg::Lm63_2019 => IesVersion::Lm63_2019,
            IesVersionArg::Lm63_2002 => IesVersion::Lm63_2002,
        }),
        ldt: formats.contains(&FileFormat::Ldt),
        exr: formats.contains(&FileFormat::Exr),
        cube_png: formats.contains(&FileFormat::Cube),
        polar_png: formats.contains(&FileFormat::Polar),
        datasheet: formats.contains(&FileFormat::Datasheet),
        tm25_rays: formats.contains(&FileFormat::Tm25).then_some(rays),
    }
}

impl BakeArgs {
    /// The scene (given unless resuming).
    pub fn scene_path(&self) -> Result<&Path> {
        self.scene
            .as_deref()
            .context("no scene given (lucerna bake SCENE --out DIR)")
    }

    pub fn out_dir(&self) -> Result<&Path> {
        self.out
            .as_deref()
            .context("no output folder given (--out DIR)")
    }

    /// The base name of the files.
    pub fn stem(&self) -> String {
        self.name.clone().unwrap_or_else(|| {
            self.scene
                .as_deref()
                .and_then(Path::file_stem)
                .map_or("luminaire".to_owned(), |s| s.to_string_lossy().into_owned())
        })
    }

    /// The flags that shape the files but not the photons (filter,
    /// pooling, table grid, formats, labels), as `lucerna bake` takes
    /// them: a part stores them so that a merge writes the files the
    /// one-machine bake would.
    pub fn export_args(&self) -> Vec<String> {
        let filter = match self.filter {
            FilterChoice::Raw => "none".to_owned(),
            FilterChoice::Automatic => "auto".to_owned(),
            FilterChoice::Threshold(t) => t.to_string(),
        };
        let join = |v: Vec<String>| v.join(",");
        let mut args = vec![
            "--c-step".to_owned(),
            self.c_step.to_string(),
            "--symmetrise".to_owned(),
            value_name(&self.symmetrise),
            "--symmetry".to_owned(),
            value_name(&self.symmetry),
            "--filter".to_owned(),
            filter,
            "--formats".to_owned(),
            join(self.formats.iter().map(value_name).collect()),
            "--ies-version".to_owned(),
            value_name(&self.ies_version),
            "--rays".to_owned(),
            self.rays.to_string(),
            "--name".to_owned(),
            self.stem(),
            "--ugr-spacing".to_owned(),
            join(self.sheet.ugr_spacing.iter().map(f64::to_string).collect()),
            "--outdoor".to_owned(),
            value_name(&self.sheet.outdoor),
        ];
        if let Some(step) = self.gamma_step {
            args.extend(["--gamma-step".to_owned(), step.to_string()]);
        }
        // Without --date each merge states its own day.
        if let Some(date) = &self.date {
            args.extend(["--date".to_owned(), date.clone()]);
        }
        args
    }
}

/// The flag a settings error is about.
fn flag_of(e: &SettingsError) -> &'static str {
    match e {
        SettingsError::Resolution(_) => "--resolution",
        SettingsError::Photons => "--photons",
        SettingsError::RelativeError(_) => "--rel-error",
        SettingsError::Time => "--time",
        SettingsError::MaxBounces(_) => "--max-bounces",
        SettingsError::Step { what: "γ", .. } => "--gamma-step",
        SettingsError::Step { .. } => "--c-step",
        SettingsError::FilterThreshold(_) => "--filter",
        _ => "an argument",
    }
}

/// Refuses a `--name` that is not a plain file name, before tracing.
pub fn check_name(args: &BakeArgs) -> Result<()> {
    if let Some(name) = &args.name
        && (name.trim().is_empty()
            || std::path::Path::new(name).file_name() != Some(std::ffi::OsStr::new(name)))
    {
        anyhow::bail!("--name: '{name}' is not a plain file name (no folders)");
    }
    Ok(())
}

/// Checks the settings, naming the flag at fault.
pub fn checked_settings(args: &BakeArgs) -> Result<SimulationSettings> {
    let settings = args.settings();
    settings
        .validate()
        .map_err(|e| anyhow::anyhow!("{}: {e}", flag_of(&e)))?;
    Ok(settings)
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
}

pub fn bake(args: &BakeArgs) -> Result<BakeSummary> {
    if args.resume.is_some() {
        return super::part_bake::resume(args);
    }
    if args.part.is_some() || args.checkpoint.is_some() || args.parts.is_some() {
        return super::part_bake::bake_part(args);
    }
    let settings = checked_settings(args)?;
    // Refused before tracing, not after.
    check_name(args)?;
    let out = args.out_dir()?;
    let luminaire = Luminaire::load(args.scene_path()?)?;
    describe_symmetry(&luminaire, &settings);
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
    let files = export(args, &snapshot)?;
    Ok(BakeSummary {
        files,
        photons: snapshot.photons,
        // Tracing alone (the final filter and export come after).
        seconds: snapshot.photons as f64 / snapshot.photons_per_second.max(1e-9),
        interrupted: snapshot.state == RunState::Finished(StopReason::Requested),
    })
}
