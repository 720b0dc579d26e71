//! The profile pane: the selected reflector's profile, large enough to
//! shape it, with the run's own photons drawn through it (those that
//! travel in the profile's plane: a revolved part's meridional rays, an
//! extruded part's section).

use std::sync::Arc;

use egui::Ui;
use glam::Vec3;
use lucerna_scene::Shape;
use lucerna_scene::shapes::{Revolved, editable_revolution};
use lucerna_simulation::Luminaire;
use lucerna_tracer::{Fate, sample_photon_paths};

use crate::command::{Command, Selection};
use crate::modelling::{
    CONVERTED_PROFILE_TOLERANCE_M, ProfilePlane, SceneEdit, lamps_in_profile_plane, profile_mut,
};
use crate::profile_editor::{Profile, profile_editor_ui, section_drawing_ui};
use crate::state::EditorState;

/// Photons traced for the drawing, and at most how many are drawn.
const PHOTONS_SAMPLED: u32 = 4000;
const RAYS_DRAWN: usize = 60;
/// A revolved part's ray is drawn if it stays this close to a meridional
/// plane (mm).
const MERIDIONAL_MM: f64 = 1.5;
/// Length of an escaped photon's last leg (mm).
const EXIT_LEG_MM: f64 = 120.0;

/// A path in a profile's plane (mm).
type PlanePath = Vec<[f64; 2]>;

/// The rays drawn, kept per luminaire and part.
#[derive(Debug, Default)]
pub struct ProfilePane {
    rays: Option<(Arc<Luminaire>, usize, Vec<PlanePath>)>,
    /// A parametric part's section as a profile, kept per shape (finding
    /// it samples the surface: milliseconds, not for every frame).
    section: Option<(Shape, Option<Revolved>)>,
}

impl ProfilePane {
    /// The run's rays through part `index`: traced again when the
    /// luminaire changes, but not while a pointer is down (a drag keeps
    /// the rays it had).
    fn shown_rays(&mut self, ui: &Ui, state: &EditorState, index: usize) -> Vec<PlanePath> {
        match state.snapshot() {
            Some(s) if ui.input(|i| !i.pointer.any_down()) || self.rays.is_some() => {
                let luminaire = s.luminaire.clone();
                self.rays_for(&luminaire, index).to_vec()
            }
            _ => Vec::new(),
        }
    }

    fn section_of(&mut self, shape: &Shape) -> Option<Revolved> {
        if !self.section.as_ref().is_some_and(|(s, _)| s == shape) {
            let section = editable_revolution(shape, CONVERTED_PROFILE_TOLERANCE_M);
            self.section = Some((shape.clone(), section));
        }
        self.section.as_ref().and_then(|(_, r)| r.clone())
    }

    fn rays_for(&mut self, luminaire: &Arc<Luminaire>, part: usize) -> &[PlanePath] {
        let fresh = self
            .rays
            .as_ref()
            .is_some_and(|(l, p, _)| Arc::ptr_eq(l, luminaire) && *p == part);
        if !fresh {
            self.rays = Some((luminaire.clone(), part, profile_rays(luminaire, part)));
        }
        self.rays.as_ref().map_or(&[], |(_, _, r)| r.as_slice())
    }
}

/// The run's first photons in part `part`'s profile plane (mm, the part's
/// frame), for a part placed by translation alone.
fn profile_rays(luminaire: &Luminaire, part: usize) -> Vec<PlanePath> {
    let Some(p) = luminaire.scene.parts.get(part) else {
        return Vec::new();
    };
    let t = &p.transform;
    if t.rotate_deg != [0.0; 3] || t.scale != [1.0; 3] {
        return Vec::new();
    }
    let offset = Vec3::new(
        t.translate[0] as f32,
        t.translate[1] as f32,
        t.translate[2] as f32,
    );
    // Every part drawn here but an extrusion is a surface of revolution.
    let revolved = !matches!(p.shape, Shape::Extruded(_));
    let paths = sample_photon_paths(&luminaire.prepared, 1, 64, PHOTONS_SAMPLED);
    let mut rays = Vec::new();
    for path in paths {
        if rays.len() >= RAYS_DRAWN || path.points.len() < 2 {
            continue;
        }
        let mut points: Vec<Vec3> = path.points.iter().map(|&q| q - offset).collect();
        if let Some(d) = path.escape_direction()
            && let Some(&last) = points.last()
        {
            points.push(last + d * (EXIT_LEG_MM as f32 / 1000.0));
        }
        let plane: Option<Vec<[f64; 2]>> = if revolved {
            // The meridional plane of the first leg's azimuth: signed
            // radius along it, and the distance off it.
            let first = points[1] - points[0];
            let azimuth = f64::from(first.y).atan2(f64::from(first.x));
            let (s, c) = azimuth.sin_cos();
            points
                .iter()
                .map(|q| {
                    let (x, y) = (f64::from(q.x), f64::from(q.y));
                    let off = (-x * s + y * c) * 1000.0;
                    (off.abs() <= MERIDIONAL_MM)
                        .then_some([(x * c + y * s) * 1000.0, f64::from(q.z) * 1000.0])
                })
                .collect()
        } else {
            Some(
                points
                    .iter()
                    .map(|q| [f64::from(q.x) * 1000.0, f64::from(q.z) * 1000.0])
                    .collect(),
            )
        };
        if let Some(ray) = plane
            && !matches!(path.fate, Fate::CutOff)
        {
            rays.push(ray);
        }
    }
    rays
}

/// A parametric surface of revolution's section, read-only, with the
/// run's rays through it, and the button that makes it an editable
/// profile; false (nothing drawn) for a part that has no such section.
fn parametric_section_ui(
    ui: &mut Ui,
    state: &mut EditorState,
    pane: &mut ProfilePane,
    index: usize,
) -> bool {
    let Some(part) = state.scene().and_then(|s| s.parts.get(index)) else {
        return false;
    };
    if !part.shape.has_parametric_section() {
        return false;
    }
    let shape = part.shape.clone();
    let Some(mut section) = pane.section_of(&shape) else {
        return false;
    };
    let Some(part) = state.scene().and_then(|s| s.parts.get(index)) else {
        return false;
    };
    let (name, kind) = (part.name.clone(), part.shape.generator().kind());
    let lamps_mm = state
        .scene()
        .map_or(Vec::new(), |s| lamps_in_profile_plane(s, index));
    let rays = pane.shown_rays(ui, state, index);
    ui.strong(format!("Section of {name} ({kind})"));
    ui.horizontal_wrapped(|ui| {
        ui.label(format!(
            "Read-only: its parameters set its shape, drawn through the {} points an editable profile would get. {} photons of the run drawn through it.",
            section.profile.len(),
            rays.len()
        ));
        if ui
            .button("Convert to editable profile")
            .on_hover_text(
                "Replace it by a revolved part whose profile lies within 0.05 mm of it; Undo restores it",
            )
            .clicked()
        {
            state.push(Command::Edit(SceneEdit::ConvertToProfile {
                part: index,
                from: Box::new(shape.clone()),
                to: section.clone(),
            }));
        }
    });
    let drawing_height = (ui.available_height() - 230.0).clamp(300.0, 1200.0);
    section_drawing_ui(
        ui,
        Profile {
            part: index,
            plane: ProfilePlane::RadiusHeight,
            points_m: &mut section.profile,
            interpolation: section.interpolation,
            segments_per_span: section.segments_per_span,
            lamps_mm: &lamps_mm,
            rays_mm: &rays,
            drawing_height,
        },
    );
    true
}

pub fn profile_pane_ui(ui: &mut Ui, state: &mut EditorState, pane: &mut ProfilePane) {
    let part = match state.selection() {
        Some(Selection::Part(i)) => Some(*i),
        _ => None,
    };
    let has_profile = |state: &EditorState, i: usize| {
        state
            .scene()
            .and_then(|s| s.parts.get(i))
            .is_some_and(|p| matches!(p.shape, Shape::Revolved(_) | Shape::Extruded(_)))
    };
    if let Some(index) = part.filter(|&i| !has_profile(state, i))
        && parametric_section_ui(ui, state, pane, index)
    {
        return;
    }
    let Some(index) = part.filter(|&i| has_profile(state, i)) else {
        ui.label(
            "Select a revolved or extruded part to shape its profile here, or a paraboloid, ellipsoid, dome or cylinder to see its section.",
        );
        // A button for each part this pane can show: its profile to edit,
        // or its section.
        let shown: Vec<(usize, String)> = state.scene().map_or(Vec::new(), |s| {
            s.parts
                .iter()
                .enumerate()
                .filter_map(|(i, p)| match p.shape {
                    Shape::Revolved(_) | Shape::Extruded(_) => {
                        Some((i, format!("Edit the profile of {}", p.name)))
                    }
                    ref shape if shape.has_parametric_section() => {
                        Some((i, format!("Show the section of {}", p.name)))
                    }
                    _ => None,
                })
                .collect()
        });
        for (i, label) in shown {
            if ui.button(label).clicked() {
                state.push(crate::command::Command::Select(Some(Selection::Part(i))));
            }
        }
        return;
    };
    let rays = pane.shown_rays(ui, state, index);
    let problems = state.problems().to_vec();
    let mut commands = Vec::new();
    let design = state.design.ticks_visible().then_some(&state.design);
    let Some(scene) = state.doc.scene.as_mut() else {
        return;
    };
    let lamps_mm = lamps_in_profile_plane(scene, index);
    let Some(part) = scene.parts.get_mut(index) else {
        return;
    };
    let name = part.name.clone();
    let (interpolation, segments_per_span) = match &part.shape {
        Shape::Revolved(s) => (s.interpolation, s.segments_per_span),
        Shape::Extruded(s) => (s.interpolation, s.segments_per_span),
        _ => return,
    };
    let Some((points_m, plane)) = profile_mut(&mut part.shape) else {
        return;
    };
    ui.strong(format!("Profile of {name}"));
    ui.label(format!(
        "{} photons of the run drawn through it (those in the profile's plane).",
        rays.len()
    ));
    // The table of points needs about 200 points of height below.
    let drawing_height = (ui.available_height() - 230.0).clamp(300.0, 1200.0);
    egui::ScrollArea::vertical()
        .auto_shrink([false, false])
        .show(ui, |ui| {
            profile_editor_ui(
                ui,
                Profile {
                    part: index,
                    plane,
                    points_m,
                    interpolation,
                    segments_per_span,
                    lamps_mm: &lamps_mm,
                    rays_mm: &rays,
                    drawing_height,
                },
                &problems,
                design.map(|design| crate::profile_editor::PointTicks {
                    part_name: &name,
                    design,
                }),
                &mut commands,
            );
        });
    for c in commands {
        state.push(c);
    }
}
