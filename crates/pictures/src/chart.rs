//! A log-log line chart (RMSE against photons, say) as PNG.

use crate::canvas::{BLACK, Canvas, GREY, LABEL_PX, TITLE_PX, WHITE, label};

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
    let y_ticks: Vec<(i32, String)> = (y0 as i32..=y1 as i32)
        .map(|e| (e, label(10f64.powi(e))))
        .collect();
    // Margins from what they hold: the widest y tick, the title and the
    // y-axis name above the plot, the x ticks and name below it, the
    // longest series name in the legend on the right.
    let swatch = 22.0;
    let legend_w = series
        .iter()
        .map(|s| Canvas::text_width(&s.name, LABEL_PX))
        .fold(0.0, f32::max);
    let right = (16.0 + swatch + 8.0 + legend_w + 8.0).min(0.4 * width as f32);
    let left = 8.0
        + y_ticks
            .iter()
            .map(|(_, t)| Canvas::text_width(t, LABEL_PX))
            .fold(0.0, f32::max)
        + 8.0;
    let top = 8.0 + TITLE_PX + 6.0 + LABEL_PX + 12.0;
    let bottom = 6.0 + LABEL_PX + 6.0 + LABEL_PX + 8.0;
    let w = (width as f32 - left - right).max(1.0);
    let h = (height as f32 - top - bottom).max(1.0);
    let px = |x: f64| left + ((x.log10() - x0) / (x1 - x0)) as f32 * w;
    let py = |y: f64| top + h - ((y.log10() - y0) / (y1 - y0)) as f32 * h;
    for e in x0 as i32..=x1 as i32 {
        let x = px(10f64.powi(e));
        c.line(x, top, x, top + h, 1.0, GREY);
        c.text_centred(
            x,
            top + h + 6.0 + 0.5 * LABEL_PX,
            &power_of_ten(e),
            LABEL_PX,
            BLACK,
        );
    }
    for (e, text) in &y_ticks {
        let y = py(10f64.powi(*e));
        c.line(left, y, left + w, y, 1.0, GREY);
        let tw = Canvas::text_width(text, LABEL_PX);
        c.text(left - 8.0 - tw, y - 0.5 * LABEL_PX, text, LABEL_PX, BLACK);
    }
    let (title, title_px) = Canvas::fit_text(title, width as f32 - 16.0, TITLE_PX);
    c.text(8.0, 8.0, &title, title_px, BLACK);
    c.text_centred(
        left + 0.5 * w,
        top + h + 6.0 + LABEL_PX + 6.0 + 0.5 * LABEL_PX,
        x_label,
        LABEL_PX,
        BLACK,
    );
    c.text(8.0, top - 8.0 - LABEL_PX, y_label, LABEL_PX, BLACK);
    let legend_x = left + w + 16.0;
    let (legend_names, legend_px): (Vec<String>, Vec<f32>) = series
        .iter()
        .map(|s| Canvas::fit_text(&s.name, width as f32 - legend_x - swatch - 14.0, LABEL_PX))
        .unzip();
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
        let ly = top + 4.0 + 1.4 * LABEL_PX * k as f32;
        c.fill_rect(
            legend_x as i64,
            (ly + 0.5 * LABEL_PX) as i64 - 2,
            swatch as i64,
            4,
            colour,
        );
        c.text(
            legend_x + swatch + 8.0,
            ly,
            &legend_names[k],
            legend_px[k],
            BLACK,
        );
    }
    c.png()
}

/// "10⁵", "10⁻³": a decade as people write it under a log axis.
fn power_of_ten(exponent: i32) -> String {
    const DIGITS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let mut s = String::from("10");
    if exponent < 0 {
        s.push('⁻');
    }
    for d in exponent.unsigned_abs().to_string().bytes() {
        s.push(DIGITS[usize::from(d - b'0')]);
    }
    s
}

#[cfg(test)]
mod tests {
    #[test]
    fn decades_are_written_with_superscripts() {
        assert_eq!(super::power_of_ten(5), "10⁵");
        assert_eq!(super::power_of_ten(-12), "10⁻¹²");
        assert_eq!(super::power_of_ten(0), "10⁰");
    }
}
