//! The polar diagram of a datasheet: the C0-C180 and C90-C270 planes in
//! cd/klm, nadir at the bottom.

use std::f64::consts::PI;

use lucerna_photometry::CandelaTable;

use crate::canvas::{BLACK, Canvas, GREY, WHITE, label, nice_step};

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
    let mut c = Canvas::new(size, size + 40, WHITE);
    let cx = size as f32 / 2.0;
    let cy = size as f32 / 2.0 + 20.0;
    let radius = size as f32 * 0.42;
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
    let step = nice_step(max / 4.0);
    let outer = (max / step).ceil().max(1.0) * step;
    // Grid: circles with values, radial lines every 30°.
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
        c.text(
            (cx + 4.0) as i64,
            (cy - r - 10.0) as i64,
            &label(ring),
            1,
            BLACK,
        );
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
    for (deg, text) in [
        (0.0f64, "0°"),
        (90.0, "90°"),
        (-90.0, "90°"),
        (165.0, "180°"),
    ] {
        let a = deg.to_radians();
        let (x, y) = (
            cx + (radius + 14.0) * a.sin() as f32,
            cy + (radius + 14.0) * a.cos() as f32,
        );
        let w = Canvas::text_width(text, 1) as f32;
        c.text((x - w / 2.0) as i64, (y - 4.0) as i64, text, 1, BLACK);
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
    let scale = if Canvas::text_width(title, 2) + 16 > i64::from(size) {
        1
    } else {
        2
    };
    c.text(8, 6, title, scale, BLACK);
    let y = (size + 20) as i64;
    c.fill_rect(8, y + 3, 20, 3, C0_C180);
    c.text(32, y, "C0-C180", 1, BLACK);
    c.fill_rect(110, y + 3, 20, 3, C90_C270);
    c.text(134, y, "C90-C270", 1, BLACK);
    c.text(i64::from(size) - 70, y, "cd/klm", 1, BLACK);
    c.png()
}
