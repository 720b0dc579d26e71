//! `lucerna report`: the photometric datasheet (HTML, PDF, JSON) of an
//! IES or EULUMDAT file, or of a luminaire scene baked first.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use lucerna_datasheet::{Datasheet, DatasheetOptions, Outdoor};

use lucerna_simulation::{BakeJob, ExportFormats, SimulationSettings};

use super::bake_run;

/// Whether the BUG rating of outdoor luminaires is shown.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum OutdoorArg {
    /// From the luminaire's name, catalogue number and keywords.
    Auto,
    Yes,
    No,
}

/// What a datasheet shows beyond the table (also for `bake --formats datasheet`).
#[derive(Debug, Clone, clap::Args)]
pub struct DatasheetArgs {
    /// UGR tables at these spacing-to-height ratios, comma-separated:
    /// 0.25 as catalogues print, 1 for CIE 190's standard table.
    #[arg(long, value_delimiter = ',', default_values_t = [0.25])]
    pub ugr_spacing: Vec<f64>,
    /// Rate the luminaire as an outdoor one (IES TM-15 BUG rating).
    #[arg(long, value_enum, default_value_t = OutdoorArg::Auto)]
    pub outdoor: OutdoorArg,
}

impl DatasheetArgs {
    pub fn options(&self, source_name: String) -> DatasheetOptions {
        DatasheetOptions {
            ugr_spacings: self.ugr_spacing.clone(),
            outdoor: match self.outdoor {
                OutdoorArg::Auto => Outdoor::Auto,
                OutdoorArg::Yes => Outdoor::Yes,
                OutdoorArg::No => Outdoor::No,
            },
            source_name,
        }
    }
}

#[derive(Debug, clap::Args)]
pub struct ReportArgs {
    /// An IES or EULUMDAT file, or a luminaire scene (.toml), which is
    /// baked first (--photons, --seed, --resolution, --backend).
    pub input: PathBuf,
    /// Output directory (created if needed): STEM_datasheet.html, .pdf
    /// and .json.
    #[arg(long)]
    pub out: PathBuf,
    /// Also print every figure of the sheet as JSON on stdout.
    #[arg(long)]
    pub json: bool,
    /// The files' base name; by default the input's name without its
    /// extension.
    #[arg(long)]
    pub name: Option<String>,
    #[command(flatten)]
    pub sheet: DatasheetArgs,
    /// Scenes only: photons to trace.
    #[arg(long, default_value_t = 5_000_000)]
    pub photons: u64,
    /// Scenes only: the RNG seed.
    #[arg(long, default_value_t = SimulationSettings::default().seed)]
    pub seed: u32,
    /// Scenes only: texels per cube-face edge.
    #[arg(long, default_value_t = SimulationSettings::default().resolution)]
    pub resolution: u32,
    /// Scenes only: cpu, gpu or auto.
    #[arg(long, default_value = "auto")]
    pub backend: lucerna_simulation::BackendRequest,
    /// Scenes only: the issue date the sheet's photometry states.
    #[arg(long)]
    pub date: Option<String>,
}

/// What a report wrote, and the sheet's JSON.
#[derive(Debug)]
pub struct ReportSummary {
    pub files: Vec<PathBuf>,
    pub json: Option<String>,
}

fn is_scene(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("toml"))
}

pub fn report(args: &ReportArgs) -> Result<ReportSummary> {
    for &s in &args.sheet.ugr_spacing {
        // Refused before a scene is traced, not after.
        if !lucerna_datasheet::ugr::is_method_spacing(s) {
            anyhow::bail!("--ugr-spacing: {s} is not one of 0.25, 0.5 or 1 (the method's arrays)");
        }
    }
    let stem = args.name.clone().unwrap_or_else(|| {
        args.input
            .file_stem()
            .map_or("luminaire".to_owned(), |s| s.to_string_lossy().into_owned())
    });
    if is_scene(&args.input) {
        // `lucerna bake SCENE --out DIR` with the bake's own defaults, then
        // the report's own settings, writing only the datasheet.
        let mut job = BakeJob::new(&args.input, &args.out);
        job.settings.stop.photons = Some(args.photons);
        job.settings.seed = args.seed;
        job.settings.resolution = args.resolution;
        job.settings.backend = args.backend;
        job.output.formats = ExportFormats {
            datasheet: true,
            ..ExportFormats::NONE
        };
        job.output.stem = stem;
        job.output.date = args.date.clone();
        job.output.datasheet = args.sheet.options(String::new());
        job.validate()?;
        let summary = bake_run::run_whole(&job)
            .with_context(|| format!("bake of {} failed", args.input.display()))?;
        let json = if args.json {
            let path = summary
                .files
                .iter()
                .find(|p| p.extension().is_some_and(|e| e == "json"))
                .context("the bake wrote no datasheet JSON")?;
            Some(std::fs::read_to_string(path)?)
        } else {
            None
        };
        return Ok(ReportSummary {
            files: summary.files,
            json,
        });
    }
    let photometry = super::input::read_photometry(&args.input)?;
    for w in photometry.consistency_warnings() {
        eprintln!("warning: {}: {w}", args.input.display());
    }
    let source = args
        .input
        .file_name()
        .map_or(String::new(), |n| n.to_string_lossy().into_owned());
    let sheet = Datasheet::new(&photometry, &args.sheet.options(source))
        .with_context(|| format!("no datasheet for {}", args.input.display()))?;
    let rendered = sheet.render()?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create output directory {}", args.out.display()))?;
    let files = rendered.files(&sheet, &args.out, &format!("{stem}_datasheet"));
    lucerna_scene::io::write_all_atomically(&files)
        .map_err(|(path, e)| anyhow::anyhow!("cannot write {}: {e}", path.display()))?;
    Ok(ReportSummary {
        files: files.into_iter().map(|(p, _)| p).collect(),
        json: args.json.then(|| sheet.json()),
    })
}
