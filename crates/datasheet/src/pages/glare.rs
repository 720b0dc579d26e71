//! The third page: the UGR table(s) of CIE 190.

use super::layout::*;
use crate::Datasheet;
use crate::section::Section;
use crate::svg::{Anchor, INK, MUTED, RULE, Rgb, SHADE, Svg};
use crate::ugr::UgrTable;

/// One UGR table (CIE 190) at one spacing, with its room rows and the
/// crosswise and endwise columns; returns the y below.
fn ugr_block(svg: &mut Svg, y: f64, t: &UgrTable) -> f64 {
    let size = 7.5;
    let room_w = 52.0;
    let cell = (CONTENT_W - room_w - 12.0) / 10.0;
    let gap = 12.0;
    let x0 = MARGIN;
    // Column groups.
    let cross_x = x0 + room_w;
    let end_x = cross_x + 5.0 * cell + gap;
    svg.text(
        cross_x + 2.5 * cell,
        y,
        size,
        Anchor::Middle,
        INK,
        "Viewed crosswise",
    );
    svg.text(
        end_x + 2.5 * cell,
        y,
        size,
        Anchor::Middle,
        INK,
        "Viewed endwise",
    );
    let mut yy = y + size * 1.6;
    let labels = ["ρ ceiling", "ρ walls", "ρ floor"];
    for (k, label) in labels.iter().enumerate() {
        svg.text(x0 + 2.0, yy, size, Anchor::Start, MUTED, label);
        for (s, rho) in t.reflectances.iter().enumerate() {
            let v = format!("{:.1}", rho[k]);
            svg.text(
                cross_x + (s as f64 + 1.0) * cell - 4.0,
                yy,
                size,
                Anchor::End,
                MUTED,
                &v,
            );
            svg.text(
                end_x + (s as f64 + 1.0) * cell - 4.0,
                yy,
                size,
                Anchor::End,
                MUTED,
                &v,
            );
        }
        yy += size * 1.45;
    }
    svg.text(x0 + 2.0, yy, size, Anchor::Start, MUTED, "Room X × Y");
    svg.line(
        x0,
        yy + 3.0,
        x0 + room_w + 10.0 * cell + gap,
        yy + 3.0,
        RULE,
        0.5,
    );
    yy += size * 1.6;
    for (r, room) in t.rooms.iter().enumerate() {
        if r > 0 && room[0] != t.rooms[r - 1][0] {
            svg.line(
                x0,
                yy - size - 2.0,
                x0 + room_w + 10.0 * cell + gap,
                yy - size - 2.0,
                Rgb(0xdde1e5),
                0.4,
            );
        }
        if r % 2 == 1 {
            svg.rect(
                x0,
                yy - size - 1.5,
                room_w + 10.0 * cell + gap,
                size * 1.45,
                SHADE,
                SHADE,
            );
        }
        svg.text(
            x0 + 2.0,
            yy,
            size,
            Anchor::Start,
            INK,
            &format!("{}H × {}H", room[0], room[1]),
        );
        // "–": no luminaire in view sends light towards the eye.
        let shown = |v: Option<f64>| v.map_or("–".to_owned(), |v| format!("{v:.1}"));
        for s in 0..5 {
            svg.text(
                cross_x + (s as f64 + 1.0) * cell - 4.0,
                yy,
                size,
                Anchor::End,
                INK,
                &shown(t.crosswise[r][s]),
            );
            svg.text(
                end_x + (s as f64 + 1.0) * cell - 4.0,
                yy,
                size,
                Anchor::End,
                INK,
                &shown(t.endwise[r][s]),
            );
        }
        yy += size * 1.45;
    }
    yy
}

/// The page of UGR tables, one per spacing asked for.
pub(super) fn glare_page(sheet: &Datasheet, pages: usize) -> Svg {
    let mut svg = Svg::new();
    header(&mut svg, sheet, 3, pages);
    let mut y = 88.0;
    let tables: Vec<&Section<UgrTable>> = std::iter::once(&sheet.ugr)
        .chain(&sheet.ugr_other_spacings)
        .collect();
    for section in tables {
        match section {
            Section::Shown(t) => {
                y = title(
                    &mut svg,
                    MARGIN,
                    y,
                    CONTENT_W,
                    &format!(
                        "UGR table (CIE 190), spacing-to-height ratio S/H = {}",
                        t.spacing
                    ),
                );
                y = ugr_block(&mut svg, y, t) + 6.0;
                y = paragraph(
                    &mut svg,
                    MARGIN,
                    y,
                    CONTENT_W,
                    7.0,
                    MUTED,
                    &format!(
                        "Uncorrected values for 1000 lm of bare-lamp flux, luminaires {} m above the eye, an array at S = {}H, observer at the middle of a wall looking along Y. For the rated {} lm add {:+.1} (8·log10(Φ/1000)). Crosswise: line of sight across the luminaire's C90-C270 axis. Tabular method of CIE 190:2010 with the position index of CIE 117 table 4.1.{}",
                        t.height_m,
                        t.spacing,
                        num(t.lamp_flux_lm, 0),
                        t.correction,
                        if t.crosswise
                            .iter()
                            .chain(&t.endwise)
                            .flatten()
                            .any(Option::is_none)
                        {
                            " –: no luminaire within the field of view sends light towards the eye (no glare on the formula's scale)."
                        } else {
                            ""
                        }
                    ),
                ) + 10.0;
            }
            Section::Omitted { omitted } => {
                y = title(&mut svg, MARGIN, y, CONTENT_W, "UGR table (CIE 190)");
                y = paragraph(&mut svg, MARGIN, y, CONTENT_W, 8.0, MUTED, omitted) + 10.0;
            }
        }
    }
    svg
}
