//! `lucerna ray-file-bench`: how fast a large TM-25 ray file reads (and
//! writes), on a synthetic file of the size makers ship.

use std::time::Instant;

use anyhow::{Context, Result};
use lucerna_photometry::tm25::{RayFileHeader, RaySet, read_ray_file, write_ray_file};

#[derive(Debug, clap::Args)]
pub struct RayFileBenchArgs {
    /// Rays in the synthetic file (20 M rays of 7 values: 560 MB).
    #[arg(long, default_value_t = 20_000_000)]
    pub rays: u64,
}

pub fn ray_file_bench(args: &RayFileBenchArgs) -> Result<()> {
    let n = args.rays;
    let started = Instant::now();
    let mut records = Vec::with_capacity(7 * n as usize);
    for i in 0..n {
        let t = i as f32 * 1e-7;
        records.extend([t.sin(), t.cos(), 0.0, 0.1, 0.2, 1.0, 1.0 / n as f32]);
    }
    let set = RaySet {
        header: RayFileHeader::luminous(n, 1.0),
        records,
        luminous_flux_lm: Vec::new(),
    };
    let made = started.elapsed();
    let dir = tempfile::tempdir().context("cannot make a scratch folder")?;
    let path = dir.path().join("bench.tm25ray");
    let started = Instant::now();
    let bytes = write_ray_file(&set);
    drop(set);
    std::fs::write(&path, &bytes).with_context(|| format!("cannot write {}", path.display()))?;
    let written = started.elapsed();
    let size = bytes.len() as f64;
    drop(bytes);
    let started = Instant::now();
    let read = read_ray_file(&path)?;
    let read_time = started.elapsed();
    let held = (read.records.len() + read.luminous_flux_lm.len()) * 4;
    println!(
        "{n} rays, {:.0} MB file (made in {:.2} s)",
        size / 1e6,
        made.as_secs_f64()
    );
    println!(
        "write  {:.2} s  {:.0} MB/s  {:.1} M rays/s",
        written.as_secs_f64(),
        size / 1e6 / written.as_secs_f64(),
        n as f64 / 1e6 / written.as_secs_f64()
    );
    println!(
        "read   {:.2} s  {:.0} MB/s  {:.1} M rays/s (every ray checked; the file is in the page cache)",
        read_time.as_secs_f64(),
        size / 1e6 / read_time.as_secs_f64(),
        n as f64 / 1e6 / read_time.as_secs_f64()
    );
    println!(
        "held   {:.0} MB: the records once ({:.0} MB) and a luminous flux per ray ({:.0} MB)",
        held as f64 / 1e6,
        read.records.len() as f64 * 4.0 / 1e6,
        read.luminous_flux_lm.len() as f64 * 4.0 / 1e6
    );
    Ok(())
}
