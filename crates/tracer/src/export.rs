//! From a traced intensity map to a photometric data set the exporters
//! write: candela table, symmetry, and the metadata of a simulation.

use lucerna_photometry::resample::{GammaGrid, TableResampler};
use lucerna_photometry::table::uniform_c_planes;
use lucerna_photometry::{Dimensions, Format, IntensityMap, LampSet, Metadata, Photometry, Symmetry};
use lucerna_scene::{Scene, TessellatedScene};

/// How the bake's table is laid out and labelled.
#[derive(Debug, Clone)]
pub struct ExportOptions {
    pub c_step_deg: f64,
    /// γ spacing; `None` chooses it: 2.5° halved until the table's flux is
    /// within 0.5 % of the traced flux (narrow beams need fine grids), down
    /// to 0.125°.
    pub gamma_step_deg: Option<f64>,
    /// Symmetry to impose by averaging (None: keep the traced asymmetry).
    pub symmetrise: Option<Symmetry>,
    /// ISO date of the bake.
    pub date: String,
    pub seed: u32,
    /// The scene file's name, for the file-generation info.
    pub scene_file: String,
}

/// The luminous opening: the luminaire's footprint seen from below (x and
/// y extent of every surface), height 0. A first approximation until
/// parts carry an explicit aperture.
pub fn luminous_opening(tessellated: &TessellatedScene) -> Dimensions {
    let (lo, hi) = tessellated.mesh.bounds().unwrap_or_default();
    Dimensions {
        length_m: f64::from(hi.x - lo.x),
        width_m: f64::from(hi.y - lo.y),
        height_m: 0.0,
        circular: false,
    }
}

/// Relative photometry of a bake: lamp lumens = emitter flux, `candela`
/// per texel (raw or filtered) resampled by cell integration; `map`
/// supplies the bookkeeping.
pub fn photometry_from_candela(
    map: &IntensityMap,
    candela: &[f64],
    scene: &Scene,
    tessellated: &TessellatedScene,
    options: &ExportOptions,
    resampler: &mut TableResampler,
) -> Photometry {
    let c_planes = uniform_c_planes(options.c_step_deg);
    let gammas = match options.gamma_step_deg {
        Some(step) => GammaGrid::Step(step),
        None => GammaGrid::Automatic {
            flux_lm: map.escaped_flux_lm(),
            tolerance: 0.005,
        },
    };
    let table = resampler.table(map.layout, candela, &c_planes, gammas);
    let (table, symmetry) = match options.symmetrise {
        Some(s) => (table.symmetrised(s), s),
        None => (table, Symmetry::None),
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
                options.scene_file, scene.name, map.photons_emitted, options.seed, options.date
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
            luminous_area: luminous_opening(tessellated),
            luminaire_dimensions: luminous_opening(tessellated),
            ldt_type: None,
            tilt: None,
            warnings: Vec::new(),
        },
    }
}
