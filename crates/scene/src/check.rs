//! What every check of a scene shares: where a value sits in the file
//! ([`FieldPath`]), the limits, and the range checks ([`Checker`]) the
//! scene and each shape use, so equal limits read the same everywhere.

use std::fmt;

/// Where a value sits in the scene file, e.g. `part[2].shape.focal_length`
/// (the TOML key path, used to find its line).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct FieldPath(pub Vec<PathSegment>);

#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PathSegment {
    Key(String),
    Index(usize),
}

impl FieldPath {
    /// The path of key `k` inside this table.
    pub fn key(&self, k: &str) -> FieldPath {
        let mut p = self.clone();
        p.0.push(PathSegment::Key(k.to_owned()));
        p
    }
    /// The path of element `i` of this array.
    pub fn index(&self, i: usize) -> FieldPath {
        let mut p = self.clone();
        p.0.push(PathSegment::Index(i));
        p
    }
}

impl fmt::Display for FieldPath {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (i, s) in self.0.iter().enumerate() {
            match s {
                PathSegment::Key(k) if i == 0 => write!(f, "{k}")?,
                PathSegment::Key(k) => write!(f, ".{k}")?,
                PathSegment::Index(n) => write!(f, "[{n}]")?,
            }
        }
        Ok(())
    }
}

/// A value that is out of range or a reference that does not resolve.
#[derive(Debug, Clone, PartialEq)]
pub struct Invalid {
    pub field: FieldPath,
    pub message: String,
}

/// Most segments a generator may be asked for in one direction; beyond
/// this a typo (an extra zero) would silently build a 100M-triangle mesh.
pub const MAX_SEGMENTS: u32 = 4096;
/// Most triangles of one part, generated or read from an OBJ file: the
/// segment limits hold per direction, and 4096 × 4096 segments would be
/// 33M triangles (3 GB) from a 344-byte file. 2M is a finely faceted CAD
/// reflector; a spun reflector needs a few thousand.
pub const MAX_PART_TRIANGLES: u64 = 2_000_000;
/// Most triangles of the enabled parts and emitters together, what the
/// tracer builds its BVHs over.
pub const MAX_SCENE_TRIANGLES: u64 = 4_000_000;
/// Largest length parameter (m) accepted for any shape.
pub const MAX_LENGTH_M: f64 = 50.0;
/// Most problems one validation lists; the rest are only counted, so a
/// generated file with a mistake in every part gives a readable report of
/// bounded size.
pub const MAX_LISTED_PROBLEMS: usize = 100;
/// Most names an "unknown material" message lists of those defined.
pub const MAX_LISTED_MATERIALS: usize = 10;
/// Names in messages are cut to this many characters.
const MAX_NAME_CHARS: usize = 64;

/// The problems of a scene: the first [`MAX_LISTED_PROBLEMS`] in file
/// order, and how many more were found.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Validation {
    pub problems: Vec<Invalid>,
    pub unlisted: usize,
}

/// Collects the problems of one scene, in file order; its range checks are
/// the ones shapes share, so equal limits read the same in every shape.
#[derive(Debug)]
pub struct Checker<'a> {
    /// The names of the scene's materials, sorted, for the references a
    /// shape makes (OBJ groups).
    materials: Vec<&'a str>,
    found: Validation,
}

/// `name` for a message, cut to [`MAX_NAME_CHARS`].
fn shortened(name: &str) -> String {
    match name.char_indices().nth(MAX_NAME_CHARS) {
        Some((end, _)) => format!("{}…", &name[..end]),
        None => name.to_owned(),
    }
}

impl<'a> Checker<'a> {
    /// A checker of a scene whose materials are named `materials`.
    pub fn new(materials: impl IntoIterator<Item = &'a str>) -> Checker<'a> {
        let mut materials: Vec<&str> = materials.into_iter().collect();
        materials.sort_unstable();
        Checker {
            materials,
            found: Validation::default(),
        }
    }

    /// The problems found.
    pub fn into_validation(self) -> Validation {
        self.found
    }

    /// Records a problem at `field` (or only counts it, past
    /// [`MAX_LISTED_PROBLEMS`]).
    pub fn fail(&mut self, field: FieldPath, message: impl Into<String>) {
        if self.found.problems.len() < MAX_LISTED_PROBLEMS {
            self.found.problems.push(Invalid {
                field,
                message: message.into(),
            });
        } else {
            self.found.unlisted += 1;
        }
    }

    /// Whether `v` is finite; a range check only makes sense after it.
    pub fn finite(&mut self, at: &FieldPath, name: &str, v: f64) -> bool {
        if v.is_finite() {
            true
        } else {
            self.fail(at.key(name), format!("must be a finite number, got {v}"));
            false
        }
    }

    /// A fraction of the incident flux, in [0, 1].
    pub fn fraction(&mut self, at: &FieldPath, name: &str, v: f64) {
        if self.finite(at, name, v) && !(0.0..=1.0).contains(&v) {
            self.fail(at.key(name), format!("must be between 0 and 1, got {v}"));
        }
    }

    /// A length in (0, MAX_LENGTH_M] metres.
    pub fn length(&mut self, at: &FieldPath, name: &str, v: f64) {
        if self.finite(at, name, v) && !(v > 0.0 && v <= MAX_LENGTH_M) {
            self.fail(
                at.key(name),
                format!("must be a length in metres, > 0 and ≤ {MAX_LENGTH_M}, got {v}"),
            );
        }
    }

    /// A length in [0, MAX_LENGTH_M] metres (an optional hole, an offset).
    pub fn non_negative(&mut self, at: &FieldPath, name: &str, v: f64) {
        if self.finite(at, name, v) && !(0.0..=MAX_LENGTH_M).contains(&v) {
            self.fail(
                at.key(name),
                format!("must be ≥ 0 and ≤ {MAX_LENGTH_M}, got {v}"),
            );
        }
    }

    /// A resolution (or count) between `min` and MAX_SEGMENTS.
    pub fn segments(&mut self, at: &FieldPath, name: &str, v: u32, min: u32) {
        if !(min..=MAX_SEGMENTS).contains(&v) {
            self.fail(
                at.key(name),
                format!("must be between {min} and {MAX_SEGMENTS}, got {v}"),
            );
        }
    }

    /// Checks the control points under `at.profile`: 2 to MAX_SEGMENTS
    /// points, each finite and within ±MAX_LENGTH_M, no zero-length span.
    /// `point_rule` is the shape's own condition on each point (a revolved
    /// profile's r ≥ 0), returning the message when a point breaks it.
    /// Returns false when the points are unusable, so that the shape's
    /// further checks on them would only repeat the problem.
    pub fn profile(
        &mut self,
        at: &FieldPath,
        profile: &[[f64; 2]],
        point_rule: impl Fn([f64; 2]) -> Option<String>,
    ) -> bool {
        let at = at.key("profile");
        if profile.len() < 2 {
            self.fail(at.clone(), "needs at least 2 control points");
            return false;
        }
        if profile.len() > MAX_SEGMENTS as usize {
            self.fail(at.clone(), format!("at most {MAX_SEGMENTS} control points"));
            return false;
        }
        for (i, p) in profile.iter().enumerate() {
            if p.iter().any(|x| !x.is_finite() || x.abs() > MAX_LENGTH_M) {
                self.fail(
                    at.index(i),
                    format!("must be finite and within ±{MAX_LENGTH_M} m, got {p:?}"),
                );
                return false;
            }
            if let Some(message) = point_rule(*p) {
                self.fail(at.index(i), message);
            }
        }
        let extent = profile
            .iter()
            .flatten()
            .map(|x| x.abs())
            .fold(0.0, f64::max);
        for i in 1..profile.len() {
            let d = ((profile[i][0] - profile[i - 1][0]).powi(2)
                + (profile[i][1] - profile[i - 1][1]).powi(2))
            .sqrt();
            if d <= 1e-9 * extent.max(1e-9) {
                self.fail(
                    at.index(i),
                    format!("repeats control point {} (zero-length span)", i - 1),
                );
            }
        }
        true
    }

    /// `segments_per_span` of a profile with `control_points` points: the
    /// samples along the whole profile stay within MAX_SEGMENTS too.
    pub fn profile_segments(
        &mut self,
        at: &FieldPath,
        control_points: usize,
        segments_per_span: u32,
    ) {
        self.segments(at, "segments_per_span", segments_per_span, 1);
        if control_points.saturating_mul(segments_per_span as usize) > MAX_SEGMENTS as usize {
            self.fail(
                at.key("segments_per_span"),
                format!("control points × segments_per_span must be ≤ {MAX_SEGMENTS}"),
            );
        }
    }

    /// `name` must be a material defined in the scene's `[materials]`.
    pub fn material_ref(&mut self, at: FieldPath, name: &str) {
        if self.materials.binary_search(&name).is_err() {
            let mut known: Vec<String> = self
                .materials
                .iter()
                .take(MAX_LISTED_MATERIALS)
                .map(|k| shortened(k))
                .collect();
            let more = self.materials.len().saturating_sub(MAX_LISTED_MATERIALS);
            if more > 0 {
                known.push(format!("… and {more} more"));
            }
            self.fail(
                at,
                format!(
                    "unknown material '{}' (materials defined: {})",
                    shortened(name),
                    if known.is_empty() {
                        "none".to_owned()
                    } else {
                        known.join(", ")
                    }
                ),
            );
        }
    }
}
