//! The analysis's pictures: each figure's histogram over the built
//! luminaires with the spec's limits and the nominal drawn, and which
//! tolerance drives which figure as bars.

use lucerna_design::{Spec, Target};
use lucerna_pictures::canvas::{BLACK, Canvas, Colour, WHITE, label};

use crate::analysis::{SampleRecord, Setup};
use crate::figures::Figure;
use crate::report::{Report, shown};

const PANEL_W: f32 = 420.0;
const PANEL_H: f32 = 270.0;
const COLUMNS: usize = 3;
const GREY: Colour = [150, 150, 150];
const BAR: Colour = [70, 120, 200];
const FAIL: Colour = [210, 60, 50];
const NOMINAL: Colour = [20, 20, 20];
const PALETTE: [Colour; 8] = [
    [70, 120, 200],
    [230, 140, 40],
    [60, 160, 90],
    [200, 60, 60],
    [140, 90, 190],
    [120, 90, 60],
    [210, 110, 180],
    [110, 110, 110],
];

/// The spec's limits on a figure: (lower, upper).
pub fn limits(setup: &Setup, figure: Figure) -> (Option<f64>, Option<f64>) {
    let spec: Option<&Spec> = match setup.judge.aim.target() {
        Target::Spec(s) => Some(s),
        Target::Distribution { .. } => None,
    };
    match (figure, spec) {
        (Figure::Beam, Some(s)) => match s.beam_angle_deg {
            Some(b) => (
                Some(b - s.beam_tolerance_deg),
                Some(b + s.beam_tolerance_deg),
            ),
            None => (None, None),
        },
        (Figure::Field, Some(s)) => (None, s.field_angle_max_deg),
        (Figure::Cutoff, Some(s)) => (None, s.cutoff_max_fraction.map(|f| 100.0 * f)),
        (Figure::Lor, Some(s)) => (s.lor_min_percent, None),
        (Figure::Ugr, Some(s)) => (None, s.ugr_max),
        (Figure::RelativeL2, None) => (None, setup.judge.max_relative_l2),
        _ => (None, None),
    }
}

/// The bins of a figure's histogram (the picture's and the editor's):
/// over the values, the nominal and the spec's limits, 5 % wider, about
/// √n bins.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Binning {
    pub lo: f64,
    pub width: f64,
    pub bins: usize,
    /// The margin added either side.
    pub pad: f64,
}

impl Binning {
    /// Bins over `values` (finite ones) and the finite `marks`.
    pub fn over(values: &[f64], marks: &[Option<f64>]) -> Binning {
        let finite = values
            .iter()
            .copied()
            .chain(marks.iter().flatten().copied())
            .filter(|v| v.is_finite());
        let (lo, hi) = finite.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        });
        let (lo, hi) = if lo <= hi { (lo, hi) } else { (0.0, 1.0) };
        let pad = ((hi - lo) * 0.05).max(1e-9 * hi.abs().max(1.0));
        let bins = ((values.len() as f64).sqrt().ceil() as usize).clamp(8, 40);
        Binning {
            lo: lo - pad,
            width: (hi - lo + 2.0 * pad) / bins as f64,
            bins,
            pad,
        }
    }

    pub fn hi(&self) -> f64 {
        self.lo + self.width * self.bins as f64
    }

    /// The bin of `v` (the ends hold what lies beyond).
    pub fn index(&self, v: f64) -> usize {
        (((v - self.lo) / self.width).max(0.0) as usize).min(self.bins - 1)
    }

    pub fn centre(&self, bin: usize) -> f64 {
        self.lo + (bin as f64 + 0.5) * self.width
    }
}

/// `histograms.png`: one panel per figure.
pub fn histograms_png(
    setup: &Setup,
    report: &Report,
    records: &[SampleRecord],
) -> Result<Vec<u8>, image::ImageError> {
    let panels: Vec<(usize, Figure)> = setup
        .figures
        .iter()
        .copied()
        .enumerate()
        .filter(|(_, f)| shown(*f))
        .collect();
    let rows = panels.len().div_ceil(COLUMNS).max(1);
    let top = 56.0;
    let mut c = Canvas::new(
        (PANEL_W * COLUMNS as f32) as u32,
        (top + PANEL_H * rows as f32) as u32,
        WHITE,
    );
    let y = &report.overall;
    c.text(
        16.0,
        12.0,
        &format!(
            "Yield {:.1} % (95 %: {:.1}–{:.1} %) of {} built luminaires{}",
            100.0 * y.value,
            100.0 * y.low,
            100.0 * y.high,
            report.samples,
            if report.refused > 0 {
                format!(", {} could not be built", report.refused)
            } else {
                String::new()
            }
        ),
        20.0,
        BLACK,
    );
    c.text(
        16.0,
        36.0,
        "bars: samples (red: outside the spec's limit); black line: the nominal; red lines: the spec's limits",
        13.0,
        GREY,
    );
    for (p, (f, figure)) in panels.iter().enumerate() {
        let x0 = PANEL_W * (p % COLUMNS) as f32;
        let y0 = top + PANEL_H * (p / COLUMNS) as f32;
        let values: Vec<f64> = records
            .iter()
            .filter_map(|r| r.measured.as_ref().map(|m| m.values[*f]))
            .filter(|v| v.is_finite())
            .collect();
        let Some(summary) = report.figures.iter().find(|s| s.figure == figure.key()) else {
            continue;
        };
        histogram_panel(
            &mut c,
            (x0, y0),
            *figure,
            &values,
            summary.nominal,
            limits(setup, *figure),
            (summary.spread.mean, summary.spread.sd),
        );
    }
    c.png()
}

fn histogram_panel(
    c: &mut Canvas,
    (x0, y0): (f32, f32),
    figure: Figure,
    values: &[f64],
    nominal: f64,
    (lower, upper): (Option<f64>, Option<f64>),
    (mean, sd): (f64, f64),
) {
    let (left, right, top, bottom) = (
        x0 + 44.0,
        x0 + PANEL_W - 16.0,
        y0 + 34.0,
        y0 + PANEL_H - 40.0,
    );
    c.text(
        x0 + 16.0,
        y0 + 6.0,
        &format!("{}   mean {}  σ {}", figure.label(), label(mean), label(sd)),
        14.0,
        BLACK,
    );
    if values.is_empty() {
        c.text(left, top + 40.0, "no sample", 14.0, GREY);
        return;
    }
    let binning = Binning::over(values, &[Some(nominal), lower, upper]);
    let (lo, hi, bins) = (binning.lo, binning.hi(), binning.bins);
    let pad = binning.pad;
    let mut counts = vec![0usize; bins];
    for v in values {
        counts[binning.index(*v)] += 1;
    }
    let most = counts.iter().copied().max().unwrap_or(1).max(1);
    let to_x = |v: f64| left + ((v - lo) / (hi - lo)) as f32 * (right - left);
    let bin_w = (right - left) / bins as f32;
    for (b, &n) in counts.iter().enumerate() {
        let h = (bottom - top) * n as f32 / most as f32;
        let centre = binning.centre(b);
        let outside = lower.is_some_and(|l| centre < l) || upper.is_some_and(|u| centre > u);
        c.fill_rect(
            (left + b as f32 * bin_w + 1.0) as i64,
            (bottom - h) as i64,
            (bin_w - 2.0).max(1.0) as i64,
            h.ceil() as i64,
            if outside { FAIL } else { BAR },
        );
    }
    c.line(left, bottom, right, bottom, 1.0, BLACK);
    c.line(left, top, left, bottom, 1.0, BLACK);
    c.text(x0 + 4.0, top - 6.0, &most.to_string(), 12.0, GREY);
    for v in [lower, upper].into_iter().flatten() {
        let x = to_x(v);
        c.line(x, top - 4.0, x, bottom, 2.0, FAIL);
    }
    if nominal.is_finite() {
        let x = to_x(nominal);
        c.line(x, top, x, bottom, 1.5, NOMINAL);
    }
    // Ticks at the ends and the middle.
    for v in [lo + pad, 0.5 * (lo + hi), hi - pad] {
        let x = to_x(v);
        c.line(x, bottom, x, bottom + 4.0, 1.0, BLACK);
        c.text_centred(x, bottom + 14.0, &label(v), 12.0, BLACK);
    }
}

/// `sensitivities.png`: per figure, each tolerance's share of its
/// variance.
pub fn sensitivities_png(setup: &Setup, report: &Report) -> Result<Vec<u8>, image::ImageError> {
    let figures: Vec<Figure> = setup
        .figures
        .iter()
        .copied()
        .filter(|f| shown(*f))
        .collect();
    let mut names: Vec<String> = Vec::new();
    for s in &report.sensitivities {
        if !names.contains(&s.tolerance) {
            names.push(s.tolerance.clone());
        }
    }
    let bar_h = 14.0;
    let group_h = bar_h * names.len().max(1) as f32 + 16.0;
    let (left, right) = (200.0, 860.0);
    let top = 70.0;
    let legend_h = 22.0 * names.len() as f32 + 20.0;
    let height = top + group_h * figures.len() as f32 + 40.0 + legend_h;
    let mut c = Canvas::new(900, height as u32, WHITE);
    c.text(
        16.0,
        12.0,
        "What drives each figure: each tolerance's first-order share of its variance",
        19.0,
        BLACK,
    );
    c.text(
        16.0,
        38.0,
        "(the thin line: the share a tolerance that does nothing would show by chance)",
        13.0,
        GREY,
    );
    let to_x = |v: f64| left + (v.clamp(0.0, 1.0) as f32) * (right - left);
    for (g, figure) in figures.iter().enumerate() {
        let y0 = top + g as f32 * group_h;
        c.text(16.0, y0 + 0.5 * group_h - 16.0, figure.label(), 14.0, BLACK);
        for (k, name) in names.iter().enumerate() {
            let Some(s) = report
                .sensitivities
                .iter()
                .find(|s| s.figure == figure.key() && &s.tolerance == name)
            else {
                continue;
            };
            let y = y0 + k as f32 * bar_h;
            let w = to_x(s.share.share) - left;
            c.fill_rect(
                left as i64,
                y as i64,
                w.max(1.0) as i64,
                (bar_h - 3.0) as i64,
                PALETTE[k % PALETTE.len()],
            );
            let noise = to_x(3.0 * s.share.noise);
            c.line(noise, y, noise, y + bar_h - 3.0, 1.0, BLACK);
            c.text(
                left + w + 6.0,
                y - 2.0,
                &format!("{:.0} %", 100.0 * s.share.share),
                11.0,
                BLACK,
            );
        }
        c.line(
            left,
            y0 + group_h - 8.0,
            right,
            y0 + group_h - 8.0,
            1.0,
            [225, 225, 225],
        );
    }
    let axis_y = top + group_h * figures.len() as f32;
    c.line(left, top - 4.0, left, axis_y, 1.0, BLACK);
    for k in 0..=4 {
        let v = f64::from(k) * 0.25;
        let x = to_x(v);
        c.line(x, axis_y, x, axis_y + 4.0, 1.0, BLACK);
        c.text_centred(
            x,
            axis_y + 14.0,
            &format!("{:.0} %", 100.0 * v),
            12.0,
            BLACK,
        );
    }
    let ly = axis_y + 34.0;
    for (k, name) in names.iter().enumerate() {
        let y = ly + 22.0 * k as f32;
        c.fill_rect(16, y as i64, 16, 14, PALETTE[k % PALETTE.len()]);
        c.text(40.0, y - 2.0, name, 14.0, BLACK);
    }
    c.png()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bins_hold_the_values_and_the_limits() {
        let values: Vec<f64> = (0..100).map(|k| 3.0 + 0.01 * f64::from(k)).collect();
        let b = Binning::over(&values, &[Some(2.0), None, Some(f64::NAN)]);
        assert_eq!(b.bins, 10);
        assert!(b.lo < 2.0 && b.hi() > 3.99);
        assert_eq!(b.index(b.lo), 0);
        assert_eq!(b.index(b.hi() + 1.0), 9);
        for v in &values {
            let k = b.index(*v);
            assert!((v - b.centre(k)).abs() <= 0.5 * b.width + 1e-12);
        }
    }
}
