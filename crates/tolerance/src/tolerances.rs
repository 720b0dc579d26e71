//! The tolerances file (TOML): what manufacturing does to a luminaire.
//!
//! ```toml
//! [[tolerance]]                 # a placement or a continuous parameter
//! at = "LED.translate_x"        # PART/EMITTER.translate_x|y|z (m), .rotate_x|y|z (°),
//! normal = { sigma = 0.1e-3 }   # PART.FIELD (a shape parameter), EMITTER.flux_lm
//! truncate = 0.3e-3             # optional: no deviation beyond ±0.3 mm
//!
//! [[tolerance]]                 # (not beside a form error of the same part)
//! at = "reflector.focal_length"
//! uniform = { half_width = 0.05e-3 }
//!
//! [[form_error]]                # a pressed part's smooth deformation
//! part = "reflector"
//! sigma = 0.05e-3               # m, along the profile's normal
//! correlation_length = 10e-3    # m, along the profile's arc length
//!
//! [[slope_error]]               # the tool's surface slope spread
//! part = "reflector"
//! sigma_rad = 1e-3              # rms slope per axis
//! ```
//!
//! Every problem is named by the file, its line and the field.

use std::path::Path;

use lucerna_design::variables::{self, Place};
use lucerna_scene::{Material, Scene, Shape};
use serde::Deserialize;
use toml::Spanned;

use crate::distribution::{Distribution, Shape as Spread};
use crate::error::ToleranceError;

/// Where a scalar tolerance acts.
#[derive(Debug, Clone, PartialEq)]
pub enum At {
    /// A placement or a shape parameter (the design's variables).
    Variable(Place),
    /// An emitter's luminous flux (lm).
    EmitterFlux(usize),
}

/// One toleranced number.
#[derive(Debug, Clone, PartialEq)]
pub struct Scalar {
    /// As the file names it: `LED.translate_x`.
    pub name: String,
    pub at: At,
    /// The scene's value.
    pub nominal: f64,
    pub distribution: Distribution,
    /// "m", "°" or "lm".
    pub unit: &'static str,
}

/// A smooth random deformation of a part's profile along its normal: a
/// Gaussian process along the arc length (squared-exponential
/// covariance), so neighbouring points move together as a pressed part's
/// do.
#[derive(Debug, Clone, PartialEq)]
pub struct FormError {
    pub part: usize,
    pub part_name: String,
    /// Standard deviation along the normal (m).
    pub sigma_m: f64,
    /// Correlation length along the arc (m).
    pub correlation_length_m: f64,
}

/// A Gaussian slope spread a tool leaves on a part's surface, added to
/// its material on every built luminaire.
#[derive(Debug, Clone, PartialEq)]
pub struct SlopeError {
    pub part: usize,
    pub part_name: String,
    /// Root-mean-square slope per surface axis (rad).
    pub sigma_rad: f64,
}

/// What manufacturing does to a luminaire.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Tolerances {
    pub scalars: Vec<Scalar>,
    pub form_errors: Vec<FormError>,
    pub slope_errors: Vec<SlopeError>,
}

impl Tolerances {
    /// Whether anything varies from one built luminaire to the next.
    pub fn is_empty(&self) -> bool {
        self.scalars.is_empty() && self.form_errors.is_empty()
    }
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawFile {
    #[serde(default)]
    tolerance: Vec<Spanned<RawScalar>>,
    #[serde(default)]
    form_error: Vec<Spanned<RawForm>>,
    #[serde(default)]
    slope_error: Vec<Spanned<RawSlope>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScalar {
    at: Spanned<String>,
    normal: Option<Spanned<RawNormal>>,
    uniform: Option<Spanned<RawUniform>>,
    truncate: Option<Spanned<f64>>,
    offset: Option<Spanned<f64>>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawNormal {
    sigma: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawUniform {
    half_width: f64,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawForm {
    part: Spanned<String>,
    sigma: Spanned<f64>,
    correlation_length: Spanned<f64>,
}

#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSlope {
    part: Spanned<String>,
    sigma_rad: Spanned<f64>,
}

/// Reads and checks a tolerances file against `scene`.
pub fn load(path: &Path, scene: &Scene) -> Result<Tolerances, ToleranceError> {
    let text =
        lucerna_scene::io::read_limited_text(path, lucerna_scene::io::MAX_PROFILE_FILE_BYTES)
            .map_err(|e| ToleranceError::File {
                path: path.display().to_string(),
                line: 0,
                field: String::new(),
                why: e.to_string(),
            })?;
    parse(&text, scene).map_err(|(line, field, why)| ToleranceError::File {
        path: path.display().to_string(),
        line,
        field,
        why,
    })
}

/// A problem: the line (1-based; 0 for the file as a whole), the field
/// and why.
type Problem = (usize, String, String);

fn line_of(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())].matches('\n').count() + 1
}

/// Parses a tolerances file's text against `scene`.
pub fn parse(text: &str, scene: &Scene) -> Result<Tolerances, Problem> {
    let raw: RawFile = toml::from_str(text).map_err(|e| {
        let line = e.span().map_or(0, |s| line_of(text, s.start));
        (line, String::new(), e.message().to_owned())
    })?;
    let at_line = |span: std::ops::Range<usize>| line_of(text, span.start);
    let mut out = Tolerances::default();
    for (i, item) in raw.tolerance.iter().enumerate() {
        let line = at_line(item.span());
        let t = item.get_ref();
        let field = |f: &str| format!("tolerance[{i}].{f}");
        let shape = match (&t.normal, &t.uniform) {
            (Some(n), None) => Spread::Normal {
                sigma: n.get_ref().sigma,
            },
            (None, Some(u)) => Spread::Uniform {
                half_width: u.get_ref().half_width,
            },
            (Some(_), Some(u)) => {
                return Err((
                    at_line(u.span()),
                    field("uniform"),
                    "give one distribution: normal or uniform, not both".to_owned(),
                ));
            }
            (None, None) => {
                return Err((
                    line,
                    field("normal"),
                    "give a distribution: normal = { sigma = … } or uniform = { half_width = … }"
                        .to_owned(),
                ));
            }
        };
        let distribution = Distribution {
            shape,
            truncate: t.truncate.as_ref().map(|s| *s.get_ref()),
            offset: t.offset.as_ref().map_or(0.0, |s| *s.get_ref()),
        };
        if let Err(why) = distribution.check() {
            let (line, f) = if why.starts_with("truncate") {
                (
                    t.truncate.as_ref().map_or(line, |s| at_line(s.span())),
                    "truncate",
                )
            } else if why.starts_with("offset") {
                (
                    t.offset.as_ref().map_or(line, |s| at_line(s.span())),
                    "offset",
                )
            } else if let Some(n) = &t.normal {
                (at_line(n.span()), "normal.sigma")
            } else if let Some(u) = &t.uniform {
                (at_line(u.span()), "uniform.half_width")
            } else {
                (line, "normal")
            };
            return Err((line, field(f), why));
        }
        let name = t.at.get_ref().clone();
        let at_problem = |why: String| {
            (
                at_line(t.at.span()),
                field("at"),
                format!("\"{name}\": {why}"),
            )
        };
        let (at, nominal, unit) = resolve(scene, &name).map_err(at_problem)?;
        if out.scalars.iter().any(|s| s.at == at) {
            return Err(at_problem("toleranced twice".to_owned()));
        }
        out.scalars.push(Scalar {
            name,
            at,
            nominal,
            distribution,
            unit,
        });
    }
    for (i, item) in raw.form_error.iter().enumerate() {
        let f = item.get_ref();
        let field = |k: &str| format!("form_error[{i}].{k}");
        let part = find_part(scene, f.part.get_ref())
            .map_err(|why| (at_line(f.part.span()), field("part"), why))?;
        if !has_profile(&scene.parts[part].shape) {
            return Err((
                at_line(f.part.span()),
                field("part"),
                format!(
                    "part '{}' is a {}: a form error needs a profile (a revolved or extruded part) or a smooth surface of revolution (paraboloid, ellipsoid, dome)",
                    scene.parts[part].name,
                    scene.parts[part].shape.kind()
                ),
            ));
        }
        let sigma = *f.sigma.get_ref();
        if !(sigma.is_finite() && sigma > 0.0) {
            return Err((
                at_line(f.sigma.span()),
                field("sigma"),
                format!("must be a positive number (m), got {sigma}"),
            ));
        }
        let corr = *f.correlation_length.get_ref();
        if !(corr.is_finite() && corr > 0.0) {
            return Err((
                at_line(f.correlation_length.span()),
                field("correlation_length"),
                format!("must be a positive number (m), got {corr}"),
            ));
        }
        if out.form_errors.iter().any(|e| e.part == part) {
            return Err((
                at_line(f.part.span()),
                field("part"),
                format!("part '{}' has a form error already", f.part.get_ref()),
            ));
        }
        out.form_errors.push(FormError {
            part,
            part_name: f.part.get_ref().clone(),
            sigma_m: sigma,
            correlation_length_m: corr,
        });
    }
    for (i, item) in raw.slope_error.iter().enumerate() {
        let s = item.get_ref();
        let field = |k: &str| format!("slope_error[{i}].{k}");
        let part = find_part(scene, s.part.get_ref())
            .map_err(|why| (at_line(s.part.span()), field("part"), why))?;
        let material = &scene.parts[part].material;
        match scene.materials.get(material) {
            Some(Material::Mirror { .. } | Material::RoughConductor { .. }) => {}
            Some(m) => {
                return Err((
                    at_line(s.part.span()),
                    field("part"),
                    format!(
                        "part '{}' is of {} material '{material}': a slope error roughens a mirror or a rough conductor",
                        s.part.get_ref(),
                        m.kind()
                    ),
                ));
            }
            None => {
                return Err((
                    at_line(s.part.span()),
                    field("part"),
                    format!("the scene has no material '{material}'"),
                ));
            }
        }
        let sigma = *s.sigma_rad.get_ref();
        if !(sigma.is_finite() && sigma > 0.0 && sigma < 0.5) {
            return Err((
                at_line(s.sigma_rad.span()),
                field("sigma_rad"),
                format!("must be a positive slope below 0.5 rad, got {sigma}"),
            ));
        }
        if out.slope_errors.iter().any(|e| e.part == part) {
            return Err((
                at_line(s.part.span()),
                field("part"),
                format!("part '{}' has a slope error already", s.part.get_ref()),
            ));
        }
        out.slope_errors.push(SlopeError {
            part,
            part_name: s.part.get_ref().clone(),
            sigma_rad: sigma,
        });
    }
    // A form error redraws its part's shape from the nominal profile: a
    // shape parameter toleranced beside it would never act.
    for (i, item) in raw.tolerance.iter().enumerate() {
        let Some(s) = out.scalars.get(i) else {
            continue;
        };
        if let At::Variable(Place::Field { part, .. }) = &s.at
            && let Some(f) = out.form_errors.iter().find(|f| f.part == *part)
        {
            return Err((
                at_line(item.get_ref().at.span()),
                format!("tolerance[{i}].at"),
                format!(
                    "\"{}\": part '{}' has a form error, which deforms its nominal profile: tolerance its shape parameters or its form, not both",
                    s.name, f.part_name
                ),
            ));
        }
    }
    if out.scalars.is_empty() && out.form_errors.is_empty() && out.slope_errors.is_empty() {
        return Err((
            0,
            String::new(),
            "the file names no tolerance ([[tolerance]], [[form_error]] or [[slope_error]])"
                .to_owned(),
        ));
    }
    Ok(out)
}

/// Whether a part's shape has a profile a form error can deform.
pub fn has_profile(shape: &Shape) -> bool {
    variables::profile(shape).is_some()
        || lucerna_scene::shapes::editable_revolution(shape, 1e-6).is_some()
}

fn find_part(scene: &Scene, name: &str) -> Result<usize, String> {
    scene
        .parts
        .iter()
        .position(|p| p.name == name)
        .ok_or_else(|| {
            let names: Vec<&str> = scene.parts.iter().map(|p| p.name.as_str()).collect();
            format!(
                "the scene has no part '{name}' (its parts: {})",
                names.join(", ")
            )
        })
}

/// Where `name` acts, its nominal value and unit.
fn resolve(scene: &Scene, name: &str) -> Result<(At, f64, &'static str), String> {
    if let Some((owner, "flux_lm")) = name.rsplit_once('.') {
        let Some(i) = scene.emitters.iter().position(|e| e.name == owner) else {
            return Err(format!("the scene has no emitter '{owner}'"));
        };
        return Ok((At::EmitterFlux(i), scene.emitters[i].flux_lm, "lm"));
    }
    if name.ends_with(".profile") || name.contains(".profile[") {
        return Err(
            "a profile is toleranced as a whole by [[form_error]] (part, sigma, correlation_length)"
                .to_owned(),
        );
    }
    let found = variables::parse(scene, &[name.to_owned()], false).map_err(|e| match e {
        lucerna_design::DesignError::Vary { why, .. } => why,
        other => other.to_string(),
    })?;
    let [v] = found.as_slice() else {
        return Err("names more than one number".to_owned());
    };
    let unit = match &v.place {
        Place::Transform { rotate: true, .. } => "°",
        Place::Field { field, .. } if field.ends_with("_deg") => "°",
        _ => "m",
    };
    Ok((At::Variable(v.place.clone()), v.start, unit))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spot() -> Scene {
        lucerna_scene::parse_scene(
            include_str!("../../../assets/luminaires/parabolic_spot.toml"),
            Path::new("spot.toml"),
        )
        .expect("the example reads")
    }

    #[test]
    fn a_full_file_reads() {
        let t = parse(
            r#"
[[tolerance]]
at = "LED.translate_x"
normal = { sigma = 0.1e-3 }
truncate = 0.3e-3

[[tolerance]]
at = "reflector.focal_length"
uniform = { half_width = 0.05e-3 }

[[tolerance]]
at = "LED.flux_lm"
normal = { sigma = 20.0 }

[[slope_error]]
part = "reflector"
sigma_rad = 1e-3
"#,
            &spot(),
        )
        .expect("reads");
        assert_eq!(t.scalars.len(), 3);
        assert_eq!(t.scalars[1].nominal, 0.025);
        assert_eq!(t.scalars[2].at, At::EmitterFlux(0));
        assert_eq!(t.slope_errors[0].sigma_rad, 1e-3);
        let t = parse(
            "[[tolerance]]\nat = \"reflector.rotate_x\"\nnormal = { sigma = 0.5 }\n\n[[form_error]]\npart = \"reflector\"\nsigma = 0.05e-3\ncorrelation_length = 10e-3\n",
            &spot(),
        )
        .expect("a placement beside a form error");
        assert_eq!(t.form_errors[0].part, 0);
    }

    fn problem(text: &str) -> Problem {
        parse(text, &spot()).expect_err("refused")
    }

    #[test]
    fn each_problem_names_its_line_and_field() {
        let (line, field, why) = problem(
            "# comment\n\n[[tolerance]]\nat = \"lamp.translate_x\"\nnormal = { sigma = 1e-4 }\n",
        );
        assert_eq!((line, field.as_str()), (4, "tolerance[0].at"));
        assert!(why.contains("no part or emitter 'lamp'"), "{why}");

        let (line, field, why) =
            problem("[[tolerance]]\nat = \"reflector.focal_width\"\nnormal = { sigma = 1e-4 }\n");
        assert_eq!((line, field.as_str()), (2, "tolerance[0].at"));
        assert!(why.contains("focal_length"), "{why}");

        let (line, field, _) =
            problem("[[tolerance]]\nat = \"LED.translate_x\"\n\nnormal = { sigma = 0.0 }\n");
        assert_eq!((line, field.as_str()), (4, "tolerance[0].normal.sigma"));

        let (line, field, _) =
            problem("[[tolerance]]\nat = \"LED.translate_x\"\nnormal = { sigma = nan }\n");
        assert_eq!((line, field.as_str()), (3, "tolerance[0].normal.sigma"));

        let (line, field, why) = problem(
            "[[tolerance]]\nat = \"LED.translate_x\"\nnormal = { sigma = 1e-4 }\ntruncate = -1e-4\n",
        );
        assert_eq!((line, field.as_str()), (4, "tolerance[0].truncate"));
        assert!(why.contains("positive"), "{why}");

        let (line, field, _) = problem(
            "[[form_error]]\npart = \"reflector\"\nsigma = 1e-5\ncorrelation_length = -1.0\n",
        );
        assert_eq!(
            (line, field.as_str()),
            (4, "form_error[0].correlation_length")
        );

        let (line, _, why) = problem(
            "[[tolerance]]\nat = \"LED.translate_x\"\nnormal = { sigma = 1e-4 }\nsigmaa = 1\n",
        );
        assert_eq!(line, 4);
        assert!(why.contains("sigmaa"), "{why}");

        let (_, _, why) = problem("");
        assert!(why.contains("no tolerance"), "{why}");

        let (line, field, why) = problem(
            "[[form_error]]\npart = \"reflector\"\nsigma = 1e-5\ncorrelation_length = 0.01\n\n[[tolerance]]\nat = \"reflector.focal_length\"\nnormal = { sigma = 1e-5 }\n",
        );
        assert_eq!((line, field.as_str()), (7, "tolerance[0].at"));
        assert!(why.contains("not both"), "{why}");
    }
}
