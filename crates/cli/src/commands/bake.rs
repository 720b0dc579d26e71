//! `lucerna bake`'s flags, converted once into a [`BakeJob`], and the one
//! dispatch between a whole bake, a part and a resume.

use std::path::PathBuf;
use std::time::Duration;

use anyhow::{Context, Result};
use lucerna_photometry::{CPlaneSymmetry, IesVersion};
use lucerna_simulation::{
    BackendRequest, BakeJob, BakeJobError, DEFAULT_BAKE_PHOTONS, ExportFormats, FilterChoice,
    PartSpec, SettingsError, SimulationSettings, StoppingRule, TableGrid,
};

use super::bake_run::{self, BakeSummary};
use super::part_bake;

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

pub fn parse_part(s: &str) -> Result<PartChoice, String> {
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
    #[arg(long, default_value_t = SimulationSettings::default().resolution)]
    pub resolution: u32,
    #[arg(long, default_value_t = SimulationSettings::default().seed)]
    pub seed: u32,
    /// cpu, gpu, or auto (a hardware GPU if there is one, else the CPU
    /// tracer: a software adapter runs on the same cores, 5x slower).
    #[arg(long, default_value = "auto")]
    pub backend: BackendRequest,
    /// Surface interactions after which a photon is cut off.
    #[arg(long, default_value_t = SimulationSettings::default().max_bounces)]
    pub max_bounces: u32,
    /// C-plane spacing of the exported table (degrees).
    #[arg(long, default_value_t = TableGrid::default().c_step_deg)]
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
    /// How a ray-file emitter's rays are used again when the bake traces
    /// more photons than the file has: `interpolate` turns each photon's
    /// direction by the file's own kernel (its width cross-validated on
    /// the rays), `loop` takes the rays as they are (each lands where it
    /// did before: spikes).
    #[arg(long, value_enum, default_value_t = RayReuseArg::Interpolate)]
    pub ray_reuse: RayReuseArg,
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

/// `--ray-reuse`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum RayReuseArg {
    Interpolate,
    Loop,
}

impl BakeArgs {
    /// The bake these flags ask for, checked, with the flag at fault
    /// named: the one conversion from the command line to a [`BakeJob`].
    pub fn job(&self) -> Result<BakeJob> {
        let scene = self
            .scene
            .as_deref()
            .context("no scene given (lucerna bake SCENE --out DIR)")?;
        let out = self
            .out
            .as_deref()
            .context("no output folder given (--out DIR)")?;
        let mut job = BakeJob::new(scene, out);
        let photons = match (self.photons, self.time, self.rel_error) {
            (None, None, None) => Some(DEFAULT_BAKE_PHOTONS),
            (p, _, _) => p,
        };
        job.settings = SimulationSettings {
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
        };
        if let Some(name) = &self.name {
            job.output.stem = name.clone();
        }
        job.output.formats = formats(&self.formats, self.ies_version, self.rays);
        job.output.symmetrise = self.symmetrise.imposed();
        job.output.date = self.date.clone();
        job.output.datasheet = self.sheet.options(String::new());
        job.loop_rays = self.ray_reuse == RayReuseArg::Loop;
        job.validate().map_err(|e| match &e {
            BakeJobError::Settings(s) => anyhow::anyhow!("{}: {e}", flag_of(s)),
            BakeJobError::Stem(_) => anyhow::anyhow!("--name: {e}"),
            _ => anyhow::anyhow!("--formats: {e}"),
        })?;
        Ok(job)
    }
}

/// The files `--formats` and `--ies-version` ask for.
fn formats(formats: &[FileFormat], version: IesVersionArg, rays: u32) -> ExportFormats {
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

/// `lucerna bake`: the one place that tells a whole bake, a part (or a
/// whole bake with checkpoints) and a resume apart.
pub fn bake(args: &BakeArgs) -> Result<BakeSummary> {
    if let Some(dir) = &args.resume {
        let part = args.part.map(|p| p.resolve(args.parts)).transpose()?;
        return part_bake::resume(dir, part, args.checkpoint);
    }
    if args.part.is_none() && args.checkpoint.is_none() && args.parts.is_none() {
        return bake_run::run_whole(&args.job()?);
    }
    let Some(total) = args.photons else {
        anyhow::bail!(
            "--part and --checkpoint need --photons TOTAL: a part is a fixed range of the \
             run's photons, the same on every machine"
        );
    };
    if args.time.is_some() || args.rel_error.is_some() {
        anyhow::bail!(
            "--time and --rel-error cannot split a bake: give its photons (--photons TOTAL)"
        );
    }
    let spec = match args.part {
        Some(choice) => choice.resolve(args.parts)?,
        None if args.parts.is_some() => anyhow::bail!("--parts N goes with --part auto"),
        None => PartSpec::WHOLE,
    };
    let job = args.job()?;
    debug_assert_eq!(job.settings.stop.photons, Some(total));
    part_bake::bake_part(&job, spec, args.part.is_none(), args.checkpoint)
}
