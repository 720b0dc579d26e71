//! `lucerna-editor [SCENE.toml]`: the editor's window (also reached through
//! `lucerna edit`), and its benchmarks. Prints the error chain as `lucerna`
//! does.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use clap::Parser;
use lucerna_editor::{BenchmarkOptions, RunOptions, View};

/// The Lucerna editor: model a luminaire, watch its light distribution
/// converge, see a room lit by it, export IES and EULUMDAT files.
#[derive(Debug, Parser)]
#[command(name = "lucerna-editor", version)]
struct Args {
    /// The scene file to open.
    scene: Option<PathBuf>,
    /// The photometric view shown first.
    #[arg(long, value_enum, default_value_t = View::Polar)]
    view: View,
    /// Run the frame-time benchmark for SECONDS (a scripted edit every
    /// 2 s), print its figures and close.
    #[arg(long, value_name = "SECONDS", value_parser = seconds, conflicts_with = "benchmark_drag")]
    benchmark: Option<Duration>,
    /// In the frame-time benchmark, repaint every frame (as while
    /// dragging).
    #[arg(long, requires = "benchmark")]
    continuous: bool,
    /// In the frame-time benchmark, export the current run again and
    /// again (every file, the automatic filter, into a temporary folder)
    /// instead of editing, and report the longest frame while one runs.
    #[arg(long, requires = "benchmark")]
    export: bool,
    /// Run the drag benchmark: drag the main part's main parameter for
    /// SECONDS, one change a frame, then release; print preview age,
    /// previews per second, release to full resolution, frame interval.
    #[arg(long, value_name = "SECONDS", value_parser = seconds)]
    benchmark_drag: Option<Duration>,
}

fn seconds(s: &str) -> Result<Duration, String> {
    s.parse::<f64>()
        .ok()
        .filter(|s| s.is_finite() && (1.0..=3600.0).contains(s))
        .map(Duration::from_secs_f64)
        .ok_or_else(|| format!("'{s}' is not a duration in seconds (1 to 3600)"))
}

fn main() -> ExitCode {
    let args = Args::parse();
    let export_into = args.export.then(|| {
        std::env::temp_dir().join(format!("lucerna-benchmark-export-{}", std::process::id()))
    });
    let options = RunOptions {
        scene: args.scene,
        view: args.view,
        benchmark: match (args.benchmark, args.benchmark_drag) {
            (Some(duration), _) => Some(BenchmarkOptions::Frames {
                duration,
                continuous: args.continuous,
                export_into: export_into.clone(),
            }),
            (None, Some(duration)) => Some(BenchmarkOptions::Drag { duration }),
            (None, None) => None,
        },
    };
    let result = lucerna_editor::run(options);
    if let Some(dir) = export_into {
        let _ = std::fs::remove_dir_all(dir);
    }
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            let mut source = std::error::Error::source(&e);
            while let Some(cause) = source {
                eprintln!("  caused by: {cause}");
                source = cause.source();
            }
            ExitCode::FAILURE
        }
    }
}
