//! `lucerna-editor [--benchmark SECONDS [--continuous]] [SCENE.toml]`: the editor's window
//! (also reached through `lucerna edit`). Prints the error chain as
//! `lucerna` does.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

fn main() -> ExitCode {
    let mut args = std::env::args_os().skip(1);
    let mut scene = None;
    let mut benchmark = None;
    let mut continuous = false;
    while let Some(arg) = args.next() {
        if arg == "--benchmark" {
            let seconds = args
                .next()
                .and_then(|s| s.to_str().and_then(|s| s.parse::<f64>().ok()))
                .filter(|s| s.is_finite() && (1.0..=3600.0).contains(s));
            match seconds {
                Some(s) => benchmark = Some(Duration::from_secs_f64(s)),
                None => {
                    eprintln!("error: --benchmark takes a duration in seconds (1 to 3600)");
                    return ExitCode::FAILURE;
                }
            }
        } else if arg == "--continuous" {
            continuous = true;
        } else if scene.is_none() {
            scene = Some(PathBuf::from(arg));
        } else {
            eprintln!("usage: lucerna-editor [--benchmark SECONDS [--continuous]] [SCENE.toml]");
            return ExitCode::FAILURE;
        }
    }
    match lucerna_editor::run(scene, benchmark.map(|d| (d, continuous))) {
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
