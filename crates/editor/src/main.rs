//! `lucerna-editor [--view NAME] [--benchmark SECONDS [--continuous]]
//! [SCENE.toml]`: the editor's window (also reached through `lucerna
//! edit`). Prints the error chain as `lucerna` does.

use std::path::PathBuf;
use std::process::ExitCode;
use std::time::Duration;

use lucerna_editor::{RunOptions, View};

const USAGE: &str = "usage: lucerna-editor [--view polar|cartesian|isocandela|cube|figures|room] \
                     [--benchmark SECONDS [--continuous]] [SCENE.toml]";

fn parse() -> Result<RunOptions, String> {
    let mut options = RunOptions::default();
    let mut args = std::env::args_os().skip(1);
    while let Some(arg) = args.next() {
        if arg == "--benchmark" {
            let seconds = args
                .next()
                .and_then(|s| s.to_str().and_then(|s| s.parse::<f64>().ok()))
                .filter(|s| s.is_finite() && (1.0..=3600.0).contains(s))
                .ok_or("--benchmark takes a duration in seconds (1 to 3600)")?;
            options.benchmark = Some(Duration::from_secs_f64(seconds));
        } else if arg == "--continuous" {
            options.continuous = true;
        } else if arg == "--view" {
            options.view = match args.next().as_ref().and_then(|s| s.to_str()) {
                Some("polar") => View::Polar,
                Some("cartesian") => View::Cartesian,
                Some("isocandela") => View::Isocandela,
                Some("cube") => View::CubeMap,
                Some("figures") => View::Figures,
                Some("room") => View::Room,
                _ => return Err(USAGE.to_owned()),
            };
        } else if options.scene.is_none() && !arg.to_string_lossy().starts_with("--") {
            options.scene = Some(PathBuf::from(arg));
        } else {
            return Err(USAGE.to_owned());
        }
    }
    Ok(options)
}

fn main() -> ExitCode {
    let options = match parse() {
        Ok(options) => options,
        Err(message) => {
            eprintln!("error: {message}");
            return ExitCode::FAILURE;
        }
    };
    match lucerna_editor::run(options) {
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
