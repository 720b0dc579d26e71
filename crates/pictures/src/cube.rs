//! The intensity map as a false-colour unwrapped cube with a legend in cd.

use lucerna_photometry::{CubeFace, CubeMapLayout};

use crate::canvas::{BLACK, Canvas, LABEL_PX, SMALL_PX, TITLE_PX, WHITE, label};
use crate::scale::{DECADES, false_colour, log_colour, log_position};

/// Face positions in the unwrapped cross (column, row) and their names,
/// each face drawn with its own (u, v) axes (u right, v down), as the cube
/// texture stores it; the editor's cube-map view lays it out the same.
pub const CROSS: [(CubeFace, u32, u32, &str); 6] = [
    (CubeFace::PosY, 1, 0, "+Y"),
    (CubeFace::NegX, 0, 1, "−X"),
    (CubeFace::PosZ, 1, 1, "+Z up"),
    (CubeFace::PosX, 2, 1, "+X"),
    (CubeFace::NegZ, 3, 1, "−Z nadir"),
    (CubeFace::NegY, 1, 2, "−Y"),
];

/// Margin around the cross, and the title strip above it, in pixels.
const MARGIN: u32 = 24;
const TITLE_H: u32 = 16;

/// The top-left pixel of `face` in a [`cube_map_png`] of faces `face_px`
/// wide.
pub fn face_origin_px(face: CubeFace, face_px: u32) -> Option<(u32, u32)> {
    let (_, col, row, _) = CROSS.iter().find(|(f, ..)| *f == face)?;
    Some((MARGIN + col * face_px, MARGIN + TITLE_H + row * face_px))
}

/// PNG of the candela map (`candela_per_texel` in texel order), faces
/// `face_px` pixels wide, on a logarithmic colour scale over three decades
/// below the peak, with its legend in cd.
pub fn cube_map_png(
    layout: CubeMapLayout,
    candela_per_texel: &[f64],
    face_px: u32,
    title: &str,
) -> Result<Vec<u8>, image::ImageError> {
    let peak = candela_per_texel.iter().copied().fold(0.0, f64::max);
    let margin = MARGIN;
    let legend_w = 150u32;
    let width = 4 * face_px + 2 * margin + legend_w;
    let height = 3 * face_px + 2 * margin + 24;
    let mut c = Canvas::new(width, height, WHITE);
    let (title, title_px) = Canvas::fit_text(title, (width - 2 * margin) as f32, TITLE_PX);
    c.text(margin as f32, 8.0, &title, title_px, BLACK);
    let n = layout.resolution;
    let top = i64::from(margin + TITLE_H);
    let mut labels = Vec::new();
    for (face, col, row, name) in CROSS {
        let x0 = i64::from(margin + col * face_px);
        let y0 = top + i64::from(row * face_px);
        for py in 0..face_px {
            for px in 0..face_px {
                let (i, j) = (px * n / face_px, py * n / face_px);
                let v = candela_per_texel[layout.texel_index(face, i, j)];
                let colour = log_colour(v, peak);
                c.blend(x0 + i64::from(px), y0 + i64::from(py), colour, 1.0);
            }
        }
        labels.push((x0, y0, name));
    }
    // Face names on a dark backing: the faces can be any colour.
    for (x0, y0, name) in labels {
        let w = Canvas::text_width(name, SMALL_PX);
        c.shade_rect(x0, y0, w as i64 + 8, SMALL_PX as i64 + 4, BLACK, 0.55);
        c.text(x0 as f32 + 4.0, y0 as f32 + 2.0, name, SMALL_PX, WHITE);
    }
    // Legend: a vertical colour bar with nice values.
    let bar_x = i64::from(margin + 4 * face_px + 20);
    let bar_h = i64::from(3 * face_px) - 20;
    for y in 0..bar_h {
        let t = 1.0 - y as f32 / bar_h as f32;
        c.fill_rect(bar_x, top + y, 24, 1, false_colour(t));
    }
    c.text(
        bar_x as f32,
        (top + bar_h + 6) as f32,
        "cd",
        LABEL_PX,
        BLACK,
    );
    if peak > 0.0 {
        for k in 0..=DECADES as i32 {
            let v = peak / 10f64.powi(k);
            let y = top + bar_h - (f64::from(log_position(v, peak)) * bar_h as f64) as i64;
            c.fill_rect(bar_x + 24, y, 6, 1, BLACK);
            c.text(
                (bar_x + 34) as f32,
                y as f32 - 0.5 * SMALL_PX,
                &label(v),
                SMALL_PX,
                BLACK,
            );
        }
    }
    c.png()
}
