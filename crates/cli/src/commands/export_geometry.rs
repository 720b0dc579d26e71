//! `lucerna export-geometry`: the luminaire's parts to CAD (STEP with
//! exact surfaces) and to mesh tools (STL, OBJ).

use std::path::PathBuf;

use anyhow::{Context, Result};
use lucerna_cad::{FinishExport, GeometryFormat, GeometryRequest, write_geometry};
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
    /// A part's finish (hammered, rippled): `named` in the STEP product's
    /// description on the smooth surface, or `geometry` cut into the
    /// surface as triangles, so the toolmaker gets the real surface.
    #[arg(long, default_value = "named", value_parser = ["named", "geometry"])]
    finish: String,
    /// With `--finish geometry`: the longest triangle edge (mm); by
    /// default a sixteenth of the finest feature (pitch, wavelength).
    #[arg(long)]
    finish_edge_mm: Option<f64>,
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
    if let Some(e) = args.finish_edge_mm
        && !(e.is_finite() && e > 0.0)
    {
        anyhow::bail!("--finish-edge-mm must be a positive length in millimetres, got {e}");
    }
    let finish = match args.finish.as_str() {
        "geometry" => FinishExport::Geometry {
            edge: args.finish_edge_mm.map(|e| e * 1e-3),
        },
        _ => {
            if args.finish_edge_mm.is_some() {
                anyhow::bail!("--finish-edge-mm goes with --finish geometry");
            }
            FinishExport::Named
        }
    };
    let request = GeometryRequest {
        formats: args.formats.clone(),
        parts: args.parts.clone(),
        finish,
    };
    let written = write_geometry(&scene, scene_dir, &args.out, stem, &request)
        .with_context(|| format!("cannot export the geometry of {}", args.scene.display()))?;
    for path in written {
        println!("wrote {}", path.display());
    }
    Ok(())
}
