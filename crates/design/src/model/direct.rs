//! The geometry a direct design works from: a revolved mirror about the
//! axis of one Lambertian LED facing along it, read from the scene; the
//! meridian model of that mirror; and the direct design itself (the
//! energy-balance mapping of [`super::mapping`] onto the light the
//! mirror should make, its profile sampled into control points).

use glam::{DQuat, DVec3};
use lucerna_scene::{Emission, EmitterShape, Interpolation, Material, Scene, Shape};

use super::mapping::{self, MappedProfile, PointSource, Wanted};
use super::meridian::MeridianModel;

/// The mirror and its source, in the part's r-z half-plane.
#[derive(Debug, Clone, PartialEq)]
pub struct Geometry {
    /// The mirror's part.
    pub part: usize,
    pub source: PointSource,
    /// The source's radius (a rectangle's: the disk of its area).
    pub source_radius: f64,
    /// The mirror's control points, as the start has them.
    pub profile: Vec<[f64; 2]>,
    pub interpolation: Interpolation,
    pub segments_per_span: u32,
    /// The mirror's reflectance, and whether it is specular (a mirror or
    /// a rough conductor, which the meridian model can trace).
    pub reflectance: f64,
    pub specular: bool,
}

/// Why a scene has no direct design.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum NotMappable {
    #[error("part '{0}' is not a revolved profile")]
    NotRevolved(String),
    #[error("part '{0}' is not on the axis (moved sideways or tilted)")]
    OffAxis(String),
    #[error("part '{0}' has straight segments; the direct design draws a Catmull-Rom curve")]
    Linear(String),
    #[error("the scene has {0} emitters; the direct design needs one")]
    Emitters(usize),
    #[error("emitter '{0}' is not a Lambertian disk or rectangle on the axis facing along it")]
    Emitter(String),
}

impl Geometry {
    /// The geometry of `part` in `scene`.
    pub fn of(scene: &Scene, part: usize) -> Result<Geometry, NotMappable> {
        let p = &scene.parts[part];
        let Shape::Revolved(shape) = &p.shape else {
            return Err(NotMappable::NotRevolved(p.name.clone()));
        };
        let t = &p.transform;
        if t.translate[0] != 0.0
            || t.translate[1] != 0.0
            || t.rotate_deg != [0.0; 3]
            || t.scale != [1.0; 3]
        {
            return Err(NotMappable::OffAxis(p.name.clone()));
        }
        if shape.interpolation != Interpolation::CatmullRom || shape.profile.len() < 3 {
            return Err(NotMappable::Linear(p.name.clone()));
        }
        let emitters: Vec<_> = scene.emitters.iter().filter(|e| e.enabled).collect();
        let [emitter] = emitters.as_slice() else {
            return Err(NotMappable::Emitters(emitters.len()));
        };
        let refuse = || NotMappable::Emitter(emitter.name.clone());
        if emitter.emission != Emission::Lambertian {
            return Err(refuse());
        }
        let et = &emitter.transform;
        if et.translate[0].abs() > 1e-9 || et.translate[1].abs() > 1e-9 {
            return Err(refuse());
        }
        let [rx, ry, rz] = et.rotate_deg.map(f64::to_radians);
        let normal = DQuat::from_euler(glam::EulerRot::ZYX, rz, ry, rx) * DVec3::NEG_Z;
        if normal.x.abs() > 1e-6 || normal.y.abs() > 1e-6 {
            return Err(refuse());
        }
        let scale = et.scale[0].abs().max(et.scale[1].abs());
        let source_radius = scale
            * match emitter.shape {
                EmitterShape::Disk { radius } => radius,
                EmitterShape::Rectangle { width, depth } => {
                    (width * depth / std::f64::consts::PI).sqrt()
                }
                _ => return Err(refuse()),
            };
        let (reflectance, specular) = match scene.materials.get(&p.material) {
            Some(Material::Mirror { reflectance }) => (*reflectance, true),
            Some(Material::RoughConductor { reflectance, .. }) => (*reflectance, true),
            Some(Material::Lambertian { albedo }) => (*albedo, false),
            Some(Material::Diffuser {
                reflectance,
                transmittance,
            }) => (reflectance + transmittance, false),
            Some(Material::Dielectric { .. }) => (1.0, false),
            _ => (0.0, false),
        };
        Ok(Geometry {
            part,
            source: PointSource {
                z: et.translate[2] - t.translate[2],
                facing_down: normal.z < 0.0,
            },
            source_radius,
            profile: shape.profile.clone(),
            interpolation: shape.interpolation,
            segments_per_span: shape.segments_per_span,
            reflectance,
            specular,
        })
    }

    /// The meridian model of this mirror, tabulating on `gammas_deg` (the
    /// target's angles), where the mirror is specular.
    pub fn model(&self, gammas_deg: &[f64]) -> Option<MeridianModel> {
        self.specular.then(|| MeridianModel {
            source_z: self.source.z,
            source_radius: self.source_radius,
            facing_down: self.source.facing_down,
            reflectance: self.reflectance,
            interpolation: self.interpolation,
            segments_per_span: self.segments_per_span,
            gammas_deg: gammas_deg.to_vec(),
        })
    }

    /// The two ends of the start's profile.
    pub fn ends(&self) -> [[f64; 2]; 2] {
        [self.profile[0], self.profile[self.profile.len() - 1]]
    }

    /// The aperture's rim, seen from the source (θ from its facing
    /// direction, radians): the end nearer the axis of the source's beam.
    pub fn rim_theta(&self) -> f64 {
        let [a, b] = self.ends();
        self.source.polar(a).0.min(self.source.polar(b).0)
    }
}

/// The direct designs for a point source between the start's ends that
/// make `wanted` (relative intensity against γ on the target's nodes):
/// the mapping's whole family ([`mapping::mapping_family`]).
pub fn mapped_profiles(
    geometry: &Geometry,
    gammas_deg: &[f64],
    wanted: &[f64],
) -> Vec<MappedProfile> {
    let sampled = Wanted::sampled(WANTED_STEP_DEG, |g| linear_at(gammas_deg, wanted, g));
    mapping::mapping_family(&geometry.source, geometry.ends(), &sampled)
}

/// The step the wanted light is sampled on for the mapping (degrees).
const WANTED_STEP_DEG: f64 = 0.02;

/// `values` at `x`, linear between `xs` (zero outside).
pub fn linear_at(xs: &[f64], values: &[f64], x: f64) -> f64 {
    let n = xs.len();
    if n == 0 || x < xs[0] || x > xs[n - 1] {
        return 0.0;
    }
    if n == 1 {
        return values[0];
    }
    let j = xs.partition_point(|&g| g <= x).clamp(1, n - 1);
    let span = xs[j] - xs[j - 1];
    let t = if span > 0.0 {
        (x - xs[j - 1]) / span
    } else {
        0.0
    };
    values[j - 1] * (1.0 - t) + values[j] * t
}
