//! The profile pane: the selected part in section, as an optics drawing
//! shows it. A revolved or extruded part's profile, large enough to shape
//! it; a paraboloid's, ellipsoid's, dome's or cylinder's exact section,
//! read-only; any other part's cut by the section plane. Around it, the
//! luminaire's other surfaces where the plane cuts them (every part,
//! hidden or not), and through it a fan of rays traced from each
//! emitter's centre and edges through the real geometry (it follows a
//! drag: each preview's luminaire is traced again), or the run's own
//! photons in that plane. The plane is a chosen C-plane through the
//! part's origin (an extruded profile's is its own, C0).

use std::sync::Arc;

use egui::Ui;
use glam::Vec3;
use lucerna_scene::Shape;
use lucerna_scene::section::{SectionPlane, section_cuts};
use lucerna_scene::shapes::{Revolved, editable_revolution};
use lucerna_scene::tessellate::SurfaceKind;
use lucerna_simulation::Luminaire;
use lucerna_tracer::{Fate, PhotonPath, sample_photon_paths, section_fan};

use crate::command::{Command, Selection};
use crate::modelling::{
    CONVERTED_PROFILE_TOLERANCE_M, ProfilePlane, SceneEdit, lamps_in_profile_plane, profile_mut,
};
use crate::profile_editor::{Profile, SectionCut, profile_editor_ui, section_drawing_ui};
use crate::state::EditorState;

/// Photons traced for the drawing, and at most how many are drawn.
const PHOTONS_SAMPLED: u32 = 4000;
const RAYS_DRAWN: usize = 60;
/// A revolved part's ray is drawn if it stays this close to a meridional
/// plane (mm).
const MERIDIONAL_MM: f64 = 1.5;
/// Length of an escaped photon's last leg (mm).
const EXIT_LEG_MM: f64 = 120.0;
/// The fan: directions from each point of an emitter, and the most
/// surfaces a ray meets.
const FAN_RAYS_PER_POINT: usize = 15;
const FAN_BOUNCES: u32 = 8;

/// Which rays the section shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RaysShown {
    /// Principal rays from each emitter's centre and edges, traced
    /// through the geometry again for each preview (they follow a drag).
    #[default]
    Fan,
    /// The run's own first photons that travel in the plane.
    RunPhotons,
}

/// A path in a profile's plane (mm).
type PlanePath = Vec<[f64; 2]>;

/// What was traced or cut for one luminaire, part and key: made again
/// when any of them changes.
#[derive(Debug)]
struct Kept<K, T> {
    luminaire: Arc<Luminaire>,
    part: usize,
    key: K,
    value: T,
}

/// `slot`'s value if it was made for `luminaire`, `part` and `key`, else
/// `make`'s, kept in it.
fn kept<'a, K: PartialEq, T>(
    slot: &'a mut Option<Kept<K, T>>,
    luminaire: &Arc<Luminaire>,
    part: usize,
    key: K,
    make: impl FnOnce() -> T,
) -> &'a T {
    let fresh = slot
        .as_ref()
        .is_some_and(|k| Arc::ptr_eq(&k.luminaire, luminaire) && k.part == part && k.key == key);
    if !fresh {
        *slot = Some(Kept {
            luminaire: luminaire.clone(),
            part,
            key,
            value: make(),
        });
    }
    match slot {
        Some(k) => &k.value,
        None => unreachable!("filled above"),
    }
}

/// What the pane shows and keeps: the plane, the rays chosen, and what
/// was traced or cut for a luminaire, part and plane.
#[derive(Debug, Default)]
pub struct ProfilePane {
    /// The section's C-plane (degrees).
    pub c_plane_deg: f64,
    pub rays_shown: RaysShown,
    rays: Option<Kept<(), Vec<PlanePath>>>,
    /// Keyed by the C-plane (its bits).
    fan: Option<Kept<u64, Vec<PlanePath>>>,
    /// Keyed by the C-plane and whether the part's own cut is drawn.
    cuts: Option<Kept<(u64, bool), Vec<SectionCut>>>,
    /// A parametric part's section as a profile, kept per shape (finding
    /// it samples the surface: milliseconds, not for every frame).
    section: Option<(Shape, Option<Revolved>)>,
}

impl ProfilePane {
    /// The rays drawn through part `index` in the section: the fan, traced
    /// again for each luminaire (each preview of a drag), or the run's
    /// photons, traced again when the luminaire changes but not while a
    /// pointer is down (a drag keeps the ones it had).
    fn shown_rays(&mut self, ui: &Ui, state: &EditorState, index: usize) -> Vec<PlanePath> {
        let Some(s) = state.snapshot() else {
            return Vec::new();
        };
        let luminaire = s.luminaire.clone();
        match self.rays_shown {
            RaysShown::Fan => self.fan_for(&luminaire, index).to_vec(),
            RaysShown::RunPhotons if ui.input(|i| !i.pointer.any_down()) || self.rays.is_some() => {
                self.rays_for(&luminaire, index).to_vec()
            }
            RaysShown::RunPhotons => Vec::new(),
        }
    }

    /// The plane of part `index`'s section: through its origin, in the
    /// chosen C-plane (an extruded profile's own, C0); None for a part
    /// drawn in its own frame that is turned or scaled.
    fn plane_of(&self, luminaire: &Luminaire, index: usize) -> Option<SectionPlane> {
        let p = luminaire.scene.parts.get(index)?;
        let t = &p.transform;
        let own_frame = matches!(p.shape, Shape::Revolved(_) | Shape::Extruded(_))
            || p.shape.has_parametric_section();
        if own_frame && (t.rotate_deg != [0.0; 3] || t.scale != [1.0; 3]) {
            return None;
        }
        let c = if matches!(p.shape, Shape::Extruded(_)) {
            0.0
        } else {
            self.c_plane_deg
        };
        let origin = Vec3::new(
            t.translate[0] as f32,
            t.translate[1] as f32,
            t.translate[2] as f32,
        );
        Some(SectionPlane::of_c_plane(origin, c))
    }

    fn fan_for(&mut self, luminaire: &Arc<Luminaire>, part: usize) -> &[PlanePath] {
        let plane = self.plane_of(luminaire, part);
        kept(
            &mut self.fan,
            luminaire,
            part,
            self.c_plane_deg.to_bits(),
            || {
                plane.map_or(Vec::new(), |plane| {
                    section_fan(&luminaire.prepared, plane, FAN_RAYS_PER_POINT, FAN_BOUNCES)
                        .iter()
                        .map(|path| in_plane_mm(&plane, path))
                        .collect()
                })
            },
        )
        .as_slice()
    }

    /// Where the plane cuts the luminaire's surfaces: the part's own cut
    /// highlighted where `own` (it has no profile curve to draw), left
    /// out otherwise.
    fn cuts_for(&mut self, luminaire: &Arc<Luminaire>, part: usize, own: bool) -> Vec<SectionCut> {
        let plane = self.plane_of(luminaire, part);
        let key = (self.c_plane_deg.to_bits(), own);
        kept(&mut self.cuts, luminaire, part, key, || {
            let Some(plane) = plane else {
                return Vec::new();
            };
            let t = &luminaire.tessellated;
            section_cuts(t, &plane)
                .into_iter()
                .filter_map(|cut| {
                    let surface = &t.surfaces[cut.surface];
                    let mine = surface.kind == SurfaceKind::Part && surface.index == part;
                    (own || !mine).then(|| SectionCut {
                        segments_mm: cut
                            .segments
                            .iter()
                            .map(|s| s.map(|p| [p[0] * 1000.0, p[1] * 1000.0]))
                            .collect(),
                        highlighted: mine,
                    })
                })
                .collect()
        })
        .clone()
    }

    /// The cuts around part `index` (its own too where `own`), for the
    /// newest luminaire shown.
    fn shown_cuts(&mut self, state: &EditorState, index: usize, own: bool) -> Vec<SectionCut> {
        match state.snapshot() {
            Some(s) => {
                let luminaire = s.luminaire.clone();
                self.cuts_for(&luminaire, index, own)
            }
            None => Vec::new(),
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
        kept(&mut self.rays, luminaire, part, (), || {
            profile_rays(luminaire, part)
        })
        .as_slice()
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

/// A path's points in the section plane (mm), its escape drawn as a last
/// leg of [`EXIT_LEG_MM`].
fn in_plane_mm(plane: &SectionPlane, path: &PhotonPath) -> PlanePath {
    let mut points: Vec<[f64; 2]> = path
        .points
        .iter()
        .map(|&q| plane.coordinates(q).0.map(|v| v * 1000.0))
        .collect();
    if let Some(d) = path.escape_direction()
        && let Some(&last) = path.points.last()
    {
        let end = last + d * (EXIT_LEG_MM as f32 / 1000.0);
        points.push(plane.coordinates(end).0.map(|v| v * 1000.0));
    }
    points
}

/// The section's controls: its C-plane (where the part's section depends
/// on it) and which rays it draws.
fn section_controls_ui(ui: &mut Ui, pane: &mut ProfilePane, c_plane: bool) {
    ui.horizontal(|ui| {
        if c_plane {
            crate::widgets::labelled(ui, "Section in C-plane", |ui| {
                ui.add(
                    egui::DragValue::new(&mut pane.c_plane_deg)
                        .range(0.0..=359.0)
                        .speed(1.0)
                        .suffix("°"),
                )
            });
        }
        crate::widgets::labelled(ui, "Rays", |ui| {
            egui::ComboBox::from_id_salt("section rays")
                .selected_text(match pane.rays_shown {
                    RaysShown::Fan => "fan from the emitters",
                    RaysShown::RunPhotons => "the run's photons",
                })
                .show_ui(ui, |ui| {
                    ui.selectable_value(&mut pane.rays_shown, RaysShown::Fan, "fan from the emitters")
                        .on_hover_text("Rays from each emitter's centre and edges, followed through the geometry: mirrors reflect, glass refracts, a diffuse surface ends them");
                    ui.selectable_value(
                        &mut pane.rays_shown,
                        RaysShown::RunPhotons,
                        "the run's photons",
                    )
                    .on_hover_text("The run's own first photons that travel in this plane");
                })
                .response
        });
    });
}

/// A part that has no profile or exact section, cut by the plane: its
/// cut highlighted among the others', with the rays through them.
fn cut_section_ui(ui: &mut Ui, state: &mut EditorState, pane: &mut ProfilePane, index: usize) {
    let Some(part) = state.scene().and_then(|s| s.parts.get(index)) else {
        return;
    };
    let (name, kind) = (part.name.clone(), part.shape.generator().kind());
    let origin = part.transform.translate;
    section_controls_ui(ui, pane, true);
    let rays = pane.shown_rays(ui, state, index);
    let cuts = pane.shown_cuts(state, index, true);
    ui.strong(format!(
        "Section of {name} ({kind}) in C{:.0}",
        pane.c_plane_deg
    ));
    if !cuts.iter().any(|c| c.highlighted) {
        ui.label("The plane does not cut it here: choose another C-plane.");
    }
    ui.label(format!(
        "Cut by the plane through its origin: it in colour, the luminaire's other surfaces in grey, {} rays through them.",
        rays.len()
    ));
    let plane = SectionPlane::of_c_plane(
        Vec3::new(origin[0] as f32, origin[1] as f32, origin[2] as f32),
        pane.c_plane_deg,
    );
    let lamps_mm: Vec<(String, [f64; 2])> = state.scene().map_or(Vec::new(), |s| {
        s.emitters
            .iter()
            .filter(|e| e.enabled)
            .map(|e| {
                let t = e.transform.translate;
                let at = Vec3::new(t[0] as f32, t[1] as f32, t[2] as f32);
                (e.name.clone(), plane.coordinates(at).0.map(|v| v * 1000.0))
            })
            .collect()
    });
    let drawing_height = (ui.available_height() - 40.0).clamp(300.0, 1200.0);
    let mut no_points = Vec::new();
    section_drawing_ui(
        ui,
        Profile {
            part: index,
            plane: ProfilePlane::WidthHeight,
            points_m: &mut no_points,
            interpolation: lucerna_scene::Interpolation::Linear,
            segments_per_span: 1,
            lamps_mm: &lamps_mm,
            rays_mm: &rays,
            cuts_mm: &cuts,
            drawing_height,
        },
    );
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
    section_controls_ui(ui, pane, true);
    let rays = pane.shown_rays(ui, state, index);
    let cuts = pane.shown_cuts(state, index, false);
    ui.strong(format!("Section of {name} ({kind})"));
    ui.horizontal_wrapped(|ui| {
        ui.label(format!(
            "Read-only: its parameters set its shape, drawn through the {} points an editable profile would get. {} rays drawn through it.",
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
            cuts_mm: &cuts,
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
    if let Some(index) = part.filter(|&i| !has_profile(state, i)) {
        if !parametric_section_ui(ui, state, pane, index) {
            cut_section_ui(ui, state, pane, index);
        }
        return;
    }
    let Some(index) = part.filter(|&i| has_profile(state, i)) else {
        ui.label(
            "Select a part to see it in section here: a revolved or extruded part's profile to shape it, any other part's section with the rays through it.",
        );
        // A button for each part: its profile to edit, or its section.
        let shown: Vec<(usize, String)> = state.scene().map_or(Vec::new(), |s| {
            s.parts
                .iter()
                .enumerate()
                .map(|(i, p)| match p.shape {
                    Shape::Revolved(_) | Shape::Extruded(_) => {
                        (i, format!("Edit the profile of {}", p.name))
                    }
                    _ => (i, format!("Show the section of {}", p.name)),
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
    let revolved = state
        .scene()
        .and_then(|s| s.parts.get(index))
        .is_some_and(|p| matches!(p.shape, Shape::Revolved(_)));
    section_controls_ui(ui, pane, revolved);
    let cuts = pane.shown_cuts(state, index, false);
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
        "{} rays drawn through it; the luminaire's other surfaces in grey where the plane cuts them.",
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
                    cuts_mm: &cuts,
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
