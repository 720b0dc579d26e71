//! Lines of equal intensity over C (across) and γ (down) for the editor's
//! isocandela view and the datasheet's isocandela chart: the table
//! sampled on a C-γ grid, and marching squares (the `contour` crate) at
//! fractions of the peak. The γ range is the lit part of the
//! distribution, so a 4° spot fills a chart rather than a strip at its
//! top.

use lucerna_photometry::CandelaTable;

/// Grid of the map: C every 2°, 181 rows over the γ range shown.
pub const C_STEP_DEG: f64 = 2.0;
pub const COLUMNS: usize = 181;
pub const ROWS: usize = 181;

/// Intensity below this fraction of the peak is outside the range shown.
const LIT_FRACTION: f64 = 0.01;
/// The narrowest γ range shown (degrees).
const MIN_RANGE_DEG: f64 = 10.0;

/// The γ range (degrees) where the table reaches 1 % of its peak in some
/// C-plane, widened by a fifth and rounded out to 5° (1° under 20°), at
/// least 10° wide, within 0°–180°.
pub fn lit_gamma_range(table: &CandelaTable) -> (f64, f64) {
    let peak = table.peak().0;
    if !(peak > 0.0) {
        return (0.0, 180.0);
    }
    let lit: Vec<f64> = table
        .gammas_deg
        .iter()
        .copied()
        .filter(|&g| {
            table
                .c_planes_deg
                .iter()
                .any(|&c| table.intensity(c, g) >= LIT_FRACTION * peak)
        })
        .collect();
    let (Some(&first), Some(&last)) = (lit.first(), lit.last()) else {
        return (0.0, 180.0);
    };
    // The next grid angle beyond each end still falls off to below the
    // threshold: include it.
    let next = |g: f64, up: bool| {
        let grid = &table.gammas_deg;
        let found = if up {
            grid.iter().copied().find(|&x| x > g)
        } else {
            grid.iter().rev().copied().find(|&x| x < g)
        };
        found.unwrap_or(g)
    };
    let (lo, hi) = (next(first, false), next(last, true));
    let margin = 0.2 * (hi - lo);
    let (lo, hi) = ((lo - margin).max(0.0), (hi + margin).min(180.0));
    let step = if hi - lo < 20.0 { 1.0 } else { 5.0 };
    let (mut lo, mut hi) = ((lo / step).floor() * step, (hi / step).ceil() * step);
    if hi - lo < MIN_RANGE_DEG {
        hi = (lo + MIN_RANGE_DEG).min(180.0);
        lo = (hi - MIN_RANGE_DEG).max(0.0);
    }
    (lo, hi)
}

/// The γ of row `row` for the range shown.
pub fn row_gamma(range: (f64, f64), row: f64) -> f64 {
    range.0 + row * (range.1 - range.0) / (ROWS - 1) as f64
}

/// The lines drawn, as fractions of the peak.
pub const LEVELS: [f64; 6] = [0.05, 0.1, 0.25, 0.5, 0.75, 0.9];

/// A line of equal intensity: its level (fraction of the peak) and its
/// polylines in (C, γ) degrees.
#[derive(Debug, Clone, PartialEq)]
pub struct Isoline {
    pub level: f64,
    pub polylines: Vec<Vec<[f64; 2]>>,
}

/// The table sampled on the map's grid over the γ range, row by γ.
pub fn sampled(table: &CandelaTable, range: (f64, f64)) -> Vec<f64> {
    let mut values = Vec::with_capacity(COLUMNS * ROWS);
    for j in 0..ROWS {
        let gamma = row_gamma(range, j as f64);
        for i in 0..COLUMNS {
            values.push(table.intensity(i as f64 * C_STEP_DEG, gamma));
        }
    }
    values
}

/// Lines of equal intensity at `LEVELS` of the peak, in (C, γ) degrees,
/// on the grid over the γ `range`.
pub fn isolines(table: &CandelaTable, range: (f64, f64)) -> Vec<Isoline> {
    let values = sampled(table, range);
    let peak = values.iter().copied().fold(0.0, f64::max);
    if !(peak > 0.0) {
        return Vec::new();
    }
    let thresholds: Vec<f64> = LEVELS.iter().map(|l| l * peak).collect();
    // The crate puts sample (i, j) at the pixel centre (i + ½, j + ½) and
    // closes each ring along the grid's border; smoothing interpolates the
    // crossings linearly between samples.
    let builder = contour::ContourBuilder::new(COLUMNS, ROWS, true);
    let Ok(lines) = builder.lines(&values, &thresholds) else {
        return Vec::new();
    };
    let on_border =
        |x: f64, y: f64| x <= 0.0 || y <= 0.0 || x >= COLUMNS as f64 || y >= ROWS as f64;
    lines
        .iter()
        .map(|line| {
            let mut polylines = Vec::new();
            for ring in &line.geometry().0 {
                // The ring's runs off the border are the isoline itself.
                let mut run: Vec<[f64; 2]> = Vec::new();
                for p in &ring.0 {
                    if on_border(p.x, p.y) {
                        if run.len() > 1 {
                            polylines.push(std::mem::take(&mut run));
                        }
                        run.clear();
                    } else {
                        run.push([(p.x - 0.5) * C_STEP_DEG, row_gamma(range, p.y - 0.5)]);
                    }
                }
                if run.len() > 1 {
                    polylines.push(run);
                }
            }
            Isoline {
                level: line.threshold() / peak,
                polylines,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// I = 1000 cos γ below the horizon: every isoline of level l lies at
    /// γ = acos(l) in every C-plane.
    #[test]
    fn isolines_of_a_cosine_lie_at_the_arccosine_of_their_level() {
        let table = CandelaTable::from_fn(5.0, 0.5, |_, g| {
            if g < 90.0 {
                1000.0 * g.to_radians().cos()
            } else {
                0.0
            }
        });
        let range = lit_gamma_range(&table);
        assert_eq!(range, (0.0, 110.0));
        let lines = isolines(&table, range);
        assert_eq!(lines.len(), LEVELS.len());
        for line in &lines {
            let expected = line.level.acos().to_degrees();
            let points: Vec<&[f64; 2]> = line.polylines.iter().flatten().collect();
            assert!(!points.is_empty());
            for p in points {
                // Linear interpolation between 0.6° rows of a cosine.
                assert!(
                    (p[1] - expected).abs() < 0.05,
                    "{} % at γ {}: {}",
                    line.level,
                    p[1],
                    expected
                );
                assert!((-1e-9..=360.0 + 1e-9).contains(&p[0]), "C {}", p[0]);
            }
        }
    }

    /// A 3.7° spot (half peak at 1.85°) fills the chart: γ up to 10°, its
    /// half-peak line at 1.85° to a tenth of a degree.
    #[test]
    fn a_narrow_beam_zooms_the_gamma_axis_to_where_the_light_is() {
        let half_angle = 1.85_f64;
        let table = CandelaTable::from_fn(5.0, 0.1, |_, g| {
            // A Gaussian beam: I = peak / 2 at the half angle.
            100_000.0 * (-(g / half_angle).powi(2) * std::f64::consts::LN_2).exp()
        });
        let range = lit_gamma_range(&table);
        assert_eq!(range, (0.0, 10.0), "{range:?}");
        let half = isolines(&table, range)
            .into_iter()
            .find(|l| (l.level - 0.5).abs() < 1e-9)
            .expect("a half-peak line");
        for p in half.polylines.iter().flatten() {
            assert!(
                (p[1] - half_angle).abs() < 0.1,
                "γ {} vs {half_angle}",
                p[1]
            );
        }
    }
}
