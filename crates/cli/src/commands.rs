//! The subcommands, each a thin layer over a library call.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::{Parser, Subcommand};

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
    /// Load, validate and tessellate a luminaire scene; print its parts,
    /// triangles, bounding box and materials.
    Validate {
        scene: PathBuf,
        /// Print the report as JSON.
        #[arg(long)]
        json: bool,
    },
}

pub fn run(cli: Cli) -> Result<()> {
    match cli.command {
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
    }
}
