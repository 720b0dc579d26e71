//! Parameter validation: every number finite and in its physical range,
//! every reference resolved, every resolution sane.
//!
//! This file holds the scene-level checks and the range checks every shape
//! shares ([`Checker`]); each shape's own ranges live with its parameters in
//! [`crate::shapes`].

use std::collections::BTreeMap;
use std::fmt;

use crate::model::{Emitter, EmitterShape, FORMAT_VERSION, LuminousOpening, Material, Part, Scene};
use crate::tessellate::emitter_triangle_count;

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
    /// The scene's materials, for the references a shape makes (OBJ groups).
    materials: &'a BTreeMap<String, Material>,
    found: Validation,
}

/// `name` for a message, cut to [`MAX_NAME_CHARS`].
fn shortened(name: &str) -> String {
    match name.char_indices().nth(MAX_NAME_CHARS) {
        Some((end, _)) => format!("{}…", &name[..end]),
        None => name.to_owned(),
    }
}

impl Checker<'_> {
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

    fn material(&mut self, at: &FieldPath, m: &Material) {
        match *m {
            Material::Absorber => {}
            Material::Lambertian { albedo } => self.fraction(at, "albedo", albedo),
            Material::Mirror { reflectance } => self.fraction(at, "reflectance", reflectance),
            Material::RoughConductor {
                reflectance,
                roughness_u,
                roughness_v,
                orientation_deg,
            } => {
                self.fraction(at, "reflectance", reflectance);
                for (name, v) in [("roughness_u", roughness_u), ("roughness_v", roughness_v)] {
                    if self.finite(at, name, v) && !(1e-4..=1.0).contains(&v) {
                        self.fail(
                            at.key(name),
                            format!("GGX roughness α must be between 0.0001 and 1, got {v}"),
                        );
                    }
                }
                self.finite(at, "orientation_deg", orientation_deg);
            }
            Material::Dielectric {
                ior,
                absorption_per_m,
            } => {
                if self.finite(at, "ior", ior) && !(1.0..=4.0).contains(&ior) {
                    self.fail(
                        at.key("ior"),
                        format!("index of refraction must be between 1 and 4, got {ior}"),
                    );
                }
                if self.finite(at, "absorption_per_m", absorption_per_m) && absorption_per_m < 0.0 {
                    self.fail(
                        at.key("absorption_per_m"),
                        format!("absorption coefficient must be ≥ 0 (1/m), got {absorption_per_m}"),
                    );
                }
            }
            Material::Diffuser {
                reflectance,
                transmittance,
            } => {
                self.fraction(at, "reflectance", reflectance);
                self.fraction(at, "transmittance", transmittance);
                if reflectance + transmittance > 1.0 + 1e-12 {
                    self.fail(
                        at.key("transmittance"),
                        format!(
                            "reflectance + transmittance must be ≤ 1 (energy), got {reflectance} + {transmittance} = {}",
                            reflectance + transmittance
                        ),
                    );
                }
            }
        }
    }

    fn transform(&mut self, at: &FieldPath, t: &crate::model::Transform) {
        let at = at.key("transform");
        for (name, v) in [
            ("translate", t.translate),
            ("rotate_deg", t.rotate_deg),
            ("scale", t.scale),
        ] {
            if v.iter().any(|x| !x.is_finite()) {
                self.fail(at.key(name), format!("must be finite numbers, got {v:?}"));
            }
        }
        if t.translate.iter().any(|x| x.abs() > MAX_LENGTH_M) {
            self.fail(
                at.key("translate"),
                format!("must be within ±{MAX_LENGTH_M} m, got {:?}", t.translate),
            );
        }
        if t.scale.iter().any(|x| x.abs() < 1e-6 || x.abs() > 1e6) {
            self.fail(
                at.key("scale"),
                format!(
                    "each factor's magnitude must be between 1e-6 and 1e6, got {:?}",
                    t.scale
                ),
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
        if !self.materials.contains_key(name) {
            let mut known: Vec<String> = self
                .materials
                .keys()
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

    /// The part's triangles, from its parameters alone, within
    /// [`MAX_PART_TRIANGLES`]; returns them to count towards the scene's.
    fn part(&mut self, at: &FieldPath, part: &Part) -> u64 {
        if part.name.trim().is_empty() {
            self.fail(at.key("name"), "must not be empty");
        }
        self.material_ref(at.key("material"), &part.material);
        let shape = part.shape.generator();
        shape.validate(&at.key("shape"), self);
        self.transform(at, &part.transform);
        // A mesh's triangles are in its file: the OBJ reader and the
        // tessellation hold it to the same limits.
        let triangles = shape.triangle_count().unwrap_or(0);
        if triangles > MAX_PART_TRIANGLES {
            self.fail(
                at.key("shape"),
                format!(
                    "the {} would have {triangles} triangles, at most {MAX_PART_TRIANGLES} (fewer segments)",
                    shape.kind()
                ),
            );
        }
        triangles
    }

    fn emitter(&mut self, at: &FieldPath, e: &Emitter) {
        if e.name.trim().is_empty() {
            self.fail(at.key("name"), "must not be empty");
        }
        if self.finite(at, "flux_lm", e.flux_lm) && !(e.flux_lm > 0.0 && e.flux_lm <= 1e7) {
            self.fail(
                at.key("flux_lm"),
                format!("luminous flux must be > 0 and ≤ 1e7 lm, got {}", e.flux_lm),
            );
        }
        let s = at.key("shape");
        match e.shape {
            EmitterShape::Disk { radius } | EmitterShape::Sphere { radius } => {
                self.length(&s, "radius", radius)
            }
            EmitterShape::Rectangle { width, depth } => {
                self.length(&s, "width", width);
                self.length(&s, "depth", depth);
            }
            EmitterShape::Cylinder { radius, height } => {
                self.length(&s, "radius", radius);
                self.length(&s, "height", height);
            }
            EmitterShape::RayFile { ref path } => {
                if path.trim().is_empty() {
                    self.fail(s.key("path"), "must name a TM-25 ray file");
                }
                if e.emission != crate::model::Emission::Lambertian {
                    self.fail(
                        at.key("emission"),
                        "a ray-file emitter takes its directions from the file: leave emission out",
                    );
                }
            }
        }
        if let crate::model::Emission::Profile(file) = &e.emission
            && file.trim().is_empty()
        {
            self.fail(
                at.key("emission").key("profile"),
                "must name an IES or LDT file",
            );
        }
        if let Some(m) = &e.material {
            self.material_ref(at.key("material"), m);
        }
        self.transform(at, &e.transform);
    }
}

/// Checks a scene's parameters; returns the first [`MAX_LISTED_PROBLEMS`]
/// problems found, in file order (see [`validation`] for their count).
pub fn validate(scene: &Scene) -> Vec<Invalid> {
    validation(scene).problems
}

/// Checks a scene's parameters: the first [`MAX_LISTED_PROBLEMS`] problems
/// in file order and the number of the others.
pub fn validation(scene: &Scene) -> Validation {
    let mut c = Checker {
        materials: &scene.materials,
        found: Validation::default(),
    };
    let root = FieldPath::default();
    if scene.format_version != FORMAT_VERSION {
        c.fail(
            root.key("format_version"),
            format!(
                "this build reads format version {FORMAT_VERSION}, the file has {}",
                scene.format_version
            ),
        );
    }
    if scene.name.trim().is_empty() {
        c.fail(root.key("name"), "must not be empty");
    }
    for (name, m) in &scene.materials {
        c.material(&root.key("materials").key(name), m);
    }
    if scene.emitters.iter().all(|e| !e.enabled) {
        c.fail(
            root.key("emitter"),
            "the luminaire needs at least one enabled [[emitter]]",
        );
    }
    let mut triangles: u64 = 0;
    let mut part_over_limit = false;
    for (i, e) in scene.emitters.iter().enumerate() {
        c.emitter(&root.key("emitter").index(i), e);
        if e.enabled {
            triangles = triangles.saturating_add(emitter_triangle_count(&e.shape));
        }
    }
    for (i, p) in scene.parts.iter().enumerate() {
        let part_triangles = c.part(&root.key("part").index(i), p);
        part_over_limit |= part_triangles > MAX_PART_TRIANGLES;
        if p.enabled {
            triangles = triangles.saturating_add(part_triangles);
        }
    }
    // One part over its own limit is the problem to fix first.
    if triangles > MAX_SCENE_TRIANGLES && !part_over_limit {
        c.fail(
            root.key("part"),
            format!(
                "the enabled parts and emitters would have {triangles} triangles together, at most {MAX_SCENE_TRIANGLES}"
            ),
        );
    }
    if let Some(opening) = &scene.opening {
        let at = root.key("opening");
        let size = |c: &mut Checker, key: &str, v: f64| {
            if !(v.is_finite() && v > 0.0 && v <= 50.0) {
                c.fail(at.key(key), format!("must be from 0 to 50 m, got {v}"));
            }
        };
        let height = |c: &mut Checker, v: f64| {
            if !(v.is_finite() && (0.0..=50.0).contains(&v)) {
                c.fail(
                    at.key("height_m"),
                    format!("must be from 0 to 50 m, got {v}"),
                );
            }
        };
        match opening {
            LuminousOpening::Rectangle {
                length_m,
                width_m,
                height_m,
            } => {
                size(&mut c, "length_m", *length_m);
                size(&mut c, "width_m", *width_m);
                height(&mut c, *height_m);
            }
            LuminousOpening::Disk {
                diameter_m,
                height_m,
            } => {
                size(&mut c, "diameter_m", *diameter_m);
                height(&mut c, *height_m);
            }
            LuminousOpening::None => {}
            LuminousOpening::PartAperture { part } => {
                if !scene.parts.iter().any(|p| &p.name == part && p.enabled) {
                    c.fail(
                        at.key("part"),
                        format!("names no enabled [[part]] ('{part}')"),
                    );
                }
            }
        }
    }
    // The writers refuse what their readers would: IES and EULUMDAT
    // files hold at most 1e9 W (`lucerna_photometry::plausible`).
    let watts = scene.export.input_watts;
    if !(watts.is_finite() && (0.0..=1e9).contains(&watts)) {
        c.fail(
            root.key("export").key("input_watts"),
            format!("must be from 0 to 1e9 W, got {watts}"),
        );
    }
    c.found
}
