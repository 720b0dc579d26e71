//! The first page: luminaire data, polar diagram, photometric figures,
//! zonal lumens and CIE flux code.

use super::layout::*;
use crate::Datasheet;
use crate::charts::{self, Frame};
use crate::luminaire::describe_dimensions;
use crate::svg::{MUTED, Svg};

/// The page of data: luminaire, polar diagram, figures, zonal lumens.
pub(super) fn photometric_data_page(sheet: &Datasheet, pages: usize) -> Svg {
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
    svg
}
