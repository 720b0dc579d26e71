//! Parameter validation: every number finite and in its physical range,
//! every reference resolved, every resolution sane.
//!
//! This file holds the scene-level checks; the range checks every shape
//! shares are in [`crate::check`], and each shape's own ranges live with
//! its parameters in [`crate::shapes`].

pub use crate::check::{
    Checker, FieldPath, Invalid, MAX_LENGTH_M, MAX_LISTED_MATERIALS, MAX_LISTED_PROBLEMS,
    MAX_PART_TRIANGLES, MAX_SCENE_TRIANGLES, MAX_SEGMENTS, PathSegment, Validation,
};
use crate::model::{Emitter, EmitterShape, FORMAT_VERSION, LuminousOpening, Material, Part, Scene};
use crate::tessellate::emitter_triangle_count;

impl Checker<'_> {
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
        if let Some(finish) = &part.finish {
            for (field, why) in finish.problems() {
                let mut path = at.key("finish");
                for k in field.split('.') {
                    path = match k.split_once('[') {
                        Some((name, index)) => path
                            .key(name)
                            .index(index.trim_end_matches(']').parse().unwrap_or(0)),
                        None => path.key(k),
                    };
                }
                self.fail(path, why);
            }
        }
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
        if e.flux_lm.is_nan() {
            let message = if matches!(e.shape, EmitterShape::RayFile { .. }) {
                "not given, and the ray file gives none (it cannot be read: lucerna validate says why)"
            } else {
                "is missing: the emitter's luminous flux (lm); only a ray-file emitter may leave it out"
            };
            self.fail(at.key("flux_lm"), message);
        } else if self.finite(at, "flux_lm", e.flux_lm) && !(e.flux_lm > 0.0 && e.flux_lm <= 1e7) {
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
    let mut c = Checker::new(scene.materials.keys().map(String::as_str));
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
        if p.finish.is_some()
            && let Some(m) = scene.materials.get(&p.material)
            && matches!(m, Material::Dielectric { .. } | Material::Diffuser { .. })
        {
            c.fail(
                root.key("part").index(i).key("finish"),
                format!(
                    "a finish is traced on reflecting surfaces (mirror, rough_conductor, lambertian); '{}' is a {}",
                    p.material,
                    m.kind()
                ),
            );
        }
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
    c.into_validation()
}
