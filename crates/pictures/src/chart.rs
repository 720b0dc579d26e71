//! A log-log line chart (RMSE against photons, say) as PNG.

use crate::canvas::{BLACK, Canvas, GREY, WHITE, label};

const PALETTE: [[u8; 3]; 8] = [
    [0, 0, 0],
    [200, 30, 40],
    [30, 70, 200],
    [20, 150, 60],
    [220, 130, 0],
    [140, 40, 160],
    [0, 150, 170],
    [120, 120, 120],
];

/// One named series of (x, y) points, x and y > 0.
#[derive(Debug, Clone)]
pub struct Series {
    pub name: String,
    pub points: Vec<(f64, f64)>,
}

/// PNG of `series` on log-log axes, `width` × `height` pixels.
pub fn log_log_chart_png(
    series: &[Series],
    title: &str,
    x_label: &str,
    y_label: &str,
    width: u32,
    height: u32,
) -> Result<Vec<u8>, image::ImageError> {
    let mut c = Canvas::new(width, height, WHITE);
    let (left, right, top, bottom) = (70.0f32, 190.0f32, 40.0f32, 50.0f32);
    let pts = series
        .iter()
        .flat_map(|s| s.points.iter())
        .filter(|p| p.0 > 0.0 && p.1 > 0.0);
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(x, y) in pts {
        x0 = x0.min(x.log10());
        x1 = x1.max(x.log10());
        y0 = y0.min(y.log10());
        y1 = y1.max(y.log10());
    }
    if x0 > x1 {
        (x0, x1, y0, y1) = (0.0, 1.0, 0.0, 1.0);
    }
    let (x0, x1) = (x0.floor(), x1.ceil().max(x0.floor() + 1.0));
    let (y0, y1) = (y0.floor(), y1.ceil().max(y0.floor() + 1.0));
    let w = width as f32 - left - right;
    let h = height as f32 - top - bottom;
    let px = |x: f64| left + ((x.log10() - x0) / (x1 - x0)) as f32 * w;
    let py = |y: f64| top + h - ((y.log10() - y0) / (y1 - y0)) as f32 * h;
    for e in x0 as i32..=x1 as i32 {
        let x = px(10f64.powi(e));
        c.line(x, top, x, top + h, 1.0, GREY);
        c.text(
            x as i64 - 12,
            (top + h + 8.0) as i64,
            &format!("1e{e}"),
            1,
            BLACK,
        );
    }
    for e in y0 as i32..=y1 as i32 {
        let y = py(10f64.powi(e));
        c.line(left, y, left + w, y, 1.0, GREY);
        c.text(8, y as i64 - 4, &label(10f64.powi(e)), 1, BLACK);
    }
    let scale = if Canvas::text_width(title, 2) + left as i64 > i64::from(width) {
        1
    } else {
        2
    };
    c.text(left as i64, 8, title, scale, BLACK);
    c.text(
        (left + w / 2.0) as i64 - 40,
        (top + h + 26.0) as i64,
        x_label,
        1,
        BLACK,
    );
    c.text(8, (top - 14.0) as i64, y_label, 1, BLACK);
    for (k, s) in series.iter().enumerate() {
        let colour = PALETTE[k % PALETTE.len()];
        let points: Vec<(f32, f32)> = s
            .points
            .iter()
            .filter(|p| p.0 > 0.0 && p.1 > 0.0)
            .map(|&(x, y)| (px(x), py(y)))
            .collect();
        c.polyline(&points, 2.0, colour);
        for &(x, y) in &points {
            c.fill_rect(x as i64 - 2, y as i64 - 2, 5, 5, colour);
        }
        let ly = (top + 10.0 + 16.0 * k as f32) as i64;
        c.fill_rect((left + w + 14.0) as i64, ly + 2, 18, 4, colour);
        c.text((left + w + 38.0) as i64, ly, &s.name, 1, BLACK);
    }
    c.png()
}
