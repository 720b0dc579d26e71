//! The polar diagram of a datasheet: the C0-C180 and C90-C270 planes in
//! cd/klm, nadir at the bottom.

use std::f64::consts::PI;

use lucerna_photometry::CandelaTable;

use crate::canvas::{BLACK, Canvas, GREY, LABEL_PX, SMALL_PX, TITLE_PX, WHITE, label};
use crate::scale::round_step;

const C0_C180: [u8; 3] = [200, 30, 40];
const C90_C270: [u8; 3] = [30, 70, 200];

/// PNG of the polar diagram, `size` pixels square. Intensities are scaled
/// to cd/klm by `per_klm` (1000 / lamp or luminaire flux).
pub fn polar_png(
    table: &CandelaTable,
    per_klm: f64,
    size: u32,
    title: &str,
) -> Result<Vec<u8>, image::ImageError> {
    let height = size + 40;
    let mut c = Canvas::new(size, height, WHITE);
    // Room for the title and the 180° label above the circle, the 0°
    // label and the legend below it, the 90° labels beside it.
    let gap = 6.0;
    let above = 8.0 + TITLE_PX + 4.0 + LABEL_PX + gap;
    let below = LABEL_PX + gap + 8.0 + LABEL_PX + 6.0;
    let beside = Canvas::text_width("90°", LABEL_PX) + gap + 4.0;
    let radius = (size as f32 * 0.42)
        .min(0.5 * (height as f32 - above - below))
        .min(0.5 * size as f32 - beside)
        .max(1.0);
    let cx = size as f32 / 2.0;
    let cy = above + 0.5 * (height as f32 - above - below);
    // Radial profile of a full plane: θ from −180° (C+180) to 180° (C).
    let profile = |c_deg: f64, theta: f64| {
        if theta >= 0.0 {
            table.intensity(c_deg, theta)
        } else {
            table.intensity(c_deg + 180.0, -theta)
        }
    };
    let max = (-180..=180)
        .flat_map(|t| [profile(0.0, f64::from(t)), profile(90.0, f64::from(t))])
        .fold(0.0, f64::max)
        * per_klm;
    let step = round_step(max / 4.0);
    let outer = (max / step).ceil().max(1.0) * step;
    // Grid: circles every `step`, radial lines every 30°.
    let mut rings = Vec::new();
    let mut ring = step;
    while ring <= outer * 1.0001 {
        let r = (ring / outer) as f32 * radius;
        let pts: Vec<(f32, f32)> = (0..=180)
            .map(|k| {
                let a = 2.0 * PI * f64::from(k) / 180.0;
                (cx + r * a.cos() as f32, cy + r * a.sin() as f32)
            })
            .collect();
        c.polyline(&pts, 1.0, GREY);
        rings.push((r, ring));
        ring += step;
    }
    for k in 0..12 {
        let a = PI * f64::from(k) / 6.0;
        c.line(
            cx,
            cy,
            cx + radius * a.sin() as f32,
            cy + radius * a.cos() as f32,
            1.0,
            GREY,
        );
    }
    // Angles outside the circle, each label's box kept `gap` clear of it:
    // γ from nadir, 0° at the bottom, 180° at the top, both halves.
    for k in -5..=6 {
        let deg = 30.0 * f64::from(k);
        let text = format!("{}°", deg.abs());
        let (sin, cos) = deg.to_radians().sin_cos();
        let (w, h) = (Canvas::text_width(&text, LABEL_PX), LABEL_PX);
        let d = radius + gap + 0.5 * (w * sin.abs() as f32 + h * cos.abs() as f32);
        c.text_centred(
            cx + d * sin as f32,
            cy + d * cos as f32,
            &text,
            LABEL_PX,
            BLACK,
        );
    }
    // Curves: θ measured from nadir (down), C0 to the right.
    for (c_deg, colour) in [(0.0, C0_C180), (90.0, C90_C270)] {
        let pts: Vec<(f32, f32)> = (-720..=720)
            .map(|k| {
                let theta = f64::from(k) / 4.0;
                let r = (profile(c_deg, theta) * per_klm / outer) as f32 * radius;
                let a = theta.to_radians();
                (cx + r * a.sin() as f32, cy + r * a.cos() as f32)
            })
            .collect();
        c.polyline(&pts, 2.0, colour);
    }
    // Ring values up the 180° axis, just inside each ring, on a light
    // backing so a curve through them does not hide them; drawn after the
    // curves for that reason.
    for (r, value) in rings {
        let text = label(value);
        let w = Canvas::text_width(&text, SMALL_PX);
        let (x, y) = (cx + 4.0, cy - r + 2.0);
        c.shade_rect(
            x as i64 - 1,
            y as i64,
            w as i64 + 3,
            SMALL_PX as i64 + 1,
            WHITE,
            0.75,
        );
        c.text(x, y, &text, SMALL_PX, BLACK);
    }
    let (title, title_px) = Canvas::fit_text(title, size as f32 - 16.0, TITLE_PX);
    c.text(8.0, 8.0, &title, title_px, BLACK);
    // Legend along the bottom: the planes' colours, the unit on the right.
    let y = height as f32 - LABEL_PX - 6.0;
    let mut x = 8.0;
    for (name, colour) in [("C0-C180", C0_C180), ("C90-C270", C90_C270)] {
        c.fill_rect(x as i64, (y + 0.5 * LABEL_PX) as i64 - 1, 22, 3, colour);
        x += 28.0;
        x += c.text(x, y, name, LABEL_PX, BLACK) + 20.0;
    }
    let unit = "cd/klm";
    c.text(
        size as f32 - 8.0 - Canvas::text_width(unit, LABEL_PX),
        y,
        unit,
        LABEL_PX,
        BLACK,
    );
    c.png()
}
