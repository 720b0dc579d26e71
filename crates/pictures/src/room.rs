//! Pictures of the preview room: the tone-mapped view with a caption, and
//! the false-colour illuminance view with a legend in lux.

use crate::canvas::{BLACK, Canvas, LABEL_PX, MIN_TEXT_PX, SMALL_PX, WHITE, contrasting, label};
use crate::scale::{LUX_PARTS, LinearScale, false_colour, log_colour};

const CAPTION_H: u32 = 22;
const LEGEND_W: u32 = 110;

fn put(c: &mut Canvas, x: u32, y: u32, rgb: [u8; 3]) {
    c.fill_rect(i64::from(x), i64::from(y), 1, 1, rgb);
}

/// A vertical colour bar from 0 to `top` lx at x = `bx`, `height` pixels
/// tall below its "lux" title, ticked every step of `scale`, or every few steps
/// where the bar is too short for a label at every one.
fn lux_legend(c: &mut Canvas, bx: i64, height: i64, scale: LinearScale) {
    let LinearScale { top, step } = scale;
    let (by, bh) = (22i64, height.max(1));
    c.text(bx as f32, 4.0, "lux", LABEL_PX, BLACK);
    for k in 0..bh {
        c.fill_rect(bx, by + k, 18, 1, false_colour(1.0 - k as f32 / bh as f32));
    }
    let step_px = step / top * bh as f64;
    let every = (f64::from(1.3 * SMALL_PX) / step_px).ceil().max(1.0);
    let mut k = 0.0;
    while k * step <= top + 1e-9 {
        let v = k * step;
        let y = by + bh - ((v / top) * bh as f64).round() as i64;
        c.fill_rect(bx + 18, y, 5, 1, BLACK);
        c.text(
            (bx + 26) as f32,
            y as f32 - 0.5 * SMALL_PX,
            &label(v),
            SMALL_PX,
            BLACK,
        );
        k += every;
    }
}

/// The caption in the strip of `CAPTION_H` pixels whose top is `y`,
/// shrunk or cut short to the picture's width.
fn caption_strip(c: &mut Canvas, y: u32, caption: &str) {
    let width = c.image.width() as f32;
    let (text, size) = Canvas::fit_text(caption, width - 12.0, LABEL_PX);
    c.text(
        6.0,
        y as f32 + 0.5 * (CAPTION_H as f32 - size),
        &text,
        size,
        BLACK,
    );
}

/// The tone-mapped view (`rgb`: 8-bit, row-major) under a caption strip.
pub fn room_view_png(
    width: u32,
    height: u32,
    rgb: &[u8],
    caption: &str,
) -> Result<Vec<u8>, image::ImageError> {
    let mut c = Canvas::new(width, height + CAPTION_H, WHITE);
    for y in 0..height {
        for x in 0..width {
            let i = 3 * (y * width + x) as usize;
            put(&mut c, x, y, [rgb[i], rgb[i + 1], rgb[i + 2]]);
        }
    }
    caption_strip(&mut c, height, caption);
    c.png()
}

/// False-colour illuminance on the visible surfaces (lx, linear scale from
/// 0 to a round number above the 99th percentile); pixels with negative
/// values (luminaires) are white.
pub fn illuminance_png(
    width: u32,
    height: u32,
    lux: &[f32],
    caption: &str,
) -> Result<Vec<u8>, image::ImageError> {
    let scale = LinearScale::over_p99(lux.iter().map(|&v| f64::from(v)), LUX_PARTS);
    let mut c = Canvas::new(width + LEGEND_W, height + CAPTION_H, WHITE);
    for y in 0..height {
        for x in 0..width {
            let v = lux[(y * width + x) as usize];
            put(&mut c, x, y, scale.colour(f64::from(v)));
        }
    }
    lux_legend(&mut c, i64::from(width) + 12, i64::from(height) - 40, scale);
    caption_strip(&mut c, height, caption);
    c.png()
}

/// Top view of the work-plane grid: each grid point's cell in false colour
/// (same linear lux scale as the view), its value printed where the cell
/// is wide enough, the figures in the caption. `xs`, `ys` are the grid
/// coordinates (m), `lux` row by row (y), x fastest; `room` is the room's
/// (width, depth) in metres, drawn as the outline; `luminaires` are plan
/// positions (m) drawn as crosses.
pub fn work_plane_png(
    xs: &[f64],
    ys: &[f64],
    lux: &[f64],
    room: (f64, f64),
    luminaires: &[(f64, f64)],
    caption: &str,
) -> Result<Vec<u8>, image::ImageError> {
    let px_per_m = (720.0 / room.0.max(room.1)).clamp(20.0, 400.0);
    let (w, h) = (
        (room.0 * px_per_m).ceil() as u32,
        (room.1 * px_per_m).ceil() as u32,
    );
    let margin = 16u32;
    let width =
        (w + 2 * margin + LEGEND_W).max(Canvas::text_width(caption, LABEL_PX).ceil() as u32 + 12);
    let height = h + 2 * margin + CAPTION_H;
    let mut c = Canvas::new(width, height, WHITE);
    let scale = LinearScale::over_max(lux.iter().copied(), LUX_PARTS);
    let cell = |v: &[f64], i: usize| -> (f64, f64) {
        // Cell edges halfway to the neighbours (or as wide as the step).
        let half = if v.len() > 1 {
            (v[1] - v[0]) / 2.0
        } else {
            0.25
        };
        (v[i] - half, v[i] + half)
    };
    // y up in the room, down on the picture.
    let to_px = |x: f64, y: f64| {
        (
            i64::from(margin) + (x * px_per_m).round() as i64,
            i64::from(margin) + ((room.1 - y) * px_per_m).round() as i64,
        )
    };
    // Luminaire crosses (±7 px with their halo) in pixels: a value they
    // would cross out is left off rather than drawn unreadable.
    let markers: Vec<(f32, f32)> = luminaires
        .iter()
        .map(|&(x, y)| {
            let (px, py) = to_px(x, y);
            (px as f32, py as f32)
        })
        .collect();
    for (j, _) in ys.iter().enumerate() {
        for (i, _) in xs.iter().enumerate() {
            let v = lux[j * xs.len() + i];
            let (x0, x1) = cell(xs, i);
            let (y0, y1) = cell(ys, j);
            let (px0, py1) = to_px(x0, y0);
            let (px1, py0) = to_px(x1, y1);
            let colour = scale.colour(v);
            c.fill_rect(px0, py0, px1 - px0, py1 - py0, colour);
            // The value at the largest size the cell holds, if any.
            let text = format!("{v:.0}");
            let (cw, ch) = ((px1 - px0) as f32, (py1 - py0) as f32);
            let (tx, ty) = ((px0 + px1) as f32 / 2.0, (py0 + py1) as f32 / 2.0);
            let size = [SMALL_PX, MIN_TEXT_PX]
                .into_iter()
                .find(|&s| Canvas::text_width(&text, s) + 4.0 < cw && s + 2.0 < ch);
            let crossed_out = |s: f32| {
                let half_w = 0.5 * Canvas::text_width(&text, s) + 7.0;
                markers
                    .iter()
                    .any(|&(mx, my)| (mx - tx).abs() < half_w && (my - ty).abs() < 0.5 * s + 7.0)
            };
            if let Some(size) = size.filter(|&s| !crossed_out(s)) {
                c.text_centred(tx, ty, &text, size, contrasting(colour));
            }
        }
    }
    // Room outline.
    let (ox0, oy1) = to_px(0.0, 0.0);
    let (ox1, oy0) = to_px(room.0, room.1);
    for (a, b) in [
        ((ox0, oy0), (ox1, oy0)),
        ((ox1, oy0), (ox1, oy1)),
        ((ox1, oy1), (ox0, oy1)),
        ((ox0, oy1), (ox0, oy0)),
    ] {
        c.line(a.0 as f32, a.1 as f32, b.0 as f32, b.1 as f32, 1.5, BLACK);
    }
    for &(px, py) in &markers {
        c.line(px - 6.0, py - 6.0, px + 6.0, py + 6.0, 2.0, WHITE);
        c.line(px - 6.0, py + 6.0, px + 6.0, py - 6.0, 2.0, WHITE);
        c.line(px - 5.0, py - 5.0, px + 5.0, py + 5.0, 1.0, BLACK);
        c.line(px - 5.0, py + 5.0, px + 5.0, py - 5.0, 1.0, BLACK);
    }
    lux_legend(
        &mut c,
        i64::from(w + 2 * margin) + 8,
        i64::from(h) - 20,
        scale,
    );
    caption_strip(&mut c, h + 2 * margin, caption);
    c.png()
}

/// Rows of square illuminance images side by side (each row `cols` images
/// of `side` × `side` values, row-major, stitched horizontally), on one
/// logarithmic false-colour scale over [`DECADES`](crate::scale::DECADES) below the first row's
/// maximum, each row labelled: for comparing a method with its reference.
pub fn image_rows_png(
    rows: &[(&str, &[f64])],
    cols: usize,
    side: usize,
    px: u32,
    caption: &str,
) -> Result<Vec<u8>, image::ImageError> {
    let label_w = 110u32;
    let width = (label_w + cols as u32 * (px + 4))
        .max(Canvas::text_width(caption, LABEL_PX).ceil() as u32 + 12);
    let height = rows.len() as u32 * (px + 4) + CAPTION_H + 4;
    let mut c = Canvas::new(width, height, WHITE);
    let max = rows
        .first()
        .map_or(1.0, |r| r.1.iter().copied().fold(0.0, f64::max))
        .max(1e-12);
    for (r, (name, values)) in rows.iter().enumerate() {
        let y0 = 2 + r as u32 * (px + 4);
        let (name, size) = Canvas::fit_text(name, label_w as f32 - 8.0, LABEL_PX);
        c.text(4.0, (y0 + px / 2) as f32 - 0.5 * size, &name, size, BLACK);
        for k in 0..cols {
            let x0 = label_w + k as u32 * (px + 4);
            for py in 0..px {
                for pxi in 0..px {
                    let i = (pxi as usize * side) / px as usize;
                    // Image rows run along +y; draw +y upwards.
                    let j = side - 1 - (py as usize * side) / px as usize;
                    let v = values
                        .get(k * side * side + j * side + i)
                        .copied()
                        .unwrap_or(0.0);
                    put(&mut c, x0 + pxi, y0 + py, log_colour(v, max));
                }
            }
        }
    }
    caption_strip(&mut c, height - CAPTION_H, caption);
    c.png()
}
