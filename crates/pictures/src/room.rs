//! Pictures of the preview room: the tone-mapped view with a caption, and
//! the false-colour illuminance view with a legend in lux.

use crate::canvas::{BLACK, Canvas, WHITE, false_colour, label, nice_step};

const CAPTION_H: u32 = 22;
const LEGEND_W: u32 = 110;

fn put(c: &mut Canvas, x: u32, y: u32, rgb: [u8; 3]) {
    c.fill_rect(i64::from(x), i64::from(y), 1, 1, rgb);
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
    c.text(6, i64::from(height) + 7, caption, 1, BLACK);
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
    let mut lit: Vec<f32> = lux
        .iter()
        .copied()
        .filter(|v| *v >= 0.0 && v.is_finite())
        .collect();
    lit.sort_by(f32::total_cmp);
    let p99 = lit
        .get(lit.len().saturating_sub(1) * 99 / 100)
        .copied()
        .unwrap_or(1.0) as f64;
    let step = nice_step(p99.max(1e-3) / 8.0);
    let top = (p99 / step).ceil().max(1.0) * step;
    let mut c = Canvas::new(width + LEGEND_W, height + CAPTION_H, WHITE);
    for y in 0..height {
        for x in 0..width {
            let v = lux[(y * width + x) as usize];
            let colour = if v < 0.0 {
                WHITE
            } else {
                false_colour((v as f64 / top) as f32)
            };
            put(&mut c, x, y, colour);
        }
    }
    // Legend: colour bar with round lux values.
    let (bx, by, bh) = (i64::from(width) + 12, 20i64, i64::from(height) - 40);
    c.text(bx, 4, "lux", 1, BLACK);
    for k in 0..bh.max(1) {
        let t = 1.0 - k as f32 / bh.max(1) as f32;
        c.fill_rect(bx, by + k, 18, 1, false_colour(t));
    }
    let mut v = 0.0;
    while v <= top + 1e-9 {
        let y = by + bh - ((v / top) * bh as f64).round() as i64;
        c.fill_rect(bx + 18, y, 5, 1, BLACK);
        c.text(bx + 26, y - 3, &label(v), 1, BLACK);
        v += step;
    }
    c.text(6, i64::from(height) + 7, caption, 1, BLACK);
    c.png()
}
