//! The intensity profile as the shaders sample it: absolute candela on a
//! regular C-γ grid, bilinear in C and γ. The CPU reference, the Monte Carlo
//! ground truth and the WGSL renderer all read this one representation, so
//! their comparisons measure the integration methods, not the lookups.

use glam::DVec3;
use lucerna_photometry::CandelaTable;
use rayon::prelude::*;

/// γ step of the grid (degrees): fine enough for narrow spots (a 5° beam
/// spans 10 samples).
pub const GAMMA_STEP_DEG: f64 = 0.5;
/// C step of the grid (degrees) for tables that vary with C.
pub const C_STEP_DEG: f64 = 2.5;

/// A C column bends the interpolant sharply when its second difference in
/// C reaches this fraction of the peak intensity (over one `C_STEP_DEG`).
pub const C_KINK_THRESHOLD: f64 = 1e-3;
/// Kinked C-planes closer than this are not cut at (the sweep would take
/// too many pieces; the rule's nodes resolve such fine C structure).
pub const MIN_C_KINK_STEP_DEG: f64 = 10.0;

/// Prefiltered levels beyond the raw grid: level k averages the profile
/// over spherical caps of radius `BLUR_BASE_DEG · 2^(k−1)`.
pub const BLUR_LEVELS: usize = 7;
/// Cap radius of the first prefiltered level (degrees).
pub const BLUR_BASE_DEG: f64 = 1.0;
/// Points per cap when each level is averaged from the one below.
const CAP_POINTS: usize = 24;

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
    /// The prefiltered levels the fan cubature reads, built on first use
    /// (the polar rule never reads them, and they are the largest cost of
    /// a grid: the editor builds one for every snapshot it previews).
    levels: std::sync::OnceLock<PrefilteredLevels>,
    /// Cumulative radial integrals per C column and hemisphere: what the
    /// polar near-field rule and its exact reference read.
    pub radial: crate::radial::RadialTables,
    /// Spacing of the C-planes where the interpolant bends sharply (the
    /// source table's planes, when it varies strongly in C): the polar
    /// rule cuts its sweep there. 0: smooth enough in C not to.
    pub c_kink_step_deg: f64,
}

impl ProfileGrid {
    /// Samples a candela table (its own linear interpolation) on the grid.
    pub fn from_table(table: &CandelaTable) -> ProfileGrid {
        ProfileGrid::from_fn(table.c_planes_deg.len() == 1, |c, g| {
            table.intensity(c % 360.0, g).max(0.0)
        })
    }

    /// A profile from a function of (C°, γ°); a rotational one is sampled
    /// at C = 0° only.
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
            levels: std::sync::OnceLock::new(),
            radial: Default::default(),
            c_kink_step_deg: 0.0,
        }
        .with_radial_tables()
        .with_c_kinks()
    }

    /// Finds the C-planes where the interpolant bends sharply (a source
    /// table's planes, linearly interpolated between): `c_kink_step_deg` is
    /// the largest spacing all of them lie on multiples of.
    fn with_c_kinks(mut self) -> ProfileGrid {
        self.c_kink_step_deg = 0.0;
        if self.c_count < 3 {
            return self;
        }
        let gc = self.gamma_count;
        let columns = self.c_count - 1; // the last repeats C = 0°
        let peak = self.candela.iter().copied().fold(0.0f32, f32::max) as f64;
        if peak <= 0.0 {
            return self;
        }
        let at = |c: usize, j: usize| self.candela[(c % columns) * gc + j] as f64;
        let kinked: Vec<usize> = (0..columns)
            .filter(|&c| {
                (0..gc).any(|j| {
                    (at(c + columns - 1, j) - 2.0 * at(c, j) + at(c + 1, j)).abs()
                        > C_KINK_THRESHOLD * peak
                })
            })
            .collect();
        // The largest spacing every kinked column lies on a multiple of
        // (column 0 alone: the whole turn).
        let step = kinked.iter().fold(columns, |g, &c| gcd(g, c));
        let step_deg = step as f64 * self.c_step_deg;
        if !kinked.is_empty() && step_deg >= MIN_C_KINK_STEP_DEG {
            self.c_kink_step_deg = step_deg;
        }
        self
    }

    /// Values per level.
    pub fn level_len(&self) -> usize {
        self.c_count * self.gamma_count
    }

    /// Grid direction of node (c index, γ index) in luminaire coordinates.
    fn node_direction(&self, ci: usize, gi: usize) -> DVec3 {
        let c = (ci as f64 * self.c_step_deg).to_radians();
        let g = (gi as f64 * self.gamma_step_deg).to_radians();
        DVec3::new(g.sin() * c.cos(), g.sin() * c.sin(), -g.cos())
    }

    /// The prefiltered levels: each averages the level below over caps
    /// twice as wide (a mip chain on the sphere), so that a lookup
    /// standing for a large solid angle returns that region's mean
    /// intensity rather than one narrow peak (the paper's future work,
    /// section 8).
    pub fn levels(&self) -> &PrefilteredLevels {
        self.levels.get_or_init(|| self.prefiltered_levels())
    }

    fn prefiltered_levels(&self) -> PrefilteredLevels {
        let n = self.level_len();
        let mut candela = self.candela.clone();
        let mut cosine = Vec::with_capacity(n * (BLUR_LEVELS + 1));
        for _ci in 0..self.c_count {
            for gi in 0..self.gamma_count {
                let cos = (gi as f64 * self.gamma_step_deg).to_radians().cos().abs();
                cosine.push(cos as f32);
            }
        }
        let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
        for level in 1..=BLUR_LEVELS {
            let radius = (BLUR_BASE_DEG * 2f64.powi(level as i32 - 1)).to_radians();
            // Nodes in parallel (a level only reads the one below).
            let (below_candela, below_cosine) = (&candela, &cosine);
            let nodes: Vec<(f32, f32)> = (0..n)
                .into_par_iter()
                .map(|node| {
                    let (ci, gi) = (node / self.gamma_count, node % self.gamma_count);
                    let axis = self.node_direction(ci, gi);
                    let u = axis.any_orthonormal_vector();
                    let v = axis.cross(u);
                    let (mut sum_i, mut sum_c) = (0.0, 0.0);
                    for k in 0..CAP_POINTS {
                        // Uniform over the cap's area (Fibonacci spiral).
                        let t = (k as f64 + 0.5) / CAP_POINTS as f64;
                        let cos_r = 1.0 - t * (1.0 - radius.cos());
                        let sin_r = (1.0 - cos_r * cos_r).max(0.0).sqrt();
                        let phi = k as f64 * golden;
                        let mut d = axis * cos_r + (u * phi.cos() + v * phi.sin()) * sin_r;
                        // Stay in the node's hemisphere: the front and back
                        // of the opening are never seen together.
                        if d.z * axis.z < 0.0 {
                            d.z = -d.z;
                        }
                        let cell = self.cell(d);
                        sum_i += self.sample_at(below_candela, cell, level - 1);
                        sum_c += self.sample_at(below_cosine, cell, level - 1);
                    }
                    (
                        (sum_i / CAP_POINTS as f64) as f32,
                        (sum_c / CAP_POINTS as f64) as f32,
                    )
                })
                .collect();
            let (next_candela, next_cosine): (Vec<f32>, Vec<f32>) = nodes.into_iter().unzip();
            candela.extend(next_candela);
            cosine.extend(next_cosine);
        }
        PrefilteredLevels { candela, cosine }
    }

    fn with_radial_tables(mut self) -> ProfileGrid {
        self.radial = crate::radial::RadialTables::new(
            self.c_count,
            self.gamma_count,
            self.gamma_step_deg,
            &self.candela,
        );
        self
    }

    /// Intensity (cd) towards a unit direction in luminaire coordinates
    /// (x = C0, y = C90, z up; γ = 0 is nadir, −z).
    pub fn candela(&self, d: DVec3) -> f64 {
        self.sample(&self.candela, d, 0)
    }

    /// I / |cos γ| (cd) over a cap of about `radius_rad` around `d`: the
    /// ratio of the prefiltered intensity and cosine (trilinear between
    /// levels).
    pub fn projected_filtered(&self, d: DVec3, radius_rad: f64) -> f64 {
        let level = filter_level(radius_rad);
        let l0 = (level.floor() as usize).min(BLUR_LEVELS);
        let t = level - l0 as f64;
        let cell = self.cell(d);
        let levels = self.levels();
        let (mut i, mut c) = (
            self.sample_at(&levels.candela, cell, l0),
            self.sample_at(&levels.cosine, cell, l0),
        );
        if t > 0.0 && l0 < BLUR_LEVELS {
            i = i * (1.0 - t) + self.sample_at(&levels.candela, cell, l0 + 1) * t;
            c = c * (1.0 - t) + self.sample_at(&levels.cosine, cell, l0 + 1) * t;
        }
        // A flat opening seen exactly edge-on has I/cos = 0/0.
        if c > 1e-9 { i / c } else { 0.0 }
    }

    /// Bilinear lookup in one level of a grid stack.
    fn sample(&self, grids: &[f32], d: DVec3, level: usize) -> f64 {
        self.sample_at(grids, self.cell(d), level)
    }

    /// The grid cell of a direction: lower C and γ indices and the
    /// fractions within the cell (computed once, read in several grids).
    fn cell(&self, d: DVec3) -> Cell {
        let horizontal = (d.x * d.x + d.y * d.y).sqrt();
        let gamma = horizontal.atan2(-d.z).to_degrees();
        let gf = (gamma / self.gamma_step_deg).clamp(0.0, (self.gamma_count - 1) as f64);
        let g0 = (gf.floor() as usize).min(self.gamma_count - 2);
        let tg = gf - g0 as f64;
        if self.c_count == 1 {
            return Cell {
                c0: 0,
                tc: 0.0,
                g0,
                tg,
            };
        }
        let c = if horizontal > 0.0 {
            d.y.atan2(d.x).to_degrees().rem_euclid(360.0)
        } else {
            0.0
        };
        let cf = (c / self.c_step_deg).clamp(0.0, (self.c_count - 1) as f64);
        let c0 = (cf.floor() as usize).min(self.c_count - 2);
        Cell {
            c0,
            tc: cf - c0 as f64,
            g0,
            tg,
        }
    }

    fn sample_at(&self, grids: &[f32], cell: Cell, level: usize) -> f64 {
        let base = level * self.level_len();
        let Cell { c0, tc, g0, tg } = cell;
        let at = |ci: usize, gi: usize| grids[base + ci * self.gamma_count + gi] as f64;
        let low = at(c0, g0) + (at(c0, g0 + 1) - at(c0, g0)) * tg;
        if self.c_count == 1 {
            return low;
        }
        let high = at(c0 + 1, g0) + (at(c0 + 1, g0 + 1) - at(c0 + 1, g0)) * tg;
        low + (high - low) * tc
    }

    /// Luminous flux (lm): the exact integral of the grid's interpolant
    /// (linear in γ) times sin γ, trapezoidal in C.
    pub fn flux_lm(&self) -> f64 {
        let step = self.gamma_step_deg.to_radians();
        // ∫ over one γ cell of (I0 + (I1 − I0) (γ − g0) / Δ) sin γ dγ.
        let cell = |g: usize, i0: f64, i1: f64| {
            let (g0, g1) = (g as f64 * step, (g + 1) as f64 * step);
            i0 * (g0.cos() - g1.cos()) + (i1 - i0) / step * (g1.sin() - g0.sin() - step * g1.cos())
        };
        let column = |c: usize| -> f64 {
            let at = |g: usize| self.candela[c * self.gamma_count + g] as f64;
            (0..self.gamma_count - 1)
                .map(|g| cell(g, at(g), at(g + 1)))
                .sum()
        };
        if self.c_count == 1 {
            return std::f64::consts::TAU * column(0);
        }
        let c_step = self.c_step_deg.to_radians();
        (0..self.c_count - 1)
            .map(|c| 0.5 * (column(c) + column(c + 1)) * c_step)
            .sum()
    }
}

fn gcd(a: usize, b: usize) -> usize {
    if b == 0 { a } else { gcd(b, a % b) }
}

/// The candela grid, then `BLUR_LEVELS` prefiltered grids (the grid's
/// layout): level k averages the profile over caps of radius
/// `BLUR_BASE_DEG · 2^(k−1)`; and |cos γ| averaged over the same caps:
/// I / |cos γ| is the opening's luminance times its area, the quantity a
/// fan triangle averages; the ratio of the two estimates it without
/// dividing by zero in the opening's plane, and exactly for a Lambertian
/// opening.
#[derive(Debug, Clone, PartialEq)]
pub struct PrefilteredLevels {
    pub candela: Vec<f32>,
    pub cosine: Vec<f32>,
}

/// A direction's place in the C-γ grid.
#[derive(Debug, Clone, Copy)]
struct Cell {
    c0: usize,
    tc: f64,
    g0: usize,
    tg: f64,
}

/// Fractional level for a filter radius: 0 below `BLUR_BASE_DEG / 2`, then
/// one level per doubling.
pub fn filter_level(radius_rad: f64) -> f64 {
    let r = radius_rad.to_degrees() / BLUR_BASE_DEG;
    if r <= 0.5 {
        0.0
    } else {
        (r.log2() + 1.0).clamp(0.0, BLUR_LEVELS as f64)
    }
}
