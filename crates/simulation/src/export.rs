//! From a snapshot to the photometric data set and files a bake writes:
//! the candela table with its declared symmetry and the metadata of a
//! simulation, then IES, LDT, EXR and PNGs, each written atomically.

use std::path::{Path, PathBuf};

use lucerna_photometry::{
    CPlaneSymmetry, CandelaTable, Dimensions, Format, IesVersion, LampSet, Metadata, Photometry,
    to_latin1, write_ies, write_ldt,
};
use lucerna_scene::{LuminousOpening, Scene, SurfaceKind, TessellatedScene, write_atomically};

use crate::{SimulationError, Snapshot};

/// How the files of a bake are labelled.
#[derive(Debug, Clone)]
pub struct ExportOptions {
    /// C-plane symmetry to impose on the table by averaging, even one the geometry
    /// lacks. `None` declares what the photons were pooled over (quadrant
    /// or one mirror plane, where the formats can say it), since a pooled
    /// table is exactly symmetric.
    pub symmetrise: Option<CPlaneSymmetry>,
    /// ISO date of the bake.
    pub date: String,
    pub seed: u32,
    /// The scene file's name, for the file-generation info.
    pub scene_file: String,
}

/// The x and y extent (m) of triangles `range` (all when `None`) seen
/// from below.
fn footprint(tessellated: &TessellatedScene, range: Option<std::ops::Range<usize>>) -> (f64, f64) {
    let mesh = &tessellated.mesh;
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for t in &mesh.triangles[range.unwrap_or(0..mesh.triangles.len())] {
        for &v in t {
            let p = mesh.positions[v as usize];
            for (k, x) in [f64::from(p.x), f64::from(p.y)].into_iter().enumerate() {
                lo[k] = lo[k].min(x);
                hi[k] = hi[k].max(x);
            }
        }
    }
    if lo[0] > hi[0] {
        (0.0, 0.0)
    } else {
        (hi[0] - lo[0], hi[1] - lo[1])
    }
}

/// The luminaire's dimensions the files declare: its footprint seen from
/// below, height 0.
pub fn luminaire_dimensions(tessellated: &TessellatedScene) -> Dimensions {
    let (length_m, width_m) = footprint(tessellated, None);
    Dimensions {
        length_m,
        width_m,
        height_m: 0.0,
        circular: false,
    }
}

/// The luminous opening the files declare: the scene's, or by default the
/// luminaire's footprint.
pub fn luminous_opening(scene: &Scene, tessellated: &TessellatedScene) -> Dimensions {
    let rectangle = |length_m, width_m, height_m| Dimensions {
        length_m,
        width_m,
        height_m,
        circular: false,
    };
    let disk = |diameter_m, height_m| Dimensions {
        length_m: diameter_m,
        width_m: 0.0,
        height_m,
        circular: true,
    };
    match &scene.opening {
        None => luminaire_dimensions(tessellated),
        Some(LuminousOpening::Rectangle {
            length_m,
            width_m,
            height_m,
        }) => rectangle(*length_m, *width_m, *height_m),
        Some(LuminousOpening::Disk {
            diameter_m,
            height_m,
        }) => disk(*diameter_m, *height_m),
        Some(LuminousOpening::None) => Dimensions::default(),
        Some(LuminousOpening::PartAperture { part }) => {
            let index = scene.parts.iter().position(|p| &p.name == part);
            let range = tessellated
                .surfaces
                .iter()
                .filter(|s| s.kind == SurfaceKind::Part && Some(s.index) == index)
                .map(|s| s.triangles.clone())
                .reduce(|a, b| a.start.min(b.start)..a.end.max(b.end));
            let (length_m, width_m) = footprint(tessellated, Some(range.unwrap_or(0..0)));
            // A surface of revolution about the axis has a round exit.
            let revolved = index.is_some_and(|i| {
                matches!(
                    scene.parts[i].shape.kind(),
                    "paraboloid" | "ellipsoid" | "revolved" | "dome" | "disk" | "cylinder"
                )
            });
            if revolved && (length_m - width_m).abs() <= 0.02 * length_m.max(width_m) {
                disk(length_m.max(width_m), 0.0)
            } else {
                rectangle(length_m, width_m, 0.0)
            }
        }
    }
}

/// Relative photometry of a snapshot: lamp lumens = emitter flux, the
/// snapshot's table (raw or filtered, pooled) with the symmetry declared.
pub fn photometry(snapshot: &Snapshot, options: &ExportOptions) -> Photometry {
    let map = &snapshot.map;
    let scene = &snapshot.luminaire.scene;
    let tessellated = &snapshot.luminaire.tessellated;
    let table: &CandelaTable = &snapshot.table;
    let declared = options
        .symmetrise
        .or(Some(snapshot.symmetry.file_symmetry()).filter(|&s| s != CPlaneSymmetry::None));
    let (table, symmetry) = match declared {
        Some(s) => (table.symmetrised(s), s),
        None => (table.clone(), CPlaneSymmetry::None),
    };
    let version = env!("CARGO_PKG_VERSION");
    Photometry {
        format: Format::Ies(2019),
        symmetry,
        table,
        meta: Metadata {
            manufacturer: scene.manufacturer.clone(),
            luminaire: scene.name.clone(),
            catalog_number: scene.name.clone(),
            test_report: format!("Lucerna simulation of {}", options.scene_file),
            test_lab: "Lucerna photon tracer (computer simulation)".to_owned(),
            issue_date: options.date.clone(),
            file_generation_info: format!(
                "Lucerna {version}; scene {} ({}); {} photons; seed {}; {}",
                options.scene_file, scene.name, snapshot.photons, options.seed, options.date
            ),
            file_generation_type: Some(lucerna_photometry::ies::FILE_GENERATION_SIMULATION),
            keywords: vec![(
                "_SIMULATION".to_owned(),
                format!(
                    "{} photons emitted, {} escaped, {} absorbed, {} cut off; LOR {:.4}",
                    map.photons_emitted,
                    map.photons_escaped(),
                    map.photons_absorbed,
                    map.photons_cut_off,
                    map.light_output_ratio()
                ),
            )],
            lamps: vec![LampSet {
                count: 1,
                kind: scene
                    .emitters
                    .iter()
                    .filter(|e| e.enabled)
                    .map(|e| e.name.as_str())
                    .collect::<Vec<_>>()
                    .join(" + "),
                flux_lm: map.emitter_flux_lm,
                colour_temperature: String::new(),
                colour_rendering: String::new(),
                watts: 0.0,
            }],
            absolute: false,
            ballast_factor: 1.0,
            input_watts: 0.0,
            luminous_area: luminous_opening(scene, tessellated),
            luminaire_dimensions: luminaire_dimensions(tessellated),
            ldt_type: None,
            tilt: None,
            warnings: Vec::new(),
        },
    }
}

/// Writes `STEM.ies` (LM-63-2019), `STEM.ldt`, `STEM.exr` (the raw map
/// with its photon counts), `STEM_cube.png` and `STEM_polar.png` into
/// `out_dir`, each atomically; returns their paths.
pub fn write_bake_files(
    snapshot: &Snapshot,
    options: &ExportOptions,
    out_dir: &Path,
    stem: &str,
) -> Result<Vec<PathBuf>, SimulationError> {
    let photometry = photometry(snapshot, options);
    let map = &snapshot.map;
    let scene = &snapshot.luminaire.scene;
    // cd/klm of the lamp (emitter) flux, as in the LDT; validation keeps
    // the flux > 0.
    let per_klm = 1000.0 / map.emitter_flux_lm;
    let title = format!("{} - {} photons", scene.name, map.photons_emitted);
    let picture = |what: &'static str| {
        move |e: &dyn std::fmt::Display| SimulationError::Picture {
            what,
            message: e.to_string(),
        }
    };
    let exr = lucerna_pictures::intensity_map_exr(
        map,
        &[
            ("lucernaSeed", options.seed.to_string()),
            ("lucernaScene", scene.name.clone()),
            ("lucernaDate", options.date.clone()),
        ],
    )
    .map_err(|e| picture("the EXR map")(&e))?;
    let cube = lucerna_pictures::cube_map_png(map.layout, &snapshot.candela, 200, &title)
        .map_err(|e| picture("the cube map")(&e))?;
    let polar = lucerna_pictures::polar_png(&photometry.table, per_klm, 640, &title)
        .map_err(|e| picture("the polar diagram")(&e))?;
    let outputs: Vec<(String, Vec<u8>)> = vec![
        (
            format!("{stem}.ies"),
            write_ies(&photometry, IesVersion::Lm63_2019)?.into_bytes(),
        ),
        (format!("{stem}.ldt"), to_latin1(&write_ldt(&photometry)?)),
        (format!("{stem}.exr"), exr),
        (format!("{stem}_cube.png"), cube),
        (format!("{stem}_polar.png"), polar),
    ];
    let mut files = Vec::new();
    for (name, bytes) in outputs {
        let path = out_dir.join(name);
        write_atomically(&path, &bytes).map_err(|source| SimulationError::Write {
            path: path.clone(),
            source,
        })?;
        files.push(path);
    }
    Ok(files)
}
