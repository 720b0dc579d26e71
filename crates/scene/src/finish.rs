//! Reflector surface finishes from their geometry: hammered or peened
//! dimples, ripples (sinusoids or trochoids), or a measured slope spread,
//! and the slope statistics a tracer needs to treat the finish as a
//! microfacet distribution (Bruneton, Neyret & Holzschuch 2010, "Real-time
//! realistic ocean lighting using seamless transitions from geometry to
//! BRDF", with one correction: a manufactured finish is often a single
//! structure, whose slopes are not Gaussian — a sinusoid's follow the
//! arcsine law, dimples leave flat land that reflects like a mirror — so
//! the distribution is the finish's own, tabulated, with the flat share
//! kept apart).
//!
//! Slopes are (∂h/∂u, ∂h/∂v) of the finish's height h over the part's
//! surface: u along the profile (a revolved or extruded part's meridian),
//! v across it (around the axis, or along the extrusion).

use serde::{Deserialize, Serialize};

/// How a part's surface is finished.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case", deny_unknown_fields)]
pub enum Finish {
    /// Spherical-cap dimples (hammered, peened): caps of a sphere of
    /// `radius`, `depth` deep, centred on a hexagonal or square pattern of
    /// `pitch` (m); the land between them stays flat.
    Dimples {
        pitch: f64,
        depth: f64,
        radius: f64,
        #[serde(default)]
        pattern: DimplePattern,
    },
    /// A sum of waves (rippled, orange peel).
    Ripples { waves: Vec<Ripple> },
    /// A measured finish given by its slope spread: Gaussian slopes of
    /// standard deviations `sigma_u`, `sigma_v` (along and across, before
    /// the turn by `orientation_deg` about the normal).
    Slopes {
        sigma_u: f64,
        sigma_v: f64,
        #[serde(default)]
        orientation_deg: f64,
    },
    /// Flat facets `size_along` × `size_around` (m) in rows along a
    /// revolved or extruded part's profile and around its axis (along
    /// the extrusion): each the plane touching the smooth surface at its
    /// centre, so its slope against the smooth normal grows across it
    /// with the surface's curvature. On a plane they are the plane.
    Facets { size_along: f64, size_around: f64 },
    /// A measured surface: a greyscale PNG height map (8 or 16 bits, path
    /// relative to the scene file) of square pixels `pixel_size` (m)
    /// across, each grey level `height_step` (m) of height, u along its
    /// rows. It repeats over the part; its slopes by central differences.
    HeightMap {
        path: String,
        pixel_size: f64,
        height_step: f64,
        /// The map as read beside the scene file (`file::parse_scene`).
        #[serde(skip)]
        heights: Option<std::sync::Arc<HeightGrid>>,
    },
}

/// A height map's grey levels, row by row (u fastest).
#[derive(Debug, Clone, PartialEq)]
pub struct HeightGrid {
    pub width: usize,
    pub height: usize,
    pub levels: Vec<f32>,
}

/// The largest height map read (pixels): a 4096² profilometer scan.
pub const MAX_HEIGHT_MAP_PIXELS: usize = 4096 * 4096;

impl HeightGrid {
    /// Decodes a greyscale PNG (8 or 16 bits; a colour image's luma), at
    /// least 3 × 3 pixels; `name` names it in errors.
    pub fn from_png(bytes: &[u8], name: &str) -> Result<HeightGrid, String> {
        let image = image::load_from_memory_with_format(bytes, image::ImageFormat::Png)
            .map_err(|e| format!("{name} is not a PNG height map: {e}"))?;
        let (width, height) = (image.width() as usize, image.height() as usize);
        if width < 3 || height < 3 {
            return Err(format!(
                "{name} is {width} × {height} pixels: a height map needs at least 3 × 3"
            ));
        }
        if width.saturating_mul(height) > MAX_HEIGHT_MAP_PIXELS {
            return Err(format!(
                "{name} is {width} × {height} pixels, more than {MAX_HEIGHT_MAP_PIXELS}"
            ));
        }
        let levels = image
            .into_luma16()
            .into_raw()
            .into_iter()
            .map(f32::from)
            .collect();
        Ok(HeightGrid {
            width,
            height,
            levels,
        })
    }

    /// The level at pixel (i, j), the map repeating.
    fn at(&self, i: isize, j: isize) -> f64 {
        let i = i.rem_euclid(self.width as isize) as usize;
        let j = j.rem_euclid(self.height as isize) as usize;
        f64::from(self.levels[j * self.width + i])
    }
}

/// Where the dimples' centres lie.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum DimplePattern {
    #[default]
    Hexagonal,
    Square,
}

/// One wave train of a rippled finish.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Ripple {
    /// Crest-to-mean height (m).
    pub amplitude: f64,
    /// m.
    pub wavelength: f64,
    /// The direction the wave runs in the surface: 0° along the profile
    /// (the beam widened radially), 90° across it (around the axis).
    #[serde(default)]
    pub direction_deg: f64,
    #[serde(default)]
    pub shape: WaveShape,
}

impl Ripple {
    /// k·a: a sine's steepest slope, a trochoid's sharpness.
    pub fn slope_amplitude(&self) -> f64 {
        std::f64::consts::TAU * self.amplitude / self.wavelength
    }
}

/// A wave's profile.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum WaveShape {
    /// h = a·sin(kx).
    #[default]
    Sine,
    /// Gerstner's trochoid x = s − a·sin(ks), h = a·cos(ks): sharp crests.
    Trochoid,
}

/// The steepest root-mean-square slope a finish may have: beyond it
/// facets face away from light arriving along the mean normal.
pub const MAX_RMS_SLOPE: f64 = 1.0;

/// Slopes at or below this magnitude are flat land.
const FLAT: f64 = 1e-12;

/// A finish's slope distribution.
#[derive(Debug, Clone, PartialEq)]
pub struct SlopeStatistics {
    /// Mean slope (u, v): zero for every finish here.
    pub mean: [f64; 2],
    /// Covariance [σu², σuv, σv²] of the slopes (flat land included).
    pub covariance: [f64; 3],
    /// The area share whose slope is exactly zero (the land between
    /// dimples): a mirror-like share of the reflection.
    pub flat_share: f64,
    /// The rest, tabulated.
    pub table: SlopeTable,
}

/// A 2-D table of the slopes' probability over [−range, range]² in
/// `bins` × `bins` cells (u fastest); it sums to 1 − flat share.
#[derive(Debug, Clone, PartialEq)]
pub struct SlopeTable {
    pub range: f64,
    pub bins: usize,
    pub probability: Vec<f64>,
}

/// Cells per table axis.
pub const TABLE_BINS: usize = 128;

impl SlopeTable {
    fn new(range: f64) -> SlopeTable {
        SlopeTable {
            range,
            bins: TABLE_BINS,
            probability: vec![0.0; TABLE_BINS * TABLE_BINS],
        }
    }

    fn add(&mut self, s: [f64; 2], weight: f64) {
        let cell = |x: f64| {
            let t = (x + self.range) / (2.0 * self.range);
            ((t * self.bins as f64) as isize).clamp(0, self.bins as isize - 1) as usize
        };
        let k = cell(s[1]) * self.bins + cell(s[0]);
        self.probability[k] += weight;
    }

    /// The marginal probability of the u slope per cell.
    pub fn marginal_u(&self) -> Vec<f64> {
        (0..self.bins)
            .map(|i| {
                (0..self.bins)
                    .map(|j| self.probability[j * self.bins + i])
                    .sum()
            })
            .collect()
    }

    /// The centre of cell `i` along an axis.
    pub fn centre(&self, i: usize) -> f64 {
        -self.range + (i as f64 + 0.5) * 2.0 * self.range / self.bins as f64
    }
}

/// The statistics of weighted slope samples, tabulated over
/// [−range, range]² (slopes beyond it in the edge cells).
pub(crate) fn statistics_of_samples(
    range: f64,
    samples: impl IntoIterator<Item = ([f64; 2], f64)>,
) -> SlopeStatistics {
    let mut acc = Accumulator::new(range);
    for (s, w) in samples {
        acc.add(s, w);
    }
    acc.finish()
}

/// Accumulates slopes into statistics.
struct Accumulator {
    weight: f64,
    flat: f64,
    sum: [f64; 2],
    sum2: [f64; 3],
    table: SlopeTable,
}

impl Accumulator {
    fn new(range: f64) -> Accumulator {
        Accumulator {
            weight: 0.0,
            flat: 0.0,
            sum: [0.0; 2],
            sum2: [0.0; 3],
            table: SlopeTable::new(range),
        }
    }

    fn add(&mut self, s: [f64; 2], w: f64) {
        self.weight += w;
        if s[0] * s[0] + s[1] * s[1] <= FLAT * FLAT {
            self.flat += w;
            return;
        }
        self.sum[0] += w * s[0];
        self.sum[1] += w * s[1];
        self.sum2[0] += w * s[0] * s[0];
        self.sum2[1] += w * s[0] * s[1];
        self.sum2[2] += w * s[1] * s[1];
        self.table.add(s, w);
    }

    fn finish(mut self) -> SlopeStatistics {
        let w = self.weight.max(1e-300);
        for p in &mut self.table.probability {
            *p /= w;
        }
        let mean = [self.sum[0] / w, self.sum[1] / w];
        SlopeStatistics {
            mean,
            covariance: [
                self.sum2[0] / w - mean[0] * mean[0],
                self.sum2[1] / w - mean[0] * mean[1],
                self.sum2[2] / w - mean[1] * mean[1],
            ],
            flat_share: self.flat / w,
            table: self.table,
        }
    }
}

impl Finish {
    /// Each problem as (field, why): nothing for a finish that can be
    /// made and traced.
    pub fn problems(&self) -> Vec<(String, String)> {
        let mut out = Vec::new();
        let positive = |out: &mut Vec<(String, String)>, field: &str, v: f64| {
            if !(v.is_finite() && v > 0.0) {
                out.push((
                    field.to_owned(),
                    format!("must be a positive length (m), got {v}"),
                ));
                false
            } else {
                true
            }
        };
        match self {
            Finish::Dimples {
                pitch,
                depth,
                radius,
                ..
            } => {
                let ok = positive(&mut out, "pitch", *pitch)
                    & positive(&mut out, "depth", *depth)
                    & positive(&mut out, "radius", *radius);
                if !ok {
                    return out;
                }
                if depth > radius {
                    out.push((
                        "depth".to_owned(),
                        format!(
                            "a spherical cap is at most as deep as its sphere's radius ({radius} m), got {depth} m"
                        ),
                    ));
                    return out;
                }
                let diameter = 2.0 * dimple_footprint(*radius, *depth);
                if *pitch < diameter * (1.0 - 1e-12) {
                    out.push((
                        "pitch".to_owned(),
                        format!(
                            "dimples of radius {radius} m and depth {depth} m are {diameter:.6} m across: the pitch must be at least that, got {pitch} m"
                        ),
                    ));
                }
            }
            Finish::Ripples { waves } => {
                if waves.is_empty() {
                    out.push(("waves".to_owned(), "name at least one wave".to_owned()));
                }
                for (i, w) in waves.iter().enumerate() {
                    let at = |f: &str| format!("waves[{i}].{f}");
                    positive(&mut out, &at("amplitude"), w.amplitude);
                    positive(&mut out, &at("wavelength"), w.wavelength);
                    if !w.direction_deg.is_finite() {
                        out.push((at("direction_deg"), "must be a finite angle".to_owned()));
                    }
                    let kh = w.slope_amplitude();
                    if w.shape == WaveShape::Trochoid && kh >= 1.0 {
                        out.push((
                            at("amplitude"),
                            format!(
                                "a trochoid loops over itself where 2π·amplitude/wavelength ≥ 1, got {kh:.3}"
                            ),
                        ));
                    }
                }
            }
            Finish::Slopes {
                sigma_u,
                sigma_v,
                orientation_deg,
            } => {
                for (f, v) in [("sigma_u", sigma_u), ("sigma_v", sigma_v)] {
                    if !(v.is_finite() && *v >= 0.0) {
                        out.push((f.to_owned(), format!("must be a slope ≥ 0, got {v}")));
                    }
                }
                if !orientation_deg.is_finite() {
                    out.push((
                        "orientation_deg".to_owned(),
                        "must be a finite angle".to_owned(),
                    ));
                }
            }
            Finish::Facets {
                size_along,
                size_around,
            } => {
                positive(&mut out, "size_along", *size_along);
                positive(&mut out, "size_around", *size_around);
            }
            Finish::HeightMap { .. } => {}
        }
        if let Finish::HeightMap {
            pixel_size,
            height_step,
            heights,
            ..
        } = self
        {
            positive(&mut out, "pixel_size", *pixel_size);
            positive(&mut out, "height_step", *height_step);
            if heights.is_none() {
                out.push(("path".to_owned(), "the height map is not read".to_owned()));
            }
        }
        if out.is_empty() {
            let rms = self.mean_square_slope().sqrt();
            if rms > MAX_RMS_SLOPE {
                out.push((
                    match self {
                        Finish::Dimples { .. } => "depth",
                        Finish::Ripples { .. } => "waves",
                        Finish::Slopes { .. } => "sigma_u",
                        Finish::HeightMap { .. } => "height_step",
                        Finish::Facets { .. } => "size_along",
                    }
                    .to_owned(),
                    format!(
                        "the finish's rms slope is {rms:.3}, above {MAX_RMS_SLOPE}: its facets would face away from the light"
                    ),
                ));
            }
        }
        out
    }

    /// The mean of |slope|² in closed form (what [`Finish::statistics`]
    /// integrates, at no cost: validation checks it on every edit): a
    /// cap's ∫|∇h|² over its cell, each wave's own (a sine's (ka)²/2, a
    /// trochoid's 1 − √(1 − (ka)²), the paper's appendix), Gaussian σ².
    pub fn mean_square_slope(&self) -> f64 {
        match self {
            Finish::Dimples {
                pitch,
                depth,
                radius,
                pattern,
            } => {
                let r = dimple_rim(*radius, *depth, *pitch);
                let big = radius * radius;
                // 2π ∫₀^r ρ³/(R² − ρ²) dρ over the cell's area.
                let integral = std::f64::consts::TAU
                    * (-0.5 * r * r - 0.5 * big * (1.0 - r * r / big).max(1e-300).ln());
                let cell = PatternCell::of(*pitch, *pattern);
                integral * cell.centres.len() as f64 / (cell.width * cell.height)
            }
            Finish::Ripples { waves } => waves
                .iter()
                .map(|w| {
                    let kh = w.slope_amplitude();
                    match w.shape {
                        WaveShape::Sine => 0.5 * kh * kh,
                        WaveShape::Trochoid => 1.0 - (1.0 - kh * kh).max(0.0).sqrt(),
                    }
                })
                .sum(),
            Finish::Slopes {
                sigma_u, sigma_v, ..
            } => sigma_u * sigma_u + sigma_v * sigma_v,
            // On a plane; a curved part's own is its layout's.
            Finish::Facets { .. } => 0.0,
            Finish::HeightMap { .. } => {
                let (mut sum, mut n) = (0.0, 0usize);
                self.for_each_map_slope(|s| {
                    sum += s[0] * s[0] + s[1] * s[1];
                    n += 1;
                });
                if n > 0 { sum / n as f64 } else { 0.0 }
            }
        }
    }

    /// Each pixel's slope of a height map (central differences, the map
    /// repeating); nothing for any other finish or an unread map.
    fn for_each_map_slope(&self, mut each: impl FnMut([f64; 2])) {
        let Finish::HeightMap {
            pixel_size,
            height_step,
            heights: Some(grid),
            ..
        } = self
        else {
            return;
        };
        let k = height_step / (2.0 * pixel_size);
        for j in 0..grid.height as isize {
            for i in 0..grid.width as isize {
                each([
                    k * (grid.at(i + 1, j) - grid.at(i - 1, j)),
                    k * (grid.at(i, j + 1) - grid.at(i, j - 1)),
                ]);
            }
        }
    }

    /// The finish's slope distribution, from its geometry: dimples
    /// integrated numerically over one cell of the pattern, waves over
    /// their phases, measured slopes as the Gaussian they state.
    pub fn statistics(&self) -> SlopeStatistics {
        match self {
            Finish::Dimples {
                pitch,
                depth,
                radius,
                pattern,
            } => dimple_statistics(*pitch, *depth, *radius, *pattern),
            Finish::Ripples { waves } => ripple_statistics(waves),
            Finish::Slopes {
                sigma_u,
                sigma_v,
                orientation_deg,
            } => gaussian_statistics(*sigma_u, *sigma_v, orientation_deg.to_radians()),
            // Flat facets on a plane are the plane (a curved part's are
            // its layout's, `FinishLayout::statistics`).
            Finish::Facets { .. } => statistics_of_samples(1e-9, [([0.0, 0.0], 1.0)]),
            Finish::HeightMap { .. } => {
                let mut steepest: f64 = 0.0;
                self.for_each_map_slope(|s| steepest = steepest.max(s[0].abs()).max(s[1].abs()));
                let mut slopes = Vec::new();
                self.for_each_map_slope(|s| slopes.push((s, 1.0)));
                statistics_of_samples(steepest.max(1e-9) * 1.0001, slopes)
            }
        }
    }
}

impl Finish {
    /// The finish in a toolmaker's words and millimetres, for a drawing
    /// or a CAD product's description.
    pub fn describe(&self) -> String {
        let mm = |m: f64| format!("{:.3} mm", m * 1e3);
        match self {
            Finish::Dimples {
                pitch,
                depth,
                radius,
                pattern,
            } => format!(
                "hammered: spherical dimples {} deep, punch radius {}, on a {} pattern of {} pitch",
                mm(*depth),
                mm(*radius),
                match pattern {
                    DimplePattern::Hexagonal => "hexagonal",
                    DimplePattern::Square => "square",
                },
                mm(*pitch)
            ),
            Finish::Ripples { waves } => {
                let each: Vec<String> = waves
                    .iter()
                    .map(|w| {
                        format!(
                            "{} amplitude {} wavelength {} at {}° to the profile",
                            match w.shape {
                                WaveShape::Sine => "sine",
                                WaveShape::Trochoid => "trochoid",
                            },
                            mm(w.amplitude),
                            mm(w.wavelength),
                            w.direction_deg
                        )
                    })
                    .collect();
                format!("rippled: {}", each.join("; "))
            }
            Finish::Slopes {
                sigma_u,
                sigma_v,
                orientation_deg,
            } => format!(
                "measured slopes: rms {sigma_u:.4} along, {sigma_v:.4} across, turned {orientation_deg}°"
            ),
            Finish::Facets {
                size_along,
                size_around,
            } => format!(
                "faceted: flat facets {} along the profile by {} around",
                mm(*size_along),
                mm(*size_around)
            ),
            Finish::HeightMap {
                path,
                pixel_size,
                height_step,
                ..
            } => format!(
                "measured height map {path}: pixels {}, {} per grey level",
                mm(*pixel_size),
                format_args!("{:.6} mm", height_step * 1e3)
            ),
        }
    }
}

impl Finish {
    /// The finish's height (m) at (u, v) on the surface (u along the
    /// profile, v across it), about its mean plane: what the geometry of
    /// the finish is, for tessellating it and for checking its
    /// statistics. Waves start at phase 0; a measured Gaussian finish has
    /// no one geometry (None).
    pub fn height(&self, u: f64, v: f64) -> Option<f64> {
        match self {
            Finish::Dimples {
                pitch,
                depth,
                radius,
                pattern,
            } => {
                let r = dimple_rim(*radius, *depth, *pitch);
                let d = PatternCell::of(*pitch, *pattern).offset(u, v);
                let rho = d[0].hypot(d[1]);
                Some(if rho < r {
                    -((radius * radius - rho * rho).sqrt() - (radius - depth))
                } else {
                    0.0
                })
            }
            Finish::Ripples { waves } => Some(
                waves
                    .iter()
                    .map(|w| {
                        let dir = w.direction_deg.to_radians();
                        let x = u * dir.cos() + v * dir.sin();
                        let k = 2.0 * std::f64::consts::PI / w.wavelength;
                        match w.shape {
                            WaveShape::Sine => w.amplitude * (k * x).sin(),
                            WaveShape::Trochoid => {
                                // x = s − a·sin(ks), h = a·cos(ks): s by
                                // Newton from x (x − s is at most a).
                                let mut s = x;
                                for _ in 0..30 {
                                    let f = s - w.amplitude * (k * s).sin() - x;
                                    let df = 1.0 - w.amplitude * k * (k * s).cos();
                                    s -= f / df;
                                }
                                w.amplitude * (k * s).cos()
                            }
                        }
                    })
                    .sum(),
            ),
            Finish::Slopes { .. } => None,
            Finish::Facets { .. } => Some(0.0),
            Finish::HeightMap {
                pixel_size,
                height_step,
                heights,
                ..
            } => {
                // Bilinear between pixel centres, the map repeating.
                let grid = heights.as_ref()?;
                let (x, y) = (u / pixel_size, v / pixel_size);
                let (i, j) = (x.floor(), y.floor());
                let (fx, fy) = (x - i, y - j);
                let (i, j) = (i as isize, j as isize);
                let level = grid.at(i, j) * (1.0 - fx) * (1.0 - fy)
                    + grid.at(i + 1, j) * fx * (1.0 - fy)
                    + grid.at(i, j + 1) * (1.0 - fx) * fy
                    + grid.at(i + 1, j + 1) * fx * fy;
                Some(level * height_step)
            }
        }
    }
}

/// The radius of a cap of a sphere of `radius`, `depth` deep, on the
/// surface.
pub fn dimple_footprint(radius: f64, depth: f64) -> f64 {
    (2.0 * radius * depth - depth * depth).max(0.0).sqrt()
}

/// A dimple's rim as a pattern of `pitch` holds it: its footprint, at
/// most half the pitch (validation refuses more; a finish built in code
/// may not be validated).
pub fn dimple_rim(radius: f64, depth: f64, pitch: f64) -> f64 {
    dimple_footprint(radius, depth).min(0.5 * pitch)
}

/// One rectangular period of a dimple pattern: p × p holding one dimple
/// (square), p × √3·p holding two (hexagonal).
struct PatternCell {
    width: f64,
    height: f64,
    centres: Vec<[f64; 2]>,
}

impl PatternCell {
    fn of(pitch: f64, pattern: DimplePattern) -> PatternCell {
        match pattern {
            DimplePattern::Square => PatternCell {
                width: pitch,
                height: pitch,
                centres: vec![[0.0, 0.0]],
            },
            DimplePattern::Hexagonal => {
                let h = 3f64.sqrt() * pitch;
                PatternCell {
                    width: pitch,
                    height: h,
                    centres: vec![[0.0, 0.0], [0.5 * pitch, 0.5 * h]],
                }
            }
        }
    }

    /// (u, v) less the nearest dimple centre, the pattern's periodic
    /// images included.
    fn offset(&self, u: f64, v: f64) -> [f64; 2] {
        let (w, h) = (self.width, self.height);
        let (x, y) = (u.rem_euclid(w), v.rem_euclid(h));
        let mut best = (f64::INFINITY, [0.0, 0.0]);
        for c in &self.centres {
            for dy in [-h, 0.0, h] {
                for dx in [-w, 0.0, w] {
                    let d = [x - c[0] - dx, y - c[1] - dy];
                    let rho = d[0].hypot(d[1]);
                    if rho < best.0 {
                        best = (rho, d);
                    }
                }
            }
        }
        best.1
    }
}

/// Samples per cell axis of the dimples' numeric integral.
const DIMPLE_SAMPLES: usize = 600;

fn dimple_statistics(
    pitch: f64,
    depth: f64,
    radius: f64,
    pattern: DimplePattern,
) -> SlopeStatistics {
    let r = dimple_rim(radius, depth, pitch);
    let steepest = r / (radius * radius - r * r).max(1e-300).sqrt();
    let mut acc = Accumulator::new(steepest.max(1e-9) * 1.0001);
    let cell = PatternCell::of(pitch, pattern);
    let (w, h) = (cell.width, cell.height);
    let ny = ((DIMPLE_SAMPLES as f64) * h / w).round() as usize;
    for j in 0..ny {
        let y = (j as f64 + 0.5) / ny as f64 * h;
        for i in 0..DIMPLE_SAMPLES {
            let x = (i as f64 + 0.5) / DIMPLE_SAMPLES as f64 * w;
            let d = cell.offset(x, y);
            let rho = d[0].hypot(d[1]);
            let slope = if rho < r {
                // h = −(√(R² − ρ²) − (R − depth)): ∂h/∂ρ = ρ/√(R² − ρ²).
                let g = 1.0 / (radius * radius - rho * rho).sqrt();
                [d[0] * g, d[1] * g]
            } else {
                [0.0, 0.0]
            };
            acc.add(slope, 1.0);
        }
    }
    acc.finish()
}

/// Phase samples of the wave sums (a Kronecker sequence over the
/// waves' phases: independent phases, as waves of unrelated wavelengths
/// have over a surface).
const RIPPLE_SAMPLES: usize = 1 << 18;

fn ripple_statistics(waves: &[Ripple]) -> SlopeStatistics {
    let slope_of = |w: &Ripple, phase: f64| -> (f64, f64) {
        // (slope along the wave, weight of this phase in surface length)
        let kh = w.slope_amplitude();
        match w.shape {
            WaveShape::Sine => (kh * phase.cos(), 1.0),
            WaveShape::Trochoid => {
                // x = s − a·sin(ks), h = a·cos(ks): dh/dx = −kh·sin / (1 − kh·cos),
                // dx/ds = 1 − kh·cos weighting the phases by surface length.
                let dxds = 1.0 - kh * phase.cos();
                (-kh * phase.sin() / dxds, dxds)
            }
        }
    };
    let steepest: f64 = waves
        .iter()
        .map(|w| {
            let kh = w.slope_amplitude();
            match w.shape {
                WaveShape::Sine => kh,
                WaveShape::Trochoid => kh / (1.0 - kh * kh).max(1e-12).sqrt(),
            }
        })
        .sum();
    let mut acc = Accumulator::new(steepest.max(1e-9) * 1.0001);
    // Irrational steps (the square roots of primes), one per wave.
    const STEPS: [f64; 8] = [
        0.414_213_562_373_095_1,
        0.732_050_807_568_877_2,
        0.236_067_977_499_789_7,
        0.645_751_311_064_590_6,
        0.316_624_790_355_399_8,
        0.605_551_275_463_989_3,
        0.123_105_625_617_660_5,
        0.358_898_943_540_673_5,
    ];
    for j in 0..RIPPLE_SAMPLES {
        let mut s = [0.0, 0.0];
        let mut weight = 1.0;
        for (i, w) in waves.iter().enumerate() {
            let t = if i == 0 {
                (j as f64 + 0.5) / RIPPLE_SAMPLES as f64
            } else {
                (0.5 + j as f64 * STEPS[(i - 1) % STEPS.len()] + i as f64 * 0.1).fract()
            };
            let (slope, wt) = slope_of(w, std::f64::consts::TAU * t);
            let dir = w.direction_deg.to_radians();
            s[0] += slope * dir.cos();
            s[1] += slope * dir.sin();
            weight *= wt;
        }
        acc.add(s, weight);
    }
    acc.finish()
}

fn gaussian_statistics(sigma_u: f64, sigma_v: f64, angle: f64) -> SlopeStatistics {
    let (c, s) = (angle.cos(), angle.sin());
    let (a, b) = (sigma_u * sigma_u, sigma_v * sigma_v);
    let covariance = [
        c * c * a + s * s * b,
        c * s * (a - b),
        s * s * a + c * c * b,
    ];
    let range = 5.0 * sigma_u.max(sigma_v).max(1e-9);
    let mut table = SlopeTable::new(range);
    // The density integrated by the midpoint rule over each cell,
    // normalised over the table (the 5σ tails left out).
    let det = (covariance[0] * covariance[2] - covariance[1] * covariance[1]).max(1e-300);
    let n = table.bins;
    let mut total = 0.0;
    for j in 0..n {
        for i in 0..n {
            let (x, y) = (table.centre(i), table.centre(j));
            let q =
                (covariance[2] * x * x - 2.0 * covariance[1] * x * y + covariance[0] * y * y) / det;
            let p = (-0.5 * q).exp();
            table.probability[j * n + i] = p;
            total += p;
        }
    }
    if total > 0.0 {
        for p in &mut table.probability {
            *p /= total;
        }
    }
    SlopeStatistics {
        mean: [0.0, 0.0],
        covariance,
        flat_share: 0.0,
        table,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_sinusoids_slopes_have_its_closed_form_variance_and_the_arcsine_law() {
        let (a, lambda) = (0.02e-3, 1e-3);
        let f = Finish::Ripples {
            waves: vec![Ripple {
                amplitude: a,
                wavelength: lambda,
                direction_deg: 0.0,
                shape: WaveShape::Sine,
            }],
        };
        let s = f.statistics();
        let amp = 2.0 * std::f64::consts::PI * a / lambda;
        let want = amp * amp / 2.0;
        assert!(
            (s.covariance[0] / want - 1.0).abs() < 1e-4,
            "{:?}",
            s.covariance
        );
        assert!(s.covariance[2].abs() < 1e-12 && s.flat_share == 0.0);
        // The arcsine law: P(s ≤ x) = 1/2 + asin(x/A)/π, cell by cell.
        let m = s.table.marginal_u();
        let width = 2.0 * s.table.range / s.table.bins as f64;
        let cdf = |x: f64| 0.5 + (x / amp).clamp(-1.0, 1.0).asin() / std::f64::consts::PI;
        for (i, p) in m.iter().enumerate() {
            let lo = s.table.centre(i) - 0.5 * width;
            let want = cdf(lo + width) - cdf(lo);
            assert!((p - want).abs() < 2e-3, "cell {i}: {p} against {want}");
        }
    }

    #[test]
    fn a_trochoids_variance_is_the_papers_appendix_formula() {
        let (a, lambda) = (0.1e-3, 1e-3);
        let f = Finish::Ripples {
            waves: vec![Ripple {
                amplitude: a,
                wavelength: lambda,
                direction_deg: 90.0,
                shape: WaveShape::Trochoid,
            }],
        };
        let s = f.statistics();
        let kh: f64 = 2.0 * std::f64::consts::PI * a / lambda;
        let want = 1.0 - (1.0 - kh * kh).sqrt();
        // Along v (90°): all of it.
        assert!(
            (s.covariance[2] / want - 1.0).abs() < 1e-3,
            "{} vs {want}",
            s.covariance[2]
        );
        assert!(s.covariance[0].abs() < 1e-9 * want);
    }

    #[test]
    fn the_closed_form_mean_square_slope_is_the_statistics() {
        let finishes = [
            Finish::Dimples {
                pitch: 2e-3,
                depth: 0.15e-3,
                radius: 3.4e-3,
                pattern: DimplePattern::Hexagonal,
            },
            Finish::Dimples {
                pitch: 3e-3,
                depth: 0.4e-3,
                radius: 1.5e-3,
                pattern: DimplePattern::Square,
            },
            Finish::Ripples {
                waves: vec![
                    Ripple {
                        amplitude: 0.02e-3,
                        wavelength: 1e-3,
                        direction_deg: 20.0,
                        shape: WaveShape::Sine,
                    },
                    Ripple {
                        amplitude: 0.05e-3,
                        wavelength: 1.3e-3,
                        direction_deg: 100.0,
                        shape: WaveShape::Trochoid,
                    },
                ],
            },
            Finish::Slopes {
                sigma_u: 0.1,
                sigma_v: 0.05,
                orientation_deg: 30.0,
            },
        ];
        for f in finishes {
            let c = f.statistics().covariance;
            let numeric = c[0] + c[2];
            let closed = f.mean_square_slope();
            assert!(
                (closed / numeric - 1.0).abs() < 0.01,
                "{f:?}: {closed} vs {numeric}"
            );
        }
    }

    #[test]
    fn dimples_match_their_integral_and_leave_their_land_flat() {
        let (pitch, depth, radius) = (2e-3, 0.15e-3, 3.4e-3);
        for pattern in [DimplePattern::Hexagonal, DimplePattern::Square] {
            let s = Finish::Dimples {
                pitch,
                depth,
                radius,
                pattern,
            }
            .statistics();
            let r = dimple_footprint(radius, depth);
            let cell = match pattern {
                DimplePattern::Hexagonal => 3f64.sqrt() / 2.0 * pitch * pitch,
                DimplePattern::Square => pitch * pitch,
            };
            let dimpled = std::f64::consts::PI * r * r / cell;
            assert!(
                (s.flat_share - (1.0 - dimpled)).abs() < 2e-3,
                "{pattern:?}: {}",
                s.flat_share
            );
            // E|s|² = (π/cell)(R² ln(R²/(R² − r²)) − r²), half per axis.
            let (r2, big) = (r * r, radius * radius);
            let want = std::f64::consts::PI / cell * (big * (big / (big - r2)).ln() - r2) / 2.0;
            for v in [s.covariance[0], s.covariance[2]] {
                assert!((v / want - 1.0).abs() < 5e-3, "{pattern:?}: {v} vs {want}");
            }
            assert!(s.covariance[1].abs() < 1e-3 * want);
        }
    }

    #[test]
    fn measured_slopes_are_the_gaussian_they_state_turned() {
        let s = Finish::Slopes {
            sigma_u: 0.02,
            sigma_v: 0.01,
            orientation_deg: 90.0,
        }
        .statistics();
        assert!((s.covariance[0] - 1e-4).abs() < 1e-12);
        assert!((s.covariance[2] - 4e-4).abs() < 1e-12);
        let total: f64 = s.table.probability.iter().sum();
        assert!((total - 1.0).abs() < 1e-9);
    }

    #[test]
    fn impossible_finishes_are_refused_naming_the_field() {
        let field = |f: Finish| f.problems().into_iter().map(|p| p.0).collect::<Vec<_>>();
        let dimples = |pitch: f64, depth: f64, radius: f64| Finish::Dimples {
            pitch,
            depth,
            radius,
            pattern: DimplePattern::Hexagonal,
        };
        assert!(field(dimples(2e-3, 0.15e-3, 3.4e-3)).is_empty());
        assert_eq!(field(dimples(1e-3, 0.15e-3, 3.4e-3)), ["pitch"]);
        assert_eq!(field(dimples(2e-3, 0.5e-3, 0.4e-3)), ["depth"]);
        assert_eq!(field(dimples(2e-3, f64::NAN, 3.4e-3)), ["depth"]);
        let wave = |amplitude: f64, shape: WaveShape| Finish::Ripples {
            waves: vec![Ripple {
                amplitude,
                wavelength: 1e-3,
                direction_deg: 0.0,
                shape,
            }],
        };
        assert_eq!(field(wave(-1e-5, WaveShape::Sine)), ["waves[0].amplitude"]);
        assert_eq!(
            field(wave(0.2e-3, WaveShape::Trochoid)),
            ["waves[0].amplitude"]
        );
        // A sine of slope amplitude 2π·0.3 = 1.9: rms 1.33 > 1.
        assert_eq!(field(wave(0.3e-3, WaveShape::Sine)), ["waves"]);
        let slopes = Finish::Slopes {
            sigma_u: 1.2,
            sigma_v: 0.1,
            orientation_deg: 0.0,
        };
        let p = slopes.problems();
        assert!(p[0].1.contains("above 1"), "{p:?}");
    }

    /// The slopes of the height function, by central differences over a
    /// patch of the surface, have the statistics computed from the
    /// finish's parameters: the two descriptions are one finish.
    #[test]
    fn the_height_field_has_the_statistics_of_its_finish() {
        let finishes = [
            Finish::Dimples {
                pitch: 2e-3,
                depth: 0.15e-3,
                radius: 3.4e-3,
                pattern: DimplePattern::Hexagonal,
            },
            Finish::Dimples {
                pitch: 2.5e-3,
                depth: 0.1e-3,
                radius: 2e-3,
                pattern: DimplePattern::Square,
            },
            Finish::Ripples {
                waves: vec![Ripple {
                    amplitude: 0.05e-3,
                    wavelength: 1e-3,
                    direction_deg: 0.0,
                    shape: WaveShape::Trochoid,
                }],
            },
        ];
        for f in &finishes {
            let want = f.statistics();
            // A patch of whole periods of the pattern.
            let (w, h) = match f {
                Finish::Dimples {
                    pitch,
                    pattern: DimplePattern::Hexagonal,
                    ..
                } => (3.0 * pitch, 2.0 * 3f64.sqrt() * pitch),
                Finish::Dimples { pitch, .. } => (3.0 * pitch, 3.0 * pitch),
                _ => (6e-3, 6e-3),
            };
            let (nu, nv) = (1200, (1200.0 * h / w) as usize);
            let e = 1e-7;
            let (mut suu, mut svv, mut flat) = (0.0, 0.0, 0usize);
            for j in 0..nv {
                for i in 0..nu {
                    let (u, v) = (
                        (i as f64 + 0.5) / nu as f64 * w,
                        (j as f64 + 0.5) / nv as f64 * h,
                    );
                    let hu =
                        (f.height(u + e, v).unwrap() - f.height(u - e, v).unwrap()) / (2.0 * e);
                    let hv =
                        (f.height(u, v + e).unwrap() - f.height(u, v - e).unwrap()) / (2.0 * e);
                    suu += hu * hu;
                    svv += hv * hv;
                    if hu.hypot(hv) < 1e-9 {
                        flat += 1;
                    }
                }
            }
            let n = (nu * nv) as f64;
            let got = [suu / n, svv / n];
            let total = want.covariance[0] + want.covariance[2];
            assert!(
                ((got[0] + got[1]) / total - 1.0).abs() < 0.02,
                "{f:?}: {got:?} against {:?}",
                want.covariance
            );
            assert!(
                (flat as f64 / n - want.flat_share).abs() < 0.01,
                "{f:?}: flat {}",
                flat as f64 / n
            );
        }
    }

    #[test]
    fn a_height_maps_slopes_are_those_of_the_surface_it_samples() {
        // A 16-bit map of a sine along its rows, 64 pixels a wavelength:
        // its slopes are the sine's (the central difference's
        // sin(kΔ)/(kΔ) is 0.998 here), and it is the height it says.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("sine.png");
        let (n, wavelength_px) = (128u32, 64.0);
        let map = image::ImageBuffer::from_fn(n, n / 2, |x, _| {
            let phase = std::f64::consts::TAU * f64::from(x) / wavelength_px;
            image::Luma([(30_000.0 + 20_000.0 * phase.sin()).round() as u16])
        });
        map.save(&path).unwrap();
        let read = |p: &std::path::Path| {
            HeightGrid::from_png(&std::fs::read(p).unwrap(), &p.display().to_string())
        };
        let grid = read(&path).unwrap();
        assert_eq!((grid.width, grid.height), (128, 64));
        let (pixel, step) = (10e-6, 1e-9);
        let f = Finish::HeightMap {
            path: "sine.png".into(),
            pixel_size: pixel,
            height_step: step,
            heights: Some(std::sync::Arc::new(grid)),
        };
        assert!(f.problems().is_empty(), "{:?}", f.problems());
        let amplitude = 20_000.0 * step;
        let k = std::f64::consts::TAU / (wavelength_px * pixel);
        let discrete = ((k * pixel).sin() / (k * pixel)).powi(2);
        let want = 0.5 * (k * amplitude).powi(2) * discrete;
        let s = f.statistics();
        assert!(
            (s.covariance[0] / want - 1.0).abs() < 0.01,
            "{:?} vs {want}",
            s.covariance
        );
        assert!(s.covariance[2] < 1e-6 * want);
        assert!((f.mean_square_slope() / want - 1.0).abs() < 0.01);
        // Heights in metres at pixel centres; between them, bilinear.
        let h = f.height(16.0 * pixel, 0.0).unwrap();
        assert!((h - 50_000.0 * step).abs() < 0.5 * step, "{h}");
        // An unreadable file says why.
        std::fs::write(dir.path().join("bad.png"), b"not a png").unwrap();
        let e = read(&dir.path().join("bad.png")).unwrap_err();
        assert!(e.contains("not a PNG height map"), "{e}");
        let tiny = image::ImageBuffer::from_fn(2, 2, |_, _| image::Luma([0u16]));
        tiny.save(dir.path().join("tiny.png")).unwrap();
        let e = read(&dir.path().join("tiny.png")).unwrap_err();
        assert!(e.contains("at least 3 × 3"), "{e}");
    }
}
