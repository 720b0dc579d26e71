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
}

/// Colours of the sheet: ink, the two main planes, grid and rules.
pub const INK: &str = "#1a1a1a";
pub const MUTED: &str = "#5f6368";
pub const GRID: &str = "#c8ccd0";
pub const RULE: &str = "#8a9096";
pub const C0_COLOUR: &str = "#1f5fbf";
pub const C90_COLOUR: &str = "#c0392b";
pub const ACCENT: &str = "#e8eef7";

/// SVG elements of one page (or one figure), in points.
#[derive(Debug, Default, Clone)]
pub struct Svg {
    body: String,
}

impl Svg {
    pub fn new() -> Svg {
        Svg::default()
    }

    /// Text at (x, y) on its baseline.
    pub fn text(&mut self, x: f64, y: f64, size: f64, anchor: Anchor, fill: &str, text: &str) {
        let _ = writeln!(
            self.body,
            r#"<text x="{x:.2}" y="{y:.2}" font-size="{size:.2}" text-anchor="{}" fill="{fill}">{}</text>"#,
            anchor.svg(),
            escape(text)
        );
    }

    /// Text rotated about its anchor by `degrees` (an axis label).
    pub fn text_rotated(
        &mut self,
        x: f64,
        y: f64,
        size: f64,
        degrees: f64,
        fill: &str,
        text: &str,
    ) {
        let _ = writeln!(
            self.body,
            r#"<text x="{x:.2}" y="{y:.2}" font-size="{size:.2}" text-anchor="middle" fill="{fill}" transform="rotate({degrees:.1} {x:.2} {y:.2})">{}</text>"#,
            escape(text)
        );
    }

    pub fn line(&mut self, x0: f64, y0: f64, x1: f64, y1: f64, stroke: &str, width: f64) {
        let _ = writeln!(
            self.body,
            r#"<line x1="{x0:.2}" y1="{y0:.2}" x2="{x1:.2}" y2="{y1:.2}" stroke="{stroke}" stroke-width="{width:.2}"/>"#
        );
    }

    /// A polyline through `points`; `dash` like "4 2" or empty.
    pub fn polyline(&mut self, points: &[[f64; 2]], stroke: &str, width: f64, dash: &str) {
        if points.len() < 2 {
            return;
        }
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
            format!(r#" stroke-dasharray="{dash}""#)
        };
        let _ = writeln!(
            self.body,
            r#"<path d="{d}" fill="none" stroke="{stroke}" stroke-width="{width:.2}" stroke-linejoin="round"{dash}/>"#
        );
    }

    pub fn rect(&mut self, x: f64, y: f64, w: f64, h: f64, fill: &str, stroke: &str) {
        let _ = writeln!(
            self.body,
            r#"<rect x="{x:.2}" y="{y:.2}" width="{w:.2}" height="{h:.2}" fill="{fill}" stroke="{stroke}" stroke-width="0.5"/>"#
        );
    }

    pub fn circle(&mut self, cx: f64, cy: f64, r: f64, stroke: &str, width: f64) {
        let _ = writeln!(
            self.body,
            r#"<circle cx="{cx:.2}" cy="{cy:.2}" r="{r:.2}" fill="none" stroke="{stroke}" stroke-width="{width:.2}"/>"#
        );
    }

    /// A filled closed polygon.
    pub fn polygon(&mut self, points: &[[f64; 2]], fill: &str, opacity: f64) {
        let pts: Vec<String> = points
            .iter()
            .map(|p| format!("{:.2},{:.2}", p[0], p[1]))
            .collect();
        let _ = writeln!(
            self.body,
            r#"<polygon points="{}" fill="{fill}" fill-opacity="{opacity:.2}" stroke="none"/>"#,
            pts.join(" ")
        );
    }

    /// The page as a standalone SVG document of A4 size in points.
    pub fn page(&self) -> String {
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
            body = self.body
        )
    }
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
