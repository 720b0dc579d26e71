//! The luminaire model as it is stored in a scene file.
//!
//! Lengths are metres, flux lumens, angles degrees (file boundary). Luminaire
//! coordinates are right-handed, z up; the photometric axis points down (−z).

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

/// Shapes have their own module, one file each; the enum is part of the
/// file format, so it is reachable from here too.
pub use crate::profile::Interpolation;
pub use crate::shapes::Shape;
use crate::shapes::defaults::{is_true, is_zero, yes};

/// The scene-file format version this build reads and writes.
pub const FORMAT_VERSION: u32 = 1;

/// A luminaire: emitters inside parts made of materials.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Scene-file format version ([`FORMAT_VERSION`]).
    pub format_version: u32,
    /// Luminaire name, carried into exported IES/LDT files.
    pub name: String,
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub description: String,
    /// Manufacturer, for exported files' `[MANUFAC]`.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub manufacturer: String,
    /// Named materials referenced by parts and emitters.
    #[serde(default)]
    pub materials: BTreeMap<String, Material>,
    /// `[[emitter]]` tables.
    #[serde(default, rename = "emitter")]
    pub emitters: Vec<Emitter>,
    /// `[[part]]` tables.
    #[serde(default, rename = "part")]
    pub parts: Vec<Part>,
    /// The luminous opening exported files declare and the preview room's
    /// polygonal light uses; unset, the luminaire's footprint seen from
    /// below.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub opening: Option<LuminousOpening>,
    /// `[export]`: what exported files say beyond the name and
    /// manufacturer; absent in older files, and not written while empty.
    #[serde(default, skip_serializing_if = "ExportKeywords::is_empty")]
    pub export: ExportKeywords,
}

impl Scene {
    /// The files the scene reads besides itself (OBJ meshes, measured
    /// emitter profiles), relative to the scene file as written, each
    /// once, in the order they appear: what a scene's identity covers.
    pub fn referenced_files(&self) -> Vec<&str> {
        let meshes = self.parts.iter().filter_map(|p| match &p.shape {
            Shape::Mesh(m) => Some(m.path.as_str()),
            _ => None,
        });
        let profiles = self.emitters.iter().filter_map(|e| match &e.emission {
            Emission::Profile(path) => Some(path.as_str()),
            _ => None,
        });
        let ray_files = self.emitters.iter().filter_map(|e| match &e.shape {
            EmitterShape::RayFile { path } => Some(path.as_str()),
            _ => None,
        });
        let mut files: Vec<&str> = Vec::new();
        for f in meshes.chain(profiles).chain(ray_files) {
            if !files.contains(&f) {
                files.push(f);
            }
        }
        files
    }

    /// Whether the two scenes emit the same light: equal but for the
    /// labels exported files carry (name, description, manufacturer,
    /// `[export]`), which an editor changes without restarting a run.
    pub fn same_light(&self, other: &Scene) -> bool {
        // Destructured whole, so that a new field has to be sorted here.
        let Scene {
            format_version,
            name: _,
            description: _,
            manufacturer: _,
            materials,
            emitters,
            parts,
            opening,
            export: _,
        } = self;
        *format_version == other.format_version
            && *materials == other.materials
            && *emitters == other.emitters
            && *parts == other.parts
            // Not light, but the luminous opening is the snapshot's: the
            // preview room lights through it.
            && *opening == other.opening
    }
}

/// The keywords of exported IES and EULUMDAT files (LM-63-2019 section
/// 5.2; EULUMDAT lines 9-12 and the lamp set). An empty field takes the
/// bake's default: the scene's name for the luminaire and its catalogue
/// number, "Lucerna simulation of FILE" for the test report, the photon
/// tracer for the laboratory, the emitters' names for the lamp.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ExportKeywords {
    /// IES `[LUMINAIRE]`, EULUMDAT luminaire name.
    #[serde(skip_serializing_if = "String::is_empty")]
    pub luminaire: String,
    /// IES `[LUMCAT]`, EULUMDAT luminaire number.
    #[serde(skip_serializing_if = "String::is_empty")]
    pub catalogue_number: String,
    /// IES `[TEST]`, EULUMDAT measurement report number.
    #[serde(skip_serializing_if = "String::is_empty")]
    pub test_report: String,
    /// IES `[TESTLAB]`.
    #[serde(skip_serializing_if = "String::is_empty")]
    pub test_lab: String,
    /// IES `[LAMP]`, EULUMDAT type of lamps.
    #[serde(skip_serializing_if = "String::is_empty")]
    pub lamp: String,
    /// IES `[LAMPCAT]`.
    #[serde(skip_serializing_if = "String::is_empty")]
    pub lamp_catalogue_number: String,
    /// EULUMDAT colour temperature of the lamps, e.g. "3000 K".
    #[serde(skip_serializing_if = "String::is_empty")]
    pub colour_temperature: String,
    /// EULUMDAT colour rendering index, e.g. "Ra 90".
    #[serde(skip_serializing_if = "String::is_empty")]
    pub colour_rendering: String,
    /// Input power of the luminaire (W): IES input watts, EULUMDAT
    /// wattage including ballast; 0 when not stated.
    #[serde(skip_serializing_if = "is_zero")]
    pub input_watts: f64,
}

impl ExportKeywords {
    pub fn is_empty(&self) -> bool {
        *self == ExportKeywords::default()
    }
}

/// The luminous opening (m), in the luminaire's frame: IES width, length
/// and height with their shape, EULUMDAT's luminous area. It matters in
/// the near field, where a room is lit by the opening's polygon.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "shape", rename_all = "snake_case", deny_unknown_fields)]
pub enum LuminousOpening {
    /// `length_m` along x (C0-C180), `width_m` along y (C90-C270).
    Rectangle {
        length_m: f64,
        width_m: f64,
        #[serde(default)]
        height_m: f64,
    },
    Disk {
        diameter_m: f64,
        #[serde(default)]
        height_m: f64,
    },
    /// A point source: the files declare no opening.
    None,
    /// The footprint seen from below of one part, e.g. a reflector's exit
    /// aperture: a disk when the part is round about the axis.
    PartAperture { part: String },
}

/// Surface or volume optical behaviour. Reflectances and transmittances are
/// fractions of the incident flux (0–1).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum Material {
    /// Absorbs every photon (black paint, the LED's PCB).
    Absorber,
    /// Ideal diffuse reflector (white paint).
    Lambertian { albedo: f64 },
    /// Ideal specular reflector (polished aluminium, silver film).
    Mirror { reflectance: f64 },
    /// Anisotropic microfacet conductor (brushed or anodised aluminium).
    /// Roughness is the GGX α along the part's local u and v axes; the
    /// anisotropy axes are rotated by `orientation_deg` about the normal.
    RoughConductor {
        reflectance: f64,
        roughness_u: f64,
        roughness_v: f64,
        #[serde(default)]
        orientation_deg: f64,
    },
    /// Smooth dielectric (lens, cover glass): Fresnel reflection and
    /// refraction. Must be a closed solid with outward normals.
    /// `absorption_per_m` is the internal absorption coefficient (1/m).
    Dielectric {
        ior: f64,
        #[serde(default)]
        absorption_per_m: f64,
    },
    /// Translucent diffuser (opal glass, frosted PMMA) as a thin sheet:
    /// Lambertian reflection and Lambertian transmission.
    Diffuser {
        reflectance: f64,
        transmittance: f64,
    },
}

impl Material {
    /// The material's kind as written in scene files.
    pub fn kind(&self) -> &'static str {
        match self {
            Material::Absorber => "absorber",
            Material::Lambertian { .. } => "lambertian",
            Material::Mirror { .. } => "mirror",
            Material::RoughConductor { .. } => "rough_conductor",
            Material::Dielectric { .. } => "dielectric",
            Material::Diffuser { .. } => "diffuser",
        }
    }
}

/// Translate · rotate · scale, applied to a part in that order from the
/// right (scale first). Rotation is by Euler angles about x, then y, then z.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Transform {
    #[serde(default)]
    pub translate: [f64; 3],
    #[serde(default)]
    pub rotate_deg: [f64; 3],
    #[serde(default = "unit_scale")]
    pub scale: [f64; 3],
}

fn unit_scale() -> [f64; 3] {
    [1.0; 3]
}

impl Default for Transform {
    fn default() -> Self {
        Transform {
            translate: [0.0; 3],
            rotate_deg: [0.0; 3],
            scale: unit_scale(),
        }
    }
}

impl Transform {
    pub fn is_identity(&self) -> bool {
        *self == Transform::default()
    }

    /// `luminaire_from_part` as a double-precision affine matrix.
    pub fn matrix(&self) -> glam::DAffine3 {
        let [rx, ry, rz] = self.rotate_deg.map(f64::to_radians);
        let rotation = glam::DQuat::from_euler(glam::EulerRot::ZYX, rz, ry, rx);
        glam::DAffine3::from_scale_rotation_translation(
            glam::DVec3::from_array(self.scale),
            rotation,
            glam::DVec3::from_array(self.translate),
        )
    }
}

/// A piece of the luminaire: a shape, where it is, what it is made of.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Part {
    pub name: String,
    pub shape: Shape,
    /// Name of a material in `[materials]`.
    pub material: String,
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    pub enabled: bool,
    #[serde(default, skip_serializing_if = "Transform::is_identity")]
    pub transform: Transform,
    /// How the surface is finished (hammered, rippled, …) on top of its
    /// shape and material.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub finish: Option<crate::finish::Finish>,
}

/// Shape of a light-emitting surface, in the emitter's local frame.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum EmitterShape {
    /// Disk in the z = 0 plane emitting towards −z (an LED's die).
    Disk { radius: f64 },
    /// Rectangle in the z = 0 plane emitting towards −z (a COB, an OLED).
    Rectangle { width: f64, depth: f64 },
    /// Sphere emitting outwards (a filament bulb's envelope).
    Sphere { radius: f64 },
    /// Cylinder about z, centred, emitting from its side outwards (a tube).
    Cylinder { radius: f64, height: f64 },
    /// An LED maker's measured rays (IES TM-25 file, path relative to the
    /// scene file): photons start at the file's rays, in the file's frame
    /// (mm) placed by the emitter's transform, sampled in proportion to
    /// each ray's luminous flux. The file gives the directions, so the
    /// emission must be Lambertian (unused); there is no surface.
    RayFile { path: String },
}

/// Angular distribution of the emission leaving each surface point.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Emission {
    /// Radiance is the same in every direction of the outward hemisphere.
    Lambertian,
    /// A measured distribution from an IES or LDT file (path relative to the
    /// scene file), in the emitter's local frame, importance-sampled by the
    /// tracer.
    Profile(String),
}

/// What `flux_lm` reads as where a scene leaves it out, until a ray file
/// gives it (every other emitter must state it).
fn flux_not_given() -> f64 {
    f64::NAN
}

/// A light source.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Emitter {
    pub name: String,
    pub shape: EmitterShape,
    /// Luminous flux emitted (lm). A ray-file emitter may leave it out:
    /// the file's own is read when the scene is ([`crate::parse_scene`]).
    #[serde(default = "flux_not_given")]
    pub flux_lm: f64,
    #[serde(default = "lambertian")]
    pub emission: Emission,
    /// Material of the emitter's own surface (photons that come back to it);
    /// absent means absorbing.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub material: Option<String>,
    #[serde(default = "yes", skip_serializing_if = "is_true")]
    pub enabled: bool,
    #[serde(default, skip_serializing_if = "Transform::is_identity")]
    pub transform: Transform,
}

fn lambertian() -> Emission {
    Emission::Lambertian
}
