//! The luminaire model as it is stored in a scene file.
//!
//! Lengths are metres, flux lumens, angles degrees (file boundary). Luminaire
//! coordinates are right-handed, z up; the photometric axis points down (−z).

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

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

/// How a 2D profile is interpolated between its control points.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Interpolation {
    /// Straight segments between control points.
    Linear,
    /// A Catmull-Rom spline through the control points (smooth, editable).
    #[default]
    CatmullRom,
}

fn default_around() -> u32 {
    64
}
fn default_along() -> u32 {
    32
}
fn default_per_span() -> u32 {
    8
}
fn yes() -> bool {
    true
}
fn is_false(b: &bool) -> bool {
    !*b
}
fn is_true(b: &bool) -> bool {
    *b
}
fn is_zero(x: &f64) -> bool {
    *x == 0.0
}
fn is_zero_u32(x: &u32) -> bool {
    *x == 0
}

/// Geometry generators. Surfaces of revolution are about the local z axis;
/// their normals point towards the axis (the lamp side). Closed solids (box,
/// cylinder) have outward normals.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum Shape {
    /// Paraboloid reflector with its focus at the origin, opening downwards
    /// (−z): vertex at z = f, `r² = 4 f (f − z)`. `neck_diameter` cuts a
    /// hole around the vertex for the lamp.
    Paraboloid {
        focal_length: f64,
        aperture_diameter: f64,
        #[serde(default, skip_serializing_if = "is_zero")]
        neck_diameter: f64,
        #[serde(default = "default_around")]
        segments_around: u32,
        #[serde(default = "default_along")]
        segments_along: u32,
        /// Flat facets (`segments_around` × `segments_along`) instead of a
        /// smooth surface.
        #[serde(default, skip_serializing_if = "is_false")]
        faceted: bool,
    },
    /// Ellipsoidal reflector section: near focus at the origin, far focus at
    /// (0, 0, −`focal_distance`), vertex `vertex_distance` above the near
    /// focus; the section ends at the plane z = −`cut_below_focus`.
    Ellipsoid {
        focal_distance: f64,
        vertex_distance: f64,
        cut_below_focus: f64,
        #[serde(default, skip_serializing_if = "is_zero")]
        neck_diameter: f64,
        #[serde(default = "default_around")]
        segments_around: u32,
        #[serde(default = "default_along")]
        segments_along: u32,
        #[serde(default, skip_serializing_if = "is_false")]
        faceted: bool,
    },
    /// A profile `[r, z]` (metres, r ≥ 0) revolved about the z axis.
    Revolved {
        profile: Vec<[f64; 2]>,
        #[serde(default)]
        interpolation: Interpolation,
        #[serde(default = "default_around")]
        segments_around: u32,
        /// Segments per span between two control points.
        #[serde(default = "default_per_span")]
        segments_per_span: u32,
        #[serde(default, skip_serializing_if = "is_false")]
        faceted: bool,
    },
    /// A profile `[x, z]` extruded along y over `length` (centred), for
    /// linear reflectors and troughs; end caps close the profile's chord.
    Extruded {
        profile: Vec<[f64; 2]>,
        length: f64,
        #[serde(default)]
        interpolation: Interpolation,
        #[serde(default = "default_per_span")]
        segments_per_span: u32,
        #[serde(default = "yes", skip_serializing_if = "is_true")]
        end_caps: bool,
    },
    /// Parallel thin blades along y, spaced along x, hanging from z = 0 down
    /// to −`blade_height`, each tilted by `tilt_deg` about its own long axis;
    /// optional cross blades along x make a cell louvre.
    Louvre {
        blade_count: u32,
        spacing: f64,
        blade_height: f64,
        blade_length: f64,
        #[serde(default, skip_serializing_if = "is_zero")]
        tilt_deg: f64,
        #[serde(default, skip_serializing_if = "is_zero_u32")]
        cross_blade_count: u32,
        #[serde(default, skip_serializing_if = "is_zero")]
        cross_spacing: f64,
    },
    /// Rectangular flat plate in the z = 0 plane, normal −z.
    Plate { width: f64, depth: f64 },
    /// Circular flat disk in the z = 0 plane, normal −z.
    Disk {
        radius: f64,
        #[serde(default = "default_around")]
        segments_around: u32,
    },
    /// Spherical cap (bell, diffuser dome): pole at z = `height`, rim in the
    /// z = 0 plane, normals towards the sphere's centre.
    Dome {
        radius: f64,
        height: f64,
        #[serde(default = "default_around")]
        segments_around: u32,
        #[serde(default = "default_along")]
        segments_along: u32,
    },
    /// Cylinder about z, centred at the origin, outward normals.
    Cylinder {
        radius: f64,
        height: f64,
        #[serde(default = "yes", skip_serializing_if = "is_true")]
        cap_top: bool,
        #[serde(default = "yes", skip_serializing_if = "is_true")]
        cap_bottom: bool,
        #[serde(default = "default_around")]
        segments_around: u32,
    },
    /// Axis-aligned box centred at the origin, outward normals.
    Box {
        size: [f64; 3],
        #[serde(default, skip_serializing_if = "is_false")]
        open_bottom: bool,
    },
    /// Wavefront OBJ mesh, path relative to the scene file. Materials are
    /// assigned per OBJ object/group name (or its `usemtl` name) through
    /// `group_materials`; the part's `material` is the default.
    Mesh {
        path: String,
        #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
        group_materials: BTreeMap<String, String>,
    },
}

impl Shape {
    pub fn kind(&self) -> &'static str {
        match self {
            Shape::Paraboloid { .. } => "paraboloid",
            Shape::Ellipsoid { .. } => "ellipsoid",
            Shape::Revolved { .. } => "revolved",
            Shape::Extruded { .. } => "extruded",
            Shape::Louvre { .. } => "louvre",
            Shape::Plate { .. } => "plate",
            Shape::Disk { .. } => "disk",
            Shape::Dome { .. } => "dome",
            Shape::Cylinder { .. } => "cylinder",
            Shape::Box { .. } => "box",
            Shape::Mesh { .. } => "mesh",
        }
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

/// A light source.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Emitter {
    pub name: String,
    pub shape: EmitterShape,
    /// Luminous flux emitted (lm).
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
