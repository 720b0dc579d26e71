//! The modelling edits apart from any drawing: new parts of every shape
//! with defaults that validate at once, and the structural edits of
//! emitters, materials and profiles, each refused with a message before
//! anything changes when it would break the scene's references.

use std::path::Path;

use lucerna_scene::shapes::{
    BoxShape, Cylinder, Disk, Dome, Ellipsoid, Extruded, Louvre, Paraboloid, Plate, Revolved,
};
use lucerna_scene::{
    Emission, Emitter, EmitterShape, Interpolation, LuminousOpening, Material, Part, Scene, Shape,
    Transform,
};

use crate::selection::Selection;

/// The part shapes the "Add part" menu creates: every generator except
/// the OBJ mesh, which comes by importing a file.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NewPart {
    Paraboloid,
    Ellipsoid,
    Disk,
    Plate,
    Dome,
    Cylinder,
    Box,
    Revolved,
    Extruded,
    Louvre,
}

impl NewPart {
    /// In the order the menu lists them: reflectors first.
    pub const ALL: [NewPart; 10] = [
        NewPart::Paraboloid,
        NewPart::Ellipsoid,
        NewPart::Revolved,
        NewPart::Extruded,
        NewPart::Dome,
        NewPart::Cylinder,
        NewPart::Box,
        NewPart::Disk,
        NewPart::Plate,
        NewPart::Louvre,
    ];

    /// The shape's `type` as scene files write it (and the new part's name).
    pub fn kind(self) -> &'static str {
        self.shape().kind()
    }

    /// A shape of this kind of a downlight's size (about 100 mm across),
    /// centred on the luminaire's axis, that validates as it is.
    pub fn shape(self) -> Shape {
        match self {
            NewPart::Paraboloid => Shape::Paraboloid(Paraboloid {
                focal_length: 0.025,
                aperture_diameter: 0.1,
                neck_diameter: 0.0,
                segments_around: 64,
                segments_along: 32,
                faceted: false,
            }),
            NewPart::Ellipsoid => Shape::Ellipsoid(Ellipsoid {
                focal_distance: 0.1,
                vertex_distance: 0.015,
                cut_below_focus: 0.03,
                neck_diameter: 0.0,
                segments_around: 64,
                segments_along: 32,
                faceted: false,
            }),
            NewPart::Disk => Shape::Disk(Disk {
                radius: 0.05,
                segments_around: 64,
            }),
            NewPart::Plate => Shape::Plate(Plate {
                width: 0.1,
                depth: 0.1,
            }),
            NewPart::Dome => Shape::Dome(Dome {
                radius: 0.05,
                height: 0.03,
                segments_around: 64,
                segments_along: 32,
            }),
            NewPart::Cylinder => Shape::Cylinder(Cylinder {
                radius: 0.05,
                height: 0.08,
                cap_top: true,
                cap_bottom: true,
                segments_around: 64,
            }),
            // A housing open towards the light exit.
            NewPart::Box => Shape::Box(BoxShape {
                size: [0.1, 0.1, 0.05],
                open_bottom: true,
            }),
            // A spun reflector from a 16 mm neck above the lamp to a
            // 100 mm rim below it.
            NewPart::Revolved => Shape::Revolved(Revolved {
                profile: vec![[0.008, 0.03], [0.02, 0.024], [0.035, 0.01], [0.05, -0.01]],
                interpolation: Interpolation::CatmullRom,
                segments_around: 64,
                segments_per_span: 8,
                faceted: false,
            }),
            // A 300 mm trough, its profile symmetric about x = 0.
            NewPart::Extruded => Shape::Extruded(Extruded {
                profile: vec![
                    [-0.05, -0.01],
                    [-0.03, 0.015],
                    [0.0, 0.025],
                    [0.03, 0.015],
                    [0.05, -0.01],
                ],
                length: 0.3,
                interpolation: Interpolation::CatmullRom,
                segments_per_span: 8,
                end_caps: true,
            }),
            NewPart::Louvre => Shape::Louvre(Louvre {
                blade_count: 5,
                spacing: 0.02,
                blade_height: 0.02,
                blade_length: 0.1,
                tilt_deg: 0.0,
                cross_blade_count: 0,
                cross_spacing: 0.0,
            }),
        }
    }
}

/// A structural edit of the scene: its own undo step, applied by
/// [`crate::EditorState`] through `structural`, or refused with a message.
#[derive(Debug, Clone, PartialEq)]
pub enum SceneEdit {
    AddEmitter,
    DuplicateEmitter(usize),
    DeleteEmitter(usize),
    AddMaterial,
    DuplicateMaterial(String),
    /// Refused while a part or emitter uses the material.
    DeleteMaterial(String),
    /// Renames the material and every reference to it.
    RenameMaterial {
        from: String,
        to: String,
    },
    /// Renames a part, and the luminous opening that names it.
    RenamePart {
        part: usize,
        to: String,
    },
    /// Inserts a control point (m) before `index` of a revolved or
    /// extruded part's profile.
    InsertProfilePoint {
        part: usize,
        index: usize,
        point_m: [f64; 2],
    },
    RemoveProfilePoint {
        part: usize,
        index: usize,
    },
    /// Replaces a parametric surface of revolution (`from`: paraboloid,
    /// ellipsoid, dome, open cylinder) by `to`, the revolved profile the
    /// pane found for it within [`CONVERTED_PROFILE_TOLERANCE_M`]
    /// (`editable_revolution`, found once, where it was drawn); undo
    /// restores the parametric part.
    ConvertToProfile {
        part: usize,
        from: Box<Shape>,
        to: Revolved,
    },
}

/// How far a converted profile may lie from the parametric surface it
/// replaces (m): the conversion aims at 0.02 mm, the promise is 0.05 mm.
pub const CONVERTED_PROFILE_TOLERANCE_M: f64 = 0.02e-3;

/// The plane a part's profile is drawn in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProfilePlane {
    /// Radius and height of a surface of revolution; r ≥ 0.
    RadiusHeight,
    /// x and height of an extrusion along y.
    WidthHeight,
}

impl ProfilePlane {
    /// The name of the horizontal coordinate, as the scene file's comments
    /// and the table write it.
    pub fn horizontal(self) -> &'static str {
        match self {
            ProfilePlane::RadiusHeight => "r",
            ProfilePlane::WidthHeight => "x",
        }
    }

    /// The nearest point the generator accepts: a revolved profile's
    /// radius cannot be negative.
    pub fn clamped(self, [h, z]: [f64; 2]) -> [f64; 2] {
        match self {
            ProfilePlane::RadiusHeight => [h.max(0.0), z],
            ProfilePlane::WidthHeight => [h, z],
        }
    }
}

/// The control points of a profile shape, with the plane they lie in.
pub fn profile_mut(shape: &mut Shape) -> Option<(&mut Vec<[f64; 2]>, ProfilePlane)> {
    match shape {
        Shape::Revolved(s) => Some((&mut s.profile, ProfilePlane::RadiusHeight)),
        Shape::Extruded(s) => Some((&mut s.profile, ProfilePlane::WidthHeight)),
        _ => None,
    }
}

/// Where the enabled emitters sit in the profile plane of part `index`,
/// with their names (mm): the lamp a reflector is drawn around. Only for
/// a part placed by translation alone, whose frame is the luminaire's
/// shifted; a rotated or scaled part gets none rather than wrong ones.
pub fn lamps_in_profile_plane(scene: &Scene, index: usize) -> Vec<(String, [f64; 2])> {
    let Some(part) = scene.parts.get(index) else {
        return Vec::new();
    };
    let t = &part.transform;
    let plane = match part.shape {
        Shape::Revolved(_) => ProfilePlane::RadiusHeight,
        Shape::Extruded(_) => ProfilePlane::WidthHeight,
        ref s if s.has_parametric_section() => ProfilePlane::RadiusHeight,
        _ => return Vec::new(),
    };
    if t.rotate_deg != [0.0; 3] || t.scale != [1.0; 3] {
        return Vec::new();
    }
    scene
        .emitters
        .iter()
        .filter(|e| e.enabled)
        .map(|e| {
            let [x, y, z] = [0, 1, 2].map(|k| e.transform.translate[k] - t.translate[k]);
            let h = match plane {
                ProfilePlane::RadiusHeight => x.hypot(y),
                ProfilePlane::WidthHeight => x,
            };
            (e.name.clone(), [h * 1000.0, z * 1000.0])
        })
        .collect()
}

/// Fewest control points a profile keeps: one span.
pub const MIN_PROFILE_POINTS: usize = 2;

impl SceneEdit {
    /// Why the edit cannot be made to `scene`, in words for the user;
    /// `None` when it can.
    pub fn refusal(&self, scene: &Scene) -> Option<String> {
        match self {
            SceneEdit::DeleteMaterial(name) => {
                let users = material_users(scene, name);
                (!users.is_empty()).then(|| {
                    format!(
                        "Cannot delete material {name}: {} uses it. Give them another material first.",
                        users.join(", ")
                    )
                })
            }
            SceneEdit::RenameMaterial { from, to } => {
                let to = to.trim();
                if to.is_empty() {
                    Some("A material's name cannot be empty.".to_owned())
                } else if to != from && scene.materials.contains_key(to) {
                    Some(format!("A material called {to} exists already."))
                } else {
                    None
                }
            }
            SceneEdit::RenamePart { part, to } => {
                let to = to.trim();
                if to.is_empty() {
                    Some("A part's name cannot be empty.".to_owned())
                } else if scene
                    .parts
                    .iter()
                    .enumerate()
                    .any(|(i, p)| i != *part && p.name == to)
                {
                    Some(format!("A part called {to} exists already."))
                } else {
                    None
                }
            }
            SceneEdit::ConvertToProfile { part, from, .. } => {
                (scene.parts.get(*part)?.shape != **from).then(|| {
                    "The part changed since its section was drawn: convert it again.".to_owned()
                })
            }
            SceneEdit::RemoveProfilePoint { part, .. } => {
                let points = scene.parts.get(*part).and_then(|p| match &p.shape {
                    Shape::Revolved(s) => Some(s.profile.len()),
                    Shape::Extruded(s) => Some(s.profile.len()),
                    _ => None,
                });
                points
                    .is_some_and(|n| n <= MIN_PROFILE_POINTS)
                    .then(|| {
                        format!(
                            "A profile needs at least {MIN_PROFILE_POINTS} control points: add one before deleting this one."
                        )
                    })
            }
            _ => None,
        }
    }

    /// Makes the edit (after [`SceneEdit::refusal`] allowed it); indices
    /// and names that no longer exist change nothing.
    pub fn apply(self, scene: &mut Scene, selection: &mut Option<Selection>) {
        match self {
            SceneEdit::AddEmitter => {
                let name = unique_name("LED", |n| scene.emitters.iter().any(|e| e.name == n));
                scene.emitters.push(Emitter {
                    name,
                    shape: EmitterShape::Disk { radius: 0.0015 },
                    flux_lm: 1000.0,
                    emission: Emission::Lambertian,
                    material: None,
                    enabled: true,
                    transform: Transform::default(),
                });
                *selection = Some(Selection::Emitter(scene.emitters.len() - 1));
            }
            SceneEdit::DuplicateEmitter(i) => {
                if let Some(emitter) = scene.emitters.get(i) {
                    let mut copy = emitter.clone();
                    copy.name = unique_name(&emitter.name, |n| {
                        scene.emitters.iter().any(|e| e.name == n)
                    });
                    scene.emitters.insert(i + 1, copy);
                    *selection = Some(Selection::Emitter(i + 1));
                }
            }
            SceneEdit::DeleteEmitter(i) => {
                if i < scene.emitters.len() {
                    scene.emitters.remove(i);
                    *selection = None;
                }
            }
            SceneEdit::AddMaterial => {
                let name = unique_name("material", |n| scene.materials.contains_key(n));
                scene
                    .materials
                    .insert(name.clone(), Material::Lambertian { albedo: 0.8 });
                *selection = Some(Selection::Material(name));
            }
            SceneEdit::DuplicateMaterial(name) => {
                if let Some(material) = scene.materials.get(&name).cloned() {
                    let copy = unique_name(&name, |n| scene.materials.contains_key(n));
                    scene.materials.insert(copy.clone(), material);
                    *selection = Some(Selection::Material(copy));
                }
            }
            SceneEdit::DeleteMaterial(name) => {
                if scene.materials.remove(&name).is_some() {
                    *selection = None;
                }
            }
            SceneEdit::RenameMaterial { from, to } => {
                let to = to.trim().to_owned();
                if let Some(material) = scene.materials.remove(&from) {
                    scene.materials.insert(to.clone(), material);
                    rename_material_references(scene, &from, &to);
                    *selection = Some(Selection::Material(to));
                }
            }
            SceneEdit::RenamePart { part, to } => {
                let to = to.trim().to_owned();
                if let Some(p) = scene.parts.get_mut(part) {
                    let from = std::mem::replace(&mut p.name, to.clone());
                    if let Some(LuminousOpening::PartAperture { part: named }) = &mut scene.opening
                        && *named == from
                    {
                        *named = to;
                    }
                }
            }
            SceneEdit::InsertProfilePoint {
                part,
                index,
                point_m,
            } => {
                if let Some((points, plane)) = scene
                    .parts
                    .get_mut(part)
                    .and_then(|p| profile_mut(&mut p.shape))
                {
                    points.insert(index.min(points.len()), plane.clamped(point_m));
                }
            }
            SceneEdit::ConvertToProfile { part, from, to } => {
                if let Some(p) = scene.parts.get_mut(part)
                    && p.shape == *from
                {
                    p.shape = Shape::Revolved(to);
                }
            }
            SceneEdit::RemoveProfilePoint { part, index } => {
                if let Some((points, _)) = scene
                    .parts
                    .get_mut(part)
                    .and_then(|p| profile_mut(&mut p.shape))
                    && index < points.len()
                {
                    points.remove(index);
                }
            }
        }
    }
}

/// Who uses material `name`, in words: "part reflector", "emitter LED".
pub fn material_users(scene: &Scene, name: &str) -> Vec<String> {
    let parts = scene.parts.iter().filter_map(|p| {
        let in_groups = match &p.shape {
            Shape::Mesh(m) => m.group_materials.values().any(|m| m == name),
            _ => false,
        };
        (p.material == name || in_groups).then(|| format!("part {}", p.name))
    });
    let emitters = scene
        .emitters
        .iter()
        .filter(|e| e.material.as_deref() == Some(name))
        .map(|e| format!("emitter {}", e.name));
    parts.chain(emitters).collect()
}

/// Every reference to material `from` (parts, OBJ groups, emitters' own
/// surfaces) now names `to`.
fn rename_material_references(scene: &mut Scene, from: &str, to: &str) {
    for part in &mut scene.parts {
        if part.material == from {
            part.material = to.to_owned();
        }
        if let Shape::Mesh(mesh) = &mut part.shape {
            for material in mesh.group_materials.values_mut() {
                if material == from {
                    *material = to.to_owned();
                }
            }
        }
    }
    for emitter in &mut scene.emitters {
        if emitter.material.as_deref() == Some(from) {
            emitter.material = Some(to.to_owned());
        }
    }
}

/// `base` or `stem 2`, `stem 3`, … whichever is not `taken` yet, where
/// `stem` is `base` without a number it already ends in (a copy of
/// "LED 2" is "LED 3", not "LED 2 2").
pub fn unique_name(base: &str, taken: impl Fn(&str) -> bool) -> String {
    if !taken(base) {
        return base.to_owned();
    }
    let stem = match base.rsplit_once(' ') {
        Some((stem, n)) if !stem.is_empty() && n.parse::<u32>().is_ok() => stem,
        _ => base,
    };
    (2..)
        .map(|k| format!("{stem} {k}"))
        .find(|n| !taken(n))
        .unwrap_or_else(|| base.to_owned())
}

/// A new part of `kind` in the scene's first material (white paint added
/// when it has none), so that it validates at once.
pub fn new_part(scene: &mut Scene, kind: NewPart) -> Part {
    let material = match scene.materials.keys().next() {
        Some(name) => name.clone(),
        None => {
            scene.materials.insert(
                "white_paint".to_owned(),
                Material::Lambertian { albedo: 0.8 },
            );
            "white_paint".to_owned()
        }
    };
    Part {
        name: unique_name(kind.kind(), |n| scene.parts.iter().any(|p| p.name == n)),
        shape: kind.shape(),
        material,
        enabled: true,
        transform: Transform::default(),
        finish: None,
    }
}

/// The emitter shape kinds as scene files write them.
pub const EMITTER_SHAPES: [&str; 5] = ["disk", "rectangle", "sphere", "cylinder", "ray_file"];

pub fn emitter_shape_kind(shape: &EmitterShape) -> &'static str {
    match shape {
        EmitterShape::Disk { .. } => "disk",
        EmitterShape::Rectangle { .. } => "rectangle",
        EmitterShape::Sphere { .. } => "sphere",
        EmitterShape::Cylinder { .. } => "cylinder",
        EmitterShape::RayFile { .. } => "ray_file",
    }
}

/// `shape` as another kind of about the same size: each shape is read as
/// two half extents (a radius, or half a side or height) and the new one
/// built from them, so switching back and forth gives the sizes back.
pub fn emitter_shape_as(shape: &EmitterShape, kind: &str) -> EmitterShape {
    let (a, b) = match *shape {
        EmitterShape::Disk { radius } | EmitterShape::Sphere { radius } => (radius, radius),
        EmitterShape::Rectangle { width, depth } => (0.5 * width, 0.5 * depth),
        EmitterShape::Cylinder { radius, height } => (radius, 0.5 * height),
        // A file has no size: a small LED's.
        EmitterShape::RayFile { .. } => (0.0015, 0.0015),
    };
    match kind {
        // The file is chosen next (Ray file field); until then the scene
        // says which field is missing.
        "ray_file" => EmitterShape::RayFile {
            path: String::new(),
        },
        "rectangle" => EmitterShape::Rectangle {
            width: 2.0 * a,
            depth: 2.0 * b,
        },
        "sphere" => EmitterShape::Sphere { radius: a },
        "cylinder" => EmitterShape::Cylinder {
            radius: a,
            height: 2.0 * b,
        },
        _ => EmitterShape::Disk { radius: a },
    }
}

/// Most files the profile chooser lists: a folder of thousands is typed.
const MAX_LISTED_PROFILES: usize = 500;

/// The measured distributions (IES, LDT) an emitter of a scene in
/// `scene_dir` can name: files in the scene's folder, in a `profiles`
/// folder inside or beside it, and one folder below those, as paths
/// relative to the scene's folder (how the scene file stores them).
pub fn profile_files_near(scene_dir: &Path) -> Vec<String> {
    let is_profile = |p: &Path| {
        p.extension()
            .and_then(|e| e.to_str())
            .is_some_and(|e| e.eq_ignore_ascii_case("ies") || e.eq_ignore_ascii_case("ldt"))
    };
    let mut folders: Vec<String> = vec![
        String::new(),
        "profiles/".to_owned(),
        "../profiles/".to_owned(),
    ];
    let mut found = Vec::new();
    let mut k = 0;
    while k < folders.len() && found.len() < MAX_LISTED_PROFILES {
        let folder = folders[k].clone();
        let top_level = k < 3;
        k += 1;
        let Ok(entries) = std::fs::read_dir(scene_dir.join(&folder)) else {
            continue;
        };
        let mut entries: Vec<_> = entries.filter_map(Result::ok).map(|e| e.path()).collect();
        entries.sort();
        for path in entries {
            let Some(name) = path.file_name().and_then(|n| n.to_str()) else {
                continue;
            };
            if path.is_dir() && top_level && !folder.is_empty() {
                folders.push(format!("{folder}{name}/"));
            } else if path.is_file() && is_profile(&path) && found.len() < MAX_LISTED_PROFILES {
                found.push(format!("{folder}{name}"));
            }
        }
    }
    found
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene() -> Scene {
        Scene {
            format_version: lucerna_scene::FORMAT_VERSION,
            name: "test".to_owned(),
            description: String::new(),
            manufacturer: String::new(),
            materials: Default::default(),
            emitters: Vec::new(),
            parts: Vec::new(),
            opening: None,
            export: Default::default(),
        }
    }

    #[test]
    fn every_new_part_validates_in_a_scene_with_an_emitter() {
        for kind in NewPart::ALL {
            let mut s = scene();
            SceneEdit::AddEmitter.apply(&mut s, &mut None);
            let part = new_part(&mut s, kind);
            assert_eq!(part.name, kind.kind());
            s.parts.push(part);
            let problems = lucerna_scene::validate(&s);
            assert!(problems.is_empty(), "{kind:?}: {problems:?}");
        }
    }

    #[test]
    fn switching_emitter_shapes_back_gives_the_sizes_back() {
        let rectangle = EmitterShape::Rectangle {
            width: 0.01,
            depth: 0.004,
        };
        for kind in EMITTER_SHAPES {
            let there = emitter_shape_as(&rectangle, kind);
            assert_eq!(emitter_shape_kind(&there), kind);
            if kind == "cylinder" {
                assert_eq!(emitter_shape_as(&there, "rectangle"), rectangle);
            }
        }
        let disk = EmitterShape::Disk { radius: 0.002 };
        // A ray file has no size to give back: it comes back a small LED.
        for kind in EMITTER_SHAPES.into_iter().filter(|&k| k != "ray_file") {
            assert_eq!(
                emitter_shape_as(&emitter_shape_as(&disk, kind), "disk"),
                disk
            );
        }
    }

    #[test]
    fn the_example_profiles_are_found_beside_the_example_scenes() {
        let scenes = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires");
        let found = profile_files_near(&scenes);
        assert!(
            found.contains(&"../profiles/samples/bega_50975_1995_single_h.ies".to_owned()),
            "{found:?}"
        );
        assert!(found.iter().any(|f| f.ends_with(".ldt")), "{found:?}");
        assert!(found.iter().all(|f| scenes.join(f).is_file()));
        assert!(profile_files_near(Path::new("/no/such/folder")).is_empty());
    }

    #[test]
    fn lamps_are_placed_in_the_part_frame_of_a_translated_part() {
        let mut s = scene();
        SceneEdit::AddEmitter.apply(&mut s, &mut None);
        s.emitters[0].transform.translate = [0.003, 0.004, 0.01];
        let mut part = new_part(&mut s, NewPart::Revolved);
        part.transform.translate = [0.0, 0.0, 0.02];
        s.parts.push(part);
        let lamps = lamps_in_profile_plane(&s, 0);
        assert_eq!(lamps.len(), 1);
        assert!((lamps[0].1[0] - 5.0).abs() < 1e-9 && (lamps[0].1[1] + 10.0).abs() < 1e-9);
        s.parts[0].transform.rotate_deg = [90.0, 0.0, 0.0];
        assert!(lamps_in_profile_plane(&s, 0).is_empty());
    }

    #[test]
    fn copies_are_numbered_from_the_stem() {
        let taken = |n: &str| ["LED", "LED 2"].contains(&n);
        assert_eq!(unique_name("LED", taken), "LED 3");
        assert_eq!(unique_name("LED 2", taken), "LED 3");
        assert_eq!(unique_name("lamp", taken), "lamp");
        assert_eq!(unique_name("2", |n| n == "2"), "2 2");
    }

    #[test]
    fn a_revolved_point_is_clamped_to_the_axis() {
        assert_eq!(
            ProfilePlane::RadiusHeight.clamped([-0.01, 0.02]),
            [0.0, 0.02]
        );
        assert_eq!(
            ProfilePlane::WidthHeight.clamped([-0.01, 0.02]),
            [-0.01, 0.02]
        );
    }
}
