//! The central views: the polar diagram and the unwrapped cube map of the
//! newest snapshot.

use std::sync::Arc;

use egui::{Color32, ColorImage, TextureHandle, TextureOptions, Ui};
use egui_plot::{Line, Plot, PlotPoint, PlotPoints, Text};
use lucerna_photometry::{CandelaTable, CubeFace, CubeMapLayout};
use lucerna_simulation::Snapshot;

use crate::colour::{DECADES, false_colour, legend_ui, log_scale};
use crate::state::{EditorState, View};

/// Face positions in the cross (column, row), each face in its own (u, v)
/// axes (u right, v down) as the cube texture stores it; the same cross as
/// `lucerna bake`'s cube PNG, so the two read alike.
const CROSS: [(CubeFace, usize, usize, &str); 6] = [
    (CubeFace::PosY, 1, 0, "+Y"),
    (CubeFace::NegX, 0, 1, "−X"),
    (CubeFace::PosZ, 1, 1, "+Z up"),
    (CubeFace::PosX, 2, 1, "+X"),
    (CubeFace::NegZ, 3, 1, "−Z nadir"),
    (CubeFace::NegY, 1, 2, "−Y"),
];

/// The cube-map texture of one snapshot, rebuilt when a new one arrives.
#[derive(Default)]
pub struct CubeTexture {
    shown: Option<Arc<Snapshot>>,
    texture: Option<TextureHandle>,
}

impl std::fmt::Debug for CubeTexture {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CubeTexture").finish_non_exhaustive()
    }
}

pub fn views_ui(ui: &mut Ui, state: &mut EditorState, cube: &mut CubeTexture) {
    ui.horizontal(|ui| {
        ui.selectable_value(&mut state.view, View::Polar, "Polar diagram");
        ui.selectable_value(&mut state.view, View::CubeMap, "Cube map");
    });
    ui.separator();
    let Some(snapshot) = state.snapshot.clone() else {
        ui.label("No light distribution yet.");
        return;
    };
    match state.view {
        View::Polar => polar_ui(ui, &snapshot.table),
        View::CubeMap => cube_map_ui(ui, &snapshot, cube),
    }
}

/// Points of the vertical plane through `c_deg` and `c_deg + 180°` in the
/// polar diagram's frame: γ = 0 straight down, plane C to the right.
fn plane_points(table: &CandelaTable, c_deg: f64) -> Vec<[f64; 2]> {
    let mut points = Vec::with_capacity(721);
    for k in (0..=360).rev() {
        let gamma = f64::from(k) * 0.5;
        let i = table.intensity(c_deg + 180.0, gamma);
        points.push([-i * gamma.to_radians().sin(), -i * gamma.to_radians().cos()]);
    }
    for k in 1..=360 {
        let gamma = f64::from(k) * 0.5;
        let i = table.intensity(c_deg, gamma);
        points.push([i * gamma.to_radians().sin(), -i * gamma.to_radians().cos()]);
    }
    points
}

pub fn polar_ui(ui: &mut Ui, table: &CandelaTable) {
    let (peak, _, _) = table.peak();
    let reach = if peak > 0.0 { peak * 1.1 } else { 1.0 };
    Plot::new("polar diagram")
        .data_aspect(1.0)
        .legend(egui_plot::Legend::default())
        .x_axis_label("cd")
        .show(ui, |plot| {
            // γ spokes every 30°, labelled at the rim.
            for k in 0..=6 {
                let gamma = f64::from(k) * 30.0;
                let (s, c) = gamma.to_radians().sin_cos();
                for side in [-1.0, 1.0] {
                    let rim = [side * reach * s, -reach * c];
                    plot.line(
                        Line::new("", PlotPoints::from(vec![[0.0, 0.0], rim]))
                            .color(Color32::from_gray(90))
                            .width(0.5),
                    );
                }
                // Unnamed items stay out of the legend.
                plot.text(Text::new(
                    "",
                    PlotPoint::new(reach * 1.05 * s, -reach * 1.05 * c),
                    format!("γ {gamma:.0}°"),
                ));
            }
            plot.line(Line::new("C0-C180", plane_points(table, 0.0)).width(2.0));
            plot.line(Line::new("C90-C270", plane_points(table, 90.0)).width(2.0));
        });
}

/// The unwrapped cross as an image of 4N × 3N texels (black off the cross).
fn cross_image(layout: CubeMapLayout, candela: &[f64]) -> ColorImage {
    let n = layout.resolution as usize;
    let peak = candela.iter().copied().fold(0.0, f64::max);
    let mut image = ColorImage::filled([4 * n, 3 * n], Color32::from_gray(24));
    for (face, col, row, _) in CROSS {
        for j in 0..n {
            for i in 0..n {
                let texel = layout.texel_index(face, i as u32, j as u32);
                let v = candela.get(texel).copied().unwrap_or(0.0);
                let (x, y) = (col * n + i, row * n + j);
                image.pixels[y * 4 * n + x] = false_colour(log_scale(v, peak));
            }
        }
    }
    image
}

/// The face and texel under cross position (x, y) in texels, if on the cross.
fn texel_at(layout: CubeMapLayout, x: f64, y: f64) -> Option<(CubeFace, f64, f64, usize)> {
    let n = f64::from(layout.resolution);
    let (col, row) = ((x / n).floor(), (y / n).floor());
    let (face, _, _, _) = CROSS
        .iter()
        .find(|(_, c, r, _)| *c as f64 == col && *r as f64 == row)?;
    let (u, v) = ((x - col * n) / n, (y - row * n) / n);
    let (i, j) = ((u * n) as u32, (v * n) as u32);
    let last = layout.resolution - 1;
    let texel = layout.texel_index(*face, i.min(last), j.min(last));
    Some((*face, 2.0 * u - 1.0, 2.0 * v - 1.0, texel))
}

pub fn cube_map_ui(ui: &mut Ui, snapshot: &Arc<Snapshot>, cube: &mut CubeTexture) {
    let layout = snapshot.map.layout;
    let fresh = cube
        .shown
        .as_ref()
        .is_some_and(|s| Arc::ptr_eq(s, snapshot));
    if !fresh || cube.texture.is_none() {
        let image = cross_image(layout, &snapshot.candela);
        match &mut cube.texture {
            Some(t) => t.set(image, TextureOptions::NEAREST),
            None => {
                cube.texture = Some(ui.ctx().load_texture(
                    "cube map",
                    image,
                    TextureOptions::NEAREST,
                ));
            }
        }
        cube.shown = Some(snapshot.clone());
    }
    let Some(texture) = &cube.texture else { return };
    let peak = snapshot.candela.iter().copied().fold(0.0, f64::max);
    ui.label(format!(
        "Log scale over {DECADES:.0} decades below the peak ({peak:.0} cd)"
    ));
    legend_ui(ui, peak);
    let available = ui.available_size();
    let width = (available.x).min((available.y - 30.0).max(60.0) * 4.0 / 3.0);
    let size = egui::vec2(width, width * 0.75);
    let response = ui.add(egui::Image::new((texture.id(), size)).sense(egui::Sense::hover()));
    let painter = ui.painter_at(response.rect);
    for (_, col, row, name) in CROSS {
        let at = response.rect.min
            + egui::vec2(
                col as f32 * size.x / 4.0 + 4.0,
                row as f32 * size.y / 3.0 + 2.0,
            );
        painter.text(
            at,
            egui::Align2::LEFT_TOP,
            name,
            egui::FontId::proportional(12.0),
            Color32::from_gray(200),
        );
    }
    let hovered = response.hover_pos().and_then(|pos| {
        let n = f64::from(layout.resolution);
        let x = f64::from((pos.x - response.rect.left()) / size.x) * 4.0 * n;
        let y = f64::from((pos.y - response.rect.top()) / size.y) * 3.0 * n;
        texel_at(layout, x, y)
    });
    match hovered {
        Some((face, a, b, texel)) => {
            let (c, gamma) = lucerna_photometry::table::angles(face.direction(a, b));
            let cd = snapshot.candela.get(texel).copied().unwrap_or(0.0);
            ui.label(format!(
                "C {:.1}°, γ {:.1}°: {cd:.0} cd",
                c.to_degrees(),
                gamma.to_degrees()
            ));
        }
        None => {
            ui.label("Hover the map to read a direction's intensity.");
        }
    }
}
