//! Candela tables on C-γ grids (photometry type C) and their symmetries
//! (resampling from cube maps is `resample`).
//!
//! Direction of (C, γ): `d = (sin γ cos C, sin γ sin C, −cos γ)`: γ = 0 at
//! nadir, C counter-clockwise seen from above, C0 along +x, C90 along +y.

use std::f64::consts::TAU;

use serde::{Deserialize, Serialize};

use crate::cubemap::Dir;

/// The C-plane symmetry a photometric file declares (what the C-planes it
/// stores stand for), apart from the luminaire's axial symmetry
/// (`AxialSymmetry`), which the tracer finds in the geometry.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CPlaneSymmetry {
    /// No symmetry: C0 to C360 stored.
    None,
    /// Mirror symmetry about the C0-C180 plane: I(C) = I(360° − C).
    AboutC0C180,
    /// Mirror symmetry about the C90-C270 plane: I(C) = I(180° − C).
    AboutC90C270,
    /// Both planes (quadrant symmetry).
    Quadrant,
    /// The same in every C-plane (rotational symmetry).
    Rotational,
}

impl CPlaneSymmetry {
    /// C angles (degrees, in [0, 360)) that the symmetry maps `c` onto,
    /// including `c` itself.
    pub fn images(self, c: f64) -> Vec<f64> {
        let w = |x: f64| x.rem_euclid(360.0);
        match self {
            CPlaneSymmetry::None => vec![w(c)],
            CPlaneSymmetry::AboutC0C180 => vec![w(c), w(360.0 - c)],
            CPlaneSymmetry::AboutC90C270 => vec![w(c), w(180.0 - c)],
            CPlaneSymmetry::Quadrant => vec![w(c), w(360.0 - c), w(180.0 - c), w(180.0 + c)],
            CPlaneSymmetry::Rotational => vec![w(c)],
        }
    }

    pub fn describe(self) -> &'static str {
        match self {
            CPlaneSymmetry::None => "none (C0-C360)",
            CPlaneSymmetry::AboutC0C180 => "about the C0-C180 plane",
            CPlaneSymmetry::AboutC90C270 => "about the C90-C270 plane",
            CPlaneSymmetry::Quadrant => "quadrant (C0-C180 and C90-C270 planes)",
            CPlaneSymmetry::Rotational => "rotational",
        }
    }
}

/// Direction of (C, γ) in radians.
pub fn direction(c: f64, gamma: f64) -> Dir {
    let (sg, cg) = gamma.sin_cos();
    let (sc, cc) = c.sin_cos();
    [sg * cc, sg * sc, -cg]
}

/// (C, γ) in radians of a direction; C in [0, 2π), γ in [0, π].
pub fn angles(d: Dir) -> (f64, f64) {
    let [x, y, z] = d;
    let horizontal = (x * x + y * y).sqrt();
    let gamma = horizontal.atan2(-z);
    let c = if horizontal == 0.0 {
        0.0
    } else {
        y.atan2(x).rem_euclid(TAU)
    };
    (c, gamma)
}

pub use crate::limits::MAX_CANDELA;

/// Absolute luminous intensities (cd) on a C-γ grid covering the whole
/// sphere of C angles. Files with symmetry are expanded on reading, so
/// every consumer sees one representation.
///
/// `c_planes_deg` is ascending in [0, 360) (a single plane means
/// rotational symmetry); `gammas_deg` is ascending in [0, 180]; intensity
/// outside the γ range is zero.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CandelaTable {
    pub c_planes_deg: Vec<f64>,
    pub gammas_deg: Vec<f64>,
    /// Row-major: `candela[c_index * gammas.len() + gamma_index]`.
    pub candela: Vec<f64>,
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum TableError {
    #[error("a table needs at least one C-plane and two γ angles")]
    TooSmall,
    #[error(
        "{what} must be ascending within {range}, at least 0.0001° apart; got {}",
        shown(values)
    )]
    Angles {
        what: &'static str,
        range: &'static str,
        values: Vec<f64>,
    },
    #[error("{expected} intensities expected, got {got}")]
    Count { expected: usize, got: usize },
    #[error("intensity {value} at C{c}° γ{gamma}° is not a number from 0 to {MAX_CANDELA:e} cd")]
    Value { value: f64, c: f64, gamma: f64 },
}

/// At most 12 values of a list, for a message that stays readable.
fn shown(values: &[f64]) -> String {
    let head: Vec<String> = values.iter().take(12).map(|v| v.to_string()).collect();
    if values.len() > 12 {
        format!("{} … ({} in all)", head.join(", "), values.len())
    } else {
        head.join(", ")
    }
}

fn strictly_ascending_within(v: &[f64], lo: f64, hi: f64, hi_inclusive: bool) -> bool {
    v.iter()
        .all(|x| x.is_finite() && *x >= lo && (*x < hi || (hi_inclusive && *x <= hi)))
        && v.windows(2).all(|w| crate::limits::apart(w[0], w[1]))
}

impl CandelaTable {
    /// Checks the grid and values; the constructor every reader goes through.
    pub fn new(
        c_planes_deg: Vec<f64>,
        gammas_deg: Vec<f64>,
        candela: Vec<f64>,
    ) -> Result<Self, TableError> {
        if c_planes_deg.is_empty() || gammas_deg.len() < 2 {
            return Err(TableError::TooSmall);
        }
        if !strictly_ascending_within(&c_planes_deg, 0.0, 360.0, false) {
            return Err(TableError::Angles {
                what: "C-plane angles",
                range: "[0°, 360°)",
                values: c_planes_deg,
            });
        }
        if !strictly_ascending_within(&gammas_deg, 0.0, 180.0, true) {
            return Err(TableError::Angles {
                what: "γ angles",
                range: "[0°, 180°]",
                values: gammas_deg,
            });
        }
        let expected = c_planes_deg.len() * gammas_deg.len();
        if candela.len() != expected {
            return Err(TableError::Count {
                expected,
                got: candela.len(),
            });
        }
        if let Some(i) = candela
            .iter()
            .position(|&v| !crate::limits::intensity_ok(v))
        {
            return Err(TableError::Value {
                value: candela[i],
                c: c_planes_deg[i / gammas_deg.len()],
                gamma: gammas_deg[i % gammas_deg.len()],
            });
        }
        Ok(CandelaTable {
            c_planes_deg,
            gammas_deg,
            candela,
        })
    }

    /// Uniform grid with `c_step_deg` (0 → one plane) and `gamma_step_deg`
    /// from γ 0° to 180°, filled by `f(c_deg, gamma_deg)`.
    pub fn from_fn(
        c_step_deg: f64,
        gamma_step_deg: f64,
        mut f: impl FnMut(f64, f64) -> f64,
    ) -> Self {
        let c_planes_deg = uniform_c_planes(c_step_deg);
        let gammas_deg = uniform_gammas(gamma_step_deg, 180.0);
        let mut candela = Vec::with_capacity(c_planes_deg.len() * gammas_deg.len());
        for &c in &c_planes_deg {
            for &g in &gammas_deg {
                candela.push(f(c, g));
            }
        }
        CandelaTable {
            c_planes_deg,
            gammas_deg,
            candela,
        }
    }

    pub fn plane(&self, c_index: usize) -> &[f64] {
        let n = self.gammas_deg.len();
        &self.candela[c_index * n..(c_index + 1) * n]
    }

    fn at(&self, c_index: usize, g_index: usize) -> f64 {
        self.candela[c_index * self.gammas_deg.len() + g_index]
    }

    /// Intensity along one C-plane at γ, linear in γ, zero outside the range.
    fn plane_intensity(&self, c_index: usize, gamma_deg: f64) -> f64 {
        let g = &self.gammas_deg;
        if gamma_deg < g[0] || gamma_deg > g[g.len() - 1] {
            return 0.0;
        }
        let j = g.partition_point(|&x| x <= gamma_deg).clamp(1, g.len() - 1);
        let t = (gamma_deg - g[j - 1]) / (g[j] - g[j - 1]);
        self.at(c_index, j - 1) * (1.0 - t) + self.at(c_index, j) * t
    }

    /// Intensity (cd) at (C, γ) in degrees: linear in γ and in C, C wrapping
    /// around 360°.
    pub fn intensity(&self, c_deg: f64, gamma_deg: f64) -> f64 {
        let c = &self.c_planes_deg;
        if c.len() == 1 {
            return self.plane_intensity(0, gamma_deg);
        }
        let c_deg = c_deg.rem_euclid(360.0);
        let i = c.partition_point(|&x| x <= c_deg);
        let (lo, hi) = if i == 0 || i == c.len() {
            (c.len() - 1, 0)
        } else {
            (i - 1, i)
        };
        let span = (c[hi] - c[lo]).rem_euclid(360.0);
        let span = if span == 0.0 { 360.0 } else { span };
        let t = (c_deg - c[lo]).rem_euclid(360.0) / span;
        self.plane_intensity(lo, gamma_deg) * (1.0 - t) + self.plane_intensity(hi, gamma_deg) * t
    }

    /// Weight (rad) of each C-plane in the integral over C: half the angle
    /// to each neighbour, around the circle.
    pub fn c_weights(&self) -> Vec<f64> {
        let c = &self.c_planes_deg;
        let n = c.len();
        if n == 1 {
            return vec![TAU];
        }
        (0..n)
            .map(|i| {
                let next = (c[(i + 1) % n] - c[i]).rem_euclid(360.0);
                let prev = (c[i] - c[(i + n - 1) % n]).rem_euclid(360.0);
                0.5 * (next + prev).to_radians()
            })
            .collect()
    }

    /// Flux (lm) between γ0 and γ1 (degrees): the exact integral of the
    /// table's piecewise-linear intensity times sin γ, per plane, summed
    /// with trapezoidal weights in C.
    pub fn flux_between_lm(&self, gamma0_deg: f64, gamma1_deg: f64) -> f64 {
        let weights = self.c_weights();
        let g = &self.gammas_deg;
        let mut total = 0.0;
        for (ci, w) in weights.iter().enumerate() {
            let mut plane = 0.0;
            for j in 0..g.len() - 1 {
                let (lo, hi) = (g[j].max(gamma0_deg), g[j + 1].min(gamma1_deg));
                if lo >= hi {
                    continue;
                }
                // I(γ) = p + q γ on this segment (radians).
                let (a, b) = (g[j].to_radians(), g[j + 1].to_radians());
                let (ia, ib) = (self.at(ci, j), self.at(ci, j + 1));
                let q = (ib - ia) / (b - a);
                let p = ia - q * a;
                // ∫ (p + q t) sin t dt = −(p + q t) cos t + q sin t
                let antiderivative = |t: f64| -(p + q * t) * t.cos() + q * t.sin();
                plane += antiderivative(hi.to_radians()) - antiderivative(lo.to_radians());
            }
            total += w * plane;
        }
        total
    }

    /// Total luminous flux (lm).
    pub fn flux_lm(&self) -> f64 {
        self.flux_between_lm(0.0, 180.0)
    }

    /// Largest intensity and its (C, γ) in degrees.
    pub fn peak(&self) -> (f64, f64, f64) {
        let n = self.gammas_deg.len();
        let (i, v) =
            self.candela
                .iter()
                .enumerate()
                .fold((0, f64::NEG_INFINITY), |(bi, bv), (i, &v)| {
                    if v > bv { (i, v) } else { (bi, bv) }
                });
        (v, self.c_planes_deg[i / n], self.gammas_deg[i % n])
    }

    /// Largest relative difference between the table and its image under
    /// `symmetry`, relative to the peak intensity.
    pub fn asymmetry(&self, symmetry: CPlaneSymmetry) -> f64 {
        let (peak, _, _) = self.peak();
        if peak <= 0.0 {
            return 0.0;
        }
        let mut worst: f64 = 0.0;
        for &c in &self.c_planes_deg {
            let images: Vec<f64> = if symmetry == CPlaneSymmetry::Rotational {
                self.c_planes_deg.clone()
            } else {
                symmetry.images(c)
            };
            for &g in &self.gammas_deg {
                let here = self.intensity(c, g);
                for &ci in &images {
                    worst = worst.max((self.intensity(ci, g) - here).abs());
                }
            }
        }
        worst / peak
    }

    /// The highest symmetry the table has within `tolerance` (fraction of the
    /// peak intensity).
    pub fn detect_symmetry(&self, tolerance: f64) -> CPlaneSymmetry {
        if self.c_planes_deg.len() == 1 || self.asymmetry(CPlaneSymmetry::Rotational) <= tolerance {
            return CPlaneSymmetry::Rotational;
        }
        let c0 = self.asymmetry(CPlaneSymmetry::AboutC0C180) <= tolerance;
        let c90 = self.asymmetry(CPlaneSymmetry::AboutC90C270) <= tolerance;
        match (c0, c90) {
            (true, true) => CPlaneSymmetry::Quadrant,
            (true, false) => CPlaneSymmetry::AboutC0C180,
            (false, true) => CPlaneSymmetry::AboutC90C270,
            (false, false) => CPlaneSymmetry::None,
        }
    }

    /// Averages each value with its symmetric images (on this grid), e.g. to
    /// halve the noise of a traced distribution known to be symmetric.
    pub fn symmetrised(&self, symmetry: CPlaneSymmetry) -> CandelaTable {
        let mut out = self.clone();
        let n = self.gammas_deg.len();
        for (ci, &c) in self.c_planes_deg.iter().enumerate() {
            let images: Vec<f64> = if symmetry == CPlaneSymmetry::Rotational {
                self.c_planes_deg.clone()
            } else {
                symmetry.images(c)
            };
            for (gi, &g) in self.gammas_deg.iter().enumerate() {
                let sum: f64 = images.iter().map(|&cc| self.intensity(cc, g)).sum();
                out.candela[ci * n + gi] = sum / images.len() as f64;
            }
        }
        out
    }

    /// The same distribution on another grid (linear interpolation).
    pub fn resampled(&self, c_planes_deg: Vec<f64>, gammas_deg: Vec<f64>) -> CandelaTable {
        let mut candela = Vec::with_capacity(c_planes_deg.len() * gammas_deg.len());
        for &c in &c_planes_deg {
            for &g in &gammas_deg {
                candela.push(self.intensity(c, g));
            }
        }
        CandelaTable {
            c_planes_deg,
            gammas_deg,
            candela,
        }
    }

    /// The γ spacing when the angles are equally spaced.
    pub fn uniform_gamma_step(&self) -> Option<f64> {
        uniform_step(&self.gammas_deg)
    }

    /// Whether the C-planes are equally spaced around the full circle.
    pub fn uniform_c_step(&self) -> Option<f64> {
        let c = &self.c_planes_deg;
        if c.len() == 1 {
            return Some(0.0);
        }
        let step = 360.0 / c.len() as f64;
        c.iter()
            .enumerate()
            .all(|(i, &x)| (x - i as f64 * step).abs() < 1e-6)
            .then_some(step)
    }

    /// Root mean square of the difference from `other` over the whole
    /// sphere, weighted by solid angle (cd): how far a design is from a
    /// reference, in one number. Midpoint rule on a 0.5° γ × 2.5° C grid
    /// of both tables' interpolated intensities.
    pub fn rms_difference_cd(&self, other: &CandelaTable) -> f64 {
        const GAMMA_STEP_DEG: f64 = 0.5;
        const C_STEP_DEG: f64 = 2.5;
        let (mut sum, mut weight) = (0.0, 0.0);
        for k in 0..(180.0 / GAMMA_STEP_DEG) as usize {
            let gamma = (k as f64 + 0.5) * GAMMA_STEP_DEG;
            let w = gamma.to_radians().sin();
            for m in 0..(360.0 / C_STEP_DEG) as usize {
                let c = m as f64 * C_STEP_DEG;
                let d = self.intensity(c, gamma) - other.intensity(c, gamma);
                sum += w * d * d;
                weight += w;
            }
        }
        if weight > 0.0 {
            (sum / weight).sqrt()
        } else {
            0.0
        }
    }

    /// Scales every intensity (e.g. relative ↔ absolute photometry).
    pub fn scaled(&self, factor: f64) -> CandelaTable {
        CandelaTable {
            candela: self.candela.iter().map(|v| v * factor).collect(),
            ..self.clone()
        }
    }
}

/// The common difference of ascending `values`, if they are equally spaced
/// (within 1e-6°).
pub fn uniform_step(values: &[f64]) -> Option<f64> {
    let step = values.get(1)? - values[0];
    values
        .windows(2)
        .all(|w| (w[1] - w[0] - step).abs() < 1e-6)
        .then_some(step)
}

/// C-planes 0, step, … below 360° (a single plane for step 0).
pub fn uniform_c_planes(step_deg: f64) -> Vec<f64> {
    if step_deg <= 0.0 {
        return vec![0.0];
    }
    let n = (360.0 / step_deg).round() as usize;
    (0..n).map(|i| i as f64 * 360.0 / n as f64).collect()
}

/// γ angles 0, step, … up to `max_deg` inclusive.
pub fn uniform_gammas(step_deg: f64, max_deg: f64) -> Vec<f64> {
    let n = (max_deg / step_deg).round() as usize;
    (0..=n).map(|i| i as f64 * max_deg / n as f64).collect()
}
