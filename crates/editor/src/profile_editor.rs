//! The profile editor of revolved (r–z) and extruded (x–z) parts: the
//! control points over the curve the generator builds from them, drawn to
//! scale in millimetres with a grid and the optical axis; points are
//! dragged, added and deleted on the drawing, and typed in the table
//! beneath it.
//!
//! A drag edits the scene in place (one undo step per drag, like any
//! field); adding and deleting points are structural edits queued as
//! [`SceneEdit`]s.

use egui::{
    Align2, CursorIcon, DragValue, FontId, Id, Key, Pos2, Rect, Role, Sense, Stroke, Ui,
    WidgetInfo, pos2, vec2,
};
use lucerna_scene::Interpolation;
use lucerna_scene::check::MAX_LENGTH_M;
use lucerna_scene::profile::sample_profile;

use crate::modelling::{MIN_PROFILE_POINTS, ProfilePlane, SceneEdit};
use crate::state::Command;

/// Height of the drawing (points).
const DRAWING_HEIGHT: f32 = 300.0;
/// Room left of and below the plot for the axes' numbers (points).
const AXIS_MARGIN: [f32; 2] = [44.0, 20.0];
/// Half the side of a control point's grab square (points).
const HANDLE_RADIUS: f32 = 7.0;
/// Smallest span the drawing shows (mm), so a tiny profile is not blown up
/// into a blur of grid lines.
const MIN_VIEW_MM: f64 = 10.0;
/// Dragged points land on this grid (mm): values that read well in the
/// table, finer than any tolerance a spun reflector is made to.
const DRAG_RESOLUTION_MM: f64 = 0.01;
/// The largest coordinate (mm) the validator accepts.
const MAX_MM: f64 = MAX_LENGTH_M * 1000.0;

/// A part's profile as the editor sees it.
pub struct Profile<'a> {
    /// Index of the part in the scene, for the edits it queues.
    pub part: usize,
    pub plane: ProfilePlane,
    /// Control points `[horizontal, z]` (m), edited in place by drags.
    pub points_m: &'a mut Vec<[f64; 2]>,
    pub interpolation: Interpolation,
    pub segments_per_span: u32,
    /// The emitters' names and positions in this plane (mm), drawn so the
    /// profile is shaped around its lamp.
    pub lamps_mm: &'a [(String, [f64; 2])],
    /// Traced photons' paths in this plane (mm), drawn faintly under the
    /// profile so the light's way through it reads at a glance.
    pub rays_mm: &'a [Vec<[f64; 2]>],
    /// Where the plane cuts the luminaire's surfaces (mm): the parts
    /// around the profile, and the part itself where it has no profile.
    pub cuts_mm: &'a [SectionCut],
    /// Height of the drawing (points).
    pub drawing_height: f32,
}

/// Where a section's plane cuts one surface (mm, the drawing's frame).
#[derive(Debug, Clone, PartialEq)]
pub struct SectionCut {
    pub segments_mm: Vec<[[f64; 2]; 2]>,
    /// The selected part's own cut (drawn as its curve), not one around it.
    pub highlighted: bool,
}

/// The part of the data plane (mm) the drawing shows and how it maps to
/// the screen: one scale for both axes, so a profile keeps its shape.
#[derive(Debug, Clone, Copy)]
struct Frame {
    plot: Rect,
    centre_mm: [f64; 2],
    /// Points per millimetre.
    scale: f64,
}

impl Frame {
    fn new(plot: Rect, view_mm: [f64; 4]) -> Frame {
        let [x0, z0, x1, z1] = view_mm;
        let scale = (f64::from(plot.width()) / (x1 - x0)).min(f64::from(plot.height()) / (z1 - z0));
        Frame {
            plot,
            centre_mm: [0.5 * (x0 + x1), 0.5 * (z0 + z1)],
            scale,
        }
    }

    fn screen_from_mm(&self, [x, z]: [f64; 2]) -> Pos2 {
        let c = self.plot.center();
        pos2(
            c.x + ((x - self.centre_mm[0]) * self.scale) as f32,
            c.y - ((z - self.centre_mm[1]) * self.scale) as f32,
        )
    }

    fn mm_from_screen(&self, p: Pos2) -> [f64; 2] {
        let c = self.plot.center();
        [
            self.centre_mm[0] + f64::from(p.x - c.x) / self.scale,
            self.centre_mm[1] - f64::from(p.y - c.y) / self.scale,
        ]
    }

    /// The data rectangle visible in the plot (mm): x0, z0, x1, z1.
    fn visible_mm(&self) -> [f64; 4] {
        let [x0, z1] = self.mm_from_screen(self.plot.left_top());
        let [x1, z0] = self.mm_from_screen(self.plot.right_bottom());
        [x0, z0, x1, z1]
    }
}

/// The view that shows every point with a margin, and the optical axis of
/// a revolved profile.
fn fitted_view_mm(points_mm: &[[f64; 2]], plane: ProfilePlane) -> [f64; 4] {
    let mut view = [
        f64::INFINITY,
        f64::INFINITY,
        f64::NEG_INFINITY,
        f64::NEG_INFINITY,
    ];
    let axis = (plane == ProfilePlane::RadiusHeight)
        .then_some([0.0, points_mm.first().map_or(0.0, |p| p[1])]);
    for p in points_mm
        .iter()
        .chain(axis.iter())
        .filter(|p| p.iter().all(|v| v.is_finite()))
    {
        view = [
            view[0].min(p[0]),
            view[1].min(p[1]),
            view[2].max(p[0]),
            view[3].max(p[1]),
        ];
    }
    if !view.iter().all(|v| v.is_finite()) {
        view = [0.0, 0.0, 0.0, 0.0];
    }
    let mut grow = |lo: usize, hi: usize| {
        let span = (view[hi] - view[lo]).max(MIN_VIEW_MM);
        let mid = 0.5 * (view[lo] + view[hi]);
        view[lo] = mid - 0.6 * span;
        view[hi] = mid + 0.6 * span;
    };
    grow(0, 2);
    grow(1, 3);
    view
}

/// A grid spacing of 1, 2 or 5 × 10ᵏ mm giving about `lines` lines over
/// `span_mm`.
fn grid_step_mm(span_mm: f64, lines: f64) -> f64 {
    lucerna_pictures::scale::round_step((span_mm / lines).max(1e-6))
}

/// `v` with as many decimals as `step` needs.
fn grid_label(v: f64, step: f64) -> String {
    let decimals = (-step.log10()).ceil().max(0.0) as usize;
    // −0 reads oddly on an axis.
    let v = if v.abs() < 0.5 * step { 0.0 } else { v };
    format!("{v:.decimals$}")
}

/// Segment `k` (from point k to k + 1) nearest to `p` and where along it
/// (`t`, not clamped, so that a point beyond an end extends the profile).
fn nearest_segment(points: &[Pos2], p: Pos2) -> Option<(usize, f32)> {
    let mut best: Option<(usize, f32, f32)> = None;
    for k in 0..points.len().saturating_sub(1) {
        let (a, b) = (points[k], points[k + 1]);
        let ab = b - a;
        let t = if ab.length_sq() > 0.0 {
            (p - a).dot(ab) / ab.length_sq()
        } else {
            0.0
        };
        let distance = p.distance(a + ab * t.clamp(0.0, 1.0));
        if best.is_none_or(|(_, _, d)| distance < d) {
            best = Some((k, t, distance));
        }
    }
    best.map(|(k, t, _)| (k, t))
}

/// Where a point added at `p` goes: into the nearest segment, or before
/// the first or after the last point when `p` lies beyond that end.
fn insertion_index(points: &[Pos2], p: Pos2) -> usize {
    match nearest_segment(points, p) {
        None => points.len(),
        Some((0, t)) if t < 0.0 => 0,
        Some((k, t)) if k + 2 == points.len() && t > 1.0 => points.len(),
        Some((k, _)) => k + 1,
    }
}

/// The point halfway along span `k` of the curve the generator builds, so
/// that a point added there leaves the shape as it was (the chord's
/// midpoint would pull a spline towards it).
fn span_midpoint_m(points_m: &[[f64; 2]], interpolation: Interpolation, k: usize) -> [f64; 2] {
    let (a, b) = (points_m[k], points_m[k + 1]);
    let chord = [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1])];
    if !points_m.iter().flatten().all(|v| v.is_finite()) {
        return chord;
    }
    // Two segments per span: sample 1 of a span is its middle.
    let strips = sample_profile(points_m, interpolation, 2);
    let middle = match interpolation {
        Interpolation::Linear => strips.get(k).and_then(|s| s.get(1)),
        Interpolation::CatmullRom => strips.first().and_then(|s| s.get(2 * k + 1)),
    };
    middle.map_or(chord, |m| [m.point.x, m.point.y])
}

fn round_to(v: f64, step: f64) -> f64 {
    (v / step).round() * step
}

/// The validator's messages about this profile's points, by point index
/// (`None`: the profile as a whole), from the panel's "field: message"
/// lines.
fn profile_problems(problems: &[String], part: usize) -> Vec<(Option<usize>, String)> {
    let prefix = format!("part[{part}].shape.profile");
    problems
        .iter()
        .filter_map(|p| p.strip_prefix(&prefix))
        .map(|rest| {
            let point = rest
                .strip_prefix('[')
                .and_then(|r| r.split(']').next())
                .and_then(|k| k.parse::<usize>().ok());
            let message = rest.split_once(": ").map_or(rest, |(_, m)| m).to_owned();
            (point, message)
        })
        .collect()
}

/// The drawing, the point buttons and the table of one profile.
/// The Design pane's ticks beside each profile point: the part's name
/// and the design state, while they are shown.
pub struct PointTicks<'a> {
    pub part_name: &'a str,
    pub design: &'a crate::design_state::DesignState,
}

pub fn profile_editor_ui(
    ui: &mut Ui,
    profile: Profile<'_>,
    problems: &[String],
    ticks: Option<PointTicks<'_>>,
    commands: &mut Vec<Command>,
) {
    let Profile {
        part,
        plane,
        points_m,
        interpolation,
        segments_per_span,
        lamps_mm,
        rays_mm,
        cuts_mm,
        drawing_height,
    } = profile;
    let id = Id::unique(("profile editor", part));
    let selected_id = id.with("selected");
    let mut selected: Option<usize> = ui
        .data(|d| d.get_temp(selected_id))
        .filter(|&k: &usize| k < points_m.len());
    let found = profile_problems(problems, part);
    let h = plane.horizontal();

    ui.label(format!(
        "Profile ({h}–z, mm): drag a point to move it, double-click to add one there, right-click a point to delete it."
    ));
    drawing_ui(
        ui,
        id,
        Profile {
            part,
            plane,
            points_m: &mut *points_m,
            interpolation,
            segments_per_span,
            lamps_mm,
            rays_mm,
            cuts_mm,
            drawing_height,
        },
        &found,
        &mut selected,
        commands,
    );

    ui.horizontal(|ui| {
        if ui
            .button("Add point")
            .on_hover_text("Adds a point halfway along the segment after the selected point")
            .clicked()
            && points_m.len() >= 2
        {
            let k = selected
                .unwrap_or(points_m.len() - 1)
                .min(points_m.len() - 2);
            commands.push(Command::Edit(SceneEdit::InsertProfilePoint {
                part,
                index: k + 1,
                point_m: span_midpoint_m(points_m, interpolation, k),
            }));
            selected = Some(k + 1);
        }
        let can_delete = selected.is_some() && points_m.len() > MIN_PROFILE_POINTS;
        if ui
            .add_enabled(can_delete, egui::Button::new("Delete point"))
            .on_disabled_hover_text("Select a point first; a profile keeps at least two")
            .clicked()
            && let Some(k) = selected
        {
            commands.push(Command::Edit(SceneEdit::RemoveProfilePoint {
                part,
                index: k,
            }));
            selected = None;
        }
        if plane == ProfilePlane::WidthHeight
            && ui
                .button("Reverse points")
                .on_hover_text("The sheet faces the right-hand side of the profile's direction")
                .clicked()
        {
            points_m.reverse();
            selected = selected.map(|k| points_m.len() - 1 - k);
        }
    });

    for (point, message) in &found {
        let text = match point {
            Some(k) => format!("Point {}: {message}", k + 1),
            None => format!("Profile: {message}"),
        };
        ui.colored_label(ui.visuals().error_fg_color, text);
    }

    table_ui(ui, id, plane, points_m, &mut selected, ticks, commands);
    ui.data_mut(|d| match selected {
        Some(k) => {
            d.insert_temp(selected_id, k);
        }
        None => d.remove::<usize>(selected_id),
    });
}

/// The drawing alone, disabled: a section that its parameters set, shown
/// with its rays but without a table or handles that would move nothing.
pub fn section_drawing_ui(ui: &mut Ui, profile: Profile<'_>) {
    let id = Id::unique(("section", profile.part));
    ui.add_enabled_ui(false, |ui| {
        drawing_ui(ui, id, profile, &[], &mut None, &mut Vec::new());
    });
}

/// The numeric table: one row per control point, in millimetres.
fn table_ui(
    ui: &mut Ui,
    id: Id,
    plane: ProfilePlane,
    points_m: &mut [[f64; 2]],
    selected: &mut Option<usize>,
    ticks: Option<PointTicks<'_>>,
    commands: &mut Vec<Command>,
) {
    let h = plane.horizontal();
    let h_min = match plane {
        ProfilePlane::RadiusHeight => 0.0,
        ProfilePlane::WidthHeight => -MAX_MM,
    };
    egui::Grid::new(id.with("table"))
        .num_columns(if ticks.is_some() { 5 } else { 3 })
        .striped(true)
        .show(ui, |ui| {
            ui.strong("Point");
            ui.strong(h);
            ui.strong("z");
            if ticks.is_some() {
                ui.strong("Vary")
                    .on_hover_text("Ticked points move in the Design pane's run; the ends are the package and the aperture");
                ui.strong("Bounds");
            }
            ui.end_row();
            for (k, [x, z]) in points_m.iter_mut().enumerate() {
                let name = format!("Point {}", k + 1);
                if ui.selectable_label(*selected == Some(k), &name).clicked() {
                    *selected = Some(k);
                }
                for (axis, range, v) in [(h, h_min..=MAX_MM, x), ("z", -MAX_MM..=MAX_MM, z)] {
                    let mut mm = *v * 1000.0;
                    let response = ui
                        .add(
                            DragValue::new(&mut mm)
                                .clamp_existing_to_range(false)
                                .speed(0.1)
                                .range(range.clone())
                                .suffix(" mm")
                                .max_decimals(3),
                        )
                        .accessible_name(format!("{name} {axis}"));
                    if response.changed() {
                        // Typed values are held to the range as dragged ones are.
                        *v = mm.clamp(*range.start(), *range.end()) / 1000.0;
                    }
                    if response.gained_focus() || response.drag_started() {
                        *selected = Some(k);
                    }
                }
                if let Some(t) = &ticks {
                    let vary = format!("{}.profile[{k}]", t.part_name);
                    let mut on = t.design.setup.is_ticked(&vary);
                    if ui
                        .add(egui::Checkbox::without_text(&mut on))
                        .accessible_name(format!("Vary {name}"))
                        .changed()
                    {
                        commands.push(Command::TickDesignVariable { vary: vary.clone(), on });
                    }
                    match t.design.bounds(&vary) {
                        Some([a, b]) if on => ui.weak(format!(
                            "{:.1} … {:.1}, {:.1} … {:.1} mm",
                            a.lower * 1000.0,
                            a.upper * 1000.0,
                            b.lower * 1000.0,
                            b.upper * 1000.0
                        )),
                        _ => ui.label(""),
                    };
                }
                ui.end_row();
            }
        });
}

fn drawing_ui(
    ui: &mut Ui,
    id: Id,
    profile: Profile<'_>,
    problems: &[(Option<usize>, String)],
    selected: &mut Option<usize>,
    commands: &mut Vec<Command>,
) {
    let Profile {
        part,
        plane,
        points_m,
        interpolation,
        segments_per_span,
        lamps_mm,
        rays_mm,
        cuts_mm,
        drawing_height,
    } = profile;
    let (total, _) = ui.allocate_exact_size(
        vec2(
            ui.available_width().max(200.0),
            drawing_height.max(DRAWING_HEIGHT),
        ),
        Sense::hover(),
    );
    let plot = Rect::from_min_max(
        pos2(total.left() + AXIS_MARGIN[0], total.top() + 6.0),
        pos2(total.right() - 6.0, total.bottom() - AXIS_MARGIN[1]),
    );
    let points_mm: Vec<[f64; 2]> = points_m
        .iter()
        .map(|p| [p[0] * 1000.0, p[1] * 1000.0])
        .collect();
    // The view holds still while anything is dragged, so a dragged point
    // stays under the pointer instead of chasing a refitted view.
    let view_id = id.with("view");
    let held = ui.input(|i| i.pointer.any_down());
    let view_mm = match ui.data(|d| d.get_temp::<[f64; 4]>(view_id)) {
        Some(view) if held => view,
        _ => {
            let shown: Vec<[f64; 2]> = points_mm
                .iter()
                .copied()
                .chain(lamps_mm.iter().map(|(_, p)| *p))
                .chain(
                    cuts_mm
                        .iter()
                        .filter(|c| c.highlighted)
                        .flat_map(|c| c.segments_mm.iter().flatten().copied()),
                )
                .collect();
            let view = fitted_view_mm(&shown, plane);
            ui.data_mut(|d| {
                d.insert_temp(view_id, view);
            });
            view
        }
    };
    let frame = Frame::new(plot, view_mm);

    let area = ui.interact(plot, id.with("area"), Sense::click());
    area.widget_info(|| WidgetInfo::labeled(Role::Canvas, true, "Profile editor"));

    let visuals = ui.visuals().clone();
    let painter = ui.painter_at(total);
    let plot_painter = ui.painter_at(plot);
    painter.rect_filled(plot, 2.0, visuals.extreme_bg_color);
    grid_ui(&painter, &plot_painter, &frame, plane, &visuals);

    // The luminaire's other surfaces where the plane cuts them, faint; a
    // part without a profile drawn as its own cut.
    for cut in cuts_mm {
        let stroke = if cut.highlighted {
            Stroke::new(2.0, visuals.hyperlink_color)
        } else {
            Stroke::new(1.5, visuals.weak_text_color())
        };
        for [a, b] in &cut.segments_mm {
            plot_painter.line_segment([frame.screen_from_mm(*a), frame.screen_from_mm(*b)], stroke);
        }
    }
    // The photons' paths, under everything else.
    let ray_stroke = Stroke::new(1.0, visuals.warn_fg_color.gamma_multiply(0.55));
    for ray in rays_mm {
        let line: Vec<Pos2> = ray.iter().map(|&p| frame.screen_from_mm(p)).collect();
        plot_painter.line(line, ray_stroke);
    }
    // The curve the generator builds from the points.
    let finite = points_m.iter().flatten().all(|v| v.is_finite());
    if points_m.len() >= 2 && finite {
        let curve_stroke = Stroke::new(2.0, visuals.hyperlink_color);
        for strip in sample_profile(points_m, interpolation, segments_per_span.clamp(1, 64)) {
            let line: Vec<Pos2> = strip
                .iter()
                .map(|s| frame.screen_from_mm([s.point.x * 1000.0, s.point.y * 1000.0]))
                .collect();
            plot_painter.line(line, curve_stroke);
        }
    }
    let screen: Vec<Pos2> = points_mm.iter().map(|&p| frame.screen_from_mm(p)).collect();
    // The control polygon, faint: the curve passes through the points.
    plot_painter.line(screen.clone(), Stroke::new(1.0, visuals.weak_text_color()));

    let mut hovered = None;
    let mut remove = None;
    for (k, &at) in screen.iter().enumerate() {
        let handle = ui
            .interact(
                Rect::from_center_size(at, vec2(2.0 * HANDLE_RADIUS, 2.0 * HANDLE_RADIUS)),
                id.with(("point", k)),
                Sense::click_and_drag(),
            )
            .on_hover_cursor(CursorIcon::Grab);
        handle.widget_info(|| {
            WidgetInfo::labeled(Role::Button, true, format!("Profile point {}", k + 1))
        });
        if handle.drag_started() || handle.clicked() {
            *selected = Some(k);
        }
        if handle.dragged() {
            ui.ctx().set_cursor_icon(CursorIcon::Grabbing);
            if let Some(pointer) = handle.interact_pointer_pos() {
                let [x, z] = frame.mm_from_screen(pointer.clamp(plot.min, plot.max));
                let mm = [
                    round_to(x, DRAG_RESOLUTION_MM).clamp(-MAX_MM, MAX_MM),
                    round_to(z, DRAG_RESOLUTION_MM).clamp(-MAX_MM, MAX_MM),
                ];
                points_m[k] = plane.clamped([mm[0] / 1000.0, mm[1] / 1000.0]);
            }
        }
        if handle.secondary_clicked() {
            remove = Some(k);
        }
        if handle.hovered() || handle.dragged() {
            hovered = Some(k);
        }
    }
    if let Some(k) = remove {
        commands.push(Command::Edit(SceneEdit::RemoveProfilePoint {
            part,
            index: k,
        }));
        *selected = None;
    }
    if area.double_clicked()
        && let Some(pointer) = area.interact_pointer_pos()
    {
        let index = insertion_index(&screen, pointer);
        let [x, z] = frame.mm_from_screen(pointer);
        commands.push(Command::Edit(SceneEdit::InsertProfilePoint {
            part,
            index,
            point_m: plane.clamped([
                round_to(x, DRAG_RESOLUTION_MM) / 1000.0,
                round_to(z, DRAG_RESOLUTION_MM) / 1000.0,
            ]),
        }));
        *selected = Some(index);
    }
    if let Some(k) = *selected
        && (area.hovered() || hovered.is_some())
        && !ui.ctx().egui_wants_keyboard_input()
        && ui.input(|i| i.key_pressed(Key::Delete))
    {
        commands.push(Command::Edit(SceneEdit::RemoveProfilePoint {
            part,
            index: k,
        }));
        *selected = None;
    }

    // The lamps, as suns: the reflector is shaped around them.
    for (name, at_mm) in lamps_mm {
        let at = frame.screen_from_mm(*at_mm);
        let sun = visuals.warn_fg_color;
        plot_painter.circle_filled(at, 3.5, sun);
        for k in 0..8 {
            let direction = egui::Vec2::angled(k as f32 * std::f32::consts::FRAC_PI_4);
            plot_painter.line_segment(
                [at + 5.0 * direction, at + 8.0 * direction],
                Stroke::new(1.0, sun),
            );
        }
        plot_painter.text(
            at + vec2(9.0, 9.0),
            Align2::LEFT_TOP,
            name,
            FontId::proportional(11.0),
            sun,
        );
    }

    // The points over everything, the invalid ones in the error colour.
    for (k, &at) in screen.iter().enumerate() {
        let invalid = problems.iter().any(|(p, _)| *p == Some(k));
        let colour = if invalid {
            visuals.error_fg_color
        } else if *selected == Some(k) {
            visuals.selection.bg_fill
        } else {
            visuals.strong_text_color()
        };
        let radius = if hovered == Some(k) { 6.0 } else { 4.0 };
        if hovered == Some(k) {
            plot_painter.circle_stroke(
                at,
                radius + 3.0,
                Stroke::new(1.5, visuals.selection.stroke.color),
            );
        }
        plot_painter.circle(
            at,
            radius,
            colour,
            Stroke::new(1.0, visuals.extreme_bg_color),
        );
        plot_painter.text(
            at + vec2(7.0, -7.0),
            Align2::LEFT_BOTTOM,
            (k + 1).to_string(),
            FontId::proportional(11.0),
            visuals.weak_text_color(),
        );
    }

    // What the pointer is over, in the field's coordinates.
    let h = plane.horizontal();
    let readout = match hovered {
        Some(k) => Some(format!(
            "Point {}: {h} {:.2} mm, z {:.2} mm",
            k + 1,
            points_m[k][0] * 1000.0,
            points_m[k][1] * 1000.0
        )),
        None => area.hover_pos().map(|p| {
            let [x, z] = frame.mm_from_screen(p);
            format!("{h} {x:.2} mm, z {z:.2} mm")
        }),
    };
    if let Some(text) = readout {
        painter.text(
            plot.right_top() + vec2(-6.0, 4.0),
            Align2::RIGHT_TOP,
            text,
            FontId::monospace(11.0),
            visuals.text_color(),
        );
    }
    if area.hovered() && hovered.is_none() {
        ui.ctx().set_cursor_icon(CursorIcon::Crosshair);
    }
}

/// Grid lines every 1, 2 or 5 × 10ᵏ mm with their values, the axes'
/// names, the z = 0 plane and the optical axis (a revolved profile's r = 0)
/// or the mid-plane (an extruded one's x = 0).
fn grid_ui(
    painter: &egui::Painter,
    plot_painter: &egui::Painter,
    frame: &Frame,
    plane: ProfilePlane,
    visuals: &egui::Visuals,
) {
    let [x0, z0, x1, z1] = frame.visible_mm();
    let step = grid_step_mm((x1 - x0).max(z1 - z0), 8.0);
    let plot = frame.plot;
    let grid = Stroke::new(1.0, visuals.weak_text_color().gamma_multiply(0.25));
    let font = FontId::proportional(10.0);
    let number = visuals.weak_text_color();
    let mut x = (x0 / step).ceil() * step;
    while x <= x1 {
        let sx = frame.screen_from_mm([x, 0.0]).x;
        plot_painter.line_segment([pos2(sx, plot.top()), pos2(sx, plot.bottom())], grid);
        painter.text(
            pos2(sx, plot.bottom() + 2.0),
            Align2::CENTER_TOP,
            grid_label(x, step),
            font.clone(),
            number,
        );
        x += step;
    }
    let mut z = (z0 / step).ceil() * step;
    while z <= z1 {
        let sz = frame.screen_from_mm([0.0, z]).y;
        plot_painter.line_segment([pos2(plot.left(), sz), pos2(plot.right(), sz)], grid);
        painter.text(
            pos2(plot.left() - 4.0, sz),
            Align2::RIGHT_CENTER,
            grid_label(z, step),
            font.clone(),
            number,
        );
        z += step;
    }
    let axis_stroke = Stroke::new(1.0, visuals.text_color().gamma_multiply(0.6));
    let origin = frame.screen_from_mm([0.0, 0.0]);
    if (z0..=z1).contains(&0.0) {
        plot_painter.line_segment(
            [pos2(plot.left(), origin.y), pos2(plot.right(), origin.y)],
            axis_stroke,
        );
    }
    if (x0..=x1).contains(&0.0) {
        let dashes = egui::Shape::dashed_line(
            &[pos2(origin.x, plot.top()), pos2(origin.x, plot.bottom())],
            Stroke::new(1.5, visuals.warn_fg_color),
            8.0,
            4.0,
        );
        plot_painter.extend(dashes);
        let name = match plane {
            ProfilePlane::RadiusHeight => "optical axis",
            ProfilePlane::WidthHeight => "mid-plane x = 0",
        };
        plot_painter.text(
            pos2(origin.x + 4.0, plot.top() + 4.0),
            Align2::LEFT_TOP,
            name,
            FontId::proportional(11.0),
            visuals.warn_fg_color,
        );
        // The origin: the focus the other reflectors are built around.
        plot_painter.circle_stroke(origin, 3.0, axis_stroke);
    }
    painter.text(
        pos2(plot.right(), plot.bottom() - 2.0),
        Align2::RIGHT_BOTTOM,
        format!("{} (mm)", plane.horizontal()),
        FontId::proportional(12.0),
        visuals.text_color(),
    );
    painter.text(
        pos2(plot.left() + 4.0, plot.top() + 2.0),
        Align2::LEFT_TOP,
        "z (mm)",
        FontId::proportional(12.0),
        visuals.text_color(),
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_steps_are_one_two_five() {
        assert_eq!(grid_step_mm(80.0, 8.0), 10.0);
        assert_eq!(grid_step_mm(120.0, 8.0), 20.0);
        assert_eq!(grid_step_mm(30.0, 8.0), 5.0);
        assert_eq!(grid_label(-0.0001, 5.0), "0");
        assert_eq!(grid_label(2.5, 0.5), "2.5");
    }

    #[test]
    fn a_point_beyond_an_end_extends_the_profile() {
        let points = [pos2(0.0, 0.0), pos2(10.0, 0.0), pos2(20.0, 0.0)];
        assert_eq!(insertion_index(&points, pos2(-5.0, 1.0)), 0);
        assert_eq!(insertion_index(&points, pos2(4.0, 1.0)), 1);
        assert_eq!(insertion_index(&points, pos2(14.0, -1.0)), 2);
        assert_eq!(insertion_index(&points, pos2(30.0, 0.0)), 3);
    }

    #[test]
    fn a_point_added_mid_span_lies_on_the_curve() {
        let points = [[0.0, 0.0], [1.0, 1.0], [2.0, 0.0], [3.0, 1.0]];
        assert_eq!(
            span_midpoint_m(&points, Interpolation::Linear, 1),
            [1.5, 0.5]
        );
        let on_spline = span_midpoint_m(&points, Interpolation::CatmullRom, 1);
        // By symmetry the spline's middle of span 1 is at x = 1.5, and it
        // bulges past the chord's midpoint (0.5) neither up nor down there.
        assert!((on_spline[0] - 1.5).abs() < 1e-12, "{on_spline:?}");
        assert!((on_spline[1] - 0.5).abs() < 1e-12, "{on_spline:?}");
        let curved = [[0.0, 0.0], [1.0, 1.0], [2.0, 1.0], [3.0, 0.0]];
        let on_arch = span_midpoint_m(&curved, Interpolation::CatmullRom, 1);
        assert!(
            on_arch[1] > 1.0,
            "the arch's top lies above its chord: {on_arch:?}"
        );
    }

    #[test]
    fn problems_are_found_by_point() {
        let problems = [
            "part[1].shape.profile[2]: two consecutive points".to_owned(),
            "part[1].shape.profile: needs at least 2 control points".to_owned(),
            "part[0].shape.profile[1]: other part".to_owned(),
        ];
        assert_eq!(
            profile_problems(&problems, 1),
            [
                (Some(2), "two consecutive points".to_owned()),
                (None, "needs at least 2 control points".to_owned())
            ]
        );
    }

    #[test]
    fn the_frame_maps_back_and_forth_at_one_scale() {
        let plot = Rect::from_min_size(pos2(10.0, 20.0), vec2(200.0, 100.0));
        let frame = Frame::new(plot, [-10.0, -10.0, 10.0, 10.0]);
        assert_eq!(frame.scale, 5.0);
        let p = [3.0, -4.0];
        let back = frame.mm_from_screen(frame.screen_from_mm(p));
        assert!((back[0] - p[0]).abs() < 1e-4 && (back[1] - p[1]).abs() < 1e-4);
    }
}
