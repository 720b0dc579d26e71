//! The Room tab: draws the live preview room of `room_state.rs` (the room
//! chosen, its fields, the picture and its figures) and queues a
//! [`RoomCommand`] for each change. Nothing here reads a file or renders.

use std::path::Path;
use std::time::Instant;

use egui::{Color32, ColorImage, TextureHandle, TextureOptions, Ui};
use lucerna_gpu::BackendRequest;
use lucerna_room::TASK_TARGETS;

use crate::colour::{LUX_PARTS, LinearScale, lux_colour, lux_legend_ui};
use crate::command::Command;
use crate::room_preview::RoomPicture;
use crate::room_state::{RoomCommand, RoomLive, RoomSurface};
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

/// What the Room tab keeps of its own: the picture shown and its texture.
#[derive(Default)]
pub struct RoomView {
    shown: RoomShown,
    texture: Option<(u64, RoomShown, TextureHandle)>,
}

impl std::fmt::Debug for RoomView {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RoomView")
            .field("shown", &self.shown)
            .finish_non_exhaustive()
    }
}

fn file_label(path: &Path) -> String {
    path.file_stem().map_or_else(
        || path.display().to_string(),
        |s| s.to_string_lossy().into_owned(),
    )
}

pub fn room_ui(ui: &mut Ui, state: &mut EditorState, view: &mut RoomView) {
    state.room.watch();
    let mut commands = Vec::new();
    egui::ScrollArea::vertical()
        .auto_shrink([false, false])
        .show(ui, |ui| {
            room_contents_ui(
                ui,
                &state.room,
                state.snapshot().is_none(),
                view,
                &mut commands,
            );
        });
    for c in commands {
        state.push(Command::Room(c));
    }
}

fn room_contents_ui(
    ui: &mut Ui,
    room: &RoomLive,
    no_snapshot: bool,
    view: &mut RoomView,
    commands: &mut Vec<RoomCommand>,
) {
    let now = Instant::now();
    // A row wider than the pane (the renderer's combo) must not widen the
    // lines below it: they wrap at the pane's own width.
    let width = ui.available_width();
    room_choice_ui(ui, room, commands);
    if let Some(e) = room.error() {
        ui.colored_label(ui.visuals().error_fg_color, e);
    }
    if let Some(path) = room.loading() {
        ui.label(format!("reading {}…", file_label(path)));
    }
    room_fields_ui(ui, room, commands);
    for p in room.problems() {
        ui.colored_label(ui.visuals().error_fg_color, p);
    }
    ui.separator();
    ui.scope(|ui| {
        ui.set_max_width(width);
        status_ui(ui, room, no_snapshot, now);
        figures_ui(ui, room, commands);
    });
    ui.horizontal(|ui| {
        for (shown, label) in [
            (RoomShown::Picture, "Picture"),
            (RoomShown::FalseColour, "False colour (lx)"),
            (RoomShown::WorkPlane, "Work plane"),
        ] {
            ui.selectable_value(&mut view.shown, shown, label);
        }
    });
    picture_ui(ui, room, view);
}

fn room_choice_ui(ui: &mut Ui, room: &RoomLive, commands: &mut Vec<RoomCommand>) {
    let current = room.room().map(|r| r.path.clone());
    let mut chosen = current.clone();
    labelled(ui, "Room", |ui| {
        egui::ComboBox::from_id_salt("room file")
            .selected_text(
                current
                    .as_deref()
                    .map_or_else(|| "none".to_owned(), file_label),
            )
            .show_ui(ui, |ui| {
                for path in room.rooms() {
                    ui.selectable_value(&mut chosen, Some(path.clone()), file_label(path));
                }
            })
            .response
    });
    if chosen != current
        && let Some(path) = chosen
    {
        commands.push(RoomCommand::Choose(path));
    }
    let mut backend = room.renderer();
    labelled(ui, "Renderer", |ui| {
        egui::ComboBox::from_id_salt("room renderer")
            .selected_text(backend_name(backend))
            .show_ui(ui, |ui| {
                for b in [
                    BackendRequest::Auto,
                    BackendRequest::Cpu,
                    BackendRequest::Gpu,
                ] {
                    ui.selectable_value(&mut backend, b, backend_name(b));
                }
            })
            .response
    });
    if backend != room.renderer() {
        commands.push(RoomCommand::Renderer(backend));
    }
}

fn backend_name(b: BackendRequest) -> &'static str {
    match b {
        BackendRequest::Auto => "Auto (hardware GPU, else CPU)",
        BackendRequest::Cpu => "CPU",
        BackendRequest::Gpu => "GPU (any adapter)",
    }
}

/// One reflectance field; a change is queued.
fn reflectance_ui(
    ui: &mut Ui,
    label: &str,
    value: f64,
    surface: RoomSurface,
    commands: &mut Vec<RoomCommand>,
) {
    let mut edited = value;
    number(ui, label, &mut edited, 0.0..=1.0, 0.005, "");
    if edited != value {
        commands.push(RoomCommand::Reflectance(surface, edited));
    }
}

/// Room size and surface reflectances.
fn room_fields_ui(ui: &mut Ui, room: &RoomLive, commands: &mut Vec<RoomCommand>) {
    let Some(draft) = room.draft() else { return };
    let name = &draft.file.name;
    let name = if name.is_empty() {
        "The room"
    } else {
        name.as_str()
    };
    ui.label(format!(
        "{name}: every luminaire it places is the edited one, with its own opening"
    ));
    let r = &draft.file.room;
    if draft.mesh.is_none() {
        let size = [r.width_m, r.depth_m, r.height_m];
        let mut edited = size;
        ui.horizontal_wrapped(|ui| {
            for (value, label) in edited.iter_mut().zip(["Width", "Depth", "Height"]) {
                number(ui, label, value, 1.0..=50.0, 0.02, " m");
            }
        });
        if edited != size {
            commands.push(RoomCommand::Resize(edited));
        }
        // A line each: a label with its value cannot wrap as one.
        for (value, label, surface) in [
            (r.floor.reflectance, "Floor reflectance", RoomSurface::Floor),
            (r.walls.reflectance, "Wall reflectance", RoomSurface::Walls),
            (
                r.ceiling.reflectance,
                "Ceiling reflectance",
                RoomSurface::Ceiling,
            ),
        ] {
            reflectance_ui(ui, label, value, surface, commands);
        }
    } else {
        ui.label("Size and surfaces from the room's OBJ.");
        reflectance_ui(
            ui,
            "Wall reflectance",
            r.walls.reflectance,
            RoomSurface::Walls,
            commands,
        );
        for (name, surface) in &r.materials {
            reflectance_ui(
                ui,
                &format!("{name} reflectance"),
                surface.reflectance,
                RoomSurface::Material(name.clone()),
                commands,
            );
        }
    }
}

fn status_ui(ui: &mut Ui, room: &RoomLive, no_snapshot: bool, now: Instant) {
    if let Some(e) = room.start_error() {
        ui.colored_label(ui.visuals().error_fg_color, e);
    }
    // Always one line here, so that the controls below stay where the
    // hand is when a render starts or ends.
    ui.label(if no_snapshot {
        "No light distribution yet."
    } else if room.is_rendering() {
        "rendering…"
    } else {
        "Picture up to date."
    });
    match room.picture() {
        Some(p) => {
            ui.label(format!(
                "Shown: generation {}, {} photons, room revision {}",
                p.generation, p.photons, p.room_revision
            ));
            if p.quality == crate::room_preview::PictureQuality::Drag {
                ui.label(
                    "Draft while dragging: 160×100, the polar rule with fewer nodes (about 0.7×); \
                     the full rule follows when the hand stops",
                );
            }
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

fn figures_ui(ui: &mut Ui, room: &RoomLive, commands: &mut Vec<RoomCommand>) {
    let current = room.target_index();
    let mut target = current;
    labelled(ui, "Task area (EN 12464-1)", |ui| {
        // As wide as the pane leaves, the task's name cut short there.
        egui::ComboBox::from_id_salt("task area")
            .selected_text(TASK_TARGETS[target].name)
            .width(ui.available_width().clamp(80.0, 260.0))
            .truncate()
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
    if target != current {
        commands.push(RoomCommand::Task(target));
    }
    let Some(p) = room.picture() else { return };
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

fn picture_ui(ui: &mut Ui, room: &RoomLive, view: &mut RoomView) {
    let Some(p) = room.picture() else { return };
    if view.shown == RoomShown::WorkPlane {
        work_plane_ui(ui, p);
        return;
    }
    let [w, h] = p.size;
    // `lucerna render --false-colour`'s scale: linear up to a round
    // number above the 99th percentile.
    let scale = LinearScale::over_p99(p.illuminance_lx.iter().map(|&v| f64::from(v)), LUX_PARTS);
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
                    .map(|&v| lux_colour(&scale, f64::from(v)))
                    .collect(),
            ),
        };
        let texture = ui
            .ctx()
            .load_texture("room view", image, TextureOptions::LINEAR);
        view.texture = Some((p.serial, view.shown, texture));
    }
    if view.shown == RoomShown::FalseColour {
        lux_legend_ui(ui, &scale);
    }
    if let Some((_, _, texture)) = &view.texture {
        let width = ui.available_width().max(50.0);
        let size = egui::vec2(width, width * h as f32 / w.max(1) as f32);
        ui.add(egui::Image::new((texture.id(), size)));
    }
}

/// The work-plane grid from above: each point's cell in false colour, the
/// room's outline, the luminaires as crosses, the lux under the pointer.
fn work_plane_ui(ui: &mut Ui, p: &RoomPicture) {
    let grid = &p.grid;
    let lux_scale = LinearScale::over_max(grid.lux.iter().copied(), LUX_PARTS);
    lux_legend_ui(ui, &lux_scale);
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
            painter.rect_filled(r, 0.0, lux_colour(&lux_scale, lux));
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
