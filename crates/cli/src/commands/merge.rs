//! `lucerna merge`: the parts of a split bake summed into the bake's
//! files.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use anyhow::{Context, Result};
use lucerna_simulation::{Luminaire, part, snapshot_of_map};

use super::bake_run;
use super::part_bake::expand_part_paths;

#[derive(Debug, clap::Args)]
pub struct MergeArgs {
    /// The parts: their manifests (STEM.part-K-of-N.json) or folders
    /// holding them.
    #[arg(required = true)]
    pub parts: Vec<PathBuf>,
    /// Output directory (created if needed) for the bake's files.
    #[arg(long)]
    pub out: PathBuf,
    /// The scene, where it is no longer at the path the parts name (its
    /// files must be the same bytes).
    #[arg(long)]
    pub scene: Option<PathBuf>,
}

/// What the merge wrote.
#[derive(Debug)]
pub struct MergeSummary {
    pub files: Vec<PathBuf>,
    pub parts: usize,
    pub photons: u64,
    pub seconds: f64,
}

pub fn merge(args: &MergeArgs) -> Result<MergeSummary> {
    let started = Instant::now();
    let paths = expand_part_paths(&args.parts)?;
    // Every check before anything is written.
    let merged = part::merge_parts(&paths)?;
    let first = paths.first().map_or(Path::new(""), PathBuf::as_path);
    let manifest = &merged.manifest;
    let scene_path = args
        .scene
        .clone()
        .unwrap_or_else(|| manifest.scene.path.clone());
    let scene = lucerna_scene::load_scene(&scene_path)
        .with_context(|| format!("the scene of {} cannot be loaded", first.display()))?;
    manifest.scene.check_unchanged(first, &scene_path, &scene)?;
    // The bake the parts belong to, written here.
    let mut job = manifest.job.clone();
    job.scene = scene_path.clone();
    job.output.out_dir = args.out.clone();
    job.validate().with_context(|| {
        format!(
            "{}: its stored bake settings are not this Lucerna's",
            first.display()
        )
    })?;
    let settings = job.settings;
    if merged.backends.len() > 1 {
        eprintln!(
            "note: the parts were traced on several backends ({}): the merged map is a valid \
             run, but not bit for bit the one-machine run of either",
            merged.backends.join("; ")
        );
    }
    let luminaire = Luminaire::new(scene, scene_path.parent().unwrap_or(Path::new(".")))?;
    bake_run::describe_symmetry(&luminaire, &settings);
    let photons = merged.map.photons_emitted;
    eprintln!(
        "merged {} parts: {photons} photons, {:.1} s of tracing in all",
        paths.len(),
        merged.wall_seconds
    );
    let snapshot = snapshot_of_map(Arc::new(luminaire), settings, merged.map)?;
    let files = bake_run::export(&job, &snapshot)?;
    Ok(MergeSummary {
        files,
        parts: paths.len(),
        photons,
        seconds: started.elapsed().as_secs_f64(),
    })
}
