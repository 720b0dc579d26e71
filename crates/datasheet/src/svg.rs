//! A small SVG writer for the datasheet's pages: text in the project's
//! font (measured with its own advances, so columns line up and long
//! names are cut rather than overflow), lines, polylines and rectangles,
//! all in points on an A4 page.

use std::fmt::Write as _;

/// The family name the SVG asks for; the PDF's font database and the
/// HTML's `@font-face` both give it the bundled DejaVu Sans.
pub const FONT_FAMILY: &str = "DejaVu Sans";

/// A4 in points.
pub const PAGE_WIDTH_PT: f64 = 595.28;
pub const PAGE_HEIGHT_PT: f64 = 841.89;

/// Width (pt) of `text` set at `size_pt` in the bundled font.
pub fn text_width_pt(text: &str, size_pt: f64) -> f64 {
    f64::from(lucerna_pictures::canvas::text_width_em(text)) * size_pt
}

/// `text` cut with an ellipsis to fit `width_pt`.
pub fn fitted(text: &str, size_pt: f64, width_pt: f64) -> String {
    if text_width_pt(text, size_pt) <= width_pt {
        return text.to_owned();
    }
    lucerna_pictures::canvas::cut_with_ellipsis(text, |t| text_width_pt(t, size_pt) <= width_pt)
}

/// `text` broken into lines of at most `width_pt` at spaces (a word
/// longer than a line is cut).
pub fn wrapped(text: &str, size_pt: f64, width_pt: f64) -> Vec<String> {
    let mut lines = Vec::new();
    let mut line = String::new();
    for word in text.split_whitespace() {
        let candidate = if line.is_empty() {
            word.to_owned()
        } else {
            format!("{line} {word}")
        };
        if text_width_pt(&candidate, size_pt) <= width_pt || line.is_empty() {
            line = candidate;
        } else {
            lines.push(fitted(&std::mem::take(&mut line), size_pt, width_pt));
            line = word.to_owned();
        }
    }
    if !line.is_empty() {
        lines.push(fitted(&line, size_pt, width_pt));
    }
    lines
}

/// XML-escaped text (and nothing that is not a character XML allows).
pub fn escape(text: &str) -> String {
    let mut s = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => s.push_str("&amp;"),
            '<' => s.push_str("&lt;"),
            '>' => s.push_str("&gt;"),
            '"' => s.push_str("&quot;"),
            '\t' | '\n' | '\r' => s.push(' '),
            c if (c as u32) < 0x20 || c == '\u{FFFE}' || c == '\u{FFFF}' => s.push(' '),
            c => s.push(c),
        }
    }
    s
}

/// Horizontal alignment of text at its anchor.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Anchor {
    Start,
    Middle,
    End,
}

impl Anchor {
    fn svg(self) -> &'static str {
        match self {
            Anchor::Start => "start",
            Anchor::Middle => "middle",
            Anchor::End => "end",
        }
    }

    /// The share of the text's width that lies before its anchor.
    pub fn offset_fraction(self) -> f64 {
        match self {
            Anchor::Start => 0.0,
            Anchor::Middle => 0.5,
            Anchor::End => 1.0,
        }
    }
}

/// An sRGB colour, 8 bits a channel (`Rgb(0x1a1a1a)`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Rgb(pub u32);

impl Rgb {
    /// The channels in 0..=1, as PDF sets them.
    pub fn unit(self) -> [f32; 3] {
        [16, 8, 0].map(|shift| ((self.0 >> shift) & 0xff) as f32 / 255.0)
    }
}

impl std::fmt::Display for Rgb {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "#{:06x}", self.0 & 0xff_ffff)
    }
}

/// Colours of the sheet: ink, the two main planes, grid and rules.
pub const INK: Rgb = Rgb(0x1a1a1a);
pub const MUTED: Rgb = Rgb(0x5f6368);
pub const GRID: Rgb = Rgb(0xc8ccd0);
pub const RULE: Rgb = Rgb(0x8a9096);
pub const C0_COLOUR: Rgb = Rgb(0x1f5fbf);
pub const C90_COLOUR: Rgb = Rgb(0xc0392b);
pub const ACCENT: Rgb = Rgb(0xe8eef7);
/// The shading behind table headers and highlighted rows.
pub const SHADE: Rgb = Rgb(0xf4f6f8);

/// One thing drawn on a page, in points from the page's top-left corner
/// (y down, as SVG has it). The SVG and the PDF are both written from
/// these, so the two cannot drift.
#[derive(Debug, Clone, PartialEq)]
pub enum Element {
    /// Text on its baseline at (x, y).
    Text {
        x: f64,
        y: f64,
        size: f64,
        anchor: Anchor,
        fill: Rgb,
        text: String,
    },
    /// An open polyline (a line is one of two points); `dash` in points,
    /// empty for a solid line.
    Polyline {
        points: Vec<[f64; 2]>,
        stroke: Rgb,
        width: f64,
        dash: Vec<f64>,
    },
    /// A filled rectangle with a 0.5 pt outline.
    Rect {
        x: f64,
        y: f64,
        w: f64,
        h: f64,
        fill: Rgb,
        stroke: Rgb,
    },
    /// A circle's outline.
    Circle {
        cx: f64,
        cy: f64,
        r: f64,
        stroke: Rgb,
        width: f64,
    },
    /// A filled closed polygon, no outline.
    Polygon {
        points: Vec<[f64; 2]>,
        fill: Rgb,
        opacity: f64,
    },
}

/// The elements of one page (or one figure), in points.
#[derive(Debug, Default, Clone)]
pub struct Svg {
    elements: Vec<Element>,
}

impl Svg {
    pub fn new() -> Svg {
        Svg::default()
    }

    /// What is drawn, in order.
    pub fn elements(&self) -> &[Element] {
        &self.elements
    }

    /// Text at (x, y) on its baseline.
    pub fn text(&mut self, x: f64, y: f64, size: f64, anchor: Anchor, fill: Rgb, text: &str) {
        self.elements.push(Element::Text {
            x,
            y,
            size,
            anchor,
            fill,
            text: text.to_owned(),
        });
    }

    pub fn line(&mut self, x0: f64, y0: f64, x1: f64, y1: f64, stroke: Rgb, width: f64) {
        self.polyline(&[[x0, y0], [x1, y1]], stroke, width, &[]);
    }

    /// A polyline through `points`; `dash` like `&[4.0, 2.0]` or empty.
    pub fn polyline(&mut self, points: &[[f64; 2]], stroke: Rgb, width: f64, dash: &[f64]) {
        if points.len() < 2 {
            return;
        }
        self.elements.push(Element::Polyline {
            points: points.to_vec(),
            stroke,
            width,
            dash: dash.to_vec(),
        });
    }

    pub fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, fill: Rgb, stroke: Rgb) {
        self.elements.push(Element::Rect {
            x,
            y,
            w,
            h,
            fill,
            stroke,
        });
    }

    pub fn circle(&mut self, cx: f64, cy: f64, r: f64, stroke: Rgb, width: f64) {
        self.elements.push(Element::Circle {
            cx,
            cy,
            r,
            stroke,
            width,
        });
    }

    /// A filled closed polygon.
    pub fn polygon(&mut self, points: &[[f64; 2]], fill: Rgb, opacity: f64) {
        self.elements.push(Element::Polygon {
            points: points.to_vec(),
            fill,
            opacity,
        });
    }

    /// The page as a standalone SVG document of A4 size in points.
    pub fn page(&self) -> String {
        let mut body = String::new();
        for element in &self.elements {
            write_element(&mut body, element);
        }
        format!(
            concat!(
                r#"<svg xmlns="http://www.w3.org/2000/svg" class="page" width="{w}" height="{h}" viewBox="0 0 {w} {h}" font-family="{font}">"#,
                "\n",
                r#"<rect x="0" y="0" width="{w}" height="{h}" fill="white"/>"#,
                "\n{body}</svg>\n"
            ),
            w = PAGE_WIDTH_PT,
            h = PAGE_HEIGHT_PT,
            font = FONT_FAMILY,
            body = body
        )
    }
}

fn write_element(body: &mut String, element: &Element) {
    let _ = match element {
        Element::Text {
            x,
            y,
            size,
            anchor,
            fill,
            text,
        } => writeln!(
            body,
            r#"<text x="{x:.2}" y="{y:.2}" font-size="{size:.2}" text-anchor="{}" fill="{fill}">{}</text>"#,
            anchor.svg(),
            escape(text)
        ),
        Element::Polyline {
            points,
            stroke,
            width,
            dash,
        } => {
            let mut d = String::new();
            for (i, p) in points.iter().enumerate() {
                let _ = write!(
                    d,
                    "{}{:.2} {:.2}",
                    if i == 0 { "M" } else { " L" },
                    p[0],
                    p[1]
                );
            }
            let dash = if dash.is_empty() {
                String::new()
            } else {
                let lengths: Vec<String> = dash.iter().map(|l| format!("{l}")).collect();
                format!(r#" stroke-dasharray="{}""#, lengths.join(" "))
            };
            writeln!(
                body,
                r#"<path d="{d}" fill="none" stroke="{stroke}" stroke-width="{width:.2}" stroke-linejoin="round"{dash}/>"#
            )
        }
        Element::Rect {
            x,
            y,
            w,
            h,
            fill,
            stroke,
        } => writeln!(
            body,
            r#"<rect x="{x:.2}" y="{y:.2}" width="{w:.2}" height="{h:.2}" fill="{fill}" stroke="{stroke}" stroke-width="0.5"/>"#
        ),
        Element::Circle {
            cx,
            cy,
            r,
            stroke,
            width,
        } => writeln!(
            body,
            r#"<circle cx="{cx:.2}" cy="{cy:.2}" r="{r:.2}" fill="none" stroke="{stroke}" stroke-width="{width:.2}"/>"#
        ),
        Element::Polygon {
            points,
            fill,
            opacity,
        } => {
            let pts: Vec<String> = points
                .iter()
                .map(|p| format!("{:.2},{:.2}", p[0], p[1]))
                .collect();
            writeln!(
                body,
                r#"<polygon points="{}" fill="{fill}" fill-opacity="{opacity:.2}" stroke="none"/>"#,
                pts.join(" ")
            )
        }
    };
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn text_is_measured_in_the_bundled_font() {
        // DejaVu Sans: digits advance 1303/2048 em.
        let w = text_width_pt("0000", 10.0);
        assert!((w - 4.0 * 1303.0 / 2048.0 * 10.0).abs() < 1e-6, "{w}");
        assert!(text_width_pt("W", 10.0) > text_width_pt("i", 10.0));
    }

    #[test]
    fn long_text_is_cut_and_wrapped_to_width() {
        let long = "Parabolic spot reflector with a very long catalogue description";
        let cut = fitted(long, 10.0, 100.0);
        assert!(cut.ends_with('…') && text_width_pt(&cut, 10.0) <= 100.0);
        let lines = wrapped(long, 10.0, 100.0);
        assert!(lines.len() > 2);
        assert!(lines.iter().all(|l| text_width_pt(l, 10.0) <= 100.0));
    }

    #[test]
    fn markup_in_names_is_escaped() {
        assert_eq!(escape("a<b & \"c\"\u{1}"), "a&lt;b &amp; &quot;c&quot; ");
    }
}
