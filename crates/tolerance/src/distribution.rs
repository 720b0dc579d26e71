//! How one toleranced quantity is spread around its nominal value: a
//! normal or a uniform deviation, optionally truncated (parts outside the
//! limits are rejected at incoming inspection) and shifted by a
//! systematic offset. Each draw is the distribution's quantile of a
//! uniform number in (0, 1), so a stratified (Sobol) sequence of uniforms
//! stays stratified.

use serde::{Deserialize, Serialize};
use statrs::distribution::{ContinuousCDF, Normal};

/// The shape of a deviation.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Shape {
    /// Normal with standard deviation `sigma`.
    Normal { sigma: f64 },
    /// Uniform between −`half_width` and +`half_width`.
    Uniform { half_width: f64 },
}

/// A deviation's distribution: shape, a systematic offset, and an
/// optional truncation of the whole deviation (offset included: parts
/// beyond ± `truncate` are sorted out).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Distribution {
    pub shape: Shape,
    /// Deviations beyond ±`truncate` never occur.
    pub truncate: Option<f64>,
    /// A systematic shift of every deviation (its mean before any
    /// truncation).
    pub offset: f64,
}

/// The uniform numbers are kept this far from 0 and 1: the normal's
/// quantile stays finite (±5.3σ).
const EDGE: f64 = 1e-7;

impl Distribution {
    /// Why the numbers cannot describe a distribution, if they cannot.
    pub fn check(&self) -> Result<(), String> {
        match self.shape {
            Shape::Normal { sigma } if !(sigma.is_finite() && sigma > 0.0) => {
                return Err(format!("sigma must be a positive number, got {sigma}"));
            }
            Shape::Uniform { half_width } if !(half_width.is_finite() && half_width > 0.0) => {
                return Err(format!(
                    "half_width must be a positive number, got {half_width}"
                ));
            }
            _ => {}
        }
        if let Some(t) = self.truncate
            && !(t.is_finite() && t > 0.0)
        {
            return Err(format!(
                "truncate (the largest deviation kept) must be a positive number, got {t}"
            ));
        }
        if !self.offset.is_finite() {
            return Err(format!(
                "offset must be a finite number, got {}",
                self.offset
            ));
        }
        if self.kept_mass() < 1e-9 {
            return Err(format!(
                "truncate: the offset {} puts every deviation beyond ± {}",
                self.offset,
                self.truncate.unwrap_or(0.0)
            ));
        }
        Ok(())
    }

    /// The normal's cumulative bounds of the kept interval, in standard
    /// units.
    fn normal_bounds(&self, sigma: f64) -> (f64, f64) {
        let unit = Normal::standard();
        match self.truncate {
            Some(t) => (
                unit.cdf((-t - self.offset) / sigma),
                unit.cdf((t - self.offset) / sigma),
            ),
            None => (0.0, 1.0),
        }
    }

    /// The uniform's kept interval.
    fn uniform_interval(&self, half_width: f64) -> (f64, f64) {
        let (mut lo, mut hi) = (self.offset - half_width, self.offset + half_width);
        if let Some(t) = self.truncate {
            lo = lo.max(-t);
            hi = hi.min(t);
        }
        (lo, hi)
    }

    /// The share of the untruncated distribution that is kept.
    fn kept_mass(&self) -> f64 {
        match self.shape {
            Shape::Normal { sigma } => {
                let (a, b) = self.normal_bounds(sigma);
                b - a
            }
            Shape::Uniform { half_width } => {
                let (lo, hi) = self.uniform_interval(half_width);
                ((hi - lo) / (2.0 * half_width)).max(0.0)
            }
        }
    }

    /// The deviation whose cumulative probability is `u` ∈ (0, 1).
    pub fn quantile(&self, u: f64) -> f64 {
        let u = u.clamp(EDGE, 1.0 - EDGE);
        match self.shape {
            Shape::Normal { sigma } => {
                let (a, b) = self.normal_bounds(sigma);
                let p = (a + u * (b - a)).clamp(EDGE * EDGE, 1.0 - EDGE * EDGE);
                self.offset + sigma * Normal::standard().inverse_cdf(p)
            }
            Shape::Uniform { half_width } => {
                let (lo, hi) = self.uniform_interval(half_width);
                lo + u * (hi - lo)
            }
        }
    }

    /// The deviation's standard deviation (about its mean).
    pub fn standard_deviation(&self) -> f64 {
        match self.shape {
            Shape::Normal { sigma } => match self.truncate {
                None => sigma,
                Some(t) => {
                    // A normal truncated to [α, β] (standard units):
                    // σ²(1 + (αφ(α) − βφ(β))/Z − ((φ(α) − φ(β))/Z)²).
                    let (al, be) = ((-t - self.offset) / sigma, (t - self.offset) / sigma);
                    let phi = |x: f64| (-0.5 * x * x).exp() / (2.0 * std::f64::consts::PI).sqrt();
                    let (a, b) = self.normal_bounds(sigma);
                    let z = b - a;
                    let m = (phi(al) - phi(be)) / z;
                    sigma
                        * (1.0 + (al * phi(al) - be * phi(be)) / z - m * m)
                            .max(0.0)
                            .sqrt()
                }
            },
            Shape::Uniform { half_width } => {
                let (lo, hi) = self.uniform_interval(half_width);
                (hi - lo) / 12f64.sqrt()
            }
        }
    }

    /// The fraction of draws at or below `x` (the analytic distribution
    /// function; the tests' truth for yields).
    pub fn cdf(&self, x: f64) -> f64 {
        match self.shape {
            Shape::Normal { sigma } => {
                let unit = Normal::standard();
                let (a, b) = self.normal_bounds(sigma);
                let x = match self.truncate {
                    Some(t) => x.clamp(-t, t),
                    None => x,
                };
                ((unit.cdf((x - self.offset) / sigma) - a) / (b - a)).clamp(0.0, 1.0)
            }
            Shape::Uniform { half_width } => {
                let (lo, hi) = self.uniform_interval(half_width);
                ((x - lo) / (hi - lo)).clamp(0.0, 1.0)
            }
        }
    }

    /// How the distribution reads in a report: "normal σ 0.0001",
    /// "uniform ±0.0002, truncated at ±0.00015".
    pub fn describe(&self) -> String {
        let mut s = match self.shape {
            Shape::Normal { sigma } => format!("normal σ {sigma}"),
            Shape::Uniform { half_width } => format!("uniform ±{half_width}"),
        };
        if self.offset != 0.0 {
            s.push_str(&format!(", offset {}", self.offset));
        }
        if let Some(t) = self.truncate {
            s.push_str(&format!(", truncated at ±{t}"));
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn normal(sigma: f64, truncate: Option<f64>) -> Distribution {
        Distribution {
            shape: Shape::Normal { sigma },
            truncate,
            offset: 0.0,
        }
    }

    #[test]
    fn the_quantile_inverts_the_distribution_function() {
        for d in [
            normal(2.0, None),
            normal(2.0, Some(1.5)),
            Distribution {
                shape: Shape::Uniform { half_width: 3.0 },
                truncate: Some(2.0),
                offset: 0.5,
            },
        ] {
            for k in 1..20 {
                let u = f64::from(k) / 20.0;
                let x = d.quantile(u);
                assert!((d.cdf(x) - u).abs() < 1e-9, "{d:?} at {u}: {}", d.cdf(x));
            }
        }
    }

    #[test]
    fn a_truncated_normal_stays_within_its_limits_and_has_its_closed_form_spread() {
        let d = normal(1.0, Some(1.0));
        let n = 200_000;
        let xs: Vec<f64> = (0..n)
            .map(|k| d.quantile((k as f64 + 0.5) / n as f64))
            .collect();
        assert!(xs.iter().all(|x| x.abs() <= 1.0 + 1e-12));
        let var = xs.iter().map(|x| x * x).sum::<f64>() / n as f64;
        // σ² (1 − 2·1·φ(1)/(2Φ(1) − 1)) = 0.2911.
        assert!((var.sqrt() - d.standard_deviation()).abs() < 1e-3);
        assert!((d.standard_deviation() - 0.2911f64.sqrt()).abs() < 1e-3);
    }

    #[test]
    fn the_truncation_bounds_the_whole_deviation_offset_included() {
        let d = Distribution {
            shape: Shape::Normal { sigma: 1.0 },
            truncate: Some(1.5),
            offset: 1.0,
        };
        let xs: Vec<f64> = (0..1000)
            .map(|k| d.quantile((k as f64 + 0.5) / 1000.0))
            .collect();
        assert!(xs.iter().all(|x| x.abs() <= 1.5 + 1e-12));
        let n = 200_000;
        let xs: Vec<f64> = (0..n)
            .map(|k| d.quantile((k as f64 + 0.5) / n as f64))
            .collect();
        let mean = xs.iter().sum::<f64>() / n as f64;
        let sd = (xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n as f64).sqrt();
        assert!(
            (sd - d.standard_deviation()).abs() < 2e-3,
            "{sd} vs {}",
            d.standard_deviation()
        );
        let beyond = Distribution {
            shape: Shape::Uniform { half_width: 0.1 },
            truncate: Some(0.2),
            offset: 0.5,
        };
        assert!(beyond.check().is_err());
    }

    #[test]
    fn nonsense_is_refused() {
        assert!(normal(0.0, None).check().is_err());
        assert!(normal(f64::NAN, None).check().is_err());
        assert!(normal(1.0, Some(-1.0)).check().is_err());
        assert!(normal(1.0, Some(0.0)).check().is_err());
        assert!(normal(1.0, Some(0.5)).check().is_ok());
    }
}
