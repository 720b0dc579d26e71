//! The room file (TOML): a box room with its surfaces, the work plane, a
//! camera, and luminaires placed by position and rotation, each with a
//! profile from an IES/LDT file or from a luminaire scene to bake.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

/// The file format version this build reads and writes.
pub const ROOM_FORMAT_VERSION: u32 = 1;
/// Largest room dimension accepted (m): beyond it a unit slip (mm for m)
/// is likelier than a real hall.
pub const MAX_ROOM_M: f64 = 500.0;
/// Most luminaires in one room after arrays are expanded.
pub const MAX_LUMINAIRES: usize = 256;
/// Largest room file read: a room is a few hundred bytes of TOML.
pub const MAX_ROOM_FILE_BYTES: u64 = 16 * lucerna_scene::io::MIB;
/// Most work-plane grid points: a 500 m hall at 0.5 m, or an office at
/// 1 cm. Each point is shaded by every light; beyond this a spacing typo
/// asks for gigabytes (500 m at 0.01 m is 2.5 billion points).
pub const MAX_WORK_PLANE_POINTS: usize = 1_000_000;

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RoomFile {
    pub version: u32,
    #[serde(default)]
    pub name: String,
    pub room: BoxRoom,
    #[serde(default)]
    pub work_plane: WorkPlane,
    pub camera: Camera,
    #[serde(rename = "luminaire", default)]
    pub luminaires: Vec<LuminaireSpec>,
}

/// A rectangular room from (0, 0, 0) to (width, depth, height): x along
/// the width, y along the depth, z up.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BoxRoom {
    pub width_m: f64,
    pub depth_m: f64,
    pub height_m: f64,
    #[serde(default = "Surface::floor")]
    pub floor: Surface,
    #[serde(default = "Surface::walls")]
    pub walls: Surface,
    #[serde(default = "Surface::ceiling")]
    pub ceiling: Surface,
    /// An OBJ file (relative to the room file) whose triangles replace the
    /// box's six surfaces in the views; the box still bounds the camera
    /// and the work plane.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub obj: Option<String>,
    /// Multiplies the OBJ's coordinates (0.001 for millimetres).
    #[serde(default = "one", skip_serializing_if = "is_one")]
    pub obj_scale: f64,
    /// Surfaces of the OBJ's objects/groups by name, else by `usemtl`
    /// name; anything unnamed here is a wall.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub materials: BTreeMap<String, Surface>,
    /// Inter-reflected light: none (direct only) or a uniform estimate.
    #[serde(default)]
    pub indirect: Indirect,
}

/// How light reflected between the room's surfaces is accounted for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Indirect {
    /// Direct light only.
    #[default]
    None,
    /// The integrating-sphere estimate: every surface gets the same
    /// indirect illuminance Φ ρ̄ / (A (1 − ρ̄)), Φ the luminaires' flux, A
    /// the room's surface area, ρ̄ its area-weighted reflectance.
    Uniform,
}

fn is_one(v: &f64) -> bool {
    *v == 1.0
}

/// A room surface: diffuse reflectance plus an optional GGX specular layer.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Surface {
    /// Diffuse reflectance ρ (0–1).
    pub reflectance: f64,
    /// Specular reflectance at normal incidence F0 (0–1; 0.04 for most
    /// dielectric finishes, 0 for none).
    #[serde(default)]
    pub specular: f64,
    /// Perceptual roughness (GGX α = roughness²), 0–1.
    #[serde(default = "default_roughness")]
    pub roughness: f64,
}

fn default_roughness() -> f64 {
    0.5
}

impl Surface {
    /// EN 12464-1's typical floor (0.2), walls (0.5), ceiling (0.7).
    pub fn floor() -> Surface {
        Surface {
            reflectance: 0.2,
            specular: 0.04,
            roughness: 0.5,
        }
    }
    pub fn walls() -> Surface {
        Surface {
            reflectance: 0.5,
            specular: 0.0,
            roughness: 0.5,
        }
    }
    pub fn ceiling() -> Surface {
        Surface {
            reflectance: 0.7,
            specular: 0.0,
            roughness: 0.5,
        }
    }
}

/// The horizontal plane where the task illuminance is assessed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct WorkPlane {
    /// Height above the floor (m); 0.75–0.85 for desks.
    #[serde(default = "default_work_plane_height")]
    pub height_m: f64,
    /// Distance between grid points (m).
    #[serde(default = "default_spacing")]
    pub spacing_m: f64,
    /// Band along the walls left out of the figures (EN 12464-1: 0.5 m).
    #[serde(default = "default_border")]
    pub border_m: f64,
}

fn default_work_plane_height() -> f64 {
    0.8
}
fn default_spacing() -> f64 {
    0.25
}
fn default_border() -> f64 {
    0.5
}

impl Default for WorkPlane {
    fn default() -> WorkPlane {
        WorkPlane {
            height_m: default_work_plane_height(),
            spacing_m: default_spacing(),
            border_m: default_border(),
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Camera {
    pub position: [f64; 3],
    pub look_at: [f64; 3],
    /// Vertical field of view (degrees).
    #[serde(default = "default_fov")]
    pub fov_deg: f64,
}

fn default_fov() -> f64 {
    60.0
}

/// One luminaire (or a regular array of identical ones).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LuminaireSpec {
    /// An IES or LDT file, relative to the room file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub profile: Option<String>,
    /// A luminaire scene (TOML) baked by the tracer, relative to the room file.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub luminaire: Option<String>,
    /// Centre of the luminous opening (m).
    pub position: [f64; 3],
    /// Rotation about the room's x, y, then z axes (degrees); zero hangs
    /// the luminaire with its nadir (γ = 0) down and C0 along +x.
    #[serde(default)]
    pub rotation_deg: [f64; 3],
    /// The luminous opening; by default from the file's luminous area.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub opening: Option<OpeningSpec>,
    /// Repeat the luminaire on a grid in x and y.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub array: Option<ArraySpec>,
    /// Multiplies the intensities (dimming, maintenance factor).
    #[serde(default = "one")]
    pub flux_factor: f64,
}

fn one() -> f64 {
    1.0
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, tag = "shape", rename_all = "lowercase")]
pub enum OpeningSpec {
    Rectangle { length_m: f64, width_m: f64 },
    Disk { diameter_m: f64 },
    Point,
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ArraySpec {
    pub count: [u32; 2],
    pub spacing_m: [f64; 2],
}

impl LuminaireSpec {
    /// Positions of every copy (the array's first copy at `position`).
    pub fn positions(&self) -> Vec<[f64; 3]> {
        match self.array {
            None => vec![self.position],
            Some(a) => {
                let mut out = Vec::new();
                for j in 0..a.count[1] {
                    for i in 0..a.count[0] {
                        out.push([
                            self.position[0] + i as f64 * a.spacing_m[0],
                            self.position[1] + j as f64 * a.spacing_m[1],
                            self.position[2],
                        ]);
                    }
                }
                out
            }
        }
    }

    /// The profile source as a path relative to `base` (the room file's
    /// directory).
    pub fn source_path(&self, base: &Path) -> Option<(SourceKind, PathBuf)> {
        match (&self.profile, &self.luminaire) {
            (Some(p), None) => Some((SourceKind::PhotometricFile, base.join(p))),
            (None, Some(l)) => Some((SourceKind::LuminaireScene, base.join(l))),
            _ => None,
        }
    }
}

/// Where a luminaire's profile comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SourceKind {
    PhotometricFile,
    LuminaireScene,
}

#[derive(Debug, thiserror::Error)]
pub enum RoomFileError {
    /// Missing, unreadable, larger than its limit or not text.
    #[error(transparent)]
    Read(#[from] lucerna_scene::file::ReadFileError),
    #[error("{path}: {message}")]
    Syntax { path: PathBuf, message: String },
    #[error("{path}: invalid room: {problems}")]
    Invalid { path: PathBuf, problems: String },
}

/// Reads (at most [`MAX_ROOM_FILE_BYTES`]) and validates a room file.
pub fn load_room(path: &Path) -> Result<RoomFile, RoomFileError> {
    let text = lucerna_scene::io::read_limited_text(path, MAX_ROOM_FILE_BYTES)?;
    parse_room(&text, path)
}

/// Parses and validates room TOML (`path` names it in errors).
pub fn parse_room(text: &str, path: &Path) -> Result<RoomFile, RoomFileError> {
    let room: RoomFile = toml::from_str(text).map_err(|e| RoomFileError::Syntax {
        path: path.to_owned(),
        message: syntax_message(text, &e),
    })?;
    let problems = validate(&room);
    if !problems.is_empty() {
        return Err(RoomFileError::Invalid {
            path: path.to_owned(),
            problems: problems.join("; "),
        });
    }
    Ok(room)
}

fn syntax_message(text: &str, e: &toml::de::Error) -> String {
    match e.span() {
        Some(span) => {
            let line = text[..span.start.min(text.len())].matches('\n').count() + 1;
            format!("line {line}: {}", e.message())
        }
        None => e.message().to_owned(),
    }
}

/// Every out-of-range value, as "field: problem".
pub fn validate(room: &RoomFile) -> Vec<String> {
    let mut p = Vec::new();
    fn check(p: &mut Vec<String>, field: &str, v: f64, lo: f64, hi: f64) {
        if !(v.is_finite() && v >= lo && v <= hi) {
            p.push(format!("{field}: must be between {lo} and {hi}, got {v}"));
        }
    }
    if room.version != ROOM_FORMAT_VERSION {
        check(&mut p, "version", room.version as f64, 1.0, 1.0);
    }
    let r = &room.room;
    check(&mut p, "room.width_m", r.width_m, 0.1, MAX_ROOM_M);
    check(&mut p, "room.depth_m", r.depth_m, 0.1, MAX_ROOM_M);
    check(&mut p, "room.height_m", r.height_m, 0.1, MAX_ROOM_M);
    let named = r
        .materials
        .iter()
        .map(|(k, s)| (format!("materials.{k}"), *s));
    let fixed = [
        ("floor", r.floor),
        ("walls", r.walls),
        ("ceiling", r.ceiling),
    ]
    .into_iter()
    .map(|(k, s)| (k.to_owned(), s));
    for (name, s) in fixed.chain(named) {
        for (what, v) in [
            ("reflectance", s.reflectance),
            ("specular", s.specular),
            ("roughness", s.roughness),
        ] {
            check(&mut p, &format!("room.{name}.{what}"), v, 0.0, 1.0);
        }
    }
    check(&mut p, "room.obj_scale", r.obj_scale, 1e-4, 1e4);
    let w = &room.work_plane;
    check(&mut p, "work_plane.height_m", w.height_m, 0.0, r.height_m);
    check(
        &mut p,
        "work_plane.spacing_m",
        w.spacing_m,
        0.01,
        MAX_ROOM_M,
    );
    check(
        &mut p,
        "work_plane.border_m",
        w.border_m,
        0.0,
        0.49 * r.width_m.min(r.depth_m),
    );
    if w.spacing_m.is_finite() && w.spacing_m > 0.0 && w.border_m.is_finite() {
        let nx = grid_count(r.width_m, w.border_m, w.spacing_m);
        let ny = grid_count(r.depth_m, w.border_m, w.spacing_m);
        let points = nx.saturating_mul(ny);
        if points > MAX_WORK_PLANE_POINTS {
            p.push(format!(
                "work_plane.spacing_m: {nx} × {ny} = {points} grid points, at most {MAX_WORK_PLANE_POINTS} (a larger spacing)"
            ));
        }
    }
    let c = &room.camera;
    let size = [r.width_m, r.depth_m, r.height_m];
    for k in 0..3 {
        check(
            &mut p,
            &format!("camera.position[{k}]"),
            c.position[k],
            0.0,
            size[k],
        );
        check(
            &mut p,
            &format!("camera.look_at[{k}]"),
            c.look_at[k],
            -MAX_ROOM_M,
            MAX_ROOM_M,
        );
    }
    check(&mut p, "camera.fov_deg", c.fov_deg, 1.0, 170.0);
    let view: f64 = (0..3)
        .map(|k| (c.look_at[k] - c.position[k]).powi(2))
        .sum::<f64>();
    if view < 1e-6 {
        p.push("camera.look_at: must differ from camera.position".to_owned());
    }
    let mut total = 0usize;
    if room.luminaires.is_empty() {
        p.push("luminaire: the room needs at least one [[luminaire]]".to_owned());
    }
    for (i, l) in room.luminaires.iter().enumerate() {
        let f = |k: &str| format!("luminaire[{i}].{k}");
        if l.profile.is_some() == l.luminaire.is_some() {
            p.push(format!(
                "luminaire[{i}]: give exactly one of `profile` (IES/LDT file) or `luminaire` (scene to bake)"
            ));
        }
        for k in 0..3 {
            check(
                &mut p,
                &f(&format!("position[{k}]")),
                l.position[k],
                -MAX_ROOM_M,
                MAX_ROOM_M,
            );
            check(
                &mut p,
                &f(&format!("rotation_deg[{k}]")),
                l.rotation_deg[k],
                -360.0,
                360.0,
            );
        }
        check(&mut p, &f("flux_factor"), l.flux_factor, 0.0, 100.0);
        match l.opening {
            Some(OpeningSpec::Rectangle { length_m, width_m }) => {
                check(&mut p, &f("opening.length_m"), length_m, 1e-3, 50.0);
                check(&mut p, &f("opening.width_m"), width_m, 1e-3, 50.0);
            }
            Some(OpeningSpec::Disk { diameter_m }) => {
                check(&mut p, &f("opening.diameter_m"), diameter_m, 1e-3, 50.0);
            }
            _ => {}
        }
        let copies = match l.array {
            Some(a) => {
                for k in 0..2 {
                    check(
                        &mut p,
                        &f(&format!("array.count[{k}]")),
                        a.count[k] as f64,
                        1.0,
                        64.0,
                    );
                    check(
                        &mut p,
                        &f(&format!("array.spacing_m[{k}]")),
                        a.spacing_m[k],
                        0.0,
                        MAX_ROOM_M,
                    );
                }
                a.count[0] as usize * a.count[1] as usize
            }
            None => 1,
        };
        total += copies;
    }
    if total > MAX_LUMINAIRES {
        p.push(format!(
            "luminaire: {total} luminaires after arrays, at most {MAX_LUMINAIRES}"
        ));
    }
    p
}

/// How many work-plane grid points [`grid_coordinates`] places along one side
/// (saturating for absurd spacings, so validation can compare it).
pub fn grid_count(length: f64, border: f64, spacing: f64) -> usize {
    let span = (length - 2.0 * border).max(0.0);
    ((span / spacing).round() as usize).max(1)
}

/// Grid points at the centres of cells of about `spacing_m`, inside the
/// border band, along one side of the room.
pub fn grid_coordinates(length: f64, border: f64, spacing: f64) -> Vec<f64> {
    let span = (length - 2.0 * border).max(0.0);
    let n = grid_count(length, border, spacing);
    (0..n)
        .map(|i| border + (i as f64 + 0.5) * span / n as f64)
        .collect()
}
