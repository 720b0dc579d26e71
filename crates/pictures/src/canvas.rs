//! A small RGB canvas: anti-aliased thick lines, filled rectangles and
//! 8×8 bitmap text (font8x8), enough for diagrams with labels.

use font8x8::UnicodeFonts;
use image::{Rgb, RgbImage};

pub type Colour = [u8; 3];
pub const WHITE: Colour = [255, 255, 255];
pub const BLACK: Colour = [0, 0, 0];
pub const GREY: Colour = [190, 190, 190];

#[derive(Debug)]
pub struct Canvas {
    pub image: RgbImage,
}

impl Canvas {
    pub fn new(width: u32, height: u32, background: Colour) -> Canvas {
        Canvas {
            image: RgbImage::from_pixel(width, height, Rgb(background)),
        }
    }

    /// Blends `colour` into pixel (x, y) with coverage `alpha` (0–1).
    pub fn blend(&mut self, x: i64, y: i64, colour: Colour, alpha: f32) {
        if x < 0
            || y < 0
            || x >= i64::from(self.image.width())
            || y >= i64::from(self.image.height())
        {
            return;
        }
        let p = self.image.get_pixel_mut(x as u32, y as u32);
        for k in 0..3 {
            let v = f32::from(p.0[k]) * (1.0 - alpha) + f32::from(colour[k]) * alpha;
            p.0[k] = v.round().clamp(0.0, 255.0) as u8;
        }
    }

    pub fn fill_rect(&mut self, x0: i64, y0: i64, w: i64, h: i64, colour: Colour) {
        for y in y0..y0 + h {
            for x in x0..x0 + w {
                self.blend(x, y, colour, 1.0);
            }
        }
    }

    /// A line of `width` pixels from (x0, y0) to (x1, y1), anti-aliased by
    /// distance to the segment.
    pub fn line(&mut self, x0: f32, y0: f32, x1: f32, y1: f32, width: f32, colour: Colour) {
        let r = 0.5 * width;
        let (minx, maxx) = (x0.min(x1) - r - 1.0, x0.max(x1) + r + 1.0);
        let (miny, maxy) = (y0.min(y1) - r - 1.0, y0.max(y1) + r + 1.0);
        let (dx, dy) = (x1 - x0, y1 - y0);
        let len2 = (dx * dx + dy * dy).max(1e-12);
        for y in miny.floor() as i64..=maxy.ceil() as i64 {
            for x in minx.floor() as i64..=maxx.ceil() as i64 {
                let (px, py) = (x as f32 + 0.5, y as f32 + 0.5);
                let t = (((px - x0) * dx + (py - y0) * dy) / len2).clamp(0.0, 1.0);
                let (cx, cy) = (x0 + t * dx, y0 + t * dy);
                let d = ((px - cx).powi(2) + (py - cy).powi(2)).sqrt();
                let coverage = (r + 0.5 - d).clamp(0.0, 1.0);
                if coverage > 0.0 {
                    self.blend(x, y, colour, coverage);
                }
            }
        }
    }

    /// A polyline through `points`.
    pub fn polyline(&mut self, points: &[(f32, f32)], width: f32, colour: Colour) {
        for w in points.windows(2) {
            self.line(w[0].0, w[0].1, w[1].0, w[1].1, width, colour);
        }
    }

    /// Text with its top-left corner at (x, y), each font pixel `scale`
    /// pixels; returns the width drawn.
    pub fn text(&mut self, x: i64, y: i64, text: &str, scale: i64, colour: Colour) -> i64 {
        let mut cx = x;
        for ch in text.chars() {
            let glyph = font8x8::BASIC_FONTS
                .get(ch)
                .or_else(|| font8x8::LATIN_FONTS.get(ch))
                .or_else(|| font8x8::GREEK_FONTS.get(ch))
                .unwrap_or([0; 8]);
            for (row, bits) in glyph.iter().enumerate() {
                for col in 0..8 {
                    if bits & (1 << col) != 0 {
                        self.fill_rect(
                            cx + col * scale,
                            y + row as i64 * scale,
                            scale,
                            scale,
                            colour,
                        );
                    }
                }
            }
            cx += 8 * scale;
        }
        cx - x
    }

    /// Width in pixels of `text` at `scale`.
    pub fn text_width(text: &str, scale: i64) -> i64 {
        text.chars().count() as i64 * 8 * scale
    }

    /// PNG bytes.
    pub fn png(&self) -> Result<Vec<u8>, image::ImageError> {
        let mut bytes = Vec::new();
        self.image.write_to(
            &mut std::io::Cursor::new(&mut bytes),
            image::ImageFormat::Png,
        )?;
        Ok(bytes)
    }
}

/// A perceptually ordered false-colour scale (dark blue → cyan → green →
/// yellow → red → white) for t in [0, 1].
pub fn false_colour(t: f32) -> Colour {
    const STOPS: [(f32, [f32; 3]); 7] = [
        (0.0, [10.0, 10.0, 40.0]),
        (0.15, [30.0, 40.0, 160.0]),
        (0.35, [20.0, 170.0, 210.0]),
        (0.55, [60.0, 200.0, 80.0]),
        (0.75, [240.0, 220.0, 40.0]),
        (0.9, [230.0, 60.0, 30.0]),
        (1.0, [255.0, 250.0, 240.0]),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    for w in STOPS.windows(2) {
        let ((t0, c0), (t1, c1)) = (w[0], w[1]);
        if t <= t1 {
            let s = (t - t0) / (t1 - t0);
            return [0, 1, 2].map(|k| (c0[k] + (c1[k] - c0[k]) * s).round() as u8);
        }
    }
    [255, 250, 240]
}

/// A round number near `v` for axis labels (1, 2, 2.5, 5 × 10ⁿ).
pub fn nice_step(v: f64) -> f64 {
    if v <= 0.0 || !v.is_finite() {
        return 1.0;
    }
    let e = 10f64.powf(v.log10().floor());
    let m = v / e;
    let n = if m <= 1.0 {
        1.0
    } else if m <= 2.0 {
        2.0
    } else if m <= 2.5 {
        2.5
    } else if m <= 5.0 {
        5.0
    } else {
        10.0
    };
    n * e
}

/// A number for a label: no trailing zeros, thousands as is.
pub fn label(v: f64) -> String {
    lucerna_photometry::photometry::format_number(v, 4)
}
