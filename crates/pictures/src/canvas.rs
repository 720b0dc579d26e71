//! A small RGB canvas: anti-aliased thick lines, filled rectangles and
//! anti-aliased TrueType text (DejaVu Sans through ab_glyph), enough for
//! diagrams with labels.

use std::sync::LazyLock;

use ab_glyph::{Font, FontRef, GlyphId, InvalidFont, PxScale, PxScaleFont, ScaleFont, point};
use image::{Rgb, RgbImage};

pub type Colour = [u8; 3];
pub const WHITE: Colour = [255, 255, 255];
pub const BLACK: Colour = [0, 0, 0];
pub const GREY: Colour = [190, 190, 190];

/// Text sizes (line height, ascent to descent, in pixels) chosen so that
/// labels read at a glance on the pictures' usual sizes (a 640 px polar
/// diagram, 200 px cube faces): DejaVu Sans' capitals are 0.63 of it.
pub const TITLE_PX: f32 = 21.0;
pub const LABEL_PX: f32 = 15.0;
pub const SMALL_PX: f32 = 14.0;
/// The smallest size `Canvas::fit_text` shrinks to before cutting text
/// short: below it digits blur into each other.
pub const MIN_TEXT_PX: f32 = 10.0;

/// DejaVu Sans, cut down to Latin, Greek and the symbols labels use
/// (`fonts/SOURCES.md` says how and from what).
pub const FONT_TTF: &[u8] = include_bytes!("../fonts/DejaVuSans-subset.ttf");

/// Parsed once; a test checks that the bundled file parses, so text is
/// never silently missing.
static FONT: LazyLock<Result<FontRef<'static>, InvalidFont>> =
    LazyLock::new(|| FontRef::try_from_slice(FONT_TTF));

/// Walks `text`'s glyphs left to right, calling `glyph(id, caret_px)` with
/// each glyph's pen position (advances plus kerning); returns the width.
fn layout(
    font: &PxScaleFont<&FontRef<'static>>,
    text: &str,
    mut glyph: impl FnMut(GlyphId, f32),
) -> f32 {
    let mut caret = 0.0;
    let mut previous: Option<GlyphId> = None;
    for ch in text.chars() {
        let id = font.glyph_id(ch);
        if let Some(p) = previous {
            caret += font.kern(p, id);
        }
        glyph(id, caret);
        caret += font.h_advance(id);
        previous = Some(id);
    }
    caret
}

/// Width of `text` in ems of the bundled font (advances and kerning): its
/// width at any type size, for layouts drawn elsewhere (the datasheet's
/// SVG pages, whose font size is the em).
pub fn text_width_em(text: &str) -> f32 {
    let Ok(font) = &*FONT else {
        return 0.55 * text.chars().count() as f32;
    };
    let em = font.units_per_em().unwrap_or(2048.0);
    // A scale of the font's height over its em makes one em one pixel.
    layout(
        &font.as_scaled(PxScale::from(font.height_unscaled() / em)),
        text,
        |_, _| {},
    )
}

/// The bundled font, parsed (`None` only if the file were broken, which
/// a test rules out).
pub fn font() -> Option<&'static FontRef<'static>> {
    FONT.as_ref().ok()
}

/// `text`'s glyphs in the bundled font, each with its pen position in ems
/// (advances plus kerning), and the width in ems, as `text_width_em`
/// measures it: for writers that place glyphs themselves, like the
/// datasheet's PDF.
pub fn glyph_run_em(text: &str) -> (Vec<(GlyphId, f32)>, f32) {
    let Ok(font) = &*FONT else {
        return (Vec::new(), 0.0);
    };
    let em = font.units_per_em().unwrap_or(2048.0);
    let mut run = Vec::with_capacity(text.len());
    let width = layout(
        &font.as_scaled(PxScale::from(font.height_unscaled() / em)),
        text,
        |id, x| run.push((id, x)),
    );
    (run, width)
}

/// `text` cut short with an ellipsis until `fits` takes it (empty if
/// nothing does).
pub fn cut_with_ellipsis(text: &str, fits: impl Fn(&str) -> bool) -> String {
    let mut cut: String = text.to_owned();
    while !cut.is_empty() {
        cut.pop();
        let shown = format!("{}…", cut.trim_end());
        if fits(&shown) {
            return shown;
        }
    }
    String::new()
}

/// Black or white, whichever reads better on `background` (by its
/// luma, Rec. 601 weights).
pub fn contrasting(background: Colour) -> Colour {
    let [r, g, b] = background.map(f32::from);
    if 0.299 * r + 0.587 * g + 0.114 * b > 140.0 {
        BLACK
    } else {
        WHITE
    }
}

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

    /// Blends `colour` over a rectangle with opacity `alpha` (0–1): a
    /// backing that keeps labels readable over curves and false colour.
    pub fn shade_rect(&mut self, x0: i64, y0: i64, w: i64, h: i64, colour: Colour, alpha: f32) {
        for y in y0..y0 + h {
            for x in x0..x0 + w {
                self.blend(x, y, colour, alpha);
            }
        }
    }

    /// Text whose line box (ascent to descent, `size_px` tall) has its
    /// top-left corner at (x, y), anti-aliased; returns the width drawn
    /// in pixels. Characters the font lacks draw as its empty box.
    pub fn text(&mut self, x: f32, y: f32, text: &str, size_px: f32, colour: Colour) -> f32 {
        let Ok(font) = &*FONT else {
            return 0.0;
        };
        let font = font.as_scaled(PxScale::from(size_px));
        // A whole-pixel baseline keeps the bottoms of the letters sharp.
        let baseline_px = (y + font.ascent()).round();
        layout(&font, text, |id, caret| {
            let glyph = id.with_scale_and_position(font.scale(), point(x + caret, baseline_px));
            if let Some(outline) = font.outline_glyph(glyph) {
                let bounds = outline.px_bounds();
                let (x0, y0) = (bounds.min.x as i64, bounds.min.y as i64);
                outline.draw(|gx, gy, coverage| {
                    self.blend(
                        x0 + i64::from(gx),
                        y0 + i64::from(gy),
                        colour,
                        coverage.min(1.0),
                    );
                });
            }
        })
    }

    /// Text whose line box is centred on (x, y); returns the width drawn.
    pub fn text_centred(
        &mut self,
        x: f32,
        y: f32,
        text: &str,
        size_px: f32,
        colour: Colour,
    ) -> f32 {
        let w = Canvas::text_width(text, size_px);
        self.text(x - 0.5 * w, y - 0.5 * size_px, text, size_px, colour)
    }

    /// Width in pixels of `text` at `size_px` (advances and kerning).
    pub fn text_width(text: &str, size_px: f32) -> f32 {
        let Ok(font) = &*FONT else {
            return 0.0;
        };
        layout(&font.as_scaled(PxScale::from(size_px)), text, |_, _| {})
    }

    /// `text` at the largest size up to `size_px`, but not under
    /// `MIN_TEXT_PX`, that fits in `max_width_px`; cut short with an
    /// ellipsis where even that is too wide, so nothing is clipped at the
    /// picture's edge.
    pub fn fit_text(text: &str, max_width_px: f32, size_px: f32) -> (String, f32) {
        let w = Canvas::text_width(text, size_px);
        if w <= max_width_px {
            return (text.to_owned(), size_px);
        }
        // Widths scale with the size; 0.999 absorbs rounding.
        let size = (0.999 * size_px * max_width_px / w).max(MIN_TEXT_PX.min(size_px));
        if Canvas::text_width(text, size) <= max_width_px {
            return (text.to_owned(), size);
        }
        (
            cut_with_ellipsis(text, |t| Canvas::text_width(t, size) <= max_width_px),
            size,
        )
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

/// A number for a label: no trailing zeros, thousands as is.
pub fn label(v: f64) -> String {
    lucerna_photometry::format_number(v, 4)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)] // reason: tests may panic
    use super::*;

    #[test]
    fn the_bundled_font_parses_and_has_the_labels_characters() {
        let font = FONT.as_ref().unwrap();
        for ch in "0123456789 abcxyzABCXYZ-+.,:;()/°γΦθπ±×−≤≥≈∞²³⁰¹⁴⁵⁶⁷⁸⁹⁻–—äöüßéèçñłŁ…Ωµ".chars()
        {
            assert_ne!(font.glyph_id(ch), GlyphId(0), "{ch:?} missing");
        }
    }

    #[test]
    fn text_is_drawn_as_wide_as_measured_with_grey_edges() {
        let mut c = Canvas::new(200, 40, WHITE);
        let w = c.text(10.0, 10.0, "C0-C180 90°", LABEL_PX, BLACK);
        assert!((w - Canvas::text_width("C0-C180 90°", LABEL_PX)).abs() < 1e-3);
        assert!(w > 60.0 && w < 110.0, "{w}");
        let inked: Vec<(u32, u32)> = c
            .image
            .enumerate_pixels()
            .filter(|(_, _, p)| p.0[0] < 250)
            .map(|(x, y, _)| (x, y))
            .collect();
        let (x0, x1) = (
            inked.iter().map(|p| p.0).min().unwrap(),
            inked.iter().map(|p| p.0).max().unwrap(),
        );
        let (y0, y1) = (
            inked.iter().map(|p| p.1).min().unwrap(),
            inked.iter().map(|p| p.1).max().unwrap(),
        );
        assert!(x0 >= 10 && f64::from(x1) <= 10.0 + f64::from(w) + 1.0);
        assert!(y0 >= 10 && f64::from(y1) <= 10.0 + f64::from(LABEL_PX));
        // Anti-aliased: some pixels are neither ink nor paper.
        let grey = c
            .image
            .pixels()
            .filter(|p| p.0[0] > 40 && p.0[0] < 215)
            .count();
        assert!(grey > 20, "{grey} grey pixels");
    }

    #[test]
    fn fitted_text_shrinks_then_is_cut_short() {
        let title = "a rather long luminaire name - 20000000 photons";
        let full = Canvas::text_width(title, TITLE_PX);
        let (same, size) = Canvas::fit_text(title, full + 1.0, TITLE_PX);
        assert_eq!((same.as_str(), size), (title, TITLE_PX));
        let (shrunk, size) = Canvas::fit_text(title, 0.8 * full, TITLE_PX);
        assert_eq!(shrunk, title);
        assert!(size < TITLE_PX && Canvas::text_width(title, size) <= 0.8 * full);
        let (cut, size) = Canvas::fit_text(title, 100.0, TITLE_PX);
        assert_eq!(size, MIN_TEXT_PX);
        assert!(
            cut.ends_with('…') && Canvas::text_width(&cut, size) <= 100.0,
            "{cut}"
        );
    }
}
