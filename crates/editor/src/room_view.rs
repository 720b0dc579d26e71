//! The live preview room: a room of `crates/room` lit by the current
//! distribution, updated as the simulation converges and after each edit.
//! The worker, the room being edited and the refinement rule live in
//! `room_preview.rs`; this file only draws them.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use egui::{Color32, ColorImage, TextureHandle, TextureOptions, Ui};

use crate::colour::false_colour;
use crate::room_preview::{
    Refinement, RenderRequest, RoomBackend, RoomPicture, RoomPreview, RoomSetup, TASK_TARGETS,
    TaskTarget, default_rooms_dir, lux_scale, room_files,
};
use crate::state::EditorState;
use crate::widgets::{labelled, number};

/// Which picture of the room is shown.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RoomShown {
    /// The tone-mapped view from the room file's camera.
    #[default]
    Picture,
    /// Illuminance on the surfaces seen, linear in lux.
    FalseColour,
    /// The work-plane grid from above, with its figures.
    WorkPlane,
}

/// The room view's own state (its room, renderer and last picture).
#[derive(Default)]
pub struct RoomView {
    /// The room files offered (found on first use).
    rooms: Option<Vec<PathBuf>>,
    /// The room as edited in the fields (may be invalid while typing).
    draft: Option<RoomSetup>,
    /// The last valid room, as rendered; `revision` counts its changes.
    room: Option<Arc<RoomSetup>>,
    revision: u64,
    /// Why the last chosen room file could not be used.
    load_error: Option<String>,
    backend: RoomBackend,
    preview: Option<RoomPreview>,
    refinement: Refinement,
    picture: Option<RoomPicture>,
    shown: RoomShown,
    /// Index into [`TASK_TARGETS`]; `None` until a room suggests one.
    target: Option<usize>,
    texture: Option<(u64, RoomShown, TextureHandle)>,
}

impl std::fmt::Debug for RoomView {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RoomView")
            .field("room", &self.room.as_ref().map(|r| r.path.clone()))
            .field("revision", &self.revision)
            .field("preview", &self.preview)
            .finish_non_exhaustive()
    }
}

impl RoomView {
    /// Takes `path` as the previewed room; on failure the current room
    /// stays and the error is shown.
    fn choose_room(&mut self, path: &Path) {
        match RoomSetup::load(path) {
            Ok(setup) => {
                self.target = Some(TaskTarget::for_room(&format!(
                    "{} {}",
                    path.display(),
                    setup.file.name
                )));
                self.draft = Some(setup.clone());
                self.room = Some(Arc::new(setup));
                self.revision += 1;
                self.load_error = None;
            }
            Err(e) => self.load_error = Some(crate::state::error_chain(&e)),
        }
    }

    /// The draft becomes the rendered room when it changed and is valid.
    fn commit_draft(&mut self) -> Vec<String> {
        let (Some(draft), Some(room)) = (&self.draft, &self.room) else {
            return Vec::new();
        };
        if draft.file == room.file {
            return Vec::new();
        }
        let problems = draft.problems();
        if problems.is_empty() {
            self.room = Some(Arc::new(draft.clone()));
            self.revision += 1;
        }
        problems
    }
}

fn file_label(path: &Path) -> String {
    path.file_stem().map_or_else(
        || path.display().to_string(),
        |s| s.to_string_lossy().into_owned(),
    )
}

pub fn room_ui(ui: &mut Ui, state: &mut EditorState, view: &mut RoomView) {
    egui::ScrollArea::vertical()
        .auto_shrink([false, false])
        .show(ui, |ui| room_contents_ui(ui, state, view));
}

fn room_contents_ui(ui: &mut Ui, state: &mut EditorState, view: &mut RoomView) {
    let now = Instant::now();
    if view.rooms.is_none() {
        let rooms = room_files(&default_rooms_dir());
        let first = rooms
            .iter()
            .find(|p| p.file_stem().is_some_and(|s| s == "office"))
            .or(rooms.first())
            .cloned();
        view.rooms = Some(rooms);
        match first {
            Some(path) => view.choose_room(&path),
            None => {
                view.load_error = Some(format!(
                    "no room files (*.toml) in {}",
                    default_rooms_dir().display()
                ));
            }
        }
    }
    if view.preview.is_none() {
        let ctx = ui.ctx().clone();
        view.preview = Some(RoomPreview::start(view.backend, move || {
            ctx.request_repaint()
        }));
        view.refinement.reset();
    }
    if let Some(preview) = &mut view.preview
        && let Some(picture) = preview.poll()
    {
        view.picture = Some(picture);
    }

    room_choice_ui(ui, view);
    if let Some(e) = &view.load_error {
        ui.colored_label(ui.visuals().error_fg_color, e);
    }
    let problems = room_fields_ui(ui, view);
    for p in &problems {
        ui.colored_label(ui.visuals().error_fg_color, p);
    }

    // Ask for a picture of the newest table and room when one is due.
    let snapshot = state.snapshot().cloned();
    if let (Some(snapshot), Some(room), Some(preview)) = (&snapshot, &view.room, &mut view.preview)
    {
        if let Some(size) = view.refinement.due(snapshot, view.revision, now) {
            preview.request(RenderRequest {
                snapshot: snapshot.clone(),
                room: room.clone(),
                room_revision: view.revision,
                size,
            });
        }
        if let Some(wait) = view.refinement.fine_due_in(now) {
            ui.ctx().request_repaint_after(wait);
        }
    }
    ui.separator();
    status_ui(ui, view, snapshot.is_none(), now);
    figures_ui(ui, view);
    ui.horizontal(|ui| {
        for (shown, label) in [
            (RoomShown::Picture, "Picture"),
            (RoomShown::FalseColour, "False colour (lx)"),
            (RoomShown::WorkPlane, "Work plane"),
        ] {
            ui.selectable_value(&mut view.shown, shown, label);
        }
    });
    picture_ui(ui, view);
}

fn room_choice_ui(ui: &mut Ui, view: &mut RoomView) {
    let current = view.room.as_ref().map(|r| r.path.clone());
    let rooms = view.rooms.clone().unwrap_or_default();
    let mut chosen = current.clone();
    labelled(ui, "Room", |ui| {
        egui::ComboBox::from_id_salt("room file")
            .selected_text(
                current
                    .as_deref()
                    .map_or_else(|| "none".to_owned(), file_label),
            )
            .show_ui(ui, |ui| {
                for path in &rooms {
                    ui.selectable_value(&mut chosen, Some(path.clone()), file_label(path));
                }
            })
            .response
    });
    if chosen != current
        && let Some(path) = chosen
    {
        view.choose_room(&path);
    }
    let mut backend = view.backend;
    labelled(ui, "Renderer", |ui| {
        egui::ComboBox::from_id_salt("room renderer")
            .selected_text(backend_name(backend))
            .show_ui(ui, |ui| {
                for b in [RoomBackend::Auto, RoomBackend::Cpu, RoomBackend::Gpu] {
                    ui.selectable_value(&mut backend, b, backend_name(b));
                }
            })
            .response
    });
    if backend != view.backend {
        view.backend = backend;
        // A fresh worker opens the chosen renderer; the old one stops.
        view.preview = None;
    }
}

fn backend_name(b: RoomBackend) -> &'static str {
    match b {
        RoomBackend::Auto => "Auto (hardware GPU, else CPU)",
        RoomBackend::Cpu => "CPU",
        RoomBackend::Gpu => "GPU (any adapter)",
    }
}

/// Room size and surface reflectances; returns the draft's problems.
fn room_fields_ui(ui: &mut Ui, view: &mut RoomView) -> Vec<String> {
    let Some(draft) = &mut view.draft else {
        return Vec::new();
    };
    let name = &draft.file.name;
    let name = if name.is_empty() {
        "The room"
    } else {
        name.as_str()
    };
    ui.label(format!(
        "{name}: every luminaire it places is the edited one, with its own opening"
    ));
    if draft.mesh.is_none() {
        let r = &draft.file.room;
        let mut size = [r.width_m, r.depth_m, r.height_m];
        ui.horizontal_wrapped(|ui| {
            for (value, label) in size.iter_mut().zip(["Width", "Depth", "Height"]) {
                number(ui, label, value, 1.0..=50.0, 0.02, " m");
            }
        });
        if size != [r.width_m, r.depth_m, r.height_m] {
            draft.resize(size);
        }
        let r = &mut draft.file.room;
        ui.horizontal_wrapped(|ui| {
            for (surface, label) in [
                (&mut r.floor, "Floor reflectance"),
                (&mut r.walls, "Wall reflectance"),
                (&mut r.ceiling, "Ceiling reflectance"),
            ] {
                number(ui, label, &mut surface.reflectance, 0.0..=1.0, 0.005, "");
            }
        });
    } else {
        ui.label("Size and surfaces from the room's OBJ.");
        let r = &mut draft.file.room;
        ui.horizontal_wrapped(|ui| {
            number(
                ui,
                "Wall reflectance",
                &mut r.walls.reflectance,
                0.0..=1.0,
                0.005,
                "",
            );
            for (name, surface) in &mut r.materials {
                number(
                    ui,
                    &format!("{name} reflectance"),
                    &mut surface.reflectance,
                    0.0..=1.0,
                    0.005,
                    "",
                );
            }
        });
    }
    view.commit_draft()
}

fn status_ui(ui: &mut Ui, view: &RoomView, no_snapshot: bool, now: Instant) {
    if let Some(e) = view.preview.as_ref().and_then(RoomPreview::start_error) {
        ui.colored_label(ui.visuals().error_fg_color, e);
    }
    let rendering = view.preview.as_ref().is_some_and(RoomPreview::is_rendering);
    if no_snapshot {
        ui.label("No light distribution yet.");
    } else if rendering {
        ui.label("rendering…");
    }
    match &view.picture {
        Some(p) => {
            ui.label(format!(
                "Shown: generation {}, {} photons, room revision {}",
                p.generation, p.photons, p.room_revision
            ));
            ui.label(format!(
                "{}×{} in {:.0} ms on {}, {:.1} s old",
                p.size[0],
                p.size[1],
                p.render_time.as_secs_f64() * 1e3,
                p.backend,
                now.saturating_duration_since(p.finished_at).as_secs_f64()
            ));
            // Keeps the age true while nothing else repaints.
            ui.ctx()
                .request_repaint_after(std::time::Duration::from_secs(1));
        }
        None if !no_snapshot => {
            ui.label("No picture yet.");
        }
        None => {}
    }
}

fn figures_ui(ui: &mut Ui, view: &mut RoomView) {
    let mut target = view.target.unwrap_or(0).min(TASK_TARGETS.len() - 1);
    labelled(ui, "Task area (EN 12464-1)", |ui| {
        egui::ComboBox::from_id_salt("task area")
            .selected_text(TASK_TARGETS[target].name)
            .width(260.0)
            .show_ui(ui, |ui| {
                for (i, t) in TASK_TARGETS.iter().enumerate() {
                    ui.selectable_value(
                        &mut target,
                        i,
                        format!("{} ({:.0} lx, U0 {:.2})", t.name, t.e_m_lx, t.u0),
                    );
                }
            })
            .response
    });
    view.target = Some(target);
    let Some(p) = &view.picture else { return };
    let f = p.figures;
    let t = TASK_TARGETS[target];
    ui.horizontal_wrapped(|ui| {
        ui.label(format!("Emin {:.1} lx", f.e_min_lx));
        ui.label(format!("Eavg {:.1} lx", f.e_avg_lx));
        ui.label(format!("Emax {:.1} lx", f.e_max_lx));
        ui.label(format!("U0 {:.2}", f.u0));
    });
    let (text, colour) = if t.met_by(&f) {
        ("meets", Color32::from_rgb(40, 160, 60))
    } else {
        ("fails", Color32::from_rgb(200, 50, 40))
    };
    ui.colored_label(
        colour,
        format!(
            "Verdict: {text} {:.0} lx, U0 {:.2} (Eavg {:.1} lx, U0 {:.2})",
            t.e_m_lx, t.u0, f.e_avg_lx, f.u0
        ),
    );
    ui.label(format!(
        "Work plane at {:.2} m, {} points; {:.1} lx of it uniform indirect light",
        p.grid.height_m, f.points, p.indirect_lux
    ));
}

fn picture_ui(ui: &mut Ui, view: &mut RoomView) {
    let Some(p) = &view.picture else { return };
    if view.shown == RoomShown::WorkPlane {
        work_plane_ui(ui, p);
        return;
    }
    let [w, h] = p.size;
    let top = lux_top(p.illuminance_lx.iter().map(|&v| f64::from(v)));
    let fresh = view
        .texture
        .as_ref()
        .is_some_and(|(serial, shown, _)| *serial == p.serial && *shown == view.shown);
    if !fresh {
        let image = match view.shown {
            RoomShown::Picture => ColorImage::from_rgb([w as usize, h as usize], &p.rgb),
            _ => ColorImage::new(
                [w as usize, h as usize],
                p.illuminance_lx
                    .iter()
                    .map(|&v| lux_colour(f64::from(v), top))
                    .collect(),
            ),
        };
        let texture = ui
            .ctx()
            .load_texture("room view", image, TextureOptions::LINEAR);
        view.texture = Some((p.serial, view.shown, texture));
    }
    if view.shown == RoomShown::FalseColour {
        lux_legend_ui(ui, top);
    }
    if let Some((_, _, texture)) = &view.texture {
        let width = ui.available_width().max(50.0);
        let size = egui::vec2(width, width * h as f32 / w.max(1) as f32);
        ui.add(egui::Image::new((texture.id(), size)));
    }
}

/// Decades of illuminance below the scale's top the false colour spans:
/// a spot's pool and the walls a thousand times darker both read.
const LUX_DECADES: f64 = 3.0;

/// The top of the scale: a round number above the 99th percentile
/// (`lucerna render`'s rule), so a few bright pixels do not set it.
fn lux_top(lux: impl Iterator<Item = f64>) -> f64 {
    let (top, _) = lux_scale(lux);
    top
}

/// Logarithmic false colour over [`LUX_DECADES`] below `top` lx (the
/// cube map's colours); luminaires (negative) white.
fn lux_colour(lux: f64, top: f64) -> Color32 {
    if lux < 0.0 {
        Color32::WHITE
    } else {
        false_colour(((lux.max(1e-9) / top).log10() / LUX_DECADES + 1.0).clamp(0.0, 1.0) as f32)
    }
}

/// Swatches at 1, 2 and 5 per decade up to the top, each labelled in lux.
fn lux_legend_ui(ui: &mut Ui, top: f64) {
    ui.horizontal_wrapped(|ui| {
        let bottom = top / 10f64.powf(LUX_DECADES);
        let mut ticks = Vec::new();
        let mut decade = 10f64.powf(bottom.log10().floor());
        while decade <= top * 1.0001 {
            for m in [1.0, 2.0, 5.0] {
                let v = decade * m;
                if v >= bottom * 0.999 && v <= top * 1.0001 {
                    ticks.push(v);
                }
            }
            decade *= 10.0;
        }
        for v in ticks {
            let (rect, _) = ui.allocate_exact_size(egui::vec2(14.0, 14.0), egui::Sense::hover());
            ui.painter().rect_filled(rect, 2.0, lux_colour(v, top));
            ui.label(if v < 10.0 {
                format!("{v:.1} lx")
            } else {
                format!("{v:.0} lx")
            });
        }
    });
}

/// The work-plane grid from above: each point's cell in false colour, the
/// room's outline, the luminaires as crosses, the lux under the pointer.
fn work_plane_ui(ui: &mut Ui, p: &RoomPicture) {
    let grid = &p.grid;
    let top = lux_top(grid.lux.iter().copied());
    lux_legend_ui(ui, top);
    let (room_w, room_d) = p.room_m;
    let width = ui.available_width().max(50.0);
    let scale = width / room_w.max(room_d).max(1e-3) as f32;
    let size = egui::vec2(room_w as f32 * scale, room_d as f32 * scale);
    let (rect, response) = ui.allocate_exact_size(size, egui::Sense::hover());
    let painter = ui.painter_at(rect);
    // Plan with y (depth) up, as architects draw it.
    let to_screen =
        |x: f64, y: f64| rect.left_bottom() + egui::vec2(x as f32 * scale, -(y as f32) * scale);
    painter.rect_filled(rect, 0.0, Color32::from_gray(40));
    let cell = |coords: &[f64], k: usize| -> (f64, f64) {
        let half_before = if k > 0 {
            0.5 * (coords[k] - coords[k - 1])
        } else if coords.len() > 1 {
            0.5 * (coords[1] - coords[0])
        } else {
            0.25
        };
        let half_after = if k + 1 < coords.len() {
            0.5 * (coords[k + 1] - coords[k])
        } else {
            half_before
        };
        (coords[k] - half_before, coords[k] + half_after)
    };
    let mut hovered = None;
    for (j, _) in grid.ys.iter().enumerate() {
        let (y0, y1) = cell(&grid.ys, j);
        for (i, _) in grid.xs.iter().enumerate() {
            let (x0, x1) = cell(&grid.xs, i);
            let Some(&lux) = grid.lux.get(j * grid.xs.len() + i) else {
                continue;
            };
            let r = egui::Rect::from_two_pos(to_screen(x0, y0), to_screen(x1, y1));
            painter.rect_filled(r, 0.0, lux_colour(lux, top));
            if response.hover_pos().is_some_and(|pos| r.contains(pos)) {
                hovered = Some((grid.xs[i], grid.ys[j], lux));
            }
        }
    }
    let stroke = egui::Stroke::new(1.5, Color32::WHITE);
    for &(x, y) in &p.luminaires_m {
        let c = to_screen(x, y);
        painter.line_segment([c - egui::vec2(5.0, 5.0), c + egui::vec2(5.0, 5.0)], stroke);
        painter.line_segment(
            [c - egui::vec2(5.0, -5.0), c + egui::vec2(5.0, -5.0)],
            stroke,
        );
    }
    painter.rect_stroke(
        rect,
        0.0,
        egui::Stroke::new(1.0, Color32::from_gray(200)),
        egui::StrokeKind::Inside,
    );
    match hovered {
        Some((x, y, lux)) => ui.label(format!("x {x:.2} m, y {y:.2} m: {lux:.1} lx")),
        None => ui.label(format!(
            "{room_w:.2} m × {room_d:.2} m; hover a cell to read its illuminance"
        )),
    };
}
