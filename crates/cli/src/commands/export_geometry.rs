//! `lucerna export-geometry`: the luminaire's parts to CAD (STEP with
//! exact surfaces) and to mesh tools (STL, OBJ).

use std::path::PathBuf;

use anyhow::{Context, Result};
use lucerna_cad::{GeometryFormat, GeometryRequest, write_geometry};
use lucerna_scene::load_scene;

#[derive(Debug, clap::Args)]
pub struct ExportGeometryArgs {
    scene: PathBuf,
    /// The folder the files go to (created if missing): OUT/STEM.step,
    /// .stl and .obj, STEM the scene file's name.
    #[arg(long)]
    out: PathBuf,
    /// Which files, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "step,stl,obj")]
    formats: Vec<GeometryFormat>,
    /// Only these parts or emitters (names as in the scene),
    /// comma-separated; by default every enabled part and emitter.
    #[arg(long, value_delimiter = ',')]
    parts: Option<Vec<String>>,
}

pub fn export_geometry(args: &ExportGeometryArgs) -> Result<()> {
    let scene = load_scene(&args.scene)
        .with_context(|| format!("scene {} is not usable", args.scene.display()))?;
    let scene_dir = args.scene.parent().unwrap_or(std::path::Path::new("."));
    let stem = args
        .scene
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("luminaire");
    let request = GeometryRequest {
        formats: args.formats.clone(),
        parts: args.parts.clone(),
    };
    let written = write_geometry(&scene, scene_dir, &args.out, stem, &request)
        .with_context(|| format!("cannot export the geometry of {}", args.scene.display()))?;
    for path in written {
        println!("wrote {}", path.display());
    }
    Ok(())
}
