//! A fast model of a revolved mirror around a small source on its axis:
//! rays traced in the meridian plane only, from points across the
//! source's diameter, each reflected ray's deposit spread sideways by the
//! source's angular size seen from its last reflection (the skew rays a
//! meridian trace leaves out). For a point source on the axis every ray
//! is meridional and the model is exact; for a source a few millimetres
//! across it is close enough to find the basin the photon tracer then
//! refines: thousands of candidates a second, where the tracer does tens.

use glam::DVec2;
use lucerna_photometry::resample::gamma_cell_edges;
use lucerna_scene::Interpolation;
use lucerna_scene::profile::{ProfileSample, sample_profile};

/// γ bins of the model's intensity (degrees): coarser than the merit's
/// grid, so each holds enough deposits near a narrow beam's peak.
pub const BIN_DEG: f64 = 0.25;

/// The cap about the axis whose mean intensity its bins take (degrees).
const AXIS_CAP_DEG: f64 = 0.75;

/// Rays across the source's angles, points across its diameter, and
/// sideways deposits per reflected ray.
const ANGLES: usize = 768;
const SOURCE_POINTS: usize = 8;
const SIDEWAYS: usize = 6;
/// The longest step of a table cell's mean.
const CELL_STEP_DEG: f64 = 0.025;
/// The golden ratio's fractional part, for the sideways points' shifts.
const GOLDEN: f64 = 0.618_033_988_749_895;
/// Reflections followed before a ray is dropped.
const MAX_BOUNCES: usize = 8;

/// What the model knows of the luminaire.
#[derive(Debug, Clone, PartialEq)]
pub struct MeridianModel {
    /// The source's height on the axis (m) and radius (m).
    pub source_z: f64,
    pub source_radius: f64,
    /// Whether the source emits towards −z.
    pub facing_down: bool,
    /// The mirror's specular reflectance.
    pub reflectance: f64,
    pub interpolation: Interpolation,
    pub segments_per_span: u32,
    /// The γ angles (degrees) of the table the light is compared with:
    /// the model tabulates on them as a bake does (each cell the mean of
    /// its solid angle) and interpolates between them as the table does,
    /// so its light and the target's differ by the light, not by the
    /// grid (a coarse cell averages out the model's ray-sampling
    /// ripple). Empty: the model's own bins.
    pub gammas_deg: Vec<f64>,
}

impl MeridianModel {
    /// The relative intensity against γ of the luminaire whose mirror has
    /// `profile` (r, z control points), on `step_deg` steps from 0° to
    /// 180° (linear between the model's bins); None where the profile
    /// cannot be sampled.
    pub fn intensity(&self, profile: &[[f64; 2]], step_deg: f64) -> Option<Vec<f64>> {
        let bins = self.bins(profile)?;
        let n = (180.0 / step_deg).round() as usize;
        if self.gammas_deg.len() < 2 {
            return Some((0..=n).map(|k| bins.at(k as f64 * step_deg)).collect());
        }
        let cells = self.cells(&bins);
        let g = &self.gammas_deg;
        Some(
            (0..=n)
                .map(|k| {
                    let gamma = k as f64 * step_deg;
                    if gamma < g[0] || gamma > g[g.len() - 1] {
                        return 0.0;
                    }
                    let j = g.partition_point(|&x| x <= gamma).clamp(1, g.len() - 1);
                    let t = (gamma - g[j - 1]) / (g[j] - g[j - 1]);
                    cells[j - 1] * (1.0 - t) + cells[j] * t
                })
                .collect(),
        )
    }

    /// The relative intensity at each of [`MeridianModel::gammas_deg`],
    /// each the mean of its cell's solid angle, as a bake tabulates it.
    pub fn at_nodes(&self, profile: &[[f64; 2]]) -> Option<Vec<f64>> {
        if self.gammas_deg.len() < 2 {
            return None;
        }
        Some(self.cells(&self.bins(profile)?))
    }

    /// Each γ cell's mean over its solid angle (midpoints at most
    /// CELL_STEP_DEG apart).
    fn cells(&self, bins: &Bins) -> Vec<f64> {
        gamma_cell_edges(&self.gammas_deg)
            .windows(2)
            .map(|e| {
                let parts = ((e[1] - e[0]) / CELL_STEP_DEG).ceil().max(1.0) as usize;
                let h = (e[1] - e[0]) / parts as f64;
                let (mut sum, mut weight) = (0.0, 0.0);
                for m in 0..parts {
                    let gamma = e[0] + (m as f64 + 0.5) * h;
                    let w = gamma.to_radians().sin();
                    sum += w * bins.at(gamma);
                    weight += w;
                }
                if weight > 0.0 {
                    sum / weight
                } else {
                    bins.at(0.5 * (e[0] + e[1]))
                }
            })
            .collect()
    }

    /// The model's own bins of intensity.
    fn bins(&self, profile: &[[f64; 2]]) -> Option<Bins> {
        if profile.len() < 2 {
            return None;
        }
        let mirror = self.mirror(profile);
        let bins = (180.0 / BIN_DEG).round() as usize;
        let mut flux = vec![0.0; bins + 1];
        let deposit = |flux: &mut Vec<f64>, gamma_deg: f64, w: f64| {
            let x = (gamma_deg / BIN_DEG).clamp(0.0, bins as f64);
            let i = (x.floor() as usize).min(bins - 1);
            let f = x - i as f64;
            flux[i] += w * (1.0 - f);
            flux[i + 1] += w * f;
        };
        let down = if self.facing_down { -1.0 } else { 1.0 };
        for k in 0..SOURCE_POINTS {
            let u = 2.0 * (k as f64 + 0.5) / SOURCE_POINTS as f64 - 1.0;
            let chord = (1.0 - u * u).sqrt();
            let origin = DVec2::new(u * self.source_radius, self.source_z);
            for j in 0..ANGLES {
                let theta = std::f64::consts::PI * ((j as f64 + 0.5) / ANGLES as f64 - 0.5);
                // Lambertian (cos θ), around the axis (|sin θ|), both
                // halves of the meridian.
                let w0 = chord * theta.cos() * theta.sin().abs();
                let mut p = origin;
                let mut d = DVec2::new(theta.sin(), down * theta.cos());
                let mut w = w0;
                let mut last_hit: Option<(usize, DVec2)> = None;
                let mut bounces = 0;
                loop {
                    let hit = mirror.nearest_hit(p, d, last_hit.map(|h| h.0));
                    match hit {
                        Some((s, t, along)) if bounces < MAX_BOUNCES => {
                            let q = p + t * d;
                            let n = mirror.normal(s, along);
                            d = d - 2.0 * d.dot(n) * n;
                            w *= self.reflectance;
                            p = q;
                            last_hit = Some((s, q));
                            bounces += 1;
                        }
                        Some(_) => break,
                        None => {
                            // γ from nadir in the meridian plane.
                            let gamma0 = d.x.abs().atan2(-d.y);
                            match last_hit {
                                None => deposit(&mut flux, gamma0.to_degrees(), w),
                                Some((_, q)) => {
                                    // Sideways: the source's chord across
                                    // the meridian at this point of its
                                    // diameter, seen from the last
                                    // reflection (the disk, not a square:
                                    // the sideways reach shrinks towards
                                    // the diameter's ends).
                                    let beta = chord * self.source_radius
                                        / (q - origin).length().max(1e-9);
                                    // Each ray's sideways points
                                    // shifted by its own share of a
                                    // step (a golden-ratio sequence):
                                    // the same points for every ray
                                    // would pile collimated light on
                                    // rings near the axis.
                                    let shift = ((k * ANGLES + j) as f64 * GOLDEN).fract();
                                    for m in 0..SIDEWAYS {
                                        let v = 2.0 * (m as f64 + shift) / SIDEWAYS as f64 - 1.0;
                                        let s = v * beta;
                                        let g = (gamma0.cos() * s.cos()).clamp(-1.0, 1.0).acos();
                                        deposit(&mut flux, g.to_degrees(), w / SIDEWAYS as f64);
                                    }
                                }
                            }
                            break;
                        }
                    }
                }
            }
        }
        // Flux per bin → intensity: the solid angle of the bin's tent
        // (the linear deposit's weight), 2π ∫ tent(γ) sin γ dγ.
        let h = BIN_DEG.to_radians();
        let omega: Vec<f64> = (0..=bins)
            .map(|i| 2.0 * std::f64::consts::PI * tent_sine_integral(i as f64 * h, h))
            .collect();
        let mut intensity: Vec<f64> = (0..=bins)
            .map(|i| {
                if omega[i] > 0.0 {
                    flux[i] / omega[i]
                } else {
                    0.0
                }
            })
            .collect();
        // Near the axis a bin's solid angle is too small for the rays to
        // fill it evenly: the cap's mean there.
        let cap = (AXIS_CAP_DEG / BIN_DEG).round() as usize;
        let mean = flux[..=cap].iter().sum::<f64>() / omega[..=cap].iter().sum::<f64>();
        for v in &mut intensity[..cap] {
            *v = mean;
        }
        Some(Bins { intensity })
    }
}

/// The model's intensity on its own [`BIN_DEG`] bins.
struct Bins {
    intensity: Vec<f64>,
}

impl Bins {
    /// Linear between the bins.
    fn at(&self, gamma_deg: f64) -> f64 {
        let bins = self.intensity.len() - 1;
        let x = (gamma_deg / BIN_DEG).clamp(0.0, bins as f64);
        let i = (x.floor() as usize).min(bins - 1);
        let f = x - i as f64;
        self.intensity[i] * (1.0 - f) + self.intensity[i + 1] * f
    }
}

impl MeridianModel {
    /// The mirror of `profile` in both halves of the meridian: (r, z) and
    /// (−r, z), with the tangents the tessellation's shading normals come
    /// from.
    fn mirror(&self, profile: &[[f64; 2]]) -> Mirror {
        let strips = sample_profile(profile, self.interpolation, self.segments_per_span);
        let mirrored: Vec<Vec<ProfileSample>> = strips
            .iter()
            .map(|strip| {
                strip
                    .iter()
                    .map(|p| ProfileSample {
                        point: DVec2::new(-p.point.x, p.point.y),
                        tangent: DVec2::new(-p.tangent.x, p.tangent.y),
                    })
                    .collect()
            })
            .collect();
        let lines: Vec<&[ProfileSample]> = strips
            .iter()
            .chain(&mirrored)
            .map(|s| s.as_slice())
            .collect();
        Mirror::new(&lines)
    }

    /// Where each ray from the source's centre goes, for `count` source
    /// angles θ (from nadir, towards +r) between `from` and `to`: θ, the
    /// signed output angle from nadir (negative: across the axis) and the
    /// reflections on the way.
    pub fn mapping(
        &self,
        profile: &[[f64; 2]],
        from: f64,
        to: f64,
        count: usize,
    ) -> Vec<(f64, f64, usize)> {
        let mirror = self.mirror(profile);
        let down = if self.facing_down { -1.0 } else { 1.0 };
        (0..count)
            .map(|j| {
                let theta = from + (to - from) * (j as f64 + 0.5) / count as f64;
                let mut p = DVec2::new(0.0, self.source_z);
                let mut d = DVec2::new(theta.sin(), down * theta.cos());
                let mut skip = None;
                let mut bounces = 0;
                while let Some((s, t, along)) = mirror.nearest_hit(p, d, skip) {
                    if bounces >= MAX_BOUNCES {
                        break;
                    }
                    let n = mirror.normal(s, along);
                    p += t * d;
                    d = d - 2.0 * d.dot(n) * n;
                    skip = Some(s);
                    bounces += 1;
                }
                (theta, d.x.atan2(-d.y), bounces)
            })
            .collect()
    }
}

/// ∫ max(0, 1 − |γ − c|/h) sin γ dγ over γ ∈ [0, π].
fn tent_sine_integral(c: f64, h: f64) -> f64 {
    // The antiderivative of (γ − a) sin γ is sin γ − (γ − a) cos γ.
    let rising = |a: f64, lo: f64, hi: f64| {
        let f = |g: f64| g.sin() - (g - a) * g.cos();
        f(hi) - f(lo)
    };
    let (lo, hi) = ((c - h).max(0.0), (c + h).min(std::f64::consts::PI));
    let mut s = 0.0;
    if c > lo {
        // (γ − (c − h))/h on [lo, c]
        s += rising(c - h, lo, c) / h;
    }
    if hi > c {
        // ((c + h) − γ)/h on [c, hi] = −(γ − (c + h))/h
        s -= rising(c + h, c, hi) / h;
    }
    s
}

/// The mirror's segments in both halves of the meridian, with their
/// ends' normals (a hit's normal is interpolated between them, as the
/// tracer interpolates a triangle's shading normals), in runs of [`RUN`]
/// with their bounding boxes, so a ray tests a run's box before its
/// segments.
struct Mirror {
    segments: Vec<(DVec2, DVec2)>,
    normals: Vec<(DVec2, DVec2)>,
    /// (first segment, end, box min, box max).
    runs: Vec<(usize, usize, DVec2, DVec2)>,
}

const RUN: usize = 8;

impl Mirror {
    fn new(strips: &[&[ProfileSample]]) -> Mirror {
        let mut segments = Vec::new();
        let mut normals = Vec::new();
        let mut runs = Vec::new();
        let normal = |p: &ProfileSample| DVec2::new(-p.tangent.y, p.tangent.x);
        for strip in strips {
            let first = segments.len();
            for w in strip.windows(2) {
                if (w[1].point - w[0].point).length_squared() > 0.0 {
                    segments.push((w[0].point, w[1].point));
                    normals.push((normal(&w[0]), normal(&w[1])));
                }
            }
            let mut k = first;
            while k < segments.len() {
                let end = (k + RUN).min(segments.len());
                let (mut lo, mut hi) =
                    (DVec2::splat(f64::INFINITY), DVec2::splat(f64::NEG_INFINITY));
                for &(a, b) in &segments[k..end] {
                    lo = lo.min(a).min(b);
                    hi = hi.max(a).max(b);
                }
                runs.push((k, end, lo, hi));
                k = end;
            }
        }
        Mirror {
            segments,
            normals,
            runs,
        }
    }

    /// The shading normal of segment `i` at `along` (0 … 1) from its
    /// first end.
    fn normal(&self, i: usize, along: f64) -> DVec2 {
        let (a, b) = self.normals[i];
        (a + along * (b - a)).normalize_or(a)
    }

    /// The nearest segment the ray `p + t d` (t > 0) meets, but `skip`:
    /// the segment, t and where along it.
    fn nearest_hit(&self, p: DVec2, d: DVec2, skip: Option<usize>) -> Option<(usize, f64, f64)> {
        let inv = DVec2::new(1.0 / d.x, 1.0 / d.y);
        let mut best: Option<(usize, f64, f64)> = None;
        for &(first, end, lo, hi) in &self.runs {
            // Slab test of the run's box.
            let (t1, t2) = ((lo - p) * inv, (hi - p) * inv);
            let near = t1.min(t2).max_element();
            let far = t1.max(t2).min_element();
            if far < near.max(0.0) || best.is_some_and(|(_, bt, _)| near > bt) {
                continue;
            }
            for i in first..end {
                if Some(i) == skip {
                    continue;
                }
                let (a, b) = self.segments[i];
                let e = b - a;
                let denom = d.perp_dot(e);
                if denom.abs() < 1e-300 {
                    continue;
                }
                let ap = a - p;
                let t = ap.perp_dot(e) / denom;
                let s = ap.perp_dot(d) / denom;
                if t > 1e-12 && (0.0..=1.0).contains(&s) && best.is_none_or(|(_, bt, _)| t < bt) {
                    best = Some((i, t, s));
                }
            }
        }
        best
    }
}

/// The model and profiles the search's tests share: the revolved
/// reflector example's mirror and the straight cone between its ends.
#[cfg(test)]
pub(crate) mod fixtures {
    use super::MeridianModel;
    use lucerna_scene::Interpolation;

    pub const REVOLVED_REFLECTOR: [[f64; 2]; 5] = [
        [0.006, 0.0],
        [0.014, -0.008],
        [0.024, -0.021],
        [0.033, -0.039],
        [0.04, -0.06],
    ];
    pub const CONE: [[f64; 2]; 5] = [
        [0.006, 0.0],
        [0.0145, -0.015],
        [0.023, -0.03],
        [0.0315, -0.045],
        [0.04, -0.06],
    ];

    /// A disk LED at the origin facing down inside a Catmull-Rom mirror.
    pub fn model(source_radius: f64, reflectance: f64) -> MeridianModel {
        MeridianModel {
            source_z: 0.0,
            source_radius,
            facing_down: true,
            reflectance,
            interpolation: Interpolation::CatmullRom,
            segments_per_span: 16,
            gammas_deg: Vec::new(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A point source at the focus of a parabola z = r²/4f − f (opening
    /// downwards: z = f − r²/4f below it), drawn as control points on it.
    fn parabola(f: f64) -> Vec<[f64; 2]> {
        (0..9)
            .map(|i| {
                let r = 0.01 + 0.005 * f64::from(i);
                [r, f - r * r / (4.0 * f)]
            })
            .collect()
    }

    #[test]
    fn a_point_source_at_a_parabolas_focus_is_reflected_along_its_axis() {
        let model = MeridianModel {
            source_z: 0.0,
            source_radius: 1e-9,
            facing_down: true,
            reflectance: 0.9,
            interpolation: Interpolation::CatmullRom,
            segments_per_span: 64,
            gammas_deg: Vec::new(),
        };
        let f = 0.01;
        let profile = parabola(f);
        // θ over the inner spans (a Catmull-Rom end span bends to its
        // phantom end point), seen from the focus.
        let theta = |p: [f64; 2]| p[0].atan2(-p[1]);
        let (lo, hi) = (theta(profile[7]), theta(profile[1]));
        let mapping = model.mapping(&profile, lo, hi, 200);
        assert!(mapping.iter().all(|&(_, _, b)| b == 1));
        let worst = mapping.iter().map(|m| m.1.abs()).fold(0.0, f64::max);
        // The Catmull-Rom curve through points on the parabola is not the
        // parabola: within a few tenths of a degree.
        assert!(worst.to_degrees() < 0.3, "{}°", worst.to_degrees());
        // A straight cone sends them elsewhere (the test can fail).
        let cone = vec![profile[0], profile[8]];
        let m = model.mapping(&cone, lo, hi, 50);
        assert!(m.iter().any(|x| x.1.abs().to_degrees() > 5.0));
    }

    #[test]
    fn with_no_mirror_in_the_way_the_light_is_the_sources_lambertian() {
        // No mirror in the way (a tiny profile far above the source): the
        // model's intensity is the source's, I(γ) ∝ cos γ below, zero above.
        let model = MeridianModel {
            source_z: 0.0,
            source_radius: 0.001,
            facing_down: true,
            reflectance: 0.9,
            interpolation: Interpolation::CatmullRom,
            segments_per_span: 4,
            gammas_deg: Vec::new(),
        };
        let profile = [[0.1, 1.0], [0.1001, 1.0001], [0.1002, 1.0002]];
        let step = 0.5;
        let i = model.intensity(&profile, step).unwrap();
        let at = |g: f64| i[(g / step) as usize];
        for g in [10.0f64, 30.0, 50.0, 70.0] {
            let ratio = at(g) / at(0.0) / g.to_radians().cos();
            assert!((ratio - 1.0).abs() < 0.03, "γ {g}: {ratio}");
        }
        assert!(at(120.0) == 0.0);
    }

    #[test]
    fn on_a_tables_grid_each_angle_holds_its_cells_mean_over_solid_angle() {
        // The revolved reflector's light tabulated on an uneven grid
        // against the untabulated light averaged over each cell by a
        // finer quadrature (0.01° steps, weighted by sin γ).
        let mut model = fixtures::model(0.0015, 0.9);
        let profile = fixtures::REVOLVED_REFLECTOR;
        let fine_step = 0.01;
        let fine = model.intensity(&profile, fine_step).unwrap();
        let gammas = vec![0.0, 1.0, 2.5, 5.0, 10.0, 20.0, 40.0, 90.0, 180.0];
        model.gammas_deg = gammas.clone();
        let step = 0.1;
        let tabulated = model.intensity(&profile, step).unwrap();
        let edges = gamma_cell_edges(&gammas);
        for (i, &g) in gammas.iter().enumerate() {
            let (lo, hi) = (edges[i], edges[i + 1]);
            let (mut sum, mut weight) = (0.0, 0.0);
            let mut k = (lo / fine_step).round() as usize;
            while (k as f64) * fine_step < hi - 1e-9 {
                let gamma = (k as f64 + 0.5) * fine_step;
                let v = 0.5 * (fine[k] + fine[k + 1]);
                sum += v * gamma.to_radians().sin();
                weight += gamma.to_radians().sin();
                k += 1;
            }
            let mean = sum / weight;
            let got = tabulated[(g / step).round() as usize];
            assert!(
                (got - mean).abs() <= 0.01 * mean.abs().max(1e-3 * fine[0]),
                "γ {g}: {got} against the cell's mean {mean}"
            );
        }
        // Between the angles, linear as a table is read.
        let (a, b) = (tabulated[100], tabulated[200]);
        assert!((tabulated[150] - 0.5 * (a + b)).abs() < 1e-9 * a.abs().max(1.0));
    }
}
