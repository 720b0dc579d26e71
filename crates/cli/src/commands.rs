//! The subcommands, each a thin layer over a library call.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};

mod bake;
mod bake_run;
mod bench;
mod convert;
mod design;
mod edit;
mod export_geometry;
mod filter_bench;
mod info;
mod input;
mod live_bench;
mod merge;
mod near_field;
mod part_bake;
mod ray_bench;
mod ray_info;
pub use part_bake::Interrupted;
mod render;
mod report;
mod split_bench;
mod tolerance;
mod validate;

#[derive(Debug, Parser)]
#[command(
    name = "lucerna",
    version,
    about = "Luminaire development: scenes, photometry files, bakes"
)]
pub struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Open the editor's window (the `lucerna-editor` binary installed
    /// beside this one) on a scene.
    Edit { scene: Option<PathBuf> },
    /// Load, validate and tessellate a luminaire scene; print its parts,
    /// triangles, bounding box and materials.
    Validate {
        scene: PathBuf,
        /// Print the report as JSON.
        #[arg(long)]
        json: bool,
    },
    /// Describe an IES or EULUMDAT file: format, symmetry, grids, flux,
    /// peak, beam and field angles, LOR, luminous dimensions; or a TM-25
    /// ray file: its header, rays, flux, source extent and the far-field
    /// figures of its rays.
    Info {
        file: PathBuf,
        /// Print the report as JSON.
        #[arg(long)]
        json: bool,
    },
    /// The photometric datasheet of an IES or EULUMDAT file, or of a
    /// scene baked first: A4 HTML and PDF (luminaire data, polar,
    /// cartesian and isocandela diagrams, zonal lumens, CIE flux code,
    /// cone diagram, luminance table, BUG, the CIE 190 UGR table) and
    /// every figure as JSON.
    Report(report::ReportArgs),
    /// Shape a luminaire toward the light wanted (an IES/LDT file or a
    /// spec), with the photon tracer in the loop: writes the designed
    /// scene, its IES and LDT, design.csv and design.png.
    Design(design::DesignArgs),
    /// Will the luminaire that is built meet its spec? Perturbed
    /// luminaires (placements, shape parameters, form and slope errors)
    /// traced with the nominal's photons: the yield with its 95 %
    /// interval, each figure's spread, what drives it, the worst sample.
    Tolerance(tolerance::ToleranceArgs),
    /// The luminaire's parts for CAD and mesh tools: STEP (AP214) with the
    /// exact surfaces (profiles revolved and extruded, planes), binary
    /// STL and OBJ of the traced triangles; millimetres, light towards
    /// −z, C0 along +x. Written all or none.
    ExportGeometry(export_geometry::ExportGeometryArgs),
    /// Trace a luminaire and write IES (LM-63-2019), LDT, the raw map as
    /// EXR, a false-colour cube map PNG and a polar diagram PNG.
    ///
    /// Split over a cluster: `--part K/N` (or `auto` under Slurm or
    /// Kubernetes) traces one part of the run's photons as a partial map,
    /// `--checkpoint 5m` writes the photons so far that often, `--resume
    /// DIR` goes on from the last checkpoint.
    Bake(bake::BakeArgs),
    /// Sum the parts of a split bake (`lucerna bake --part K/N`) exactly
    /// and write the bake's files: the same bytes as the bake on one
    /// machine. Checks that the parts are of one run, each once, and
    /// names any photons missing.
    Merge(merge::MergeArgs),
    /// What a split bake costs besides tracing: writing a partial map (a
    /// checkpoint) and merging N parts, on maps as dense as a final
    /// bake's parts.
    SplitBench(split_bench::SplitBenchArgs),
    /// How fast a TM-25 ray file of makers' size (20 M rays) reads and
    /// writes, rays/s and MB/s, and the memory it takes.
    RayFileBench(ray_bench::RayFileBenchArgs),
    /// Measure photons/s, rays/s and bounces per photon of every example on
    /// every available backend, and BVH build times.
    Bench(bench::BenchArgs),
    /// Evaluate the pull-push filter: RMSE against a reference for raw,
    /// fixed and automatic thresholds over photon counts (CSV + PNG), and
    /// filter timings.
    FilterBench(filter_bench::FilterBenchArgs),
    /// What a live preview pays per snapshot: candela table and figures
    /// (first and cached) and the automatic filter's live path, amortised.
    LiveBench(live_bench::LiveBenchArgs),
    /// Light a room with photometric profiles (cubature + LTC) and write a
    /// PNG view, the work-plane lux grid and Emin/Eavg/Emax/U0.
    Render(render::RenderArgs),
    /// The near-field evaluation of the cubature paper (section 6,
    /// Figure 10) on our profiles: NRMS per profile and height against
    /// Monte Carlo, CSV and pictures.
    NearFieldEval(near_field::NearFieldArgs),
    /// Frame times of the room renderer for 1, 4 and 16 luminaires, next
    /// to the point-light baseline, per backend.
    RenderBench(render::RenderBenchArgs),
    /// Convert between IES (LM-63-2002, LM-63-2019) and EULUMDAT, keeping
    /// the metadata both formats hold; or a TM-25 ray file's far field to
    /// IES or EULUMDAT.
    Convert {
        input: PathBuf,
        /// The file to write; by default INPUT with the extension of
        /// `--to`.
        output: Option<PathBuf>,
        /// Output format; by default from OUTPUT's extension (.ies → 2019).
        #[arg(long, value_enum)]
        to: Option<convert::OutFormat>,
        /// Resample onto equal C-plane steps of this many degrees (linear
        /// interpolation), e.g. 5 or 15.
        #[arg(long)]
        resample_c: Option<f64>,
    },
}

pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
        Command::Edit { scene } => edit::edit(scene.as_deref()),
        Command::Validate { scene, json } => {
            let report = validate::report(&scene)
                .with_context(|| format!("scene {} is not usable", scene.display()))?;
            if json {
                println!("{}", serde_json::to_string_pretty(&report)?);
            } else {
                print!("{report}");
            }
            Ok(())
        }
        Command::RayFileBench(args) => ray_bench::ray_file_bench(&args),
        Command::ExportGeometry(args) => export_geometry::export_geometry(&args),
        Command::Render(args) => render::render(&args),
        Command::RenderBench(args) => render::render_bench(&args),
        Command::NearFieldEval(args) => near_field::near_field_eval(&args),
        Command::Info { file, json } if input::is_ray_file(&file) => {
            let report = ray_info::report(&file)?;
            if json {
                println!("{}", serde_json::to_string_pretty(&report)?);
            } else {
                print!("{report}");
            }
            Ok(())
        }
        Command::Info { file, json } => {
            let report = info::report(&file)?;
            if json {
                println!("{}", serde_json::to_string_pretty(&report)?);
            } else {
                print!("{report}");
            }
            Ok(())
        }
        Command::Bake(args) => {
            let what = match (&args.scene, &args.resume) {
                (Some(scene), _) => format!("bake of {}", scene.display()),
                (None, Some(dir)) => format!("resumed bake in {}", dir.display()),
                (None, None) => "bake".to_owned(),
            };
            let summary = bake::bake(&args).with_context(|| format!("{what} failed"))?;
            if summary.interrupted {
                println!("interrupted: writing what was traced");
            }
            println!(
                "{} photons traced in {:.1} s ({:.2} M photons/s)",
                summary.photons,
                summary.seconds,
                summary.photons as f64 / summary.seconds.max(1e-9) / 1e6
            );
            for f in &summary.files {
                println!("wrote {}", f.display());
            }
            Ok(())
        }
        Command::Merge(args) => {
            let summary = merge::merge(&args).context("merge failed")?;
            println!(
                "{} parts merged: {} photons, in {:.2} s",
                summary.parts, summary.photons, summary.seconds
            );
            for f in &summary.files {
                println!("wrote {}", f.display());
            }
            Ok(())
        }
        Command::Report(args) => {
            let summary = report::report(&args)
                .with_context(|| format!("no datasheet of {}", args.input.display()))?;
            if let Some(json) = &summary.json {
                println!("{json}");
            } else {
                for f in &summary.files {
                    println!("wrote {}", f.display());
                }
            }
            Ok(())
        }
        Command::Design(args) => design::design(&args),
        Command::Tolerance(args) => tolerance::tolerance(&args),
        Command::Bench(args) => bench::bench(&args),
        Command::SplitBench(args) => split_bench::split_bench(&args),
        Command::LiveBench(args) => live_bench::live_bench(&args),
        Command::FilterBench(args) => filter_bench::filter_bench(&args),
        Command::Convert {
            input,
            output,
            to,
            resample_c,
        } => {
            let output = match (output, to) {
                (Some(o), _) => o,
                (None, Some(to)) => input.with_extension(to.extension()),
                (None, None) => anyhow::bail!(
                    "name the output file, or give --to ies|ies2002|ldt to write beside the input"
                ),
            };
            println!("{}", convert::convert(&input, &output, to, resample_c)?);
            Ok(())
        }
    }
}
