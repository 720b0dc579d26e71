//! The numbers a tolerance analysis reports: yields with their 95 %
//! confidence intervals, each figure's spread, and which tolerance drives
//! which figure.

use nalgebra::{DMatrix, DVector};
use serde::Serialize;

/// z of a two-sided 95 % interval.
const Z95: f64 = 1.959_963_984_540_054;

/// A fraction of samples with its 95 % confidence interval.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Fraction {
    pub passed: usize,
    pub samples: usize,
    pub value: f64,
    pub low: f64,
    pub high: f64,
}

impl Fraction {
    /// `passed` of `samples` with the Wilson score interval (which stays
    /// inside [0, 1] and is right near 0 and 1, where a normal
    /// approximation is not).
    pub fn wilson(passed: usize, samples: usize) -> Fraction {
        if samples == 0 {
            return Fraction {
                passed,
                samples,
                value: f64::NAN,
                low: 0.0,
                high: 1.0,
            };
        }
        let n = samples as f64;
        let p = passed as f64 / n;
        let z2 = Z95 * Z95;
        let centre = (p + z2 / (2.0 * n)) / (1.0 + z2 / n);
        let half = Z95 / (1.0 + z2 / n) * (p * (1.0 - p) / n + z2 / (4.0 * n * n)).sqrt();
        Fraction {
            passed,
            samples,
            value: p,
            low: (centre - half).max(0.0),
            high: (centre + half).min(1.0),
        }
    }

    /// The interval's half width.
    pub fn half_width(&self) -> f64 {
        0.5 * (self.high - self.low)
    }
}

/// A figure's distribution over the samples.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Spread {
    pub count: usize,
    /// Of them, the infinite ones (a UGR the table cannot give): in the
    /// quantiles and the extremes, not in the mean and σ.
    pub unbounded: usize,
    pub mean: f64,
    pub sd: f64,
    pub q05: f64,
    pub q50: f64,
    pub q95: f64,
    pub min: f64,
    pub max: f64,
}

impl Spread {
    /// Of the values that are numbers (a refused sample has none): the
    /// mean and σ of the finite ones.
    pub fn of(values: &[f64]) -> Spread {
        let mut all: Vec<f64> = values.iter().copied().filter(|x| !x.is_nan()).collect();
        all.sort_by(f64::total_cmp);
        let v: Vec<f64> = all.iter().copied().filter(|x| x.is_finite()).collect();
        let n = v.len();
        let unbounded = all.len() - n;
        if all.is_empty() {
            return Spread {
                count: 0,
                unbounded: 0,
                mean: f64::NAN,
                sd: f64::NAN,
                q05: f64::NAN,
                q50: f64::NAN,
                q95: f64::NAN,
                min: f64::NAN,
                max: f64::NAN,
            };
        }
        let mean = if n > 0 {
            v.iter().sum::<f64>() / n as f64
        } else {
            f64::NAN
        };
        let sd = if n > 1 {
            (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1) as f64).sqrt()
        } else {
            0.0
        };
        Spread {
            count: all.len(),
            unbounded,
            mean,
            sd,
            q05: quantile(&all, 0.05),
            q50: quantile(&all, 0.5),
            q95: quantile(&all, 0.95),
            min: all[0],
            max: all[all.len() - 1],
        }
    }
}

/// The `p` quantile of sorted values, linearly interpolated between
/// order statistics (Hyndman & Fan's type 7, as R and NumPy default to).
pub fn quantile(sorted: &[f64], p: f64) -> f64 {
    let n = sorted.len();
    if n == 0 {
        return f64::NAN;
    }
    let h = (n - 1) as f64 * p.clamp(0.0, 1.0);
    let lo = h.floor() as usize;
    let hi = (lo + 1).min(n - 1);
    let f = h - lo as f64;
    if f == 0.0 || sorted[lo] == sorted[hi] {
        return sorted[lo];
    }
    sorted[lo] + f * (sorted[hi] - sorted[lo])
}

/// A tolerance's first-order share of a figure's variance, with the
/// share's noise (its standard deviation for a tolerance that does
/// nothing).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Share {
    pub share: f64,
    pub noise: f64,
}

/// The first-order share Var(E[y|u])/Var(y) of a scalar tolerance whose
/// uniform numbers are `u` (∈ [0, 1)): the correlation ratio of `y`
/// binned by `u` in equal bins (the Sobol points fill them evenly), less
/// its expectation (B−1)/(N−1) for a tolerance that does nothing. It
/// sees a figure that moves either way of the nominal (a beam widened by
/// an offset to either side), which a linear regression would not.
pub fn binned_share(u: &[f64], y: &[f64]) -> Option<Share> {
    let n = y.len();
    if n < 8 || u.len() != n {
        return None;
    }
    let bins = ((n as f64).sqrt() / 2.0).round().clamp(2.0, 16.0) as usize;
    let mean = y.iter().sum::<f64>() / n as f64;
    let total: f64 = y.iter().map(|v| (v - mean).powi(2)).sum();
    if !(total > 0.0) {
        return None;
    }
    let mut sum = vec![0.0; bins];
    let mut count = vec![0usize; bins];
    for (&ui, &yi) in u.iter().zip(y) {
        let b = ((ui * bins as f64) as usize).min(bins - 1);
        sum[b] += yi;
        count[b] += 1;
    }
    let between: f64 = sum
        .iter()
        .zip(&count)
        .filter(|(_, c)| **c > 0)
        .map(|(s, &c)| c as f64 * (s / c as f64 - mean).powi(2))
        .sum();
    let eta2 = between / total;
    let bias = (bins - 1) as f64 / (n - 1) as f64;
    Some(Share {
        share: ((eta2 - bias) / (1.0 - bias)).clamp(0.0, 1.0),
        noise: (2.0 * (bins - 1) as f64).sqrt() / n as f64,
    })
}

/// The first-order share of a group of inputs `x` (one row of features
/// per sample: a form error's deviations at a few points along the
/// profile): the adjusted R² of a least-squares fit of `y` on the
/// features and their squares.
pub fn regression_share(x: &[Vec<f64>], y: &[f64]) -> Option<Share> {
    let n = y.len();
    let m = x.first()?.len();
    let p = 2 * m;
    if n < p + 8 || x.len() != n {
        return None;
    }
    let mean = y.iter().sum::<f64>() / n as f64;
    let total: f64 = y.iter().map(|v| (v - mean).powi(2)).sum();
    if !(total > 0.0) {
        return None;
    }
    // Features standardised, so the squares do not swamp the fit.
    let mut columns: Vec<Vec<f64>> = Vec::with_capacity(p);
    for k in 0..m {
        let c: Vec<f64> = x.iter().map(|r| r[k]).collect();
        columns.push(c.clone());
        columns.push(c.iter().map(|v| v * v).collect());
    }
    for c in &mut columns {
        let mu = c.iter().sum::<f64>() / n as f64;
        let sd = (c.iter().map(|v| (v - mu).powi(2)).sum::<f64>() / n as f64).sqrt();
        for v in c.iter_mut() {
            *v = if sd > 0.0 { (*v - mu) / sd } else { 0.0 };
        }
    }
    let design = DMatrix::from_fn(
        n,
        p + 1,
        |i, j| if j == 0 { 1.0 } else { columns[j - 1][i] },
    );
    let target = DVector::from_column_slice(y);
    let fit = design.clone().svd(true, true).solve(&target, 1e-12).ok()?;
    let residual = target - design * fit;
    let r2 = 1.0 - residual.norm_squared() / total;
    let adjusted = 1.0 - (1.0 - r2) * (n - 1) as f64 / (n - p - 1) as f64;
    Some(Share {
        share: adjusted.clamp(0.0, 1.0),
        noise: (2.0 * p as f64).sqrt() / n as f64,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wilsons_interval_matches_its_closed_form() {
        // 50 of 100: 0.5 ± 0.0962 (Wilson; Newcombe 1998's table).
        let f = Fraction::wilson(50, 100);
        assert!((f.low - 0.4038).abs() < 1e-4 && (f.high - 0.5962).abs() < 1e-4);
        // 0 of 10: [0, 0.2775].
        let f = Fraction::wilson(0, 10);
        assert_eq!(f.low, 0.0);
        assert!((f.high - 0.2775).abs() < 1e-4);
    }

    #[test]
    fn quantiles_interpolate_between_order_statistics() {
        let v = [1.0, 2.0, 3.0, 4.0, 5.0];
        assert_eq!(quantile(&v, 0.5), 3.0);
        assert!((quantile(&v, 0.05) - 1.2).abs() < 1e-12);
        assert_eq!(quantile(&v, 1.0), 5.0);
    }

    #[test]
    fn a_share_sees_a_two_sided_effect_and_not_a_null_one() {
        let n = 400;
        let u: Vec<f64> = (0..n).map(|k| (k as f64 + 0.5) / n as f64).collect();
        // A pseudo-random second input, unrelated to y.
        let w: Vec<f64> = (0..n).map(|k| ((k as f64) * 0.618_034).fract()).collect();
        let y: Vec<f64> = u.iter().map(|x| (x - 0.5f64).abs()).collect();
        let s = binned_share(&u, &y).expect("a share");
        assert!(s.share > 0.95, "{s:?}");
        let null = binned_share(&w, &y).expect("a share");
        assert!(null.share < 3.0 * null.noise + 0.02, "{null:?}");
        let rows: Vec<Vec<f64>> = u.iter().map(|x| vec![x - 0.5]).collect();
        let r = regression_share(&rows, &y).expect("a share");
        // |x| against x and x²: most of it.
        assert!(r.share > 0.9, "{r:?}");
    }
}
