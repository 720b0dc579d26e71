//! A design's files, written all or none: the designed scene (the start
//! scene's file with the varied values replaced in place, so its comments,
//! order and labels stay), its bake as IES and EULUMDAT, `design.csv` (one
//! row per traced candidate) and `design.png` (the merit over time, the
//! target beside the result).

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use lucerna_photometry::IntensityMap;
use lucerna_scene::{Scene, parse_scene};
use lucerna_simulation::{
    BackendRequest, ExportFormats, ExportOptions, ExportRequest, Luminaire, SimulationSettings,
    StoppingRule,
};
use toml_edit::{Array, DocumentMut, Item, Value};

pub use crate::outcome::Outcome;
use crate::traced::evaluate::Evaluator;
use crate::variables::{Place, Variable};
use crate::{Design, DesignError, Target};

/// Lengths are written to the nanometre, angles to 10⁻⁹°: finer than any
/// tool makes, and the file stays readable.
const DECIMALS: i32 = 9;

/// `values` rounded as the designed scene's file writes them.
pub fn rounded(_variables: &[Variable], values: &[f64]) -> Vec<f64> {
    let k = 10f64.powi(DECIMALS);
    values.iter().map(|v| (v * k).round() / k).collect()
}

/// The designed scene's file: the start's text with each varied value
/// replaced (its comments, order and labels kept); the scene re-serialised
/// where the start's layout cannot take the edit.
pub fn scene_text(design: &Design) -> Result<String, DesignError> {
    let edited = edit_in_place(
        &design.start_text,
        &design.start,
        &design.variables,
        &design.found.values,
    );
    let text = match edited {
        Some(t) => t,
        None => lucerna_scene::scene_to_toml(&design.scene).map_err(|e| {
            DesignError::Output(format!("the designed scene cannot be written: {e}"))
        })?,
    };
    // What is written is what was designed.
    let back = parse_scene(&text, Path::new("designed.toml"))
        .map_err(|e| DesignError::Output(format!("the designed scene does not read back: {e}")))?;
    if back != design.scene {
        return Err(DesignError::Output(
            "the designed scene reads back different from the design".to_owned(),
        ));
    }
    Ok(text)
}

fn edit_in_place(
    text: &str,
    start: &Scene,
    variables: &[Variable],
    values: &[f64],
) -> Option<String> {
    let mut doc: DocumentMut = text.parse().ok()?;
    let parts = doc.get_mut("part")?.as_array_of_tables_mut()?;
    for (v, &x) in variables.iter().zip(values) {
        let (part, name) = match &v.place {
            Place::Field { part, .. } | Place::ProfilePoint { part, .. } => {
                (*part, &start.parts[*part].name)
            }
        };
        let table = parts
            .iter_mut()
            .nth(part)
            .filter(|t| t.get("name").and_then(Item::as_str) == Some(name))?;
        let shape = table.get_mut("shape")?;
        let shape: &mut dyn toml_edit::TableLike = match shape {
            Item::Table(t) => t,
            Item::Value(Value::InlineTable(t)) => t,
            _ => return None,
        };
        match &v.place {
            Place::Field { field, .. } => {
                let old = shape
                    .get(field)
                    .and_then(|i| i.as_value())
                    .map(|v| v.decor().clone());
                let mut value = Value::from(x);
                if let Some(decor) = old {
                    *value.decor_mut() = decor;
                }
                shape.insert(field, Item::Value(value));
            }
            Place::ProfilePoint { point, coord, .. } => {
                let array: &mut Array = shape.get_mut("profile")?.as_array_mut()?;
                let pair = array.get_mut(*point)?.as_array_mut()?;
                let slot = pair.get_mut(*coord)?;
                let decor = slot.decor().clone();
                *slot = Value::from(x);
                *slot.decor_mut() = decor;
            }
        }
    }
    Some(doc.to_string())
}

/// `design.csv`: evaluation, seconds, photons, merit (empty where the
/// candidate was refused), what the merit measures, each variable.
pub fn history_csv(design: &Design) -> String {
    let mut out = String::from("evaluation,elapsed_s,photons,merit,measure");
    for v in &design.variables {
        let _ = write!(out, ",{}", v.name);
    }
    out.push('\n');
    for r in &design.found.history {
        let _ = write!(
            out,
            "{},{:.3},{},{},{}",
            r.evaluation,
            r.elapsed_s,
            r.photons,
            r.merit.map_or(String::new(), |m| format!("{m:.6}")),
            r.measure
        );
        for x in &r.values {
            let _ = write!(out, ",{x:.9}");
        }
        out.push('\n');
    }
    out
}

/// Everything `lucerna design` writes, in memory, with the outcome.
#[derive(Debug)]
pub struct Files {
    pub files: Vec<(PathBuf, Vec<u8>)>,
    pub outcome: Outcome,
}

/// Bakes the designed scene (and the start, for the comparison) with
/// `photons`, and renders every file of the design into `out_dir`.
pub fn files(
    design: &Design,
    out_dir: &Path,
    stem: &str,
    date: &str,
    photons: u64,
) -> Result<Files, DesignError> {
    let text = scene_text(design)?;
    let bake =
        |scene: &Scene| -> Result<(Arc<Luminaire>, lucerna_simulation::Snapshot), DesignError> {
            let luminaire = Arc::new(
                Luminaire::new(scene.clone(), &design.scene_dir)
                    .map_err(|e| DesignError::Output(e.to_string()))?,
            );
            let settings = SimulationSettings {
                resolution: design.resolution,
                seed: design.seed,
                backend: BackendRequest::Cpu,
                stop: StoppingRule {
                    photons: Some(photons),
                    ..StoppingRule::default()
                },
                ..SimulationSettings::default()
            };
            let snapshot = lucerna_simulation::bake(luminaire.clone(), settings)
                .map_err(|e| DesignError::Output(e.to_string()))?;
            Ok((luminaire, snapshot))
        };
    let (luminaire, snapshot) = bake(&design.scene)?;
    let (_, start_snapshot) = bake(&design.start)?;
    let evaluator = Evaluator::new(
        &design.scene_dir,
        design.seed,
        design.resolution,
        luminaire.find_symmetry().symmetry,
        &design.variables,
        design.aim.grid(),
    );
    let table = evaluator.tabulate(&snapshot.map);
    let start_table = evaluator.tabulate(&start_snapshot.map);
    let lor = |m: &IntensityMap| m.light_output_ratio();
    let (remaining_difference, start_difference) = match design.aim.target() {
        Target::Distribution { absolute, .. } => (
            Some(design.aim.relative_l2(&table, *absolute)),
            Some(design.aim.relative_l2(&start_table, *absolute)),
        ),
        Target::Spec(_) => (None, None),
    };
    let terms = design.aim.terms(
        &table,
        lor(&snapshot.map),
        design.lamp_flux_lm,
        &luminaire.luminous_opening,
    );
    let scene_file = format!("{stem}.toml");
    let options = ExportOptions {
        symmetrise: None,
        date: date.to_owned(),
        seed: design.seed,
        scene_file: scene_file.clone(),
        labels: None,
    };
    let mut request = ExportRequest::new(&snapshot, options, out_dir, stem);
    request.formats = ExportFormats {
        ies: Some(lucerna_photometry::IesVersion::Lm63_2019),
        ldt: true,
        exr: false,
        cube_png: false,
        polar_png: false,
        datasheet: false,
        tm25_rays: None,
    };
    let exported = request
        .render(&snapshot)
        .map_err(|e| DesignError::Output(e.to_string()))?;
    let outcome = Outcome {
        remaining_difference,
        start_difference,
        terms,
        photons,
        table,
        start_table,
    };
    let png = crate::picture::design_png(design, &outcome)
        .map_err(|e| DesignError::Output(format!("design.png: {e}")))?;
    let mut files = vec![(out_dir.join(&scene_file), text.into_bytes())];
    files.extend(exported.files);
    files.push((out_dir.join("design.csv"), history_csv(design).into_bytes()));
    files.push((out_dir.join("design.png"), png));
    Ok(Files { files, outcome })
}

/// Writes `files` all or none.
pub fn write(files: &[(PathBuf, Vec<u8>)]) -> Result<(), DesignError> {
    if let Some((dir, _)) = files.first()
        && let Some(parent) = dir.parent()
    {
        std::fs::create_dir_all(parent).map_err(|source| DesignError::Write {
            path: parent.display().to_string(),
            source,
        })?;
    }
    lucerna_scene::write_all_atomically(files).map_err(|(path, source)| DesignError::Write {
        path: path.display().to_string(),
        source,
    })
}
