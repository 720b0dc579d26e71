//! The second page: cartesian diagram (narrow beams), isocandela chart,
//! cone diagram, luminance table and BUG rating.

use super::layout::*;
use crate::Datasheet;
use crate::charts::{self, Frame};
use crate::section::Section;
use crate::svg::{Anchor, INK, MUTED, Svg};

/// Whether the beam is narrow enough for the cartesian diagram.
fn narrow(sheet: &Datasheet) -> Option<f64> {
    let [Some(a), Some(b)] = sheet.angles.field_angle_deg else {
        return None;
    };
    let beam = sheet
        .angles
        .beam_angle_deg
        .iter()
        .flatten()
        .fold(0.0f64, |m, v| m.max(*v));
    (beam < crate::cone::CONE_MAX_BEAM_DEG).then(|| {
        let half_field = 0.5 * a.max(b);
        lucerna_pictures::scale::round_step(1.6 * half_field).clamp(2.0, 90.0)
    })
}

/// The page of diagrams: cartesian, isocandela, cone, luminance, BUG.
pub(super) fn diagrams_page(sheet: &Datasheet, pages: usize) -> Svg {
    let mut svg = Svg::new();
    header(&mut svg, sheet, 2, pages);
    let col = 0.5 * (CONTENT_W - 16.0);
    let x2 = MARGIN + col + 16.0;
    let top = 88.0;
    let table_klm = &sheet.table_cd_per_klm;
    let y_left = match narrow(sheet) {
        Some(limit) => {
            let y = title(
                &mut svg,
                MARGIN,
                top,
                col,
                &format!("Cartesian diagram I(γ), ±{limit:.0}° (cd/klm)"),
            );
            charts::cartesian(
                &mut svg,
                Frame {
                    x: MARGIN,
                    y: y - 4.0,
                    w: col,
                    h: 210.0,
                },
                table_klm,
                limit,
            );
            y + 212.0
        }
        None => {
            let y = title(&mut svg, MARGIN, top, col, "Cartesian diagram");
            paragraph(
                &mut svg,
                MARGIN,
                y,
                col,
                7.5,
                MUTED,
                "Drawn for narrow beams (beam angle under 60°); this distribution is broad: see the polar diagram.",
            ) + 6.0
        }
    };
    let y = title(&mut svg, x2, top, col, "Isocandela chart (seen from below)");
    charts::isocandela(
        &mut svg,
        Frame {
            x: x2,
            y: y - 4.0,
            w: col,
            h: col + 30.0,
        },
        table_klm,
    );
    let y_right = y + col + 34.0;

    // Cone diagram.
    let y = y_left.max(y_right) + 6.0;
    let yc = title(&mut svg, MARGIN, y, col, "Cone diagram");
    let mut y_cone = match &sheet.cone {
        Section::Shown(cone) => {
            charts::cone(
                &mut svg,
                Frame {
                    x: MARGIN,
                    y: yc - 4.0,
                    w: col,
                    h: 150.0,
                },
                cone,
            );
            yc + 152.0
        }
        Section::Omitted { omitted } => paragraph(
            &mut svg,
            MARGIN,
            yc,
            col,
            7.5,
            MUTED,
            &format!("Left out: {omitted}."),
        ),
    };
    // Luminance table.
    let yl = title(&mut svg, x2, y, col, "Luminance (cd/m²)");
    let y_lum = match &sheet.luminance {
        Section::Shown(t) => {
            let mut rows = vec![{
                let mut h = vec!["γ".to_owned()];
                h.extend(t.c_planes_deg.iter().map(|c| format!("C{c:.0}")));
                h
            }];
            for (g, row) in t.gammas_deg.iter().zip(&t.cd_per_m2) {
                let mut r = vec![format!("{g:.0}°")];
                r.extend(row.iter().map(|v| format!("{v:.0}")));
                rows.push(r);
            }
            let yy = table(
                &mut svg,
                x2,
                yl,
                &[0.25 * col, 0.25 * col, 0.25 * col, 0.25 * col],
                &rows,
                1,
                BODY,
            );
            let verdict: Vec<String> = t
                .screen_limits
                .iter()
                .map(|l| {
                    format!(
                        "{} {} cd/m² ({})",
                        if l.kept { "keeps" } else { "exceeds" },
                        l.limit_cd_per_m2,
                        l.applies_to
                    )
                })
                .collect();
            paragraph(
                &mut svg,
                x2,
                yy + 4.0,
                col,
                7.0,
                MUTED,
                &format!(
                    "Over the luminous opening's projected area. EN 12464-1 limits for luminaires reflected in display screens, mean luminance at γ ≥ 65° all around: highest here {:.0} cd/m², so it {}.",
                    t.max_at_screen_angles_cd_per_m2,
                    verdict.join("; and ")
                ),
            )
        }
        Section::Omitted { omitted } => paragraph(&mut svg, x2, yl, col, 7.5, MUTED, omitted),
    };
    y_cone = y_cone.max(y_lum) + 8.0;
    // BUG rating.
    let yb = title(
        &mut svg,
        MARGIN,
        y_cone,
        CONTENT_W,
        "BUG rating (IES TM-15-11)",
    );
    match &sheet.bug {
        Section::Shown(b) => {
            svg.text(MARGIN, yb + 4.0, 14.0, Anchor::Start, INK, &b.label);
            let z = &b.zones_lm;
            let rows = vec![
                ["", "L 0-30°", "M 30-60°", "H 60-80°", "VH 80-90°"]
                    .map(str::to_owned)
                    .to_vec(),
                vec![
                    "Front (lm)".to_owned(),
                    num(z.fl, 0),
                    num(z.fm, 0),
                    num(z.fh, 0),
                    num(z.fvh, 0),
                ],
                vec![
                    "Back (lm)".to_owned(),
                    num(z.bl, 0),
                    num(z.bm, 0),
                    num(z.bh, 0),
                    num(z.bvh, 0),
                ],
                vec![
                    "Up (lm)".to_owned(),
                    format!("UL {}", num(z.ul, 0)),
                    format!("UH {}", num(z.uh, 0)),
                    String::new(),
                    String::new(),
                ],
            ];
            table(
                &mut svg,
                MARGIN + 90.0,
                yb,
                &[70.0, 60.0, 60.0, 60.0, 60.0],
                &rows,
                1,
                BODY,
            );
        }
        Section::Omitted { omitted } => {
            paragraph(&mut svg, MARGIN, yb, CONTENT_W, 7.5, MUTED, omitted);
        }
    }
    svg
}
