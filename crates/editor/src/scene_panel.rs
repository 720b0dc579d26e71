//! The scene panel: emitters, parts and materials; the selected item's
//! properties; validation problems.

use std::path::Path;

use egui::{Id, Response, Ui};
use lucerna_scene::{
    Emission, Emitter, EmitterShape, Interpolation, Material, Part, Scene, Shape, Transform,
};

use crate::design_state::DesignState;
use crate::modelling::{
    EMITTER_SHAPES, NewPart, SceneEdit, emitter_shape_as, emitter_shape_kind, material_users,
    profile_files_near, profile_mut,
};
use crate::state::{Command, EditorState, Selection};
use crate::widgets::{degrees, flag, labelled, length_mm, number, offset_mm, segments, text};

/// Longest length a field accepts (mm): a luminaire, not a building.
const MAX_MM: f64 = 10_000.0;

pub fn scene_panel_ui(ui: &mut Ui, state: &mut EditorState) {
    let mut commands = Vec::new();
    let scene_dir = state.scene_dir();
    let ray_files = ray_files_read(state);
    let Some(scene) = &mut state.doc.scene else {
        ui.label("No scene loaded: open a scene file.");
        return;
    };
    ui.heading(&scene.name);
    tree_ui(ui, scene, state.doc.selection.as_ref(), &mut commands);
    ui.separator();
    ui.horizontal_wrapped(|ui| {
        ui.menu_button("Add part", |ui| {
            for kind in NewPart::ALL {
                if ui.button(format!("Add {}", kind.kind())).clicked() {
                    commands.push(Command::AddPart(kind));
                }
            }
        });
        if ui.button("Add emitter").clicked() {
            commands.push(Command::Edit(SceneEdit::AddEmitter));
        }
        if ui
            .button("Add ray-file emitter…")
            .on_hover_text(
                "An LED maker's IES TM-25 ray file (.tm25ray): photons start at its rays",
            )
            .clicked()
        {
            commands.push(Command::FileDialog(
                crate::command::DialogKind::RayFileEmitter,
            ));
        }
        if ui.button("Add material").clicked() {
            commands.push(Command::Edit(SceneEdit::AddMaterial));
        }
    });
    if let Some(error) = &state.doc.edit_error {
        ui.colored_label(ui.visuals().error_fg_color, error);
    }
    ui.separator();
    let materials: Vec<String> = scene.materials.keys().cloned().collect();
    match state.doc.selection.clone() {
        Some(Selection::Part(i)) => {
            if let Some(part) = scene.parts.get_mut(i) {
                let design = state.design.ticks_visible().then_some(&state.design);
                part_ui(ui, i, part, &materials, design, &mut commands);
                ui.horizontal(|ui| {
                    if ui.button("Duplicate part").clicked() {
                        commands.push(Command::DuplicatePart(i));
                    }
                    if ui.button("Delete part").clicked() {
                        commands.push(Command::DeletePart(i));
                    }
                });
                tolerances_ui(ui, scene, &Selection::Part(i), &mut state.tolerance);
            }
        }
        Some(Selection::Emitter(i)) => {
            if let Some(emitter) = scene.emitters.get_mut(i) {
                emitter_ui(ui, i, emitter, &materials, &scene_dir, &ray_files);
                ui.horizontal(|ui| {
                    if ui.button("Duplicate emitter").clicked() {
                        commands.push(Command::Edit(SceneEdit::DuplicateEmitter(i)));
                    }
                    if ui.button("Delete emitter").clicked() {
                        commands.push(Command::Edit(SceneEdit::DeleteEmitter(i)));
                    }
                });
                tolerances_ui(ui, scene, &Selection::Emitter(i), &mut state.tolerance);
            }
        }
        Some(Selection::Material(name)) => {
            let users = material_users(scene, &name);
            if let Some(material) = scene.materials.get_mut(&name) {
                ui.strong(format!("Material {name}"));
                let renamed = committed_text(
                    ui,
                    Id::unique(("material name", &name)),
                    "Material name",
                    &name,
                );
                if let Some(to) = renamed
                    && to != name
                {
                    commands.push(Command::Edit(SceneEdit::RenameMaterial {
                        from: name.clone(),
                        to,
                    }));
                }
                material_ui(ui, material);
                if users.is_empty() {
                    ui.label("Used by nothing yet.");
                } else {
                    ui.label(format!("Used by {}.", users.join(", ")));
                }
                ui.horizontal(|ui| {
                    if ui.button("Duplicate material").clicked() {
                        commands.push(Command::Edit(SceneEdit::DuplicateMaterial(name.clone())));
                    }
                    if ui.button("Delete material").clicked() {
                        commands.push(Command::Edit(SceneEdit::DeleteMaterial(name.clone())));
                    }
                });
            }
        }
        None => {
            ui.label("Select an emitter, part or material to edit it.");
        }
    }
    if !state.doc.problems.is_empty() {
        ui.separator();
        ui.colored_label(
            ui.visuals().error_fg_color,
            "Invalid scene (not simulated; the last valid one keeps running):",
        );
        for problem in &state.doc.problems {
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
                let off = if e.enabled { "" } else { " (off)" };
                item(
                    ui,
                    Selection::Emitter(i),
                    format!("Emitter {}{off}", e.name),
                );
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

fn part_ui(
    ui: &mut Ui,
    index: usize,
    part: &mut Part,
    materials: &[String],
    design: Option<&DesignState>,
    commands: &mut Vec<Command>,
) {
    ui.strong(format!("Part ({})", part.shape.generator().kind()));
    // Committed whole: the luminous opening may name the part.
    let id = Id::unique(("part name", index));
    if let Some(to) = committed_text(ui, id, "Name", &part.name)
        && to != part.name
    {
        commands.push(Command::Edit(SceneEdit::RenamePart { part: index, to }));
    }
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
    let mut fields = ShapeFields {
        part: &part.name,
        design,
        commands,
    };
    shape_ui(ui, &mut part.shape, &mut fields);
    transform_ui(ui, &mut part.transform);
    ui.separator();
    crate::finish_fields::finish_ui(ui, &mut part.finish, &mut |ui, field, label| {
        fields.tick(ui, &format!("finish.{field}"), label, Unit::Finish);
    });
}

#[derive(Clone, Copy)]
enum Unit {
    Millimetres,
    Degrees,
    /// A finish's number: micrometres for lengths, plain for slopes.
    Finish,
}

/// What a part's shape fields are drawn with: the part's name and the
/// Design pane's ticks beside each continuous parameter (shown while the
/// pane is in front or something is ticked; a ticked value shows the
/// bounds the design keeps it in), and the commands they queue.
struct ShapeFields<'a> {
    part: &'a str,
    design: Option<&'a DesignState>,
    commands: &'a mut Vec<Command>,
}

impl ShapeFields<'_> {
    /// A length in mm with its tick beside it.
    fn length(&mut self, ui: &mut Ui, field: &str, label: &str, metres: &mut f64) {
        ui.horizontal(|ui| {
            length_mm(ui, label, metres, MAX_MM);
            self.tick(ui, field, label, Unit::Millimetres);
        });
    }

    fn tick(&mut self, ui: &mut Ui, field: &str, label: &str, unit: Unit) {
        let Some(design) = self.design else { return };
        let vary = format!("{}.{field}", self.part);
        let mut on = design.setup.is_ticked(&vary);
        let tick = ui
            .add(egui::Checkbox::without_text(&mut on))
            .on_hover_text("Vary it in the Design pane's run")
            .accessible_name(format!("Vary {label}"));
        if tick.changed() {
            self.commands.push(Command::TickDesignVariable {
                vary: vary.clone(),
                on,
            });
        }
        if on && let Some([v]) = design.bounds(&vary) {
            let text = match unit {
                Unit::Millimetres => {
                    format!("{:.1} … {:.1} mm", v.lower * 1000.0, v.upper * 1000.0)
                }
                Unit::Degrees => format!("{:.1} … {:.1}°", v.lower, v.upper),
                Unit::Finish if field.contains("sigma") => {
                    format!("{:.3} … {:.3}", v.lower, v.upper)
                }
                Unit::Finish => format!("{:.3} … {:.3} mm", v.lower * 1000.0, v.upper * 1000.0),
            };
            ui.weak(text).on_hover_text(
                "The design keeps it between these bounds, where the scene stays valid",
            );
        }
    }
}

/// Every generator parameter with its unit; the profile shapes point to
/// the profile pane.
fn shape_ui(ui: &mut Ui, shape: &mut Shape, fields: &mut ShapeFields<'_>) {
    match shape {
        Shape::Paraboloid(s) => {
            fields.length(ui, "focal_length", "Focal length", &mut s.focal_length);
            fields.length(
                ui,
                "aperture_diameter",
                "Aperture diameter",
                &mut s.aperture_diameter,
            );
            fields.length(ui, "neck_diameter", "Neck diameter", &mut s.neck_diameter);
            segments(ui, "Segments around", &mut s.segments_around, 3);
            segments(ui, "Segments along", &mut s.segments_along, 1);
            flag(ui, "Faceted", &mut s.faceted);
        }
        Shape::Ellipsoid(s) => {
            fields.length(
                ui,
                "focal_distance",
                "Focal distance",
                &mut s.focal_distance,
            );
            fields.length(
                ui,
                "vertex_distance",
                "Vertex distance",
                &mut s.vertex_distance,
            );
            fields.length(
                ui,
                "cut_below_focus",
                "Cut below focus",
                &mut s.cut_below_focus,
            );
            fields.length(ui, "neck_diameter", "Neck diameter", &mut s.neck_diameter);
            segments(ui, "Segments around", &mut s.segments_around, 3);
            segments(ui, "Segments along", &mut s.segments_along, 1);
            flag(ui, "Faceted", &mut s.faceted);
        }
        Shape::Disk(s) => {
            fields.length(ui, "radius", "Radius", &mut s.radius);
            segments(ui, "Segments around", &mut s.segments_around, 3);
        }
        Shape::Plate(s) => {
            fields.length(ui, "width", "Width", &mut s.width);
            fields.length(ui, "depth", "Depth", &mut s.depth);
        }
        Shape::Dome(s) => {
            fields.length(ui, "radius", "Radius", &mut s.radius);
            fields.length(ui, "height", "Height", &mut s.height);
            segments(ui, "Segments around", &mut s.segments_around, 3);
            segments(ui, "Segments along", &mut s.segments_along, 1);
        }
        Shape::Cylinder(s) => {
            fields.length(ui, "radius", "Radius", &mut s.radius);
            fields.length(ui, "height", "Height", &mut s.height);
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
        Shape::Revolved(s) => {
            interpolation_ui(ui, &mut s.interpolation);
            segments(ui, "Segments around", &mut s.segments_around, 3);
            segments(ui, "Segments per span", &mut s.segments_per_span, 1);
            flag(ui, "Faceted", &mut s.faceted);
        }
        Shape::Extruded(s) => {
            fields.length(ui, "length", "Length", &mut s.length);
            interpolation_ui(ui, &mut s.interpolation);
            segments(ui, "Segments per span", &mut s.segments_per_span, 1);
            flag(ui, "End caps", &mut s.end_caps);
        }
        Shape::Louvre(s) => {
            segments(ui, "Blade count", &mut s.blade_count, 1);
            fields.length(ui, "spacing", "Blade spacing", &mut s.spacing);
            fields.length(ui, "blade_height", "Blade height", &mut s.blade_height);
            fields.length(ui, "blade_length", "Blade length", &mut s.blade_length);
            // The validator refuses ±89° and beyond (blades edge-on).
            ui.horizontal(|ui| {
                number(ui, "Blade tilt", &mut s.tilt_deg, -88.9..=88.9, 0.5, "°");
                fields.tick(ui, "tilt_deg", "Blade tilt", Unit::Degrees);
            });
            segments(ui, "Cross blade count", &mut s.cross_blade_count, 0);
            if s.cross_blade_count > 0 {
                if s.cross_spacing <= 0.0 {
                    s.cross_spacing = s.spacing;
                }
                fields.length(
                    ui,
                    "cross_spacing",
                    "Cross blade spacing",
                    &mut s.cross_spacing,
                );
            }
        }
        Shape::Mesh(m) => {
            ui.label(format!("Triangles from the OBJ file {}", m.path));
            for (group, material) in &m.group_materials {
                ui.label(format!("Group {group}: material {material}"));
            }
        }
    }
    if let Some((points_m, _)) = profile_mut(shape) {
        ui.separator();
        ui.label(format!("Profile: {} points", points_m.len()));
        if ui
            .button("Edit the profile")
            .on_hover_text("Shape it in the Profile pane, with the run's photons drawn through it")
            .clicked()
        {
            fields
                .commands
                .push(Command::ShowPane(crate::dock::Pane::Profile));
        }
    } else {
        ui.separator();
        let hover = if shape.has_parametric_section() {
            "Its section in the Profile pane, with rays traced through it; convert it there to shape it freely"
        } else {
            "Its cut by a C-plane in the Profile pane, among the luminaire's other surfaces, with rays traced through it"
        };
        if ui.button("Show the section").on_hover_text(hover).clicked() {
            fields
                .commands
                .push(Command::ShowPane(crate::dock::Pane::Profile));
        }
    }
}

fn interpolation_ui(ui: &mut Ui, interpolation: &mut Interpolation) {
    labelled(ui, "Interpolation", |ui| {
        egui::ComboBox::from_id_salt("interpolation")
            .selected_text(match interpolation {
                Interpolation::Linear => "Straight segments",
                Interpolation::CatmullRom => "Smooth (Catmull-Rom)",
            })
            .show_ui(ui, |ui| {
                ui.selectable_value(
                    interpolation,
                    Interpolation::CatmullRom,
                    "Smooth (Catmull-Rom)",
                );
                ui.selectable_value(interpolation, Interpolation::Linear, "Straight segments");
            })
            .response
    });
}

/// A text field whose value is taken only when the user is done with it
/// (Enter or leaving the field): names and file paths that mean something
/// only once complete. While the field has focus its text lives in the
/// UI's memory under `id`; returns the text when committed.
fn committed_text(ui: &mut Ui, id: Id, label: &str, value: &str) -> Option<String> {
    let mut buffer: String = ui
        .data(|d| d.get_temp(id))
        .unwrap_or_else(|| value.to_owned());
    let response: Response = labelled(ui, label, |ui| ui.text_edit_singleline(&mut buffer));
    if response.lost_focus() {
        ui.data_mut(|d| d.remove::<String>(id));
        // Escape leaves the field as it was.
        let cancelled = ui.input(|i| i.key_pressed(egui::Key::Escape));
        (!cancelled).then(|| buffer.trim().to_owned())
    } else {
        if response.has_focus() {
            ui.data_mut(|d| {
                d.insert_temp(id, buffer);
            });
        } else {
            ui.data_mut(|d| d.remove::<String>(id));
        }
        None
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

/// What the running simulation read of each ray file: its path as the
/// scene gives it, and the file's own figures.
#[derive(Debug, Clone, PartialEq)]
pub struct RayFileRead {
    pub path: String,
    pub rays: usize,
    /// As the header declares it (None: unknown), and the rays' sum.
    pub declared_lm: Option<f32>,
    pub summed_lm: f64,
}

/// The ray files the running simulation's scene holds (read once there:
/// the panel reads no file).
fn ray_files_read(state: &EditorState) -> Vec<RayFileRead> {
    let Some(snapshot) = state.snapshot() else {
        return Vec::new();
    };
    snapshot
        .luminaire
        .prepared
        .emitters
        .iter()
        .filter_map(|prepared| match (&prepared.shape, &prepared.directions) {
            (
                EmitterShape::RayFile { path },
                lucerna_tracer::prepared::EmitterDirections::RayFile(sampler),
            ) => Some(RayFileRead {
                path: path.clone(),
                rays: sampler.rays.len(),
                declared_lm: sampler.rays.header.luminous_flux_lm,
                summed_lm: sampler.total_lm,
            }),
            _ => None,
        })
        .collect()
}

fn emitter_ui(
    ui: &mut Ui,
    index: usize,
    e: &mut Emitter,
    materials: &[String],
    scene_dir: &Path,
    ray_files: &[RayFileRead],
) {
    ui.strong("Emitter");
    text(ui, "Name", &mut e.name);
    flag(ui, "Enabled", &mut e.enabled);
    number(ui, "Flux", &mut e.flux_lm, 0.0..=1e7, 1.0, " lm");
    if let EmitterShape::RayFile { path } = &e.shape {
        // The file's own flux beside the one the scene sets: flux_lm
        // scales the rays to it.
        let words = match ray_files.iter().find(|r| &r.path == path) {
            Some(r) => {
                let own = match r.declared_lm {
                    Some(declared) => format!(
                        "{declared:.1} lm declared, {:.1} lm in its rays",
                        r.summed_lm
                    ),
                    None => format!("{:.1} lm in its rays (none declared)", r.summed_lm),
                };
                format!("The file: {own}, {} rays", r.rays)
            }
            None => "The file: not read yet (see the problems below)".to_owned(),
        };
        ui.label(words)
            .on_hover_text("The emitter sends Flux; the file's rays say only how it is shared out");
    }
    let mut kind = emitter_shape_kind(&e.shape);
    labelled(ui, "Emitter shape", |ui| {
        egui::ComboBox::from_id_salt("emitter shape")
            .selected_text(kind)
            .show_ui(ui, |ui| {
                for k in EMITTER_SHAPES {
                    ui.selectable_value(&mut kind, k, k);
                }
            })
            .response
    });
    if kind != emitter_shape_kind(&e.shape) {
        e.shape = emitter_shape_as(&e.shape, kind);
    }
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
        EmitterShape::RayFile { path } => {
            text(ui, "Ray file", path).on_hover_text(
                "An IES TM-25 ray file (.tm25ray), relative to the scene file: photons start at its rays, placed by the transform",
            );
        }
    }
    if !matches!(e.shape, EmitterShape::RayFile { .. }) {
        emission_ui(ui, index, &mut e.emission, scene_dir);
    }
    labelled(ui, "Emitter material", |ui| {
        egui::ComboBox::from_id_salt("emitter material")
            .selected_text(e.material.as_deref().unwrap_or("absorbing (none)"))
            .show_ui(ui, |ui| {
                ui.selectable_value(&mut e.material, None, "absorbing (none)");
                for m in materials {
                    ui.selectable_value(&mut e.material, Some(m.clone()), m);
                }
            })
            .response
    });
    transform_ui(ui, &mut e.transform);
}

/// Lambertian emission or a measured IES/LDT distribution from a file
/// relative to the scene's folder, with whether that file is there.
fn emission_ui(ui: &mut Ui, index: usize, emission: &mut Emission, scene_dir: &Path) {
    let measured = matches!(emission, Emission::Profile(_));
    let mut choice = measured;
    labelled(ui, "Emission", |ui| {
        egui::ComboBox::from_id_salt("emission")
            .selected_text(if choice {
                "Measured (IES/LDT file)"
            } else {
                "Lambertian"
            })
            .show_ui(ui, |ui| {
                ui.selectable_value(&mut choice, false, "Lambertian");
                ui.selectable_value(&mut choice, true, "Measured (IES/LDT file)");
            })
            .response
    });
    if choice != measured {
        *emission = if choice {
            Emission::Profile(String::new())
        } else {
            Emission::Lambertian
        };
    }
    if let Emission::Profile(file) = emission {
        if let Some(path) = committed_text(
            ui,
            Id::unique(("profile file", index)),
            "Profile file",
            file,
        ) {
            *file = path;
        }
        ui.menu_button("Choose profile file", |ui| {
            let found = profile_files_near(scene_dir);
            if found.is_empty() {
                ui.label("No IES or LDT files in or beside the scene's folder.");
            }
            egui::ScrollArea::vertical()
                .max_height(320.0)
                .show(ui, |ui| {
                    for f in found {
                        if ui.button(&f).clicked() {
                            *file = f;
                        }
                    }
                });
        });
        let resolved = scene_dir.join(file.as_str());
        if file.trim().is_empty() {
            ui.label("Name an IES or LDT file, relative to the scene's folder.");
        } else if resolved.is_file() {
            ui.label(format!("Reads {}", resolved.display()));
        } else {
            ui.colored_label(
                ui.visuals().error_fg_color,
                format!("No such file: {}", resolved.display()),
            );
        }
    }
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

/// The selected part's or emitter's manufacturing tolerances, under its
/// parameters, while the Tolerance pane is shown (and no analysis runs).
fn tolerances_ui(
    ui: &mut Ui,
    scene: &Scene,
    selection: &Selection,
    tolerance: &mut crate::tolerance_state::ToleranceState,
) {
    if !tolerance.shown || tolerance.is_running() {
        return;
    }
    ui.separator();
    crate::tolerance_pane::selected_ui(ui, scene, Some(selection), &mut tolerance.setup);
}
