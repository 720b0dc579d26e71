//! `lucerna split-bench`: what splitting a bake costs besides tracing —
//! writing a partial map (each checkpoint, and each part's end) and
//! merging N of them — on maps as dense as a final bake's parts.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::{Duration, Instant};

use anyhow::{Context, Result};
use lucerna_photometry::{CubeMapLayout, IntensityMap};
use lucerna_simulation::part::{
    self, SceneIdentity, TraceIdentity, manifest_file_name, new_manifest,
};
use lucerna_simulation::{Luminaire, PartSpec};

use super::bake::parse_duration;

#[derive(Debug, clap::Args)]
pub struct SplitBenchArgs {
    /// Parts to merge.
    #[arg(long, default_value_t = 64)]
    pub parts: u32,
    /// Texels per cube-face edge of the parts.
    #[arg(long, default_value_t = 1024)]
    pub resolution: u32,
    /// Mean escaped photons per texel of one part: a 10¹¹-photon bake at
    /// 1024² in 64 parts has about 250.
    #[arg(long, default_value_t = 250)]
    pub mean_count: u64,
    /// The checkpoint interval the overhead is given for.
    #[arg(long, default_value = "5m", value_parser = parse_duration)]
    pub interval: Duration,
    /// Folder for the parts (default: a temporary one, removed after).
    #[arg(long)]
    pub dir: Option<PathBuf>,
}

/// Counts of a part: exponentially distributed about `mean` (a beam's
/// few bright texels and a long dim tail), from a fixed hash so every run
/// writes the same files.
fn synthetic_map(
    layout: CubeMapLayout,
    mean: u64,
    part: u32,
    photons: u64,
    flux: f64,
) -> IntensityMap {
    let mut map = IntensityMap::new(layout, flux);
    for (i, c) in map.counts.iter_mut().enumerate() {
        let mut h = (i as u64) ^ (u64::from(part) << 40) ^ 0x9e37_79b9_7f4a_7c15;
        h = (h ^ (h >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        h = (h ^ (h >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        h ^= h >> 31;
        let u = ((h >> 11) as f64 + 0.5) / (1u64 << 53) as f64;
        *c = (-(u.ln()) * mean as f64) as u64;
    }
    let escaped: u64 = map.counts.iter().sum();
    // Every photon escaped or absorbed (an exponential sum stays far
    // below the callers' 1.25 × the mean; should it not, all escaped).
    map.photons_emitted = photons.max(escaped);
    map.photons_absorbed = map.photons_emitted - escaped;
    map
}

pub fn split_bench(args: &SplitBenchArgs) -> Result<()> {
    anyhow::ensure!(
        (1..=4096).contains(&args.parts) && (1..=2048).contains(&args.resolution),
        "--parts must be 1 to 4096 and --resolution 1 to 2048"
    );
    anyhow::ensure!(
        (1..=1_000_000).contains(&args.mean_count),
        "--mean-count must be 1 to 1 000 000"
    );
    let scene_path = super::bench::example_scenes(&[])?
        .into_iter()
        .next()
        .context("no example scene")?;
    let luminaire = Arc::new(Luminaire::load(&scene_path)?);
    let scene = SceneIdentity::of(&scene_path, &luminaire.scene)?;
    let flux = luminaire.prepared.total_flux_lm;
    let temp;
    let dir = match &args.dir {
        Some(d) => {
            std::fs::create_dir_all(d)?;
            d.clone()
        }
        None => {
            temp = tempfile::tempdir()?;
            temp.path().to_path_buf()
        }
    };
    let layout = CubeMapLayout::new(args.resolution);
    // Photons per part: more than the escaped ones with room to spare.
    let per_part = (args.mean_count * layout.texel_count() as u64) * 5 / 4 + 1000;
    let total = per_part * u64::from(args.parts);
    let trace = TraceIdentity {
        resolution: args.resolution,
        seed: 1,
        max_bounces: 64,
        photons_total: total,
        parts: args.parts,
        emitter_flux_lm: flux,
    };
    println!(
        "{} parts of {}² per face ({} texels), {} escaped photons per texel on average",
        args.parts,
        args.resolution,
        layout.texel_count(),
        args.mean_count
    );
    let job = lucerna_simulation::BakeJob::new(&scene_path, &dir);
    let mut paths = Vec::new();
    let mut write_seconds = Vec::new();
    let mut bytes = 0u64;
    for k in 1..=args.parts {
        let spec = PartSpec::new(k, args.parts)?;
        let map = synthetic_map(layout, args.mean_count, k, spec.range(total).len(), flux);
        let mut manifest = new_manifest(scene.clone(), trace, job.clone(), spec, "cpu", false);
        let path = dir.join(manifest_file_name("bench", spec));
        let t = Instant::now();
        part::write_part(&path, &mut manifest, &map)?;
        write_seconds.push(t.elapsed().as_secs_f64());
        bytes += manifest.counts.bytes;
        paths.push(path);
    }
    write_seconds.sort_by(f64::total_cmp);
    let median_write = write_seconds[write_seconds.len() / 2];
    println!(
        "write of one part (a checkpoint): median {:.1} ms, max {:.1} ms; {:.1} MB per part ({:.2} bytes per texel)",
        1e3 * median_write,
        1e3 * write_seconds.last().copied().unwrap_or(0.0),
        bytes as f64 / f64::from(args.parts) / 1e6,
        bytes as f64 / f64::from(args.parts) / layout.texel_count() as f64
    );
    let t = Instant::now();
    let merged = part::merge_parts(&paths)?;
    let merge = t.elapsed().as_secs_f64();
    anyhow::ensure!(merged.map.photons_emitted == total && merged.map.is_balanced());
    println!(
        "merge of {} parts: {:.2} s ({:.0} MB/s of counts files, {:.1} ms per part)",
        args.parts,
        merge,
        bytes as f64 / merge / 1e6,
        1e3 * merge / f64::from(args.parts)
    );
    // A checkpoint of the bake's default 256² map too.
    let small = CubeMapLayout::new(256);
    let map = synthetic_map(
        small,
        args.mean_count,
        1,
        small.texel_count() as u64 * args.mean_count * 2,
        flux,
    );
    let spec = PartSpec::WHOLE;
    let trace = TraceIdentity {
        resolution: 256,
        photons_total: map.photons_emitted,
        parts: 1,
        ..trace
    };
    let mut manifest = new_manifest(scene, trace, job, spec, "cpu", false);
    let path = dir.join(manifest_file_name("bench-256", spec));
    let mut small_seconds = Vec::new();
    for _ in 0..9 {
        let t = Instant::now();
        part::write_part(&path, &mut manifest, &map)?;
        small_seconds.push(t.elapsed().as_secs_f64());
    }
    small_seconds.sort_by(f64::total_cmp);
    let median_small = small_seconds[small_seconds.len() / 2];
    let interval = args.interval.as_secs_f64();
    println!(
        "checkpoint overhead every {:.0} s: {:.4} % of the bake at {}², {:.4} % at 256² ({:.1} ms a checkpoint)",
        interval,
        100.0 * median_write / interval,
        args.resolution,
        100.0 * median_small / interval,
        1e3 * median_small
    );
    Ok(())
}
