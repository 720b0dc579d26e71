//! `lucerna-fuzz`: a long mutation campaign over every file Lucerna reads;
//! findings are written to a folder, a case per sub-folder.

use std::path::PathBuf;

use anyhow::{Context, Result};
use clap::Parser;
use lucerna_fuzz::{Target, campaign};

#[derive(Debug, Parser)]
#[command(
    name = "lucerna-fuzz",
    about = "Mutation fuzzing of IES/LDT, scene and room files"
)]
struct Args {
    /// photometry, scene, room, rayfile or all.
    #[arg(long, default_value = "all")]
    target: String,
    /// Mutated inputs per target.
    #[arg(long, default_value_t = 100_000)]
    inputs: usize,
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Where findings are written.
    #[arg(long, default_value = "target/fuzz-findings")]
    findings: PathBuf,
}

fn main() -> Result<()> {
    let args = Args::parse();
    let targets: Vec<Target> = match args.target.as_str() {
        "all" => Target::ALL.to_vec(),
        name => vec![
            Target::ALL
                .into_iter()
                .find(|t| t.name() == name)
                .with_context(|| {
                    format!("unknown target '{name}' (photometry, scene, room, rayfile, all)")
                })?,
        ],
    };
    // Panics are findings here: keep their messages off the console.
    std::panic::set_hook(Box::new(|_| {}));
    let mut total = 0;
    for target in targets {
        let start = std::time::Instant::now();
        let findings = campaign(target, args.inputs, args.seed);
        println!(
            "{}: {} inputs in {:.1} s, {} findings",
            target.name(),
            args.inputs,
            start.elapsed().as_secs_f64(),
            findings.len()
        );
        for (k, f) in findings.iter().enumerate() {
            let dir = args
                .findings
                .join(target.name())
                .join(format!("{}-{k}", args.seed));
            for (name, bytes) in &f.files {
                let path = dir.join(name);
                if let Some(parent) = path.parent() {
                    std::fs::create_dir_all(parent)?;
                }
                std::fs::write(&path, bytes)?;
            }
            std::fs::write(dir.join("FINDING.txt"), &f.what)?;
            println!(
                "  {}: {}",
                dir.display(),
                f.what.lines().next().unwrap_or("")
            );
        }
        total += findings.len();
    }
    if total > 0 {
        anyhow::bail!("{total} findings");
    }
    Ok(())
}
