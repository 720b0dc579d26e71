//! `lucerna bake`: trace a luminaire headlessly and write its photometry.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use anyhow::{Context, Result, bail};
use indicatif::{ProgressBar, ProgressStyle};
use lucerna_photometry::{
    AxialSymmetry, CubeMapLayout, IesVersion, IntensityMap, Symmetry, TexelSymmetry, to_latin1,
    write_ies, write_ldt,
};
use lucerna_scene::{Scene, TessellatedScene, load_scene, tessellate, write_atomically};
use lucerna_tracer::export::{ExportOptions, photometry_from_candela};
use lucerna_tracer::{
    BackendRequest, PreparedScene, Session, TraceSettings, choose_backend, luminaire_symmetry,
};

/// Which tracer runs the bake.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum Backend {
    /// The WGSL kernel on a GPU adapter.
    Gpu,
    /// The native CPU tracer.
    Cpu,
    /// A hardware GPU if there is one, else the CPU tracer.
    Auto,
}

/// Symmetry to impose on the baked table.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum SymmetryArg {
    None,
    Rotational,
    Quadrant,
    C0C180,
    C90C270,
}

/// Whether photons are pooled over the luminaire's symmetry.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum PoolSymmetry {
    /// The symmetry found in the luminaire's geometry.
    Auto,
    /// No pooling.
    None,
}

#[derive(Debug, clap::Args)]
pub struct BakeArgs {
    /// The luminaire scene (TOML).
    pub scene: PathBuf,
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
    #[arg(long, value_enum, default_value_t = Backend::Auto)]
    pub backend: Backend,
    /// Surface interactions after which a photon is cut off.
    #[arg(long, default_value_t = 64)]
    pub max_bounces: u32,
    /// C-plane spacing of the exported table (degrees).
    #[arg(long, default_value_t = 5.0)]
    pub c_step: f64,
    /// γ spacing of the exported table (degrees); by default 2.5°, refined
    /// until the table holds the traced flux within 0.5 % (narrow beams).
    #[arg(long)]
    pub gamma_step: Option<f64>,
    /// Average the exported table over a symmetry the user imposes (even
    /// one the geometry lacks, such as rotational), and declare it in the
    /// files. By default the files declare what the photons were pooled
    /// over (`--symmetry`): quadrant or one mirror plane, where the formats
    /// can say it.
    #[arg(long, value_enum, default_value_t = SymmetryArg::None)]
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
    #[arg(long, default_value = "none", value_parser = parse_filter)]
    pub filter: FilterChoice,
    /// Output directory (created if needed).
    #[arg(long)]
    pub out: PathBuf,
}

/// Raw map (`None`) or the filter with a threshold.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FilterChoice(pub Option<lucerna_filter::Threshold>);

/// `none`, `auto` or a photon threshold.
pub fn parse_filter(s: &str) -> Result<FilterChoice, String> {
    match s {
        "none" => Ok(FilterChoice(None)),
        "auto" => Ok(FilterChoice(Some(lucerna_filter::Threshold::Automatic))),
        _ => match s.parse::<f64>() {
            Ok(t) if t.is_finite() && (1.0..=1e9).contains(&t) => {
                Ok(FilterChoice(Some(lucerna_filter::Threshold::Fixed(t))))
            }
            _ => Err(format!("'{s}' is not none, auto or a photon threshold ≥ 1")),
        },
    }
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

fn check(args: &BakeArgs) -> Result<()> {
    if !(8..=2048).contains(&args.resolution) {
        bail!(
            "--resolution must be between 8 and 2048 texels per face edge, got {}",
            args.resolution
        );
    }
    if let Some(p) = args.photons
        && p == 0
    {
        bail!("--photons must be at least 1");
    }
    if let Some(e) = args.rel_error
        && !(e > 0.0 && e < 1.0)
    {
        bail!("--rel-error must be between 0 and 1, got {e}");
    }
    if !(1..=100_000).contains(&args.max_bounces) {
        bail!(
            "--max-bounces must be between 1 and 100000, got {}",
            args.max_bounces
        );
    }
    for (name, v) in [
        ("--c-step", Some(args.c_step)),
        ("--gamma-step", args.gamma_step),
    ] {
        let Some(v) = v else { continue };
        if !(v > 0.0 && v <= 90.0 && (180.0 / v).fract().abs() < 1e-9) {
            bail!("{name} must divide 180° evenly (e.g. 1, 2.5, 5, 10), got {v}");
        }
    }
    Ok(())
}

/// A luminaire scene loaded, tessellated and prepared for tracing.
pub fn load_luminaire(path: &Path) -> Result<(Scene, TessellatedScene, PreparedScene)> {
    let scene = load_scene(path)?;
    let dir = path.parent().unwrap_or(Path::new("."));
    let tessellated = tessellate(&scene, dir)?;
    let prepared = PreparedScene::new(&scene, &tessellated, dir)?;
    Ok((scene, tessellated, prepared))
}

/// The symmetry the photons are pooled over, with a line saying which.
pub fn pooling_symmetry(
    choice: PoolSymmetry,
    scene: &Scene,
    tessellated: &TessellatedScene,
    layout: CubeMapLayout,
) -> TexelSymmetry {
    let symmetry = match choice {
        PoolSymmetry::None => AxialSymmetry::None,
        PoolSymmetry::Auto => {
            let found = luminaire_symmetry(scene, tessellated);
            if let Some(why) = &found.limited_by {
                eprintln!("symmetry: {why}");
            }
            found.symmetry
        }
    };
    if symmetry != AxialSymmetry::None {
        eprintln!(
            "symmetry: {symmetry}: each photon counted in its {} images",
            symmetry.order()
        );
    }
    TexelSymmetry::new(layout, symmetry)
}

/// The map's candela per texel as exported: raw, or filtered (with a line
/// on what the filter did); both pooled over `symmetry`.
pub fn exported_candela(
    map: &IntensityMap,
    filter: FilterChoice,
    symmetry: &TexelSymmetry,
) -> Vec<f64> {
    match filter.0 {
        Some(threshold) => {
            let settings = lucerna_filter::FilterSettings {
                threshold,
                ..Default::default()
            };
            let (candela, report) = lucerna_filter::filter_map(map, &settings, symmetry);
            eprintln!(
                "filtered: {}{}, {} of {} texels replaced, renormalised by {:.4}",
                report.settings,
                if threshold == lucerna_filter::Threshold::Automatic {
                    " (chosen by cross-validation)"
                } else {
                    ""
                },
                report.replaced.iter().filter(|&&r| r).count(),
                report.replaced.len(),
                report.renormalisation
            );
            if let Some(a) = report.automatic {
                eprintln!(
                    "estimated error of the exported map (RMSE per texel / mean, cross-validated): {:.1} % filtered, {:.1} % raw",
                    100.0 * a.estimated_rmse,
                    100.0 * a.raw_estimated_rmse
                );
            }
            candela
        }
        None => map.symmetrised(symmetry).candela(),
    }
}

pub fn bake(args: &BakeArgs) -> Result<BakeSummary> {
    check(args)?;
    let (scene, tessellated, prepared) = load_luminaire(&args.scene)?;
    let settings = TraceSettings {
        seed: args.seed,
        max_bounces: args.max_bounces,
        layout: CubeMapLayout::new(args.resolution),
    };
    let limit = match (args.photons, args.time, args.rel_error) {
        (None, None, None) => Some(10_000_000),
        (p, _, _) => p,
    };
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create output directory {}", args.out.display()))?;

    let stop = Arc::new(AtomicBool::new(false));
    {
        let stop = stop.clone();
        // A second handler cannot be set (tests run bakes in one process):
        // then Ctrl+C simply ends the process.
        let _ = ctrlc::set_handler(move || stop.store(true, Ordering::SeqCst));
    }
    let request = match args.backend {
        Backend::Gpu => BackendRequest::Gpu,
        Backend::Cpu => BackendRequest::Cpu,
        Backend::Auto => BackendRequest::Auto,
    };
    let (backend, choice) = choose_backend(request, &prepared, &settings)?;
    eprintln!("tracing on the {} ({})", backend.describe(), choice.reason);
    let symmetry = pooling_symmetry(args.symmetry, &scene, &tessellated, settings.layout);
    let mut session = Session::with_backend(prepared, settings, backend);
    // The reported (and --rel-error's) peak error is the pooled map's.
    session.pool_over(symmetry.symmetry);
    let bar = match limit {
        Some(n) => ProgressBar::new(n),
        None => ProgressBar::new_spinner(),
    };
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} [{elapsed_precise}] {bar:30} {human_pos} photons ({per_sec}, ETA {eta}) {msg}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    let start = Instant::now();
    let mut interrupted = false;
    loop {
        let done = session.map().photons_emitted;
        let remaining = limit.map_or(u64::MAX, |l| l.saturating_sub(done));
        if remaining == 0 {
            break;
        }
        if args.time.is_some_and(|t| start.elapsed() >= t) {
            break;
        }
        if stop.load(Ordering::SeqCst) {
            interrupted = true;
            break;
        }
        let report = session.iterate_at_most(remaining)?;
        bar.set_position(report.photons_total);
        bar.set_message(format!(
            "{:.2} M rays/s, {:.2} bounces, peak ±{:.2} %, flux ±{:.3} %",
            report.rays_per_second / 1e6,
            report.mean_bounces,
            100.0 * report.peak_relative_error,
            100.0 * report.flux_relative_error
        ));
        if args
            .rel_error
            .is_some_and(|e| report.peak_relative_error <= e)
        {
            break;
        }
    }
    bar.finish();
    let map = session.snapshot();
    let seconds = start.elapsed().as_secs_f64();
    let date = chrono::Local::now().format("%Y-%m-%d").to_string();
    let stem = args
        .scene
        .file_stem()
        .map_or("luminaire".to_owned(), |s| s.to_string_lossy().into_owned());
    let candela = exported_candela(&map, args.filter, &symmetry);
    let options = ExportOptions {
        c_step_deg: args.c_step,
        gamma_step_deg: args.gamma_step,
        symmetrise: match args.symmetrise {
            // A pooled map is exactly symmetric: the files say so (and
            // store only the C-planes the symmetry needs).
            SymmetryArg::None => {
                Some(symmetry.symmetry.file_symmetry()).filter(|&s| s != Symmetry::None)
            }
            SymmetryArg::Rotational => Some(Symmetry::Rotational),
            SymmetryArg::Quadrant => Some(Symmetry::Quadrant),
            SymmetryArg::C0C180 => Some(Symmetry::AboutC0C180),
            SymmetryArg::C90C270 => Some(Symmetry::AboutC90C270),
        },
        date: date.clone(),
        seed: args.seed,
        scene_file: args
            .scene
            .file_name()
            .map_or(String::new(), |s| s.to_string_lossy().into_owned()),
    };
    let photometry = photometry_from_candela(
        &map,
        &candela,
        &scene,
        &tessellated,
        &options,
        &mut lucerna_photometry::resample::TableResampler::new(),
    );
    // cd/klm of the lamp (emitter) flux, as in the LDT; validation keeps
    // the flux > 0.
    let per_klm = 1000.0 / map.emitter_flux_lm;
    let title = format!("{} - {} photons", scene.name, map.photons_emitted);
    let outputs: Vec<(String, Vec<u8>)> = vec![
        (
            format!("{stem}.ies"),
            write_ies(&photometry, IesVersion::Lm63_2019).into_bytes(),
        ),
        (format!("{stem}.ldt"), to_latin1(&write_ldt(&photometry))),
        (
            format!("{stem}.exr"),
            lucerna_pictures::intensity_map_exr(
                &map,
                &[
                    ("lucernaSeed", args.seed.to_string()),
                    ("lucernaScene", scene.name.clone()),
                    ("lucernaDate", date),
                ],
            )?,
        ),
        (
            format!("{stem}_cube.png"),
            lucerna_pictures::cube_map_png(map.layout, &candela, 200, &title)?,
        ),
        (
            format!("{stem}_polar.png"),
            lucerna_pictures::polar_png(&photometry.table, per_klm, 640, &title)?,
        ),
    ];
    let mut files = Vec::new();
    for (name, bytes) in outputs {
        let path = args.out.join(name);
        write_atomically(&path, &bytes)
            .with_context(|| format!("cannot write {}", path.display()))?;
        files.push(path);
    }
    Ok(BakeSummary {
        files,
        photons: map.photons_emitted,
        seconds,
        interrupted,
    })
}
