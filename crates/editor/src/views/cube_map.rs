//! The unwrapped cube map of the newest snapshot, with the direction, C,
//! γ and candela under the cursor.

use std::sync::Arc;

use egui::{Color32, ColorImage, TextureHandle, TextureOptions, Ui};
use lucerna_photometry::{CubeFace, CubeMapLayout};
use lucerna_simulation::Snapshot;

use crate::colour::{DECADES, intensity_colour, legend_ui};

/// The cross `lucerna bake`'s cube PNG lays the faces out in, so the two
/// read alike: (face, column, row, name).
const CROSS: [(CubeFace, u32, u32, &str); 6] = lucerna_pictures::cube::CROSS;

/// The cube-map texture of one snapshot, rebuilt when a new one arrives.
#[derive(Default)]
pub struct CubeTexture {
    shown: Option<Arc<Snapshot>>,
    texture: Option<TextureHandle>,
    /// The shown map's peak (cd), found once per snapshot.
    peak: f64,
}

impl std::fmt::Debug for CubeTexture {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CubeTexture").finish_non_exhaustive()
    }
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
                let (x, y) = (col as usize * n + i, row as usize * n + j);
                image.pixels[y * 4 * n + x] = intensity_colour(v, peak);
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
        cube.peak = snapshot.candela.iter().copied().fold(0.0, f64::max);
    }
    let Some(texture) = &cube.texture else { return };
    let peak = cube.peak;
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The editor's cube and `lucerna bake`'s `_cube.png` give every texel
    /// the same colour: a map spanning five decades, one pixel per texel,
    /// compared face by face away from the PNG's face labels.
    #[test]
    fn the_exported_cube_png_and_the_editors_cube_colour_a_map_alike() {
        let layout = CubeMapLayout::new(64);
        let n = layout.resolution;
        let candela: Vec<f64> = (0..layout.texel_count())
            .map(|t| 10f64.powf(5.0 * ((t * 7919) % 1000) as f64 / 1000.0))
            .collect();
        let editor = cross_image(layout, &candela);
        let png = lucerna_pictures::cube::cube_map_png(layout, &candela, n, "test").unwrap();
        let exported = image::load_from_memory(&png).unwrap().to_rgb8();
        let mut compared = 0;
        let mut distinct = std::collections::HashSet::new();
        for (face, col, row, _) in CROSS {
            let (x0, y0) = lucerna_pictures::cube::face_origin_px(face, n).unwrap();
            for j in n / 2..n {
                for i in n / 2..n {
                    let p = exported.get_pixel(x0 + i, y0 + j).0;
                    let e = editor.pixels[((row * n + j) * 4 * n + col * n + i) as usize];
                    assert_eq!([e.r(), e.g(), e.b()], p, "{face:?} texel ({i}, {j})");
                    distinct.insert(p);
                    compared += 1;
                }
            }
        }
        assert_eq!(compared, 6 * (n / 2) * (n / 2));
        // The map really spans the palette, not one colour everywhere.
        assert!(distinct.len() > 50, "{} colours", distinct.len());
    }
}
