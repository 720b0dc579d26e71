//! The scene panel: emitters, parts and materials; the selected item's
//! properties; validation problems.

use egui::Ui;
use lucerna_scene::{Emitter, EmitterShape, Material, Part, Scene, Shape, Transform};

use crate::state::{Command, EditorState, NewPart, Selection};
use crate::widgets::{degrees, flag, length_mm, number, offset_mm, segments, text};

/// Longest length a field accepts (mm): a luminaire, not a building.
const MAX_MM: f64 = 10_000.0;

pub fn scene_panel_ui(ui: &mut Ui, state: &mut EditorState) {
    let mut commands = Vec::new();
    let Some(scene) = &mut state.scene else {
        ui.label("No scene loaded: open a scene file.");
        return;
    };
    ui.heading(&scene.name);
    tree_ui(ui, scene, state.selection.as_ref(), &mut commands);
    ui.separator();
    ui.horizontal_wrapped(|ui| {
        for (kind, label) in [
            (NewPart::Paraboloid, "Add paraboloid"),
            (NewPart::Disk, "Add disk"),
            (NewPart::Plate, "Add plate"),
        ] {
            if ui.button(label).clicked() {
                commands.push(Command::AddPart(kind));
            }
        }
    });
    ui.separator();
    match state.selection.clone() {
        Some(Selection::Part(i)) => {
            let materials: Vec<String> = scene.materials.keys().cloned().collect();
            if let Some(part) = scene.parts.get_mut(i) {
                part_ui(ui, part, &materials);
                ui.horizontal(|ui| {
                    if ui.button("Duplicate part").clicked() {
                        commands.push(Command::DuplicatePart(i));
                    }
                    if ui.button("Delete part").clicked() {
                        commands.push(Command::DeletePart(i));
                    }
                });
            }
        }
        Some(Selection::Emitter(i)) => {
            if let Some(emitter) = scene.emitters.get_mut(i) {
                emitter_ui(ui, emitter);
            }
        }
        Some(Selection::Material(name)) => {
            if let Some(material) = scene.materials.get_mut(&name) {
                ui.strong(format!("Material {name}"));
                material_ui(ui, material);
            }
        }
        None => {
            ui.label("Select an emitter, part or material to edit it.");
        }
    }
    if !state.problems.is_empty() {
        ui.separator();
        ui.colored_label(
            ui.visuals().error_fg_color,
            "Invalid scene (not simulated; the last valid one keeps running):",
        );
        for problem in &state.problems {
            ui.colored_label(ui.visuals().error_fg_color, problem);
        }
    }
    for c in commands {
        state.push(c);
    }
}

fn tree_ui(ui: &mut Ui, scene: &Scene, selected: Option<&Selection>, commands: &mut Vec<Command>) {
    let mut item = |ui: &mut Ui, selection: Selection, text: String| {
        let is_selected = selected == Some(&selection);
        if ui.selectable_label(is_selected, text).clicked() {
            commands.push(Command::Select(Some(selection)));
        }
    };
    egui::CollapsingHeader::new("Emitters")
        .default_open(true)
        .show(ui, |ui| {
            for (i, e) in scene.emitters.iter().enumerate() {
                item(ui, Selection::Emitter(i), format!("Emitter {}", e.name));
            }
        });
    egui::CollapsingHeader::new("Parts")
        .default_open(true)
        .show(ui, |ui| {
            for (i, p) in scene.parts.iter().enumerate() {
                let off = if p.enabled { "" } else { " (off)" };
                item(
                    ui,
                    Selection::Part(i),
                    format!("Part {} ({}){off}", p.name, p.shape.generator().kind()),
                );
            }
        });
    egui::CollapsingHeader::new("Materials")
        .default_open(true)
        .show(ui, |ui| {
            for (name, m) in &scene.materials {
                item(
                    ui,
                    Selection::Material(name.clone()),
                    format!("Material {name} ({})", m.kind()),
                );
            }
        });
}

fn part_ui(ui: &mut Ui, part: &mut Part, materials: &[String]) {
    ui.strong(format!("Part ({})", part.shape.generator().kind()));
    text(ui, "Name", &mut part.name);
    flag(ui, "Enabled", &mut part.enabled);
    crate::widgets::labelled(ui, "Material", |ui| {
        egui::ComboBox::from_id_salt("part material")
            .selected_text(part.material.clone())
            .show_ui(ui, |ui| {
                for m in materials {
                    ui.selectable_value(&mut part.material, m.clone(), m);
                }
            })
            .response
    });
    ui.label("Shape");
    shape_ui(ui, &mut part.shape);
    transform_ui(ui, &mut part.transform);
}

/// Every generator parameter with its unit; shapes drawn from curves or
/// files are edited in the scene file for now.
fn shape_ui(ui: &mut Ui, shape: &mut Shape) {
    match shape {
        Shape::Paraboloid(s) => {
            length_mm(ui, "Focal length", &mut s.focal_length, MAX_MM);
            length_mm(ui, "Aperture diameter", &mut s.aperture_diameter, MAX_MM);
            length_mm(ui, "Neck diameter", &mut s.neck_diameter, MAX_MM);
            segments(ui, "Segments around", &mut s.segments_around, 3);
            segments(ui, "Segments along", &mut s.segments_along, 1);
            flag(ui, "Faceted", &mut s.faceted);
        }
        Shape::Ellipsoid(s) => {
            length_mm(ui, "Focal distance", &mut s.focal_distance, MAX_MM);
            length_mm(ui, "Vertex distance", &mut s.vertex_distance, MAX_MM);
            length_mm(ui, "Cut below focus", &mut s.cut_below_focus, MAX_MM);
            length_mm(ui, "Neck diameter", &mut s.neck_diameter, MAX_MM);
            segments(ui, "Segments around", &mut s.segments_around, 3);
            segments(ui, "Segments along", &mut s.segments_along, 1);
            flag(ui, "Faceted", &mut s.faceted);
        }
        Shape::Disk(s) => {
            length_mm(ui, "Radius", &mut s.radius, MAX_MM);
            segments(ui, "Segments around", &mut s.segments_around, 3);
        }
        Shape::Plate(s) => {
            length_mm(ui, "Width", &mut s.width, MAX_MM);
            length_mm(ui, "Depth", &mut s.depth, MAX_MM);
        }
        Shape::Dome(s) => {
            length_mm(ui, "Radius", &mut s.radius, MAX_MM);
            length_mm(ui, "Height", &mut s.height, MAX_MM);
            segments(ui, "Segments around", &mut s.segments_around, 3);
            segments(ui, "Segments along", &mut s.segments_along, 1);
        }
        Shape::Cylinder(s) => {
            length_mm(ui, "Radius", &mut s.radius, MAX_MM);
            length_mm(ui, "Height", &mut s.height, MAX_MM);
            flag(ui, "Cap top", &mut s.cap_top);
            flag(ui, "Cap bottom", &mut s.cap_bottom);
            segments(ui, "Segments around", &mut s.segments_around, 3);
        }
        Shape::Box(s) => {
            length_mm(ui, "Size x", &mut s.size[0], MAX_MM);
            length_mm(ui, "Size y", &mut s.size[1], MAX_MM);
            length_mm(ui, "Size z", &mut s.size[2], MAX_MM);
            flag(ui, "Open bottom", &mut s.open_bottom);
        }
        Shape::Revolved(_) | Shape::Extruded(_) | Shape::Louvre(_) | Shape::Mesh(_) => {
            ui.label("This shape's parameters are edited in the scene file.");
        }
    }
}

fn transform_ui(ui: &mut Ui, t: &mut Transform) {
    ui.label("Transform");
    for (axis, v) in ["x", "y", "z"].iter().zip(t.translate.iter_mut()) {
        offset_mm(ui, &format!("Translate {axis}"), v);
    }
    for (axis, v) in ["x", "y", "z"].iter().zip(t.rotate_deg.iter_mut()) {
        degrees(ui, &format!("Rotate {axis}"), v);
    }
    for (axis, v) in ["x", "y", "z"].iter().zip(t.scale.iter_mut()) {
        number(ui, &format!("Scale {axis}"), v, -100.0..=100.0, 0.01, "×");
    }
}

fn emitter_ui(ui: &mut Ui, e: &mut Emitter) {
    ui.strong("Emitter");
    text(ui, "Name", &mut e.name);
    flag(ui, "Enabled", &mut e.enabled);
    number(ui, "Flux", &mut e.flux_lm, 0.0..=1e7, 1.0, " lm");
    match &mut e.shape {
        EmitterShape::Disk { radius } | EmitterShape::Sphere { radius } => {
            length_mm(ui, "Emitter radius", radius, MAX_MM);
        }
        EmitterShape::Rectangle { width, depth } => {
            length_mm(ui, "Emitter width", width, MAX_MM);
            length_mm(ui, "Emitter depth", depth, MAX_MM);
        }
        EmitterShape::Cylinder { radius, height } => {
            length_mm(ui, "Emitter radius", radius, MAX_MM);
            length_mm(ui, "Emitter height", height, MAX_MM);
        }
    }
    transform_ui(ui, &mut e.transform);
}

/// The material kinds in the order the kind menu lists them, each with
/// plausible defaults for when the user switches to it.
fn default_of_kind(kind: &str) -> Material {
    match kind {
        "lambertian" => Material::Lambertian { albedo: 0.8 },
        "mirror" => Material::Mirror { reflectance: 0.9 },
        "rough_conductor" => Material::RoughConductor {
            reflectance: 0.9,
            roughness_u: 0.1,
            roughness_v: 0.1,
            orientation_deg: 0.0,
        },
        "dielectric" => Material::Dielectric {
            ior: 1.49,
            absorption_per_m: 0.0,
        },
        "diffuser" => Material::Diffuser {
            reflectance: 0.3,
            transmittance: 0.6,
        },
        _ => Material::Absorber,
    }
}

const KINDS: [&str; 6] = [
    "absorber",
    "lambertian",
    "mirror",
    "rough_conductor",
    "dielectric",
    "diffuser",
];

fn material_ui(ui: &mut Ui, m: &mut Material) {
    let mut kind = m.kind();
    crate::widgets::labelled(ui, "Kind", |ui| {
        egui::ComboBox::from_id_salt("material kind")
            .selected_text(kind)
            .show_ui(ui, |ui| {
                for k in KINDS {
                    ui.selectable_value(&mut kind, k, k);
                }
            })
            .response
    });
    if kind != m.kind() {
        *m = default_of_kind(kind);
    }
    match m {
        Material::Absorber => {
            ui.label("Absorbs every photon.");
        }
        Material::Lambertian { albedo } => {
            number(ui, "Albedo", albedo, 0.0..=1.0, 0.005, "");
        }
        Material::Mirror { reflectance } => {
            number(ui, "Reflectance", reflectance, 0.0..=1.0, 0.005, "");
        }
        Material::RoughConductor {
            reflectance,
            roughness_u,
            roughness_v,
            orientation_deg,
        } => {
            number(ui, "Reflectance", reflectance, 0.0..=1.0, 0.005, "");
            number(ui, "Roughness u (GGX α)", roughness_u, 0.0..=1.0, 0.002, "");
            number(ui, "Roughness v (GGX α)", roughness_v, 0.0..=1.0, 0.002, "");
            degrees(ui, "Orientation", orientation_deg);
        }
        Material::Dielectric {
            ior,
            absorption_per_m,
        } => {
            number(ui, "Refractive index", ior, 1.0..=4.0, 0.005, "");
            number(ui, "Absorption", absorption_per_m, 0.0..=1e4, 0.1, " 1/m");
        }
        Material::Diffuser {
            reflectance,
            transmittance,
        } => {
            number(ui, "Reflectance", reflectance, 0.0..=1.0, 0.005, "");
            number(ui, "Transmittance", transmittance, 0.0..=1.0, 0.005, "");
        }
    }
}
