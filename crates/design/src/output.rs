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
use crate::variables::{Owner, Place, Variable};
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
        &design.scene,
        &design.variables,
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

/// The start's text with each varied value set to the designed scene's
/// (a varied profile written whole: a design may give it more points);
/// None where the text's layout cannot take the edit.
fn edit_in_place(
    text: &str,
    start: &Scene,
    designed: &Scene,
    variables: &[Variable],
) -> Option<String> {
    let mut doc: DocumentMut = text.parse().ok()?;
    for v in variables {
        let (section, index, name) = match &v.place {
            Place::Transform {
                owner: Owner::Emitter(i),
                ..
            } => ("emitter", *i, &start.emitters.get(*i)?.name),
            place => {
                let part = place.part()?;
                ("part", part, &start.parts.get(part)?.name)
            }
        };
        let table = doc
            .get_mut(section)?
            .as_array_of_tables_mut()?
            .iter_mut()
            .nth(index)
            .filter(|t| t.get("name").and_then(Item::as_str) == Some(name))?;
        match &v.place {
            Place::Field { part, field } => {
                let shape = table_like(table.get_mut("shape")?)?;
                let value = crate::variables::value_at(designed, &v.place)?;
                let _ = part;
                let old = shape
                    .get(field)
                    .and_then(|i| i.as_value())
                    .map(|v| v.decor().clone());
                let mut value = Value::from(value);
                if let Some(decor) = old {
                    *value.decor_mut() = decor;
                }
                shape.insert(field, Item::Value(value));
            }
            Place::Finish { field, .. } => {
                let finish = table_like(table.get_mut("finish")?)?;
                let value = Value::from(crate::variables::value_at(designed, &v.place)?);
                match field.split_once('.') {
                    Some((array, rest)) => {
                        let (name, index) = array.strip_suffix(']')?.split_once('[')?;
                        let index: usize = index.parse().ok()?;
                        let wave = finish
                            .get_mut(name)?
                            .as_array_mut()?
                            .get_mut(index)?
                            .as_inline_table_mut()?;
                        wave.insert(rest, value);
                    }
                    None => {
                        finish.insert(field, Item::Value(value));
                    }
                }
            }
            Place::ProfilePoint { part, .. } => {
                let shape = table_like(table.get_mut("shape")?)?;
                let points = crate::variables::profile(&designed.parts.get(*part)?.shape)?;
                let array: &mut Array = shape.get_mut("profile")?.as_array_mut()?;
                if array.len() != points.len() {
                    let mut whole = Array::new();
                    for p in points {
                        let mut pair = Array::new();
                        pair.push(p[0]);
                        pair.push(p[1]);
                        whole.push(pair);
                    }
                    *array = whole;
                    continue;
                }
                for (k, p) in points.iter().enumerate() {
                    let pair = array.get_mut(k)?.as_array_mut()?;
                    for (coord, x) in p.iter().enumerate() {
                        let slot = pair.get_mut(coord)?;
                        let decor = slot.decor().clone();
                        *slot = Value::from(*x);
                        *slot.decor_mut() = decor;
                    }
                }
            }
            Place::Transform { rotate, axis, .. } => {
                let transform = table_like(table.get_mut("transform")?)?;
                let key = if *rotate { "rotate_deg" } else { "translate" };
                let value = crate::variables::value_at(designed, &v.place)?;
                let array: &mut Array = transform.get_mut(key)?.as_array_mut()?;
                let slot = array.get_mut(*axis)?;
                let decor = slot.decor().clone();
                *slot = Value::from(value);
                *slot.decor_mut() = decor;
            }
        }
    }
    Some(doc.to_string())
}

/// A table or an inline table.
fn table_like(item: &mut Item) -> Option<&mut dyn toml_edit::TableLike> {
    match item {
        Item::Table(t) => Some(t),
        Item::Value(Value::InlineTable(t)) => Some(t),
        _ => None,
    }
}

/// `design.csv`: evaluation, seconds, photons (0: judged by a model),
/// merit (empty where the candidate was refused), what the merit
/// measures, the phase that judged it, each variable.
pub fn history_csv(design: &Design) -> String {
    let mut out = String::from("evaluation,elapsed_s,photons,merit,measure,phase");
    for v in &design.variables {
        let _ = write!(out, ",{}", v.name);
    }
    out.push('\n');
    for r in &design.found.history {
        let _ = write!(
            out,
            "{},{:.3},{},{},{},{}",
            r.evaluation,
            r.elapsed_s,
            r.photons,
            r.merit.map_or(String::new(), |m| format!("{m:.6}")),
            r.measure,
            r.phase.name()
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

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)] // reason: tests may panic
    use super::*;
    use crate::variables::{parse, set, value_at};

    #[test]
    fn a_finishs_numbers_are_variables_within_what_can_be_made_and_written_in_place() {
        let text = std::fs::read_to_string(concat!(
            env!("CARGO_MANIFEST_DIR"),
            "/../../assets/luminaires/hammered_spot.toml"
        ))
        .unwrap();
        let start = parse_scene(&text, Path::new("hammered_spot.toml")).unwrap();
        let vars = parse(&start, &["reflector.finish.depth".to_owned()], false).unwrap();
        let depth = &vars[0];
        assert!((depth.start - 0.15e-3).abs() < 1e-12);
        // Shallower down to a quarter; no deeper than where the 3.4 mm
        // punch's dimples touch on the 2 mm pitch (0.1501 mm).
        assert!((depth.lower - 0.0375e-3).abs() < 1e-9, "{}", depth.lower);
        assert!(
            depth.upper >= 0.15e-3 && depth.upper < 0.1502e-3,
            "{}",
            depth.upper
        );
        let mut designed = start.clone();
        set(&mut designed, &depth.place, 0.1e-3).unwrap();
        assert_eq!(value_at(&designed, &depth.place), Some(0.1e-3));
        // Written into the start's own text, its comments kept.
        let edited = edit_in_place(&text, &start, &designed, &vars).unwrap();
        assert!(edited.contains("depth = 0.0001,"), "{edited}");
        assert!(edited.contains("# The parabolic spot (f = 25 mm, 100 mm aperture) hammered"));
        assert_eq!(parse_scene(&edited, Path::new("x.toml")).unwrap(), designed);
        // What a finish does not have is named with what it has.
        let e = parse(&start, &["reflector.finish.amplitude".to_owned()], false).unwrap_err();
        let why = format!("{e}");
        assert!(
            why.contains("no number 'amplitude'") && why.contains("depth"),
            "{why}"
        );
    }
}
