//! `lucerna`: the headless command line. Parses arguments, calls the
//! library crates, prints the error chain.

mod commands;

use clap::Parser;

fn main() -> std::process::ExitCode {
    // `lucerna validate … | head`: end quietly when the output is closed.
    sigpipe::reset();
    quiet_mesa_device_select();
    let cli = commands::Cli::parse();
    match commands::run(cli) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            for cause in e.chain().skip(1) {
                eprintln!("  caused by: {cause}");
            }
            if e.downcast_ref::<commands::Interrupted>().is_some() {
                std::process::ExitCode::from(commands::Interrupted::EXIT_CODE)
            } else {
                std::process::ExitCode::FAILURE
            }
        }
    }
}

/// Mesa's Vulkan device-select layer prints "XDG_RUNTIME_DIR is invalid"
/// (twice, as an "error") on machines without a session, which reads like
/// a failure of ours; it has a documented switch to stay out of the way.
fn quiet_mesa_device_select() {
    if std::env::var_os("NODEVICE_SELECT").is_none() {
        #[allow(unsafe_code)]
        // SAFETY: called first thing in main, before any other thread
        // exists, so nothing reads the environment concurrently.
        unsafe {
            std::env::set_var("NODEVICE_SELECT", "1");
        }
    }
}
