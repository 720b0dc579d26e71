//! `lucerna merge`: the parts of a split bake summed into the bake's
//! files.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use anyhow::{Context, Result};
use lucerna_simulation::{Luminaire, part, snapshot_of_map};

use super::bake;
use super::part_bake::{check_scene_unchanged, expand_part_paths, stored_bake_args};

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
    check_scene_unchanged(first, manifest, &scene_path, &scene)?;
    let stored = stored_bake_args(first, manifest, &scene_path, &args.out)?;
    let settings = bake::checked_settings(&stored)?;
    if merged.backends.len() > 1 {
        eprintln!(
            "note: the parts were traced on several backends ({}): the merged map is a valid \
             run, but not bit for bit the one-machine run of either",
            merged.backends.join("; ")
        );
    }
    let luminaire = Luminaire::new(scene, scene_path.parent().unwrap_or(Path::new(".")))?;
    bake::describe_symmetry(&luminaire, &settings);
    let photons = merged.map.photons_emitted;
    eprintln!(
        "merged {} parts: {photons} photons, {:.1} s of tracing in all",
        paths.len(),
        merged.wall_seconds
    );
    let snapshot = snapshot_of_map(Arc::new(luminaire), settings, merged.map)?;
    let files = bake::export(&stored, &snapshot)?;
    Ok(MergeSummary {
        files,
        parts: paths.len(),
        photons,
        seconds: started.elapsed().as_secs_f64(),
    })
}
