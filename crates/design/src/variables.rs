//! What a design may change: a part's continuous shape parameter
//! (`PART.FIELD`: a focal length, an aperture, a cone angle), a number of
//! its finish (`PART.finish.depth`, `PART.finish.waves[0].amplitude`) or
//! the control points of a revolved or extruded part's profile
//! (`PART.profile`), each between bounds inside the valid scene space.

use lucerna_scene::{Scene, Shape, validate};

use crate::DesignError;

/// Where a variable lives in the scene.
#[derive(Debug, Clone, PartialEq)]
pub enum Place {
    /// A number of the part's `shape` table.
    Field { part: usize, field: String },
    /// A part's or an emitter's placement: `translate` (m) or `rotate_deg`
    /// along `axis` (0: x, 1: y, 2: z).
    Transform {
        owner: Owner,
        rotate: bool,
        axis: usize,
    },
    /// A number of the part's `finish` table: `depth`, `pitch`, or a
    /// wave's `waves[K].amplitude`.
    Finish { part: usize, field: String },
    /// Coordinate `coord` (0: r or x, 1: z) of profile point `point`.
    ProfilePoint {
        part: usize,
        point: usize,
        coord: usize,
    },
}

/// What a placement belongs to.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Owner {
    Part(usize),
    Emitter(usize),
}

impl Place {
    /// The part whose shape or placement this changes (None: an emitter).
    pub fn part(&self) -> Option<usize> {
        match self {
            Place::Field { part, .. }
            | Place::Finish { part, .. }
            | Place::ProfilePoint { part, .. } => Some(*part),
            Place::Transform {
                owner: Owner::Part(part),
                ..
            } => Some(*part),
            Place::Transform { .. } => None,
        }
    }
}

/// How far a placement may move either way from the start: millimetres
/// for a translation (a design nudges an LED or a cap, it does not
/// rebuild the luminaire), degrees for a rotation.
const TRANSLATE_RANGE_M: f64 = 0.01;
const ROTATE_RANGE_DEG: f64 = 45.0;

/// One number a design varies, with its bounds.
#[derive(Debug, Clone, PartialEq)]
pub struct Variable {
    /// As `design.csv` heads its column: `reflector.focal_length`,
    /// `reflector.profile[2].z`.
    pub name: String,
    pub place: Place,
    /// The start scene's value.
    pub start: f64,
    pub lower: f64,
    pub upper: f64,
}

/// The variables' values at normalised coordinates `x` (each in [0, 1]
/// between its bounds).
pub fn values_at(variables: &[Variable], x: &[f64]) -> Vec<f64> {
    variables.iter().zip(x).map(|(v, &t)| v.at(t)).collect()
}

impl Variable {
    /// The value at `t` ∈ [0, 1] between the bounds.
    pub fn at(&self, t: f64) -> f64 {
        self.lower + t * (self.upper - self.lower)
    }

    /// Where `value` lies between the bounds (0 … 1).
    pub fn fraction(&self, value: f64) -> f64 {
        if self.upper > self.lower {
            (value - self.lower) / (self.upper - self.lower)
        } else {
            0.5
        }
    }
}

/// The variables `--vary` names: `PART.FIELD`, `PART.profile` (a
/// profile's two end points stay unless `free_ends`) or one point,
/// `PART.profile[INDEX]`.
pub fn parse(
    scene: &Scene,
    vary: &[String],
    free_ends: bool,
) -> Result<Vec<Variable>, DesignError> {
    if vary.is_empty() {
        return Err(DesignError::Vary {
            what: String::new(),
            why: "name at least one variable (--vary PART.FIELD or PART.profile)".to_owned(),
        });
    }
    let mut out: Vec<Variable> = Vec::new();
    for spec in vary {
        let bad = |why: String| DesignError::Vary {
            what: spec.clone(),
            why,
        };
        if let Some((part_name, field)) = spec.split_once(".finish.") {
            out.push(finish_variable(scene, spec, part_name, field).map_err(bad)?);
            continue;
        }
        let Some((part_name, field)) = spec.rsplit_once('.') else {
            return Err(bad("write it as PART.FIELD or PART.profile".to_owned()));
        };
        if let Some(v) = placement(scene, spec, part_name, field) {
            out.push(v.map_err(bad)?);
            continue;
        }
        let Some(part) = scene.parts.iter().position(|p| p.name == part_name) else {
            let names: Vec<&str> = scene.parts.iter().map(|p| p.name.as_str()).collect();
            let emitters: Vec<&str> = scene.emitters.iter().map(|e| e.name.as_str()).collect();
            return Err(bad(format!(
                "the scene has no part '{part_name}' (its parts: {}; an emitter ({}) takes only translate_x/y/z and rotate_x/y/z)",
                names.join(", "),
                emitters.join(", ")
            )));
        };
        if field == "profile" || field.starts_with("profile[") {
            let Some(points) = profile(&scene.parts[part].shape) else {
                return Err(bad(format!(
                    "part '{part_name}' is a {}, which has no profile (revolved and extruded parts have one)",
                    scene.parts[part].shape.kind()
                )));
            };
            let n = points.len();
            let range = if field == "profile" {
                if free_ends {
                    0..n
                } else {
                    1..n.saturating_sub(1)
                }
            } else {
                // One point, named by its index from 0 (its ends too: naming
                // one frees it).
                let index = field
                    .strip_prefix("profile[")
                    .and_then(|t| t.strip_suffix(']'))
                    .and_then(|t| t.parse::<usize>().ok())
                    .ok_or_else(|| {
                        bad("write one point as PART.profile[INDEX], INDEX from 0".to_owned())
                    })?;
                if index >= n {
                    return Err(bad(format!(
                        "the profile has {n} points (profile[0] to profile[{}])",
                        n - 1
                    )));
                }
                index..index + 1
            };
            if range.is_empty() {
                return Err(bad(format!(
                    "the profile has {n} points and its two ends stay where they are: add interior points, or --free-ends"
                )));
            }
            out.extend(profile_variables(scene, part, range));
            continue;
        }
        let start = field_value(&scene.parts[part].shape, field).map_err(bad)?;
        let place = Place::Field {
            part,
            field: field.to_owned(),
        };
        let (lower, upper) = valid_range(scene, &place, start);
        out.push(Variable {
            name: spec.clone(),
            place,
            start,
            lower,
            upper,
        });
    }
    for (i, v) in out.iter().enumerate() {
        if out[..i].iter().any(|w| w.place == v.place) {
            return Err(DesignError::Vary {
                what: v.name.clone(),
                why: "named twice".to_owned(),
            });
        }
    }
    Ok(out)
}

/// A placement variable (`NAME.translate_z`, `NAME.rotate_x`: degrees) of
/// the part or emitter called `name`; None where `field` is not one.
fn placement(
    scene: &Scene,
    spec: &str,
    name: &str,
    field: &str,
) -> Option<Result<Variable, String>> {
    let (rotate, axis) = match field {
        "translate_x" => (false, 0),
        "translate_y" => (false, 1),
        "translate_z" => (false, 2),
        "rotate_x" => (true, 0),
        "rotate_y" => (true, 1),
        "rotate_z" => (true, 2),
        _ => return None,
    };
    let (owner, transform) = if let Some(i) = scene.parts.iter().position(|p| p.name == name) {
        (Owner::Part(i), &scene.parts[i].transform)
    } else if let Some(i) = scene.emitters.iter().position(|e| e.name == name) {
        (Owner::Emitter(i), &scene.emitters[i].transform)
    } else {
        return Some(Err(format!("the scene has no part or emitter '{name}'")));
    };
    let start = if rotate {
        transform.rotate_deg[axis]
    } else {
        transform.translate[axis]
    };
    let reach = if rotate {
        ROTATE_RANGE_DEG
    } else {
        TRANSLATE_RANGE_M
    };
    Some(Ok(Variable {
        name: spec.to_owned(),
        place: Place::Transform {
            owner,
            rotate,
            axis,
        },
        start,
        lower: start - reach,
        upper: start + reach,
    }))
}

/// The variables of profile points `range` of `part` (both coordinates
/// each), bounded by the profile's box grown by half its extent either
/// way (a revolved profile's r by the axis).
fn profile_variables(scene: &Scene, part: usize, range: std::ops::Range<usize>) -> Vec<Variable> {
    let Some(points) = profile(&scene.parts[part].shape) else {
        return Vec::new();
    };
    let part_name = &scene.parts[part].name;
    let (lo, hi) = profile_box(points);
    let revolved = matches!(scene.parts[part].shape, Shape::Revolved(_));
    let mut out = Vec::new();
    for point in range {
        for coord in 0..2 {
            let extent = (hi[coord] - lo[coord]).max(1e-3);
            let mut lower = lo[coord] - 0.5 * extent;
            if revolved && coord == 0 {
                lower = lower.max(0.0);
            }
            out.push(Variable {
                name: format!(
                    "{part_name}.profile[{point}].{}",
                    match (coord, revolved) {
                        (0, true) => "r",
                        (0, false) => "x",
                        _ => "z",
                    }
                ),
                place: Place::ProfilePoint { part, point, coord },
                start: points[point][coord],
                lower,
                upper: hi[coord] + 0.5 * extent,
            });
        }
    }
    out
}

/// The profile's control points of a revolved or extruded shape.
pub fn profile(shape: &Shape) -> Option<&[[f64; 2]]> {
    match shape {
        Shape::Revolved(s) => Some(&s.profile),
        Shape::Extruded(s) => Some(&s.profile),
        _ => None,
    }
}

/// The profile's control points of a revolved or extruded shape, to edit.
pub fn profile_mut(shape: &mut Shape) -> Option<&mut Vec<[f64; 2]>> {
    match shape {
        Shape::Revolved(s) => Some(&mut s.profile),
        Shape::Extruded(s) => Some(&mut s.profile),
        _ => None,
    }
}

fn profile_box(points: &[[f64; 2]]) -> ([f64; 2], [f64; 2]) {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for p in points {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    (lo, hi)
}

/// A finish's number (`PART.finish.FIELD`) as a variable.
fn finish_variable(
    scene: &Scene,
    spec: &str,
    part_name: &str,
    field: &str,
) -> Result<Variable, String> {
    let part = scene
        .parts
        .iter()
        .position(|p| p.name == part_name)
        .ok_or_else(|| format!("the scene has no part '{part_name}'"))?;
    let finish = scene.parts[part]
        .finish
        .as_ref()
        .ok_or_else(|| format!("part '{part_name}' has no finish"))?;
    let start = finish_value(finish, field)?;
    let place = Place::Finish {
        part,
        field: field.to_owned(),
    };
    let (lower, upper) = valid_range(scene, &place, start);
    Ok(Variable {
        name: spec.to_owned(),
        place,
        start,
        lower,
        upper,
    })
}

/// The TOML value at `field` of a finish's table (`depth`,
/// `waves[1].amplitude`), for reading or writing.
fn finish_slot<'a>(table: &'a mut toml::Table, field: &str) -> Option<&'a mut toml::Value> {
    match field.split_once('.') {
        Some((array, rest)) => {
            let (name, index) = array.strip_suffix(']')?.split_once('[')?;
            let index: usize = index.parse().ok()?;
            let item = table.get_mut(name)?.as_array_mut()?.get_mut(index)?;
            item.as_table_mut()?.get_mut(rest)
        }
        None => table.get_mut(field),
    }
}

fn finish_value(finish: &lucerna_scene::finish::Finish, field: &str) -> Result<f64, String> {
    let mut table = toml::Table::try_from(finish).map_err(|e| e.to_string())?;
    let numbers = || table_numbers(&toml::Table::try_from(finish).unwrap_or_default()).join(", ");
    match finish_slot(&mut table, field) {
        Some(toml::Value::Float(v)) => Ok(*v),
        Some(_) => Err(format!(
            "'{field}' of the finish is not a continuous number"
        )),
        None => Err(format!(
            "the finish has no number '{field}' (it has: {})",
            numbers()
        )),
    }
}

/// A finish table's continuous numbers as they are named in `--vary`.
fn table_numbers(table: &toml::Table) -> Vec<String> {
    let mut out = Vec::new();
    for (k, v) in table {
        match v {
            toml::Value::Float(_) => out.push(k.clone()),
            toml::Value::Array(items) => {
                for (i, item) in items.iter().enumerate() {
                    if let Some(t) = item.as_table() {
                        for (f, x) in t {
                            if x.is_float() {
                                out.push(format!("{k}[{i}].{f}"));
                            }
                        }
                    }
                }
            }
            _ => {}
        }
    }
    out
}

/// A shape's parameters as a TOML table (how the scene file spells them).
fn shape_table(shape: &Shape) -> Option<toml::Table> {
    toml::Table::try_from(shape).ok()
}

/// The value of a continuous parameter, or why it is not one.
fn field_value(shape: &Shape, field: &str) -> Result<f64, String> {
    let table = shape_table(shape).ok_or("the shape cannot be read as a table")?;
    match table.get(field) {
        Some(toml::Value::Float(v)) => Ok(*v),
        Some(toml::Value::Integer(_)) => Err(format!(
            "'{field}' of a {} is a count, not a continuous parameter",
            shape.kind()
        )),
        Some(toml::Value::Boolean(_)) => Err(format!(
            "'{field}' of a {} is a switch, not a continuous parameter",
            shape.kind()
        )),
        Some(_) => Err(format!("'{field}' of a {} is not a number", shape.kind())),
        None => {
            let numbers: Vec<String> = table
                .iter()
                .filter(|(_, v)| v.is_float())
                .map(|(k, _)| k.clone())
                .collect();
            // Optional parameters left at their default are not written:
            // what the shape takes there tells what they are.
            let takes = |v: toml::Value| {
                let mut table = table.clone();
                table.insert(field.to_owned(), v);
                table.try_into::<Shape>().is_ok()
            };
            if takes(toml::Value::Float(0.0)) {
                return Ok(0.0);
            }
            if takes(toml::Value::Boolean(false)) {
                return Err(format!(
                    "'{field}' of a {} is a switch, not a continuous parameter",
                    shape.kind()
                ));
            }
            if takes(toml::Value::Integer(1)) {
                return Err(format!(
                    "'{field}' of a {} is a count, not a continuous parameter",
                    shape.kind()
                ));
            }
            Err(format!(
                "a {} has no continuous parameter '{field}' (it has: {})",
                shape.kind(),
                numbers.join(", ")
            ))
        }
    }
}

/// The value at `place` in `scene`.
pub fn value_at(scene: &Scene, place: &Place) -> Option<f64> {
    match place {
        Place::Field { part, field } => field_value(&scene.parts.get(*part)?.shape, field).ok(),
        Place::Finish { part, field } => {
            finish_value(scene.parts.get(*part)?.finish.as_ref()?, field).ok()
        }
        Place::ProfilePoint { part, point, coord } => {
            Some(profile(&scene.parts.get(*part)?.shape)?.get(*point)?[*coord])
        }
        Place::Transform {
            owner,
            rotate,
            axis,
        } => {
            let t = match owner {
                Owner::Part(i) => &scene.parts.get(*i)?.transform,
                Owner::Emitter(i) => &scene.emitters.get(*i)?.transform,
            };
            Some(if *rotate {
                t.rotate_deg[*axis]
            } else {
                t.translate[*axis]
            })
        }
    }
}

/// `scene` with `place` set to `value`; None if the shape refuses it.
pub fn set(scene: &mut Scene, place: &Place, value: f64) -> Option<()> {
    match place {
        Place::Field { part, field } => {
            let shape = &mut scene.parts.get_mut(*part)?.shape;
            let mut table = shape_table(shape)?;
            table.insert(field.clone(), toml::Value::Float(value));
            *shape = table.try_into().ok()?;
        }
        Place::Finish { part, field } => {
            use lucerna_scene::finish::Finish;
            let finish = scene.parts.get_mut(*part)?.finish.as_mut()?;
            let mut table = toml::Table::try_from(&*finish).ok()?;
            *finish_slot(&mut table, field)? = toml::Value::Float(value);
            let mut changed: Finish = table.try_into().ok()?;
            // A height map's pixels are read, not written: kept.
            if let (Finish::HeightMap { heights: read, .. }, Finish::HeightMap { heights, .. }) =
                (&*finish, &mut changed)
            {
                heights.clone_from(read);
            }
            *finish = changed;
        }
        Place::ProfilePoint { part, point, coord } => {
            let points = profile_mut(&mut scene.parts.get_mut(*part)?.shape)?;
            points.get_mut(*point)?[*coord] = value;
        }
        Place::Transform {
            owner,
            rotate,
            axis,
        } => {
            let transform = match owner {
                Owner::Part(i) => &mut scene.parts.get_mut(*i)?.transform,
                Owner::Emitter(i) => &mut scene.emitters.get_mut(*i)?.transform,
            };
            if !value.is_finite() {
                return None;
            }
            if *rotate {
                transform.rotate_deg[*axis] = value;
            } else {
                transform.translate[*axis] = value;
            }
        }
    }
    Some(())
}

/// `scene` with every variable at its value.
pub fn apply(scene: &Scene, variables: &[Variable], values: &[f64]) -> Option<Scene> {
    let mut s = scene.clone();
    for (v, &x) in variables.iter().zip(values) {
        set(&mut s, &v.place, x)?;
    }
    Some(s)
}

/// Whether the scene validates with `place` at `value`.
fn valid_at(scene: &Scene, place: &Place, value: f64) -> bool {
    let mut s = scene.clone();
    set(&mut s, place, value).is_some() && validate(&s).is_empty()
}

/// The contiguous range around `start` where the scene stays valid,
/// within a factor of four either way (an angle ±45°; a length that
/// starts at zero up to 50 mm): a design never leaves the valid scene
/// space, and bounds found from the shape's own checks cannot drift from
/// them.
fn valid_range(scene: &Scene, place: &Place, start: f64) -> (f64, f64) {
    let angle = matches!(place, Place::Field { field, .. } | Place::Finish { field, .. } if field.ends_with("_deg"));
    let steps = 64;
    let candidate = |k: i32| -> f64 {
        let t = f64::from(k) / f64::from(steps);
        if angle {
            start + 45.0 * t
        } else if start > 0.0 {
            start * 4f64.powf(t)
        } else if start < 0.0 {
            start * 4f64.powf(-t)
        } else {
            0.05 * t.max(0.0)
        }
    };
    let walk = |dir: i32| -> f64 {
        let mut last = start;
        for k in 1..=steps {
            let x = candidate(dir * k);
            if !valid_at(scene, place, x) {
                break;
            }
            last = x;
        }
        last
    };
    let (a, b) = (walk(-1), walk(1));
    (a.min(b), a.max(b))
}
