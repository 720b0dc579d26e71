//! `lucerna-editor [SCENE.toml]`: the editor's window (also reached through
//! `lucerna edit`). Prints the error chain as `lucerna` does.

use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    let scene = std::env::args_os().nth(1).map(PathBuf::from);
    match lucerna_editor::run(scene) {
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
