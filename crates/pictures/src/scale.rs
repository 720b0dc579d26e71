//! The visual rules every picture shares, exported or on screen: the
//! false-colour palette, the logarithmic intensity scale, round steps and
//! 1-2-5 ticks, and the linear lux scale's top. The editor draws with
//! these too, so a colour or a tick means the same in a PNG and a window.

use crate::canvas::Colour;

/// Decades below the peak the logarithmic scale spans: stray light a
/// thousand times dimmer than the beam still shows.
pub const DECADES: f64 = 3.0;

/// A perceptually ordered false-colour scale (dark blue → cyan → green →
/// yellow → red → white) for t in [0, 1]; NaN is the bottom.
pub fn false_colour(t: f32) -> Colour {
    const STOPS: [(f32, [f32; 3]); 7] = [
        (0.0, [10.0, 10.0, 40.0]),
        (0.15, [30.0, 40.0, 160.0]),
        (0.35, [20.0, 170.0, 210.0]),
        (0.55, [60.0, 200.0, 80.0]),
        (0.75, [240.0, 220.0, 40.0]),
        (0.9, [230.0, 60.0, 30.0]),
        (1.0, [255.0, 250.0, 240.0]),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    for w in STOPS.windows(2) {
        let ((t0, c0), (t1, c1)) = (w[0], w[1]);
        if t <= t1 {
            let s = (t - t0) / (t1 - t0);
            return [0, 1, 2].map(|k| (c0[k] + (c1[k] - c0[k]) * s).round() as u8);
        }
    }
    [255, 250, 240]
}

/// Position of `v` on the logarithmic scale over [`DECADES`] below `top`,
/// in [0, 1] (0 for nothing, or no top).
pub fn log_position(v: f64, top: f64) -> f32 {
    if v <= 0.0 || top <= 0.0 || !v.is_finite() || !top.is_finite() {
        0.0
    } else {
        ((v / top).log10() / DECADES + 1.0).clamp(0.0, 1.0) as f32
    }
}

/// The false colour of `v` on the logarithmic scale below `peak` (the
/// cube maps, the isocandela map, the 3D view's cube).
pub fn log_colour(v: f64, peak: f64) -> Colour {
    false_colour(log_position(v, peak))
}

/// The smallest round step (1, 2 or 5 × 10ⁿ) at least `rough`; 1 for
/// nothing sensible.
pub fn round_step(rough: f64) -> f64 {
    if !(rough > 0.0 && rough.is_finite()) {
        return 1.0;
    }
    let decade = 10f64.powf(rough.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * decade)
        // The decade's own power can land a hair below `rough`.
        .find(|s| *s >= rough * (1.0 - 1e-12))
        .unwrap_or(10.0 * decade)
}

/// The ticks at 1, 2 and 5 per decade from `bottom` to `top` (both > 0),
/// ascending: a log scale's legend.
pub fn ticks_125(bottom: f64, top: f64) -> Vec<f64> {
    let mut ticks = Vec::new();
    if !(bottom > 0.0 && top >= bottom && top.is_finite()) {
        return ticks;
    }
    let mut decade = 10f64.powf(bottom.log10().floor());
    while decade <= top * 1.0001 {
        for m in [1.0, 2.0, 5.0] {
            let v = decade * m;
            if v >= bottom * 0.999 && v <= top * 1.0001 {
                ticks.push(v);
            }
        }
        decade *= 10.0;
    }
    ticks
}

/// A linear scale from 0 to a round `top`, ticked every `step`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LinearScale {
    pub top: f64,
    pub step: f64,
}

impl LinearScale {
    /// About `parts` round steps up to `high`, the top the first step at
    /// or above it.
    pub fn up_to(high: f64, parts: f64) -> LinearScale {
        let high = if high.is_finite() {
            high.max(1e-3)
        } else {
            1.0
        };
        let step = round_step(high / parts);
        LinearScale {
            top: (high / step).ceil().max(1.0) * step,
            step,
        }
    }

    /// The scale of an illuminance picture: up to the 99th percentile of
    /// the lit values (negative ones, luminaires, and non-finite ones
    /// left out), so a few bright pixels do not set it.
    pub fn over_p99(values: impl Iterator<Item = f64>, parts: f64) -> LinearScale {
        let mut lit: Vec<f64> = values.filter(|v| *v >= 0.0 && v.is_finite()).collect();
        lit.sort_by(f64::total_cmp);
        let p99 = lit
            .get(lit.len().saturating_sub(1) * 99 / 100)
            .copied()
            .unwrap_or(1.0);
        LinearScale::up_to(p99, parts)
    }

    /// The scale of a work-plane grid: up to its largest value.
    pub fn over_max(values: impl Iterator<Item = f64>, parts: f64) -> LinearScale {
        let max = values.filter(|v| v.is_finite()).fold(0.0, f64::max);
        LinearScale::up_to(max, parts)
    }

    /// Position of `v` on the scale, in [0, 1].
    pub fn position(&self, v: f64) -> f32 {
        (v / self.top).clamp(0.0, 1.0) as f32
    }

    /// The false colour of `v`: white for a negative value (a luminaire
    /// seen in the view).
    pub fn colour(&self, v: f64) -> Colour {
        if v < 0.0 {
            crate::canvas::WHITE
        } else {
            false_colour(self.position(v))
        }
    }

    /// The tick values 0, step, 2 step … top.
    pub fn ticks(&self) -> Vec<f64> {
        let n = (self.top / self.step).round() as usize;
        (0..=n).map(|k| k as f64 * self.step).collect()
    }
}

/// Parts of an illuminance picture's linear scale (view and work plane).
pub const LUX_PARTS: f64 = 8.0;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_steps_are_the_smallest_1_2_5_at_least_the_rough_one() {
        for (rough, step) in [
            (0.7, 1.0),
            (1.0, 1.0),
            (1.01, 2.0),
            (2.0, 2.0),
            (2.6, 5.0),
            (5.0, 5.0),
            (7.0, 10.0),
            (275.0, 500.0),
            (100.0, 100.0),
            (0.03, 0.05),
            (30_250.0, 50_000.0),
        ] {
            assert_eq!(round_step(rough), step, "{rough}");
        }
        assert_eq!(round_step(0.0), 1.0);
        assert_eq!(round_step(f64::NAN), 1.0);
        assert_eq!(round_step(-3.0), 1.0);
    }

    #[test]
    fn ticks_are_1_2_5_per_decade_within_the_range() {
        assert_eq!(
            ticks_125(0.5, 120.0),
            vec![0.5, 1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0]
        );
        assert!(ticks_125(0.0, 10.0).is_empty());
        assert!(ticks_125(10.0, 1.0).is_empty());
    }

    #[test]
    fn the_log_scale_spans_its_decades_below_the_top() {
        assert_eq!(log_position(1000.0, 1000.0), 1.0);
        assert!((log_position(10.0, 1000.0) - 1.0 / 3.0).abs() < 1e-6);
        assert_eq!(log_position(0.5, 1000.0), 0.0);
        assert_eq!(log_position(0.0, 1000.0), 0.0);
        assert_eq!(log_position(f64::NAN, 1000.0), 0.0);
        assert_eq!(log_colour(1000.0, 1000.0), false_colour(1.0));
    }

    #[test]
    fn a_linear_scale_tops_a_round_number_above_its_high_value() {
        let s = LinearScale::up_to(437.0, 8.0);
        assert_eq!((s.top, s.step), (500.0, 100.0));
        assert_eq!(s.ticks(), vec![0.0, 100.0, 200.0, 300.0, 400.0, 500.0]);
        // 99 of 100 values at 10 lx, one at 10 000: the outlier does not
        // set the top, luminaires (negative) are left out.
        let mut v = vec![10.0; 99];
        v.push(10_000.0);
        v.push(-1.0);
        let s = LinearScale::over_p99(v.into_iter(), 8.0);
        assert_eq!((s.top, s.step), (10.0, 2.0));
        assert_eq!(s.colour(-1.0), crate::canvas::WHITE);
        assert_eq!(s.colour(10.0), false_colour(1.0));
        let s = LinearScale::over_max([3.0, f64::NAN, 41.0].into_iter(), 8.0);
        assert_eq!((s.top, s.step), (50.0, 10.0));
    }

    #[test]
    fn the_palette_is_ordered_dark_to_light() {
        let luma =
            |c: Colour| 0.299 * f64::from(c[0]) + 0.587 * f64::from(c[1]) + 0.114 * f64::from(c[2]);
        assert!(luma(false_colour(0.0)) < 30.0);
        assert!(luma(false_colour(1.0)) > 240.0);
        assert_eq!(false_colour(f32::NAN), false_colour(0.0));
        assert_eq!(false_colour(2.0), false_colour(1.0));
    }
}
