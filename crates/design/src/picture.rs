//! `design.png`: the merit over time (every traced candidate, and the
//! best so far per stage), and the target beside the result (and the
//! start) as a polar diagram of the C0-C180 plane and a cartesian I(γ).

use lucerna_photometry::CandelaTable;
use lucerna_pictures::canvas::{BLACK, Canvas, Colour, WHITE};

use crate::outcome::Outcome;
use crate::{Design, Target};

/// A curve drawn: its table, colour, legend name and line width.
type Curve<'a> = (&'a CandelaTable, Colour, &'a str, f32);

const W: u32 = 1500;
const H: u32 = 540;
const PANEL: f32 = 500.0;
const GREY: Colour = [150, 150, 150];
const LIGHT: Colour = [225, 225, 225];
const RESULT: Colour = [20, 90, 200];
const TARGET: Colour = [200, 40, 40];
const START: Colour = [140, 140, 140];

/// The picture as PNG bytes.
pub fn design_png(design: &Design, outcome: &Outcome) -> Result<Vec<u8>, image::ImageError> {
    let mut c = Canvas::new(W, H, WHITE);
    merit_panel(&mut c, design);
    // The curves, scaled like the merit: the result to the target's flux
    // unless the target is absolute.
    let (target, absolute) = match design.aim.target() {
        Target::Distribution {
            table, absolute, ..
        } => (Some(table), *absolute),
        Target::Spec(_) => (None, true),
    };
    let scale_to = |t: &CandelaTable| -> f64 {
        match target {
            Some(goal) if !absolute && t.flux_lm() > 0.0 => goal.flux_lm() / t.flux_lm(),
            _ => 1.0,
        }
    };
    let result = outcome.table.scaled(scale_to(&outcome.table));
    let start = outcome.start_table.scaled(scale_to(&outcome.start_table));
    // The target drawn wide beneath the design, so both show where they
    // agree.
    let mut curves: Vec<Curve> = vec![(&start, START, "start", 2.0)];
    if let Some(t) = target {
        curves.push((t, TARGET, "target", 5.0));
    }
    curves.push((&result, RESULT, "design", 2.0));
    polar_panel(&mut c, PANEL, &curves);
    cartesian_panel(&mut c, 2.0 * PANEL, &curves);
    c.png()
}

fn title(c: &mut Canvas, x: f32, text: &str) {
    c.text(x + 16.0, 24.0, text, 17.0, BLACK);
}

/// Merit against seconds, log scale: dots per candidate, the best so far.
fn merit_panel(c: &mut Canvas, design: &Design) {
    title(c, 0.0, "Merit over time (log scale; dots: candidates)");
    let (x0, y0, w, h) = (60.0f32, 50.0f32, PANEL - 80.0, H as f32 - 110.0);
    let records: Vec<(f64, f64, u64)> = design
        .found
        .history
        .iter()
        .filter_map(|r| Some((r.elapsed_s, r.merit?, r.photons)))
        .filter(|(_, m, _)| *m > 0.0 && m.is_finite())
        .collect();
    axes(c, x0, y0, w, h);
    if records.is_empty() {
        return;
    }
    let t_max = records.iter().map(|r| r.0).fold(1e-3, f64::max);
    let (lo, hi) = records.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), r| {
        (lo.min(r.1), hi.max(r.1))
    });
    let (l0, l1) = (
        lo.log10().floor(),
        hi.log10().ceil().max(lo.log10().floor() + 1.0),
    );
    let px = |t: f64| x0 + (t / t_max) as f32 * w;
    let py = |m: f64| y0 + h - ((m.log10() - l0) / (l1 - l0)) as f32 * h;
    for d in (l0 as i32)..=(l1 as i32) {
        let y = py(10f64.powi(d));
        c.line(x0, y, x0 + w, y, 1.0, LIGHT);
        c.text(8.0, y - 6.0, &format!("1e{d}"), 12.0, GREY);
    }
    for &(t, m, _) in &records {
        let (x, y) = (px(t), py(m));
        c.fill_rect(x as i64 - 1, y as i64 - 1, 3, 3, [160, 180, 220]);
    }
    // Best so far within each stage (merits of different photon counts
    // are not comparable).
    let mut best: Vec<(f32, f32)> = Vec::new();
    let mut current = (0u64, f64::INFINITY);
    for &(t, m, photons) in &records {
        if photons != current.0 {
            if best.len() > 1 {
                c.polyline(&best, 2.0, RESULT);
            }
            best.clear();
            current = (photons, f64::INFINITY);
        }
        if m < current.1 {
            current.1 = m;
        }
        best.push((px(t), py(current.1)));
    }
    if best.len() > 1 {
        c.polyline(&best, 2.0, RESULT);
    }
    c.text_centred(
        x0 + 0.5 * w,
        y0 + h + 36.0,
        &format!("time (s), 0 … {t_max:.1}"),
        13.0,
        BLACK,
    );
}

fn axes(c: &mut Canvas, x0: f32, y0: f32, w: f32, h: f32) {
    c.line(x0, y0, x0, y0 + h, 1.0, BLACK);
    c.line(x0, y0 + h, x0 + w, y0 + h, 1.0, BLACK);
}

/// The highest peak of the curves (cd), if any holds light: both
/// diagrams share one scale.
fn highest_peak(curves: &[Curve]) -> Option<f64> {
    let peak = curves
        .iter()
        .map(|(t, _, _, _)| t.peak().0)
        .fold(0.0, f64::max);
    (peak > 0.0).then_some(peak)
}

/// The C0-C180 plane in polar form: γ from nadir, down the page.
fn polar_panel(c: &mut Canvas, left: f32, curves: &[Curve]) {
    title(c, left, "Polar, C0-C180 (cd)");
    let (cx, cy, radius) = (left + 0.5 * PANEL, 80.0f32, PANEL * 0.42);
    let Some(peak) = highest_peak(curves) else {
        return;
    };
    for k in 1..=4 {
        let r = radius * k as f32 / 4.0;
        let ring: Vec<(f32, f32)> = (0..=180)
            .map(|a| {
                let g = (a as f32).to_radians();
                (cx + r * g.cos(), cy + r * g.sin())
            })
            .collect();
        c.polyline(&ring, 1.0, LIGHT);
        c.text(
            cx + 4.0,
            cy + r - 4.0,
            &lucerna_pictures::canvas::label(peak * k as f64 / 4.0),
            11.0,
            GREY,
        );
    }
    for (table, colour, _, width) in curves {
        let mut points = Vec::new();
        for k in -180..=180 {
            let g = f64::from(k) * 0.5;
            let (plane, gamma) = if g < 0.0 { (180.0, -g) } else { (0.0, g) };
            let v = table.intensity(plane, gamma) / peak;
            // Down the page is nadir; C0 to the right.
            let a = (90.0 - g).to_radians();
            points.push((
                cx + (radius as f64 * v * a.cos()) as f32,
                cy + (radius as f64 * v * a.sin()) as f32,
            ));
        }
        c.polyline(&points, *width, *colour);
    }
    legend(c, left + 20.0, H as f32 - 40.0, curves);
}

/// I(γ) in C0 from nadir to where the light ends (at least 10°).
fn cartesian_panel(c: &mut Canvas, left: f32, curves: &[Curve]) {
    title(c, left, "Cartesian, C0 (cd against γ)");
    let (x0, y0, w, h) = (left + 60.0, 50.0f32, PANEL - 90.0, H as f32 - 110.0);
    axes(c, x0, y0, w, h);
    let Some(peak) = highest_peak(curves) else {
        return;
    };
    // The widest angle where any curve holds 0.5 % of the peak.
    let reach = curves
        .iter()
        .flat_map(|(t, _, _, _)| (0..=720).map(move |k| (f64::from(k) * 0.25, *t)))
        .filter(|(g, t)| t.intensity(0.0, *g) > 0.005 * peak)
        .map(|(g, _)| g)
        .fold(10.0, f64::max)
        .min(180.0);
    let g_max = (reach * 1.1).ceil();
    let px = |g: f64| x0 + (g / g_max) as f32 * w;
    let py = |v: f64| y0 + h - (v / peak) as f32 * h;
    for k in 0..=4 {
        let v = peak * f64::from(k) / 4.0;
        c.line(x0, py(v), x0 + w, py(v), 1.0, LIGHT);
        c.text(
            left + 4.0,
            py(v) + 5.0,
            &lucerna_pictures::canvas::label(v),
            11.0,
            GREY,
        );
    }
    for k in 0..=4 {
        let g = g_max * f64::from(k) / 4.0;
        c.text_centred(px(g), y0 + h + 18.0, &format!("{g:.0}°"), 12.0, BLACK);
    }
    for (table, colour, _, width) in curves {
        let points: Vec<(f32, f32)> = (0..=400)
            .map(|k| {
                let g = g_max * f64::from(k) / 400.0;
                (px(g), py(table.intensity(0.0, g)))
            })
            .collect();
        c.polyline(&points, *width, *colour);
    }
}

fn legend(c: &mut Canvas, x: f32, y: f32, curves: &[Curve]) {
    let mut at = x;
    for (_, colour, name, _) in curves {
        c.line(at, y, at + 24.0, y, 3.0, *colour);
        let w = c.text(at + 30.0, y - 8.0, name, 14.0, BLACK);
        at += 50.0 + w;
    }
}
