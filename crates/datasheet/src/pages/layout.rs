//! The pages' layout kit: margins, the header and footer, section titles,
//! paragraphs, label/value rows and tables.

use crate::Datasheet;
use crate::svg::{
    ACCENT, Anchor, INK, MUTED, PAGE_HEIGHT_PT, PAGE_WIDTH_PT, RULE, Rgb, SHADE, Svg, fitted,
    wrapped,
};

pub(super) const MARGIN: f64 = 40.0;
pub(super) const CONTENT_W: f64 = PAGE_WIDTH_PT - 2.0 * MARGIN;
pub(super) const BODY: f64 = 8.0;
pub(super) const ROW: f64 = 11.5;

/// A number with `decimals` decimals.
pub(super) fn num(v: f64, decimals: usize) -> String {
    format!("{v:.decimals$}")
}

pub(super) fn angle(a: Option<f64>) -> String {
    a.map_or("—".to_owned(), |v| format!("{v:.1}°"))
}

/// The page header: the luminaire's name and maker, and the sheet's kind.
pub(super) fn header(svg: &mut Svg, sheet: &Datasheet, page: usize, pages: usize) {
    let l = &sheet.luminaire;
    svg.rect(0.0, 0.0, PAGE_WIDTH_PT, 62.0, ACCENT, ACCENT);
    svg.text(
        MARGIN,
        30.0,
        15.0,
        Anchor::Start,
        INK,
        &fitted(&l.name, 15.0, CONTENT_W - 130.0),
    );
    let maker: Vec<&str> = [l.manufacturer.as_str(), l.catalogue_number.as_str()]
        .into_iter()
        .filter(|s| !s.is_empty())
        .collect();
    let sub = if maker.is_empty() {
        "Manufacturer not given in the file".to_owned()
    } else {
        maker.join(" · ")
    };
    svg.text(
        MARGIN,
        46.0,
        8.5,
        Anchor::Start,
        MUTED,
        &fitted(&sub, 8.5, CONTENT_W - 130.0),
    );
    svg.text(
        PAGE_WIDTH_PT - MARGIN,
        30.0,
        9.0,
        Anchor::End,
        INK,
        "Photometric datasheet",
    );
    svg.text(
        PAGE_WIDTH_PT - MARGIN,
        46.0,
        7.5,
        Anchor::End,
        MUTED,
        &format!("page {page} of {pages}"),
    );
    // Footer.
    let y = PAGE_HEIGHT_PT - 24.0;
    svg.line(
        MARGIN,
        y - 10.0,
        PAGE_WIDTH_PT - MARGIN,
        y - 10.0,
        RULE,
        0.5,
    );
    let source = if sheet.options.source_name.is_empty() {
        String::new()
    } else {
        format!(" from {}", sheet.options.source_name)
    };
    svg.text(
        MARGIN,
        y,
        6.5,
        Anchor::Start,
        MUTED,
        &fitted(
            &format!(
                "Made by Lucerna {}{source} ({}). Values for the file's photometry.",
                env!("CARGO_PKG_VERSION"),
                l.file_format
            ),
            6.5,
            CONTENT_W,
        ),
    );
}

/// A section title with a rule under it; returns the y below.
pub(super) fn title(svg: &mut Svg, x: f64, y: f64, w: f64, text: &str) -> f64 {
    svg.text(x, y, 10.0, Anchor::Start, INK, text);
    svg.line(x, y + 3.5, x + w, y + 3.5, RULE, 0.6);
    y + 15.0
}

/// Paragraph text wrapped to `w`; returns the y below.
pub(super) fn paragraph(
    svg: &mut Svg,
    x: f64,
    mut y: f64,
    w: f64,
    size: f64,
    fill: Rgb,
    text: &str,
) -> f64 {
    for line in wrapped(text, size, w) {
        svg.text(x, y, size, Anchor::Start, fill, &line);
        y += size * 1.35;
    }
    y
}

/// Label / value rows; returns the y below.
pub(super) fn pairs(svg: &mut Svg, x: f64, mut y: f64, w: f64, rows: &[(&str, String)]) -> f64 {
    let label_w = 0.42 * w;
    for (label, value) in rows {
        svg.text(x, y, BODY, Anchor::Start, MUTED, label);
        svg.text(
            x + label_w,
            y,
            BODY,
            Anchor::Start,
            INK,
            &fitted(value, BODY, w - label_w),
        );
        y += ROW;
    }
    y
}

/// A table: the first column left-aligned, the others right-aligned in
/// their columns; `header` rows in muted ink over a rule. Returns the y
/// below.
pub(super) fn table(
    svg: &mut Svg,
    x: f64,
    mut y: f64,
    widths: &[f64],
    rows: &[Vec<String>],
    header: usize,
    size: f64,
) -> f64 {
    let total: f64 = widths.iter().sum();
    for (r, row) in rows.iter().enumerate() {
        if r >= header && (r - header) % 2 == 1 {
            svg.rect(x, y - size - 1.5, total, size * 1.45, SHADE, SHADE);
        }
        let mut cx = x;
        for (c, cell) in row.iter().enumerate() {
            let w = widths.get(c).copied().unwrap_or(30.0);
            let fill = if r < header { MUTED } else { INK };
            if c == 0 {
                svg.text(
                    cx + 2.0,
                    y,
                    size,
                    Anchor::Start,
                    fill,
                    &fitted(cell, size, w - 4.0),
                );
            } else {
                svg.text(cx + w - 3.0, y, size, Anchor::End, fill, cell);
            }
            cx += w;
        }
        if r + 1 == header {
            svg.line(x, y + 3.0, x + total, y + 3.0, RULE, 0.5);
        }
        y += size * 1.45;
    }
    y
}

/// The text, or a dash where there is none.
pub(super) fn or_dash(s: &str) -> String {
    if s.is_empty() {
        "—".to_owned()
    } else {
        s.to_owned()
    }
}
