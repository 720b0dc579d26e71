//! The datasheet's A4 pages as SVG, and the HTML that shows them.
//!
//! Page 1: luminaire data, polar diagram, photometric figures, zonal
//! lumens and CIE flux code. Page 2: cartesian diagram (narrow beams),
//! isocandela chart, cone diagram, luminance table, BUG rating. Page 3:
//! the UGR table(s). Every section left out says why in its place.

use base64::Engine as _;

use crate::Datasheet;
use crate::charts::{self, Frame};
use crate::luminaire::describe_dimensions;
use crate::section::Section;
use crate::svg::{
    ACCENT, Anchor, INK, MUTED, PAGE_HEIGHT_PT, PAGE_WIDTH_PT, RULE, Svg, fitted, wrapped,
};
use crate::ugr::UgrTable;

const MARGIN: f64 = 40.0;
const CONTENT_W: f64 = PAGE_WIDTH_PT - 2.0 * MARGIN;
const BODY: f64 = 8.0;
const ROW: f64 = 11.5;

/// A number with `decimals` decimals.
fn num(v: f64, decimals: usize) -> String {
    format!("{v:.decimals$}")
}

fn angle(a: Option<f64>) -> String {
    a.map_or("—".to_owned(), |v| format!("{v:.1}°"))
}

/// The page header: the luminaire's name and maker, and the sheet's kind.
fn header(svg: &mut Svg, sheet: &Datasheet, page: usize, pages: usize) {
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
fn title(svg: &mut Svg, x: f64, y: f64, w: f64, text: &str) -> f64 {
    svg.text(x, y, 10.0, Anchor::Start, INK, text);
    svg.line(x, y + 3.5, x + w, y + 3.5, RULE, 0.6);
    y + 15.0
}

/// Paragraph text wrapped to `w`; returns the y below.
fn paragraph(svg: &mut Svg, x: f64, mut y: f64, w: f64, size: f64, fill: &str, text: &str) -> f64 {
    for line in wrapped(text, size, w) {
        svg.text(x, y, size, Anchor::Start, fill, &line);
        y += size * 1.35;
    }
    y
}

/// Label / value rows; returns the y below.
fn pairs(svg: &mut Svg, x: f64, mut y: f64, w: f64, rows: &[(&str, String)]) -> f64 {
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
fn table(
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
            svg.rect(x, y - size - 1.5, total, size * 1.45, "#f4f6f8", "#f4f6f8");
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

fn page1(sheet: &Datasheet, pages: usize) -> String {
    let mut svg = Svg::new();
    header(&mut svg, sheet, 1, pages);
    let l = &sheet.luminaire;
    let col = 0.5 * (CONTENT_W - 16.0);
    let mut y = title(&mut svg, MARGIN, 88.0, col, "Luminaire data");
    let mut rows: Vec<(&str, String)> = vec![
        ("Luminaire", l.name.clone()),
        ("Manufacturer", or_dash(&l.manufacturer)),
        ("Catalogue number", or_dash(&l.catalogue_number)),
        ("Dimensions", describe_dimensions(&l.luminaire_dimensions)),
        ("Luminous opening", describe_dimensions(&l.luminous_opening)),
    ];
    for lamp in &l.lamps {
        rows.push((
            "Lamps",
            format!(
                "{} × {}{}",
                lamp.count.abs(),
                if lamp.kind.is_empty() {
                    "lamp"
                } else {
                    &lamp.kind
                },
                if lamp.flux_lm > 0.0 {
                    format!(", {} lm", num(lamp.flux_lm, 0))
                } else {
                    String::new()
                }
            ),
        ));
    }
    rows.push((
        "Lamp flux",
        l.lamp_flux_lm
            .map_or("— (absolute photometry)".to_owned(), |f| {
                format!("{} lm", num(f, 0))
            }),
    ));
    rows.push((
        "Luminaire flux",
        format!("{} lm", num(l.luminaire_flux_lm, 1)),
    ));
    rows.push((
        "LOR",
        l.light_output_ratio_percent
            .map_or("100 % (absolute photometry)".to_owned(), |v| {
                format!("{v:.1} %")
            }),
    ));
    rows.push((
        "Power",
        l.power_w.map_or("— (not in the file)".to_owned(), |w| {
            format!("{} W", num(w, 1))
        }),
    ));
    rows.push((
        "Efficacy",
        l.efficacy_lm_per_w
            .map_or("—".to_owned(), |e| format!("{e:.1} lm/W")),
    ));
    for v in &l.variants {
        rows.push((
            "Variant",
            format!(
                "set {}: {} × {}, {} lm lamps → {} lm{}",
                v.set,
                v.lamps.count.abs(),
                if v.lamps.kind.trim().is_empty() {
                    "lamp"
                } else {
                    v.lamps.kind.trim()
                },
                num(v.lamps.flux_lm, 0),
                num(v.luminaire_flux_lm, 0),
                v.efficacy_lm_per_w
                    .map_or(String::new(), |e| format!(", {e:.1} lm/W"))
            ),
        ));
    }
    rows.push(("CCT", or_dash(&l.cct)));
    rows.push(("Colour rendering", or_dash(&l.cri)));
    rows.push(("Test report", or_dash(&l.test_report)));
    rows.push(("Issue date", or_dash(&l.issue_date)));
    rows.push(("Photometry", format!("{}, {}", l.photometry, l.file_format)));
    rows.push(("Symmetry", sheet.symmetry.clone()));
    y = pairs(&mut svg, MARGIN, y, col, &rows);

    // Polar diagram on the right.
    let x2 = MARGIN + col + 16.0;
    let py = title(&mut svg, x2, 88.0, col, "Polar diagram (cd/klm)");
    charts::polar(
        &mut svg,
        Frame {
            x: x2,
            y: py - 4.0,
            w: col,
            h: col + 16.0,
        },
        &sheet.table_cd_per_klm,
    );
    y = y.max(py + col + 24.0);

    // Photometric figures.
    y = title(&mut svg, MARGIN, y + 6.0, CONTENT_W, "Photometric figures");
    let a = &sheet.angles;
    let y_left = pairs(
        &mut svg,
        MARGIN,
        y,
        col,
        &[
            (
                "Peak intensity",
                format!(
                    "{} cd/klm ({} cd)",
                    num(sheet.peak_cd_per_klm, 0),
                    num(sheet.peak_cd, 0)
                ),
            ),
            (
                "at",
                format!("C {:.1}°, γ {:.1}°", sheet.peak_c_deg, sheet.peak_gamma_deg),
            ),
            (
                "Downward flux fraction",
                format!("{:.1} %", sheet.downward_flux_fraction_percent),
            ),
            (
                "CIE flux code",
                sheet.cie_flux_code.map(|n| n.to_string()).join(" "),
            ),
        ],
    );
    let rows = vec![
        vec!["".to_owned(), "C0-C180".to_owned(), "C90-C270".to_owned()],
        vec![
            "Beam angle (50 %)".to_owned(),
            angle(a.beam_angle_deg[0]),
            angle(a.beam_angle_deg[1]),
        ],
        vec![
            "Field angle (10 %)".to_owned(),
            angle(a.field_angle_deg[0]),
            angle(a.field_angle_deg[1]),
        ],
    ];
    let y_right = table(
        &mut svg,
        x2,
        y,
        &[0.5 * col, 0.25 * col, 0.25 * col],
        &rows,
        1,
        BODY,
    );
    y = y_left.max(y_right) + 4.0;

    // Zonal lumens.
    y = title(&mut svg, MARGIN, y + 4.0, CONTENT_W, "Zonal lumen summary");
    let mut rows = vec![vec![
        "Zone".to_owned(),
        "lm".to_owned(),
        "% luminaire".to_owned(),
        "% lamps".to_owned(),
    ]];
    for z in &sheet.zonal_lumens {
        rows.push(vec![
            format!("{:.0}°–{:.0}°", z.gamma_from_deg, z.gamma_to_deg),
            num(z.flux_lm, 1),
            format!("{:.1}", z.percent_of_luminaire),
            z.percent_of_lamp
                .map_or("—".to_owned(), |v| format!("{v:.1}")),
        ]);
    }
    let ty = table(
        &mut svg,
        MARGIN,
        y,
        &[0.34 * col, 0.22 * col, 0.22 * col, 0.22 * col],
        &rows,
        1,
        BODY,
    );
    let code = sheet.cie_flux_code;
    paragraph(
        &mut svg,
        x2,
        y,
        col,
        7.5,
        MUTED,
        &format!(
            "CIE flux code {} {} {} {} {} (CIE 52): N1 {} %, N2 {} % and N3 {} % of the downward flux lie within 41.4°, 60° and 75.5° of the nadir (cones of π/2, π and 3π/2 sr); N4 {} % of the luminaire's flux goes downwards; N5 {} % is the light output ratio.",
            code[0],
            code[1],
            code[2],
            code[3],
            code[4],
            code[0],
            code[1],
            code[2],
            code[3],
            code[4]
        ),
    );
    y = ty + 8.0;
    if !sheet.notes.is_empty() {
        y = title(&mut svg, MARGIN, y + 4.0, CONTENT_W, "Notes");
        for note in &sheet.notes {
            y = paragraph(&mut svg, MARGIN, y, CONTENT_W, 7.5, MUTED, note) + 2.0;
        }
    }
    svg.page()
}

fn or_dash(s: &str) -> String {
    if s.is_empty() {
        "—".to_owned()
    } else {
        s.to_owned()
    }
}

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

fn page2(sheet: &Datasheet, pages: usize) -> String {
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
    svg.page()
}

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
                "#dde1e5",
                0.4,
            );
        }
        if r % 2 == 1 {
            svg.rect(
                x0,
                yy - size - 1.5,
                room_w + 10.0 * cell + gap,
                size * 1.45,
                "#f4f6f8",
                "#f4f6f8",
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

fn page3(sheet: &Datasheet, pages: usize) -> String {
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
    svg.page()
}

/// The sheet's pages as standalone SVG documents.
pub fn pages(sheet: &Datasheet) -> Vec<String> {
    let n = 3;
    vec![page1(sheet, n), page2(sheet, n), page3(sheet, n)]
}

/// The HTML: the pages inline (text stays text), A4 when printed, the
/// bundled font embedded so it looks the same everywhere.
pub fn html(pages: &[String], title: &str) -> String {
    let font = base64::engine::general_purpose::STANDARD.encode(lucerna_pictures::canvas::FONT_TTF);
    let mut body = String::new();
    for p in pages {
        body.push_str("<section class=\"sheet\">\n");
        body.push_str(p);
        body.push_str("</section>\n");
    }
    format!(
        concat!(
            "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n",
            "<title>{title}</title>\n<style>\n",
            "@font-face {{ font-family: \"DejaVu Sans\"; src: url(data:font/ttf;base64,{font}) format(\"truetype\"); }}\n",
            "@page {{ size: A4; margin: 0; }}\n",
            "body {{ margin: 0; background: #e9ecef; font-family: \"DejaVu Sans\", sans-serif; }}\n",
            ".sheet {{ width: 210mm; height: 297mm; margin: 8mm auto; background: white; box-shadow: 0 1px 4px rgba(0,0,0,.25); }}\n",
            ".sheet svg {{ width: 210mm; height: 297mm; display: block; }}\n",
            "@media print {{ body {{ background: white; }} .sheet {{ margin: 0; box-shadow: none; page-break-after: always; }} }}\n",
            "</style>\n</head>\n<body>\n{body}</body>\n</html>\n"
        ),
        title = crate::svg::escape(title),
        font = font,
        body = body
    )
}
