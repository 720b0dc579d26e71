//! The datasheet's figures as SVG: the polar diagram and the cartesian
//! I(γ) of the two main planes in cd/klm, the isocandela chart, and the
//! cone diagram of a narrow beam. Each draws into a box of the page.

use lucerna_photometry::CandelaTable;
use lucerna_pictures::isocandela::{isolines, lit_gamma_range};
use lucerna_pictures::scale::round_step;

use crate::cone::ConeDiagram;
use crate::svg::{Anchor, C0_COLOUR, C90_COLOUR, GRID, INK, MUTED, RULE, Rgb, Svg};

/// A box on the page (pt).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    pub x: f64,
    pub y: f64,
    pub w: f64,
    pub h: f64,
}

/// Intensity along the full plane through C and C + 180° at the signed
/// angle θ (θ ≥ 0: γ = θ in C; θ < 0: γ = −θ in C + 180°).
fn plane_value(table: &CandelaTable, c_deg: f64, theta_deg: f64) -> f64 {
    if theta_deg >= 0.0 {
        table.intensity(c_deg, theta_deg)
    } else {
        table.intensity(c_deg + 180.0, -theta_deg)
    }
}

/// The signed angles a plane's curve is drawn through: the table's own γ
/// angles (where its linear interpolant bends) within ±`limit`, or a 0.25°
/// walk where the grid is finer than that would show.
fn curve_angles(table: &CandelaTable, limit_deg: f64) -> Vec<f64> {
    let g: Vec<f64> = table
        .gammas_deg
        .iter()
        .copied()
        .filter(|&g| g <= limit_deg)
        .collect();
    let grid: Vec<f64> = if g.len() <= 1500 {
        g
    } else {
        (0..=(limit_deg / 0.25) as usize)
            .map(|k| k as f64 * 0.25)
            .collect()
    };
    let mut angles: Vec<f64> = grid.iter().rev().map(|&x| -x).collect();
    angles.extend(grid.iter().copied().filter(|&x| x > 0.0));
    if angles.first().is_some_and(|&a| a > -limit_deg) {
        angles.insert(0, -limit_deg);
    }
    if angles.last().is_some_and(|&a| a < limit_deg) {
        angles.push(limit_deg);
    }
    angles
}

/// Legend of the two planes at (x, y).
fn plane_legend(svg: &mut Svg, x: f64, y: f64) {
    svg.polyline(&[[x, y - 3.0], [x + 16.0, y - 3.0]], C0_COLOUR, 1.4, &[]);
    svg.text(x + 20.0, y, 7.5, Anchor::Start, INK, "C0 – C180");
    svg.polyline(
        &[[x + 72.0, y - 3.0], [x + 88.0, y - 3.0]],
        C90_COLOUR,
        1.4,
        &[4.0, 2.0],
    );
    svg.text(x + 92.0, y, 7.5, Anchor::Start, INK, "C90 – C270");
}

/// Formats a scale value without needless decimals.
pub fn tick_label(v: f64) -> String {
    if v.abs() >= 100.0 || v == v.round() {
        format!("{v:.0}")
    } else if (10.0 * v).round() == 10.0 * v {
        format!("{v:.1}")
    } else {
        format!("{v:.2}")
    }
}

/// The polar diagram of a table in cd/klm: both main planes, nadir down,
/// C0 and C90 to the right.
pub fn polar(svg: &mut Svg, frame: Frame, table: &CandelaTable) {
    let legend_h = 14.0;
    let r = 0.5 * frame.w.min(frame.h - legend_h) - 12.0;
    let (cx, cy) = (frame.x + 0.5 * frame.w, frame.y + 12.0 + r);
    let peak = table.peak().0;
    let step = round_step(peak.max(1e-9) / 4.0);
    let top = (peak / step).ceil().max(1.0) * step;
    let at = |theta_deg: f64, v: f64| {
        let rr = r * (v / top).min(1.0);
        let t = theta_deg.to_radians();
        [cx + rr * t.sin(), cy + rr * t.cos()]
    };
    // Rings at the scale's steps, spokes every 30°.
    let rings = (top / step).round() as usize;
    for k in 1..=rings {
        svg.circle(cx, cy, r * k as f64 / rings as f64, GRID, 0.5);
    }
    for k in 0..12 {
        let t = (k as f64 * 30.0).to_radians();
        svg.line(cx, cy, cx + r * t.sin(), cy + r * t.cos(), GRID, 0.5);
    }
    for deg in [0, 30, 60, 90, 120, 150, 180] {
        for side in [-1.0, 1.0] {
            if (deg == 0 || deg == 180) && side < 0.0 {
                continue;
            }
            let t = (side * deg as f64).to_radians();
            let (x, y) = (cx + (r + 7.0) * t.sin(), cy + (r + 7.0) * t.cos() + 2.5);
            svg.text(x, y, 6.5, Anchor::Middle, MUTED, &format!("{deg}°"));
        }
    }
    for k in 1..=rings {
        let v = step * k as f64;
        // Along the upward spoke, where a downlight's curves are not.
        svg.text(
            cx + 2.0,
            cy - r * k as f64 / rings as f64 + 7.0,
            6.0,
            Anchor::Start,
            MUTED,
            &tick_label(v),
        );
    }
    let angles = curve_angles(table, 180.0);
    for (c, colour, dash) in [
        (0.0, C0_COLOUR, &[][..]),
        (90.0, C90_COLOUR, &[4.0, 2.0][..]),
    ] {
        let points: Vec<[f64; 2]> = angles
            .iter()
            .map(|&t| at(t, plane_value(table, c, t)))
            .collect();
        svg.polyline(&points, colour, 1.3, dash);
    }
    svg.text(frame.x, frame.y + 7.0, 7.0, Anchor::Start, MUTED, "cd/klm");
    svg.text(
        frame.x + frame.w,
        frame.y + 7.0,
        6.5,
        Anchor::End,
        MUTED,
        "C180 / C270 left · C0 / C90 right",
    );
    plane_legend(svg, cx - 60.0, frame.y + frame.h - 2.0);
}

/// The cartesian I(γ) of both main planes over ±`limit_deg`, cd/klm.
pub fn cartesian(svg: &mut Svg, frame: Frame, table: &CandelaTable, limit_deg: f64) {
    let (left, bottom) = (frame.x + 34.0, frame.y + frame.h - 34.0);
    let (right, top_y) = (frame.x + frame.w - 6.0, frame.y + 12.0);
    let peak = table.peak().0;
    let step = round_step(peak.max(1e-9) / 5.0);
    let top = (peak / step).ceil().max(1.0) * step;
    let x_of = |t: f64| left + (t + limit_deg) / (2.0 * limit_deg) * (right - left);
    let y_of = |v: f64| bottom - (v / top).min(1.0) * (bottom - top_y);
    let x_step = round_step(limit_deg / 4.0);
    let mut t = -(limit_deg / x_step).floor() * x_step;
    while t <= limit_deg + 1e-9 {
        svg.line(x_of(t), top_y, x_of(t), bottom, GRID, 0.5);
        svg.text(
            x_of(t),
            bottom + 9.0,
            6.5,
            Anchor::Middle,
            MUTED,
            &format!("{}°", tick_label(t.abs())),
        );
        t += x_step;
    }
    let ticks = (top / step).round() as usize;
    for k in 0..=ticks {
        let v = step * k as f64;
        svg.line(left, y_of(v), right, y_of(v), GRID, 0.5);
        svg.text(
            left - 3.0,
            y_of(v) + 2.2,
            6.5,
            Anchor::End,
            MUTED,
            &tick_label(v),
        );
    }
    svg.line(left, bottom, right, bottom, RULE, 0.7);
    svg.line(left, top_y, left, bottom, RULE, 0.7);
    let angles = curve_angles(table, limit_deg);
    for (c, colour, dash) in [
        (0.0, C0_COLOUR, &[][..]),
        (90.0, C90_COLOUR, &[4.0, 2.0][..]),
    ] {
        let points: Vec<[f64; 2]> = angles
            .iter()
            .map(|&t| [x_of(t), y_of(plane_value(table, c, t))])
            .collect();
        svg.polyline(&points, colour, 1.3, dash);
    }
    svg.text(frame.x, frame.y + 7.0, 7.0, Anchor::Start, MUTED, "cd/klm");
    svg.text(
        0.5 * (left + right),
        bottom + 19.0,
        7.0,
        Anchor::Middle,
        MUTED,
        "γ (C180 / C270 left, C0 / C90 right)",
    );
    plane_legend(svg, 0.5 * (left + right) - 60.0, frame.y + frame.h - 2.0);
}

/// The levels' colours, from the outermost (5 %) to the peak.
const LEVEL_COLOURS: [Rgb; 6] = [
    Rgb(0x6a3d9a),
    Rgb(0x1f78b4),
    Rgb(0x33a02c),
    Rgb(0xe6ab02),
    Rgb(0xe6550d),
    Rgb(0xb2182b),
];

/// The isocandela chart: lines of equal intensity at fractions of the
/// peak, seen from below the luminaire in an azimuthal projection (γ
/// from the centre, C round it, C0 to the right, C90 up), over the lit γ
/// range.
pub fn isocandela(svg: &mut Svg, frame: Frame, table: &CandelaTable) {
    let range = lit_gamma_range(table);
    let g_max = range.1.max(1.0);
    let r = 0.5 * frame.w.min(frame.h - 26.0) - 12.0;
    let (cx, cy) = (frame.x + 0.5 * frame.w, frame.y + 12.0 + r);
    let at = |c: f64, g: f64| {
        let rr = r * g / g_max;
        let t = c.to_radians();
        [cx + rr * t.cos(), cy - rr * t.sin()]
    };
    let ring_step = round_step(g_max / 4.0);
    let mut g = ring_step;
    while g <= g_max + 1e-9 {
        svg.circle(cx, cy, r * g / g_max, GRID, 0.5);
        svg.text(
            cx + r * g / g_max * 0.707 + 1.0,
            cy - r * g / g_max * 0.707 - 1.0,
            6.0,
            Anchor::Start,
            MUTED,
            &format!("γ {}°", tick_label(g)),
        );
        g += ring_step;
    }
    for k in 0..8 {
        let c = k as f64 * 45.0;
        let end = at(c, g_max);
        svg.line(cx, cy, end[0], end[1], GRID, 0.5);
        let label = at(c, g_max * (1.0 + 9.0 / r));
        svg.text(
            label[0],
            label[1] + 2.2,
            6.5,
            Anchor::Middle,
            MUTED,
            &format!("C{}", c as i64),
        );
    }
    let peak = table.peak().0;
    let lines = isolines(table, range);
    for (i, line) in lines.iter().enumerate() {
        let colour = LEVEL_COLOURS[i.min(LEVEL_COLOURS.len() - 1)];
        for polyline in &line.polylines {
            let points: Vec<[f64; 2]> = polyline.iter().map(|p| at(p[0], p[1])).collect();
            svg.polyline(&points, colour, 1.0, &[]);
        }
    }
    // Legend: level, cd/klm.
    let y = frame.y + frame.h - 14.0;
    let per = frame.w / lines.len().max(1) as f64;
    for (i, line) in lines.iter().enumerate() {
        let colour = LEVEL_COLOURS[i.min(LEVEL_COLOURS.len() - 1)];
        let x = frame.x + i as f64 * per;
        svg.polyline(&[[x, y - 3.0], [x + 10.0, y - 3.0]], colour, 1.6, &[]);
        svg.text(
            x + 13.0,
            y,
            6.5,
            Anchor::Start,
            INK,
            &format!("{:.0} %", 100.0 * line.level),
        );
        svg.text(
            x + 13.0,
            y + 9.0,
            6.0,
            Anchor::Start,
            MUTED,
            &format!("{:.0}", line.level * peak),
        );
    }
    svg.text(
        frame.x,
        frame.y + 7.0,
        7.0,
        Anchor::Start,
        MUTED,
        "% of peak, cd/klm",
    );
}

/// The cone diagram: the beam's cone from the luminaire down to 5 m, with
/// the illuminance at its centre and its diameters at each metre.
pub fn cone(svg: &mut Svg, frame: Frame, cone: &ConeDiagram) {
    let apex = [frame.x + 0.32 * frame.w, frame.y + 10.0];
    let depth = frame.h - 24.0;
    let half_w = 0.22 * frame.w;
    let last = cone.rows.len().max(1) as f64;
    svg.polygon(
        &[
            apex,
            [apex[0] - half_w, apex[1] + depth],
            [apex[0] + half_w, apex[1] + depth],
        ],
        Rgb(0xf7d774),
        0.55,
    );
    svg.line(
        apex[0],
        apex[1],
        apex[0] - half_w,
        apex[1] + depth,
        RULE,
        0.6,
    );
    svg.line(
        apex[0],
        apex[1],
        apex[0] + half_w,
        apex[1] + depth,
        RULE,
        0.6,
    );
    let x_text = frame.x + 0.58 * frame.w;
    svg.text(x_text, frame.y + 7.0, 6.5, Anchor::Start, MUTED, "E centre");
    svg.text(
        x_text + 0.2 * frame.w,
        frame.y + 7.0,
        6.5,
        Anchor::Start,
        MUTED,
        "Ø C0 / C90 planes",
    );
    for (k, row) in cone.rows.iter().enumerate() {
        let y = apex[1] + depth * (k as f64 + 1.0) / last;
        let w = half_w * (k as f64 + 1.0) / last;
        svg.line(apex[0] - w, y, apex[0] + w, y, INK, 0.6);
        svg.text(
            apex[0] - half_w - 6.0,
            y + 2.2,
            7.0,
            Anchor::End,
            INK,
            &format!("{} m", row.distance_m),
        );
        svg.text(
            x_text,
            y + 2.2,
            7.0,
            Anchor::Start,
            INK,
            &format!("{:.0} lx", row.centre_lux),
        );
        svg.text(
            x_text + 0.2 * frame.w,
            y + 2.2,
            7.0,
            Anchor::Start,
            INK,
            &format!(
                "{:.2} / {:.2} m",
                row.beam_diameter_m[0], row.beam_diameter_m[1]
            ),
        );
    }
    svg.text(
        frame.x,
        frame.y + frame.h - 1.0,
        6.5,
        Anchor::Start,
        MUTED,
        &format!(
            "beam angle (50 %) {:.1}° / {:.1}°; E = I(γ 0°) / d² for the file's flux",
            cone.beam_angle_deg[0], cone.beam_angle_deg[1]
        ),
    );
}
