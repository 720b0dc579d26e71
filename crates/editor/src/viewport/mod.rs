//! The 3D viewport: the luminaire's parts shaded by material, emitters
//! glowing, the selected part highlighted; orbit, pan, zoom, frame-all and
//! the datasheet views; a click selects the part under the pointer (the
//! tracer's BVH picks it); the cube around the luminaire shows the current
//! intensity map in false colour (the paper's Figure 3), and a toggle draws
//! a sample of traced photon paths coloured by bounce count.

mod camera;
mod geometry;
mod render;

use std::sync::Arc;

use egui::{Color32, Rect, Sense, Ui, Vec2};
use glam::{Vec2 as GVec2, Vec3};
use lucerna_scene::SurfaceKind;
use lucerna_simulation::{Luminaire, Snapshot};
use lucerna_tracer::{PhotonPath, sample_photon_paths};

pub use camera::{Bounds, OrbitCamera, StandardView};
pub use render::GpuTarget;

use crate::colour::{DECADES, intensity_colour};
use crate::state::{Command, EditorState, Selection};
use geometry::{LineVertex, MeshVertex, axis_lines, bounce_colour, cube_edges, path_lines};
use render::{CubeTexels, Uniforms, ViewportFrame, paint_callback};

/// What is drawn around the luminaire to show its light.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CubeShown {
    Off,
    /// The exported map: pooled, and filtered if the settings say so.
    #[default]
    Exported,
    /// The photon counts as traced, before pooling and filtering.
    Raw,
    /// The exported table as a surface: each direction as far out as it
    /// is bright, as optics and lighting tools show a distribution.
    Solid,
}

impl CubeShown {
    fn label(self) -> &'static str {
        match self {
            CubeShown::Off => "No cube",
            CubeShown::Exported => "Cube: exported map",
            CubeShown::Raw => "Cube: raw counts",
            CubeShown::Solid => "Photometric solid",
        }
    }

    /// Whether a cube of texels is drawn.
    fn is_cube(self) -> bool {
        matches!(self, CubeShown::Exported | CubeShown::Raw)
    }
}

/// Photons traced again for the path display; the escaped ones among
/// them are drawn.
const PATH_PHOTONS: u32 = 3000;
/// Paths drawn at most: enough to see a stray reflection, few enough to
/// read.
const MAX_PATHS: usize = 400;
/// The cube's half edge over the luminaire's bounding radius.
const CUBE_REACH: f32 = 1.3;

/// The photometric solid built for a snapshot at a radius (m), and the
/// peak (cd) it is scaled to.
type BuiltSolid = (Arc<Snapshot>, f32, Arc<Vec<MeshVertex>>, f64);

/// Paths traced for a luminaire with (seed, bounce limit).
type SampledPaths = (Arc<Luminaire>, (u32, u32), Arc<Vec<PhotonPath>>);

/// The viewport's own state: camera, display choices and what it has
/// built from the current luminaire and snapshot.
#[derive(Default)]
pub struct Viewport {
    pub camera: OrbitCamera,
    pub cube: CubeShown,
    pub show_paths: bool,
    pub show_axes: bool,
    /// The renderer's target; none where egui does not draw with wgpu
    /// (some tests), when the view shows a note instead.
    pub target: Option<GpuTarget>,
    /// Width over height of the view as last drawn.
    aspect: f32,
    framed: Option<Arc<Luminaire>>,
    mesh: Option<ShownMesh>,
    cube_texels: Option<(Arc<Snapshot>, CubeShown, CubeTexels, f64)>,
    solid: Option<BuiltSolid>,
    /// Keyed by the luminaire and the seed and bounce limit they were
    /// traced with, so they stay the run's photons when those change.
    paths: Option<SampledPaths>,
    lines: Option<(LinesKey, Arc<Vec<LineVertex>>)>,
}

impl std::fmt::Debug for Viewport {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Viewport")
            .field("camera", &self.camera)
            .field("cube", &self.cube)
            .field("show_paths", &self.show_paths)
            .finish_non_exhaustive()
    }
}

#[derive(Debug, Clone, PartialEq)]
struct LinesKey {
    paths: Option<usize>,
    axes: bool,
    cube: bool,
    centre: Vec3,
    reach: f32,
}

/// The luminaire a mesh was built of, whether it shows finishes, the
/// vertices and their bounds.
type ShownMesh = (Arc<Luminaire>, bool, Arc<Vec<MeshVertex>>, Bounds);

impl Viewport {
    pub fn new(target: Option<GpuTarget>) -> Self {
        Viewport {
            show_axes: true,
            target,
            ..Viewport::default()
        }
    }

    /// The luminaire's vertices and bounds, rebuilt when it changes; a
    /// finish is shown by its normals except while a drag changes the
    /// scene (its preview takes a few tenths of a second: the frame after
    /// the release has it).
    fn mesh_of(
        &mut self,
        luminaire: &Arc<Luminaire>,
        finishes: bool,
    ) -> (Arc<Vec<MeshVertex>>, Bounds) {
        match &self.mesh {
            Some((l, shown, mesh, bounds)) if Arc::ptr_eq(l, luminaire) && *shown == finishes => {
                (mesh.clone(), *bounds)
            }
            _ => {
                let mut vertices = geometry::luminaire_vertices(&luminaire.tessellated, finishes);
                let mut bounds = Bounds::of_points(&luminaire.tessellated.mesh.positions);
                // A ray-file emitter has no surface: its rays' starts show
                // where it is, marks 0.4 % of the view across.
                let marks =
                    geometry::ray_origin_marks(&luminaire.prepared, 4e-3 * bounds.radius.max(1e-3));
                if !marks.is_empty() {
                    let points: Vec<Vec3> = marks.iter().map(|v| Vec3::from(v.position)).collect();
                    let mut all = luminaire.tessellated.mesh.positions.clone();
                    all.extend(points);
                    bounds = Bounds::of_points(&all);
                    vertices.extend(marks);
                }
                let mesh = Arc::new(vertices);
                self.mesh = Some((luminaire.clone(), finishes, mesh.clone(), bounds));
                (mesh, bounds)
            }
        }
    }

    /// The cube's texels and the peak they are scaled to, rebuilt per
    /// snapshot.
    fn cube_of(&mut self, snapshot: &Arc<Snapshot>) -> Option<(CubeTexels, f64)> {
        if !self.cube.is_cube() {
            return None;
        }
        if let Some((s, shown, texels, peak)) = &self.cube_texels
            && Arc::ptr_eq(s, snapshot)
            && *shown == self.cube
        {
            return Some((texels.clone(), *peak));
        }
        let layout = snapshot.map.layout;
        let raw;
        let candela: &[f64] = match self.cube {
            CubeShown::Raw => {
                raw = snapshot.map.candela();
                &raw
            }
            _ => &snapshot.candela,
        };
        let peak = candela.iter().copied().fold(0.0, f64::max);
        let texels = CubeTexels {
            resolution: layout.resolution,
            texels: Arc::new(geometry::cube_texels(layout, candela, peak)),
        };
        self.cube_texels = Some((snapshot.clone(), self.cube, texels.clone(), peak));
        Some((texels, peak))
    }

    /// The photometric solid of the snapshot's table, `radius` (m) at its
    /// peak, about the luminaire's origin, and the peak; rebuilt per
    /// snapshot.
    fn solid_of(
        &mut self,
        snapshot: &Arc<Snapshot>,
        radius: f32,
    ) -> Option<(Arc<Vec<MeshVertex>>, f64)> {
        if self.cube != CubeShown::Solid {
            return None;
        }
        if let Some((s, r, solid, peak)) = &self.solid
            && Arc::ptr_eq(s, snapshot)
            && *r == radius
        {
            return Some((solid.clone(), *peak));
        }
        let solid = Arc::new(geometry::photometric_solid(
            &snapshot.table,
            Vec3::ZERO,
            radius,
        ));
        let peak = snapshot.table.peak().0;
        self.solid = Some((snapshot.clone(), radius, solid.clone(), peak));
        Some((solid, peak))
    }

    /// The escaped photons of the run's first iteration, traced again.
    fn paths_of(
        &mut self,
        luminaire: &Arc<Luminaire>,
        seed: u32,
        bounces: u32,
    ) -> Arc<Vec<PhotonPath>> {
        if let Some((l, key, paths)) = &self.paths
            && Arc::ptr_eq(l, luminaire)
            && *key == (seed, bounces)
        {
            return paths.clone();
        }
        let mut paths = sample_photon_paths(&luminaire.prepared, seed, bounces, PATH_PHOTONS);
        paths.retain(|p| p.escape_direction().is_some());
        paths.truncate(MAX_PATHS);
        let paths = Arc::new(paths);
        self.paths = Some((luminaire.clone(), (seed, bounces), paths.clone()));
        paths
    }

    fn lines_of(
        &mut self,
        paths: Option<&Arc<Vec<PhotonPath>>>,
        centre: Vec3,
        reach: f32,
        axis_length: f32,
    ) -> Arc<Vec<LineVertex>> {
        let key = LinesKey {
            paths: paths.map(|p| Arc::as_ptr(p) as usize),
            axes: self.show_axes,
            cube: self.cube.is_cube(),
            centre,
            reach,
        };
        if let Some((k, lines)) = &self.lines
            && *k == key
        {
            return lines.clone();
        }
        let mut lines = if self.show_axes {
            axis_lines(axis_length)
        } else {
            Vec::new()
        };
        if self.cube.is_cube() {
            lines.extend(cube_edges(centre, reach));
        }
        if let Some(paths) = paths {
            lines.extend(path_lines(paths, centre, reach));
        }
        let lines = Arc::new(lines);
        self.lines = Some((key, lines.clone()));
        lines
    }
}

/// The selection a hit on `triangle` of the luminaire makes.
fn selection_of_triangle(luminaire: &Luminaire, triangle: usize) -> Option<Selection> {
    let t = &luminaire.tessellated;
    let surface = &t.surfaces[geometry::surface_of_triangle(t, triangle)?];
    Some(match surface.kind {
        SurfaceKind::Part => Selection::Part(surface.index),
        SurfaceKind::Emitter => Selection::Emitter(surface.index),
    })
}

/// The surface index the selection highlights, if it is drawn.
fn highlighted_surface(luminaire: &Luminaire, selection: Option<&Selection>) -> u32 {
    let wanted = match selection {
        Some(Selection::Part(i)) => (SurfaceKind::Part, *i),
        Some(Selection::Emitter(i)) => (SurfaceKind::Emitter, *i),
        _ => return u32::MAX,
    };
    luminaire
        .tessellated
        .surfaces
        .iter()
        .position(|s| (s.kind, s.index) == wanted)
        .map_or(u32::MAX, |s| s as u32)
}

/// Picks what lies under `ndc` in a view of `aspect`.
pub fn pick(
    camera: &OrbitCamera,
    luminaire: &Luminaire,
    ndc: GVec2,
    aspect: f32,
    depth_bounds: Bounds,
) -> Option<Selection> {
    let (origin, dir) = camera.ray(ndc, aspect, depth_bounds);
    let hit =
        luminaire
            .prepared
            .bvh
            .intersect_any_surface(origin.into(), dir.into(), f32::INFINITY)?;
    selection_of_triangle(luminaire, hit.triangle as usize)
}

fn toolbar_ui(ui: &mut Ui, vp: &mut Viewport, bounds: Option<Bounds>) {
    ui.horizontal_wrapped(|ui| {
        for view in StandardView::ALL {
            if ui.button(view.label()).clicked() {
                vp.camera.look_from(view);
                if let Some(b) = bounds {
                    vp.camera.frame(b, vp.aspect);
                }
            }
        }
        if ui
            .button("Frame all")
            .on_hover_text("F, or double-click the view")
            .clicked()
            && let Some(b) = bounds
        {
            vp.camera.frame(b, vp.aspect);
        }
        ui.separator();
        egui::ComboBox::from_id_salt("cube shown")
            .selected_text(vp.cube.label())
            .show_ui(ui, |ui| {
                for c in [
                    CubeShown::Exported,
                    CubeShown::Raw,
                    CubeShown::Solid,
                    CubeShown::Off,
                ] {
                    ui.selectable_value(&mut vp.cube, c, c.label());
                }
            })
            .response
            .on_hover_text(
                "What shows the light around the luminaire: the intensity cube, or the \
                 photometric solid (each direction as far out as it is bright)",
            );
        ui.checkbox(&mut vp.show_paths, "Photon paths");
        ui.checkbox(&mut vp.show_axes, "Axes");
    });
}

/// Converts a gamma colour to the linear clear colour.
fn linear_rgb(c: Color32) -> [f32; 3] {
    let [r, g, b, _] = egui::Rgba::from(c).to_array();
    [r, g, b]
}

pub fn viewport_ui(ui: &mut Ui, state: &mut EditorState, vp: &mut Viewport) {
    let snapshot = state.run.snapshot.clone();
    let luminaire = snapshot.as_ref().map(|s| s.luminaire.clone());
    let finishes = !(state.is_coarse_preview() || state.doc.in_gesture());
    let mesh = luminaire.as_ref().map(|l| vp.mesh_of(l, finishes));
    toolbar_ui(ui, vp, mesh.as_ref().map(|m| m.1));
    let size = ui.available_size().max(Vec2::splat(32.0));
    let (rect, response) = ui.allocate_exact_size(size, Sense::click_and_drag());
    let aspect = rect.width() / rect.height().max(1.0);
    vp.aspect = aspect;
    response.widget_info(|| egui::WidgetInfo::labeled(egui::Role::Canvas, true, "Luminaire in 3D"));
    let (Some(snapshot), Some(luminaire), Some((mesh, bounds))) = (snapshot, luminaire, mesh)
    else {
        ui.painter().text(
            rect.center(),
            egui::Align2::CENTER_CENTER,
            "No luminaire yet",
            egui::FontId::proportional(14.0),
            ui.visuals().weak_text_color(),
        );
        return;
    };
    // A new document is framed once; edits keep the camera where it is.
    if snapshot.generation == 0
        && !vp
            .framed
            .as_ref()
            .is_some_and(|f| Arc::ptr_eq(f, &luminaire))
        || vp.framed.is_none()
    {
        vp.camera.frame(bounds, aspect);
        vp.framed = Some(luminaire.clone());
    }
    let reach = CUBE_REACH * bounds.radius;
    // Depth planes hold the cube's corners and the paths drawn to it, and
    // the photometric solid (`reach` at its peak from the origin).
    let depth_bounds = Bounds {
        centre: bounds.centre,
        radius: (reach * 3f32.sqrt()).max(reach + bounds.centre.length()),
    };
    interact(
        ui,
        &response,
        rect,
        vp,
        &luminaire,
        bounds,
        depth_bounds,
        state,
    );

    let cube = vp.cube_of(&snapshot);
    let solid = vp.solid_of(&snapshot, reach);
    let paths = vp.show_paths.then(|| {
        vp.paths_of(
            &luminaire,
            state.run.settings.seed,
            state.run.settings.max_bounces,
        )
    });
    let lines = vp.lines_of(paths.as_ref(), bounds.centre, reach, 0.6 * bounds.radius);
    let selected = highlighted_surface(&luminaire, state.doc.selection.as_ref());
    match vp.target {
        Some(target) => {
            let ppp = ui.ctx().pixels_per_point();
            let uniforms = Uniforms {
                view_projection: vp
                    .camera
                    .view_projection(aspect, depth_bounds)
                    .to_cols_array_2d(),
                eye: vp.camera.eye().extend(1.0).to_array(),
                cube: bounds.centre.extend(reach).to_array(),
                selected_surface: selected,
                _pad: [0; 3],
            };
            let frame = ViewportFrame {
                target,
                size_px: [
                    (rect.width() * ppp).round().max(1.0) as u32,
                    (rect.height() * ppp).round().max(1.0) as u32,
                ],
                uniforms,
                background: linear_rgb(ui.visuals().extreme_bg_color),
                mesh,
                solid: solid.as_ref().map(|(s, _)| s.clone()),
                cube: cube.as_ref().map(|(c, _)| c.clone()),
                lines,
            };
            ui.painter().add(paint_callback(rect, frame));
        }
        None => {
            ui.painter().text(
                rect.center(),
                egui::Align2::CENTER_CENTER,
                "The 3D view needs the wgpu renderer",
                egui::FontId::proportional(14.0),
                ui.visuals().weak_text_color(),
            );
        }
    }
    overlay_ui(
        ui,
        rect,
        vp,
        cube.map(|(_, peak)| peak)
            .or(solid.as_ref().map(|(_, peak)| *peak)),
        paths.as_deref(),
        bounds,
        depth_bounds,
    );
}

#[allow(clippy::too_many_arguments)]
fn interact(
    ui: &Ui,
    response: &egui::Response,
    rect: Rect,
    vp: &mut Viewport,
    luminaire: &Luminaire,
    bounds: Bounds,
    depth_bounds: Bounds,
    state: &mut EditorState,
) {
    let delta = response.drag_delta();
    let delta = GVec2::new(delta.x, delta.y);
    let pan = response.dragged_by(egui::PointerButton::Secondary)
        || response.dragged_by(egui::PointerButton::Middle)
        || (response.dragged_by(egui::PointerButton::Primary) && ui.input(|i| i.modifiers.shift));
    if pan {
        vp.camera.pan(delta, rect.height());
    } else if response.dragged_by(egui::PointerButton::Primary) {
        vp.camera.orbit(delta);
    }
    if response.hovered() {
        let scroll = ui.input(|i| i.smooth_scroll_delta.y);
        if scroll != 0.0 {
            vp.camera.zoom(scroll, bounds);
        }
        if ui.input(|i| i.key_pressed(egui::Key::F)) && !ui.ctx().egui_wants_keyboard_input() {
            vp.camera.frame(bounds, vp.aspect);
        }
    }
    if response.double_clicked() {
        vp.camera.frame(bounds, vp.aspect);
    } else if response.clicked()
        && let Some(pos) = response.interact_pointer_pos()
    {
        let ndc = GVec2::new(
            2.0 * (pos.x - rect.left()) / rect.width() - 1.0,
            1.0 - 2.0 * (pos.y - rect.top()) / rect.height(),
        );
        let aspect = rect.width() / rect.height().max(1.0);
        let picked = pick(&vp.camera, luminaire, ndc, aspect, depth_bounds);
        state.push(Command::Select(picked));
    }
}

/// Legends and axis names drawn over the picture.
fn overlay_ui(
    ui: &Ui,
    rect: Rect,
    vp: &Viewport,
    peak: Option<f64>,
    paths: Option<&Vec<PhotonPath>>,
    bounds: Bounds,
    depth_bounds: Bounds,
) {
    let painter = ui.painter_at(rect);
    let font = egui::FontId::proportional(12.0);
    let text = Color32::from_gray(220);
    let mut y = rect.top() + 6.0;
    if let Some(peak) = peak {
        let name = match vp.cube {
            CubeShown::Raw => "Cube: raw counts, log",
            CubeShown::Solid => "Photometric solid: distance linear in cd, colour log",
            _ => "Cube: exported map, log",
        };
        painter.text(
            egui::pos2(rect.left() + 8.0, y),
            egui::Align2::LEFT_TOP,
            format!("{name} over {DECADES:.0} decades"),
            font.clone(),
            text,
        );
        y += 16.0;
        let mut x = rect.left() + 8.0;
        for k in (0..=DECADES as i32).rev() {
            let v = peak / 10f64.powi(k);
            let swatch = Rect::from_min_size(egui::pos2(x, y), egui::vec2(12.0, 12.0));
            painter.rect_filled(swatch, 2.0, intensity_colour(v, peak));
            let label = painter.text(
                egui::pos2(x + 16.0, y),
                egui::Align2::LEFT_TOP,
                format!("{v:.0} cd"),
                font.clone(),
                text,
            );
            x = label.right() + 10.0;
        }
        y += 18.0;
    }
    if let Some(paths) = paths {
        let mut x = rect.left() + 8.0;
        let label = painter.text(
            egui::pos2(x, y),
            egui::Align2::LEFT_TOP,
            format!("{} escaped photon paths, bounces:", paths.len()),
            font.clone(),
            text,
        );
        x = label.right() + 8.0;
        for (b, name) in [(0, "0"), (1, "1"), (2, "2"), (3, "3"), (4, "4+")] {
            let label = painter.text(
                egui::pos2(x, y),
                egui::Align2::LEFT_TOP,
                name,
                font.clone(),
                bounce_colour(b),
            );
            x = label.right() + 8.0;
        }
    }
    if vp.show_axes {
        let aspect = rect.width() / rect.height().max(1.0);
        for (axis, name) in [(Vec3::X, "C0 (x)"), (Vec3::Y, "C90 (y)"), (Vec3::Z, "z up")] {
            let tip = axis * 0.6 * bounds.radius * 1.08;
            if let Some(ndc) = vp.camera.project(tip, aspect, depth_bounds) {
                let at = egui::pos2(
                    rect.left() + 0.5 * (ndc.x + 1.0) * rect.width(),
                    rect.top() + 0.5 * (1.0 - ndc.y) * rect.height(),
                );
                // A dark halo keeps the name readable over a white part.
                for offset in [egui::vec2(1.0, 1.0), egui::vec2(-1.0, -1.0)] {
                    painter.text(
                        at + offset,
                        egui::Align2::CENTER_CENTER,
                        name,
                        font.clone(),
                        Color32::from_black_alpha(200),
                    );
                }
                painter.text(at, egui::Align2::CENTER_CENTER, name, font.clone(), text);
            }
        }
    }
    painter.text(
        rect.left_bottom() + egui::vec2(8.0, -6.0),
        egui::Align2::LEFT_BOTTOM,
        "Drag: orbit · Shift/right drag: pan · Scroll: zoom · Click: select",
        font,
        Color32::from_gray(160),
    );
}
