//! The intensity profile as the shaders sample it: absolute candela on a
//! regular C-γ grid, bilinear in C and γ. The CPU reference, the Monte Carlo
//! ground truth and the WGSL renderer all read this one representation, so
//! their comparisons measure the integration methods, not the lookups.

use glam::DVec3;
use lucerna_photometry::CandelaTable;

/// γ step of the grid (degrees): fine enough for narrow spots (a 5° beam
/// spans 10 samples).
pub const GAMMA_STEP_DEG: f64 = 0.5;
/// C step of the grid (degrees) for tables that vary with C.
pub const C_STEP_DEG: f64 = 2.5;

/// Candela on `c_count × gamma_count` grid points: C = i·c_step over
/// [0°, 360°] (the last column repeats C = 0°), γ = j·γ step over [0°, 180°].
#[derive(Debug, Clone, PartialEq)]
pub struct ProfileGrid {
    /// Number of C columns (1 for a rotationally symmetric table).
    pub c_count: usize,
    pub gamma_count: usize,
    pub c_step_deg: f64,
    pub gamma_step_deg: f64,
    /// Row-major by C column: `candela[c * gamma_count + g]`.
    pub candela: Vec<f32>,
}

impl ProfileGrid {
    /// Samples a candela table (its own linear interpolation) on the grid.
    pub fn from_table(table: &CandelaTable) -> ProfileGrid {
        let gamma_count = (180.0 / GAMMA_STEP_DEG).round() as usize + 1;
        let rotational = table.c_planes_deg.len() == 1;
        let c_count = if rotational {
            1
        } else {
            (360.0 / C_STEP_DEG).round() as usize + 1
        };
        let mut candela = Vec::with_capacity(c_count * gamma_count);
        for i in 0..c_count {
            let c = if rotational { 0.0 } else { i as f64 * C_STEP_DEG };
            for j in 0..gamma_count {
                let g = j as f64 * GAMMA_STEP_DEG;
                candela.push(table.intensity(c % 360.0, g).max(0.0) as f32);
            }
        }
        ProfileGrid {
            c_count,
            gamma_count,
            c_step_deg: C_STEP_DEG,
            gamma_step_deg: GAMMA_STEP_DEG,
            candela,
        }
    }

    /// A profile from a function of (C°, γ°), for tests and analytic cases.
    pub fn from_fn(rotational: bool, f: impl Fn(f64, f64) -> f64) -> ProfileGrid {
        let gamma_count = (180.0 / GAMMA_STEP_DEG).round() as usize + 1;
        let c_count = if rotational {
            1
        } else {
            (360.0 / C_STEP_DEG).round() as usize + 1
        };
        let mut candela = Vec::with_capacity(c_count * gamma_count);
        for i in 0..c_count {
            for j in 0..gamma_count {
                candela.push(f(i as f64 * C_STEP_DEG, j as f64 * GAMMA_STEP_DEG) as f32);
            }
        }
        ProfileGrid {
            c_count,
            gamma_count,
            c_step_deg: C_STEP_DEG,
            gamma_step_deg: GAMMA_STEP_DEG,
            candela,
        }
    }

    /// Intensity (cd) towards a unit direction in luminaire coordinates
    /// (x = C0, y = C90, z up; γ = 0 is nadir, −z).
    pub fn candela(&self, d: DVec3) -> f64 {
        let horizontal = (d.x * d.x + d.y * d.y).sqrt();
        let gamma = horizontal.atan2(-d.z).to_degrees();
        let gf = (gamma / self.gamma_step_deg).clamp(0.0, (self.gamma_count - 1) as f64);
        let g0 = (gf.floor() as usize).min(self.gamma_count - 2);
        let tg = gf - g0 as f64;
        if self.c_count == 1 {
            let a = self.candela[g0] as f64;
            let b = self.candela[g0 + 1] as f64;
            return a + (b - a) * tg;
        }
        let c = if horizontal > 0.0 {
            d.y.atan2(d.x).to_degrees().rem_euclid(360.0)
        } else {
            0.0
        };
        let cf = (c / self.c_step_deg).clamp(0.0, (self.c_count - 1) as f64);
        let c0 = (cf.floor() as usize).min(self.c_count - 2);
        let tc = cf - c0 as f64;
        let at = |ci: usize, gi: usize| self.candela[ci * self.gamma_count + gi] as f64;
        let low = at(c0, g0) + (at(c0, g0 + 1) - at(c0, g0)) * tg;
        let high = at(c0 + 1, g0) + (at(c0 + 1, g0 + 1) - at(c0 + 1, g0)) * tg;
        low + (high - low) * tc
    }

    /// Largest tabulated intensity (cd).
    pub fn peak_candela(&self) -> f64 {
        self.candela.iter().fold(0.0f64, |m, &v| m.max(v as f64))
    }
}
