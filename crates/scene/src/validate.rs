//! Parameter validation: every number finite and in its physical range,
//! every reference resolved, every resolution sane.

use std::fmt;

use crate::model::{Emitter, EmitterShape, FORMAT_VERSION, Material, Part, Scene, Shape};

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
    fn key(&self, k: &str) -> FieldPath {
        let mut p = self.clone();
        p.0.push(PathSegment::Key(k.to_owned()));
        p
    }
    fn index(&self, i: usize) -> FieldPath {
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
/// Largest length parameter (m) accepted for any shape.
pub const MAX_LENGTH_M: f64 = 50.0;

struct Checker {
    problems: Vec<Invalid>,
}

impl Checker {
    fn fail(&mut self, field: FieldPath, message: impl Into<String>) {
        self.problems.push(Invalid {
            field,
            message: message.into(),
        });
    }

    fn finite(&mut self, at: &FieldPath, name: &str, v: f64) -> bool {
        if v.is_finite() {
            true
        } else {
            self.fail(at.key(name), format!("must be a finite number, got {v}"));
            false
        }
    }

    fn fraction(&mut self, at: &FieldPath, name: &str, v: f64) {
        if self.finite(at, name, v) && !(0.0..=1.0).contains(&v) {
            self.fail(at.key(name), format!("must be between 0 and 1, got {v}"));
        }
    }

    /// A length in (0, MAX_LENGTH_M] metres.
    fn length(&mut self, at: &FieldPath, name: &str, v: f64) {
        if self.finite(at, name, v) && !(v > 0.0 && v <= MAX_LENGTH_M) {
            self.fail(
                at.key(name),
                format!("must be a length in metres, > 0 and ≤ {MAX_LENGTH_M}, got {v}"),
            );
        }
    }

    fn non_negative(&mut self, at: &FieldPath, name: &str, v: f64) {
        if self.finite(at, name, v) && !(0.0..=MAX_LENGTH_M).contains(&v) {
            self.fail(
                at.key(name),
                format!("must be ≥ 0 and ≤ {MAX_LENGTH_M}, got {v}"),
            );
        }
    }

    fn segments(&mut self, at: &FieldPath, name: &str, v: u32, min: u32) {
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

    fn profile(&mut self, at: &FieldPath, profile: &[[f64; 2]], revolved: bool) {
        let at = at.key("profile");
        if profile.len() < 2 {
            self.fail(at.clone(), "needs at least 2 control points");
            return;
        }
        if profile.len() > MAX_SEGMENTS as usize {
            self.fail(at.clone(), format!("at most {MAX_SEGMENTS} control points"));
            return;
        }
        for (i, p) in profile.iter().enumerate() {
            if p.iter().any(|x| !x.is_finite() || x.abs() > MAX_LENGTH_M) {
                self.fail(
                    at.index(i),
                    format!("must be finite and within ±{MAX_LENGTH_M} m, got {p:?}"),
                );
                return;
            }
            if revolved && p[0] < 0.0 {
                self.fail(
                    at.index(i),
                    format!("radius r must be ≥ 0 in a revolved profile, got {}", p[0]),
                );
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
        if revolved {
            // A span lying on the axis revolves into nothing.
            for i in 1..profile.len() {
                if profile[i][0] == 0.0 && profile[i - 1][0] == 0.0 {
                    self.fail(
                        at.index(i),
                        "two consecutive points on the axis (r = 0) give a zero-area surface",
                    );
                }
            }
        }
    }

    fn shape(&mut self, at: &FieldPath, shape: &Shape) {
        let at = at.key("shape");
        match shape {
            &Shape::Paraboloid {
                focal_length,
                aperture_diameter,
                neck_diameter,
                segments_around,
                segments_along,
                ..
            } => {
                self.length(&at, "focal_length", focal_length);
                self.length(&at, "aperture_diameter", aperture_diameter);
                self.non_negative(&at, "neck_diameter", neck_diameter);
                if neck_diameter >= aperture_diameter {
                    self.fail(
                        at.key("neck_diameter"),
                        format!(
                            "must be smaller than aperture_diameter ({aperture_diameter}), got {neck_diameter}"
                        ),
                    );
                }
                self.segments(&at, "segments_around", segments_around, 3);
                self.segments(&at, "segments_along", segments_along, 1);
            }
            &Shape::Ellipsoid {
                focal_distance,
                vertex_distance,
                cut_below_focus,
                neck_diameter,
                segments_around,
                segments_along,
                ..
            } => {
                self.length(&at, "focal_distance", focal_distance);
                self.length(&at, "vertex_distance", vertex_distance);
                self.non_negative(&at, "neck_diameter", neck_diameter);
                if self.finite(&at, "cut_below_focus", cut_below_focus) {
                    // The section must run from the vertex (z = vertex_distance)
                    // to the cut plane, above the far vertex.
                    let far_vertex = focal_distance + vertex_distance;
                    if !(cut_below_focus > -vertex_distance && cut_below_focus < far_vertex) {
                        self.fail(
                            at.key("cut_below_focus"),
                            format!(
                                "must lie between −vertex_distance ({}) and the far vertex ({far_vertex}), got {cut_below_focus}",
                                -vertex_distance
                            ),
                        );
                    }
                }
                let c = 0.5 * focal_distance;
                let a = c + vertex_distance;
                let b = (a * a - c * c).sqrt();
                if neck_diameter >= 2.0 * b {
                    self.fail(
                        at.key("neck_diameter"),
                        format!(
                            "must be smaller than the ellipsoid's minor diameter {}",
                            2.0 * b
                        ),
                    );
                } else if cut_below_focus.is_finite() && neck_diameter > 0.0 {
                    let t0 = (0.5 * neck_diameter / b).asin();
                    let z0 = -c + a * t0.cos();
                    if -cut_below_focus >= z0 {
                        self.fail(
                            at.key("cut_below_focus"),
                            "the cut plane lies above the neck: the section is empty",
                        );
                    }
                }
                self.segments(&at, "segments_around", segments_around, 3);
                self.segments(&at, "segments_along", segments_along, 1);
            }
            Shape::Revolved {
                profile,
                segments_around,
                segments_per_span,
                ..
            } => {
                self.profile(&at, profile, true);
                self.segments(&at, "segments_around", *segments_around, 3);
                self.segments(&at, "segments_per_span", *segments_per_span, 1);
                if profile.len().saturating_mul(*segments_per_span as usize) > MAX_SEGMENTS as usize
                {
                    self.fail(
                        at.key("segments_per_span"),
                        format!("control points × segments_per_span must be ≤ {MAX_SEGMENTS}"),
                    );
                }
            }
            Shape::Extruded {
                profile,
                length,
                segments_per_span,
                ..
            } => {
                self.profile(&at, profile, false);
                self.length(&at, "length", *length);
                self.segments(&at, "segments_per_span", *segments_per_span, 1);
                if profile.len().saturating_mul(*segments_per_span as usize) > MAX_SEGMENTS as usize
                {
                    self.fail(
                        at.key("segments_per_span"),
                        format!("control points × segments_per_span must be ≤ {MAX_SEGMENTS}"),
                    );
                }
            }
            &Shape::Louvre {
                blade_count,
                spacing,
                blade_height,
                blade_length,
                tilt_deg,
                cross_blade_count,
                cross_spacing,
            } => {
                self.segments(&at, "blade_count", blade_count, 1);
                self.length(&at, "spacing", spacing);
                self.length(&at, "blade_height", blade_height);
                self.length(&at, "blade_length", blade_length);
                if self.finite(&at, "tilt_deg", tilt_deg) && tilt_deg.abs() >= 89.0 {
                    self.fail(
                        at.key("tilt_deg"),
                        format!("must be within ±89°, got {tilt_deg}"),
                    );
                }
                if cross_blade_count > MAX_SEGMENTS {
                    self.fail(
                        at.key("cross_blade_count"),
                        format!("must be ≤ {MAX_SEGMENTS}, got {cross_blade_count}"),
                    );
                }
                if cross_blade_count > 0 {
                    self.length(&at, "cross_spacing", cross_spacing);
                    if blade_count < 2 {
                        self.fail(
                            at.key("cross_blade_count"),
                            "cross blades span between blades: needs blade_count ≥ 2",
                        );
                    }
                }
            }
            &Shape::Plate { width, depth } => {
                self.length(&at, "width", width);
                self.length(&at, "depth", depth);
            }
            &Shape::Disk {
                radius,
                segments_around,
            } => {
                self.length(&at, "radius", radius);
                self.segments(&at, "segments_around", segments_around, 3);
            }
            &Shape::Dome {
                radius,
                height,
                segments_around,
                segments_along,
            } => {
                self.length(&at, "radius", radius);
                self.length(&at, "height", height);
                if height > 2.0 * radius {
                    self.fail(
                        at.key("height"),
                        format!(
                            "a spherical cap is at most 2 × radius = {} high",
                            2.0 * radius
                        ),
                    );
                }
                self.segments(&at, "segments_around", segments_around, 3);
                self.segments(&at, "segments_along", segments_along, 1);
            }
            &Shape::Cylinder {
                radius,
                height,
                segments_around,
                ..
            } => {
                self.length(&at, "radius", radius);
                self.length(&at, "height", height);
                self.segments(&at, "segments_around", segments_around, 3);
            }
            Shape::Box { size, .. } => {
                for (i, &v) in size.iter().enumerate() {
                    if !(v.is_finite() && v > 0.0 && v <= MAX_LENGTH_M) {
                        self.fail(
                            at.key("size").index(i),
                            format!(
                                "must be a length in metres, > 0 and ≤ {MAX_LENGTH_M}, got {v}"
                            ),
                        );
                    }
                }
            }
            Shape::Mesh { path, .. } => {
                if path.trim().is_empty() {
                    self.fail(at.key("path"), "must name an OBJ file");
                }
            }
        }
    }

    fn material_ref(&mut self, scene: &Scene, at: FieldPath, name: &str) {
        if !scene.materials.contains_key(name) {
            let known: Vec<&str> = scene.materials.keys().map(String::as_str).collect();
            self.fail(
                at,
                format!(
                    "unknown material '{name}' (materials defined: {})",
                    if known.is_empty() {
                        "none".to_owned()
                    } else {
                        known.join(", ")
                    }
                ),
            );
        }
    }

    fn part(&mut self, scene: &Scene, at: &FieldPath, part: &Part) {
        if part.name.trim().is_empty() {
            self.fail(at.key("name"), "must not be empty");
        }
        self.material_ref(scene, at.key("material"), &part.material);
        if let Shape::Mesh {
            group_materials, ..
        } = &part.shape
        {
            for (group, material) in group_materials {
                self.material_ref(
                    scene,
                    at.key("shape").key("group_materials").key(group),
                    material,
                );
            }
        }
        self.shape(at, &part.shape);
        self.transform(at, &part.transform);
    }

    fn emitter(&mut self, scene: &Scene, at: &FieldPath, e: &Emitter) {
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
            self.material_ref(scene, at.key("material"), m);
        }
        self.transform(at, &e.transform);
    }
}

/// Checks a scene's parameters; returns every problem found, in file order.
pub fn validate(scene: &Scene) -> Vec<Invalid> {
    let mut c = Checker {
        problems: Vec::new(),
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
    for (i, e) in scene.emitters.iter().enumerate() {
        c.emitter(scene, &root.key("emitter").index(i), e);
    }
    for (i, p) in scene.parts.iter().enumerate() {
        c.part(scene, &root.key("part").index(i), p);
    }
    c.problems
}
