//! A pressed part's form error: a smooth random deformation of its
//! profile along the profile's normal, a Gaussian process along the arc
//! length with squared-exponential covariance
//! σ²·exp(−Δs²/(2ℓ²)), so neighbouring points move together.
//!
//! The part's profile is its own (a revolved or extruded part) or the
//! spline a surface of revolution converts to (a paraboloid within 1 µm),
//! with each span subdivided until the points are at most ℓ/4 apart along
//! the arc: the process is resolved wherever it bends, and the spline
//! through the subdivided points is the nominal profile itself.

use lucerna_design::variables;
use lucerna_scene::profile::{Interpolation, sample_profile};
use lucerna_scene::shapes::{Revolved, editable_revolution};
use lucerna_scene::{Scene, Shape};
use nalgebra::{DMatrix, DVector};

use crate::tolerances::FormError;

/// The most points a deformed profile gets (a correlation length far
/// below the part's size is white noise at this spacing).
pub const MAX_POINTS: usize = 257;

/// How far a surface of revolution's spline may stray from it (m).
const CONVERSION_TOLERANCE_M: f64 = 1e-6;

/// The form error of one part, ready to draw.
#[derive(Debug, Clone)]
pub struct FormErrorModel {
    pub part: usize,
    /// The part's shape with the subdivided profile.
    shape: Shape,
    /// The subdivided profile's points, their unit normals and arc
    /// lengths (m).
    points: Vec<[f64; 2]>,
    normals: Vec<[f64; 2]>,
    pub arc_m: Vec<f64>,
    /// Lower Cholesky factor of the covariance.
    factor: DMatrix<f64>,
    revolved: bool,
}

impl FormErrorModel {
    /// The model of `error` on its part of `scene`.
    pub fn new(scene: &Scene, error: &FormError) -> Result<FormErrorModel, String> {
        let part = &scene.parts[error.part];
        let base: Shape = if variables::profile(&part.shape).is_some() {
            part.shape.clone()
        } else {
            Shape::Revolved(
                editable_revolution(&part.shape, CONVERSION_TOLERANCE_M).ok_or_else(|| {
                    format!(
                        "part '{}' ({}) cannot be written as a profile within {} µm",
                        part.name,
                        part.shape.kind(),
                        CONVERSION_TOLERANCE_M * 1e6
                    )
                })?,
            )
        };
        let (points, interpolation, per_span, revolved) = match &base {
            Shape::Revolved(s) => (&s.profile, s.interpolation, s.segments_per_span, true),
            Shape::Extruded(s) => (&s.profile, s.interpolation, s.segments_per_span, false),
            _ => return Err(format!("part '{}' has no profile", part.name)),
        };
        // Subdivide every span alike until the longest is ≤ ℓ/4.
        let span_length = |a: [f64; 2], b: [f64; 2]| (b[0] - a[0]).hypot(b[1] - a[1]);
        let longest = sample_profile(points, interpolation, 16)
            .iter()
            .flat_map(|strip| strip.windows(2))
            .map(|w| span_length([w[0].point.x, w[0].point.y], [w[1].point.x, w[1].point.y]))
            .fold(0.0, f64::max)
            * 16.0;
        if points.len() > MAX_POINTS {
            return Err(format!(
                "the profile of part '{}' has {} points: a form error deforms at most {MAX_POINTS}",
                part.name,
                points.len()
            ));
        }
        let spans = points.len() - 1;
        let wanted = (4.0 * longest / error.correlation_length_m).ceil().max(1.0);
        let most = ((MAX_POINTS - 1) / spans).max(1);
        let k = (wanted as usize).clamp(1, most);
        let (new_points, normals) = subdivided(points, interpolation, k as u32);
        let mut arc_m = vec![0.0];
        for w in new_points.windows(2) {
            let last = *arc_m.last().unwrap_or(&0.0);
            arc_m.push(last + span_length(w[0], w[1]));
        }
        let new_per_span = per_span.div_ceil(k as u32).max(1);
        let shape = match &base {
            Shape::Revolved(s) => Shape::Revolved(Revolved {
                profile: new_points.clone(),
                segments_per_span: new_per_span,
                ..s.clone()
            }),
            Shape::Extruded(s) => {
                let mut s = s.clone();
                s.profile = new_points.clone();
                s.segments_per_span = new_per_span;
                Shape::Extruded(s)
            }
            _ => unreachable!("a profile's shape"),
        };
        let factor = covariance_factor(&arc_m, error.sigma_m, error.correlation_length_m);
        Ok(FormErrorModel {
            part: error.part,
            shape,
            points: new_points,
            normals,
            arc_m,
            factor,
            revolved,
        })
    }

    /// How many standard normal numbers one deformation takes.
    pub fn dimension(&self) -> usize {
        self.points.len()
    }

    /// The deviations along the normal (m) of standard normals `z`.
    pub fn deviations(&self, z: &[f64]) -> Vec<f64> {
        (&self.factor * DVector::from_column_slice(z))
            .iter()
            .copied()
            .collect()
    }

    /// The slopes dδ/ds of deviations `d` along the arc (central
    /// differences; one-sided at the ends).
    pub fn slopes(&self, d: &[f64]) -> Vec<f64> {
        let n = d.len().min(self.arc_m.len());
        (0..n)
            .map(|i| {
                let (a, b) = (i.saturating_sub(1), (i + 1).min(n - 1));
                let ds = self.arc_m[b] - self.arc_m[a];
                if ds > 0.0 { (d[b] - d[a]) / ds } else { 0.0 }
            })
            .collect()
    }

    /// The deformed profile's points.
    pub fn deformed(&self, deviations: &[f64]) -> Vec<[f64; 2]> {
        self.points
            .iter()
            .zip(&self.normals)
            .zip(deviations)
            .map(|((p, n), d)| {
                let mut q = [p[0] + d * n[0], p[1] + d * n[1]];
                if self.revolved && (q[0] < 0.0 || p[0] == 0.0) {
                    // A point on the axis moves along it (a ring of
                    // nanometres there would be a fan of slivers).
                    q[0] = 0.0;
                }
                q
            })
            .collect()
    }

    /// `scene` with the part deformed by `deviations`.
    pub fn apply(&self, scene: &mut Scene, deviations: &[f64]) {
        let mut shape = self.shape.clone();
        if let Some(points) = variables::profile_mut(&mut shape) {
            *points = self.deformed(deviations);
        }
        scene.parts[self.part].shape = shape;
    }
}

/// The profile's points subdivided `k` times a span (the control points
/// kept), and the unit normal at each (at a corner of straight segments,
/// the mean of the two sides').
fn subdivided(
    points: &[[f64; 2]],
    interpolation: Interpolation,
    k: u32,
) -> (Vec<[f64; 2]>, Vec<[f64; 2]>) {
    let mut out: Vec<[f64; 2]> = Vec::new();
    let mut tangents: Vec<[f64; 2]> = Vec::new();
    for strip in sample_profile(points, interpolation, k) {
        for (i, s) in strip.iter().enumerate() {
            let p = [s.point.x, s.point.y];
            let t = [s.tangent.x, s.tangent.y];
            if i == 0
                && let Some(last) = out.last()
                && (last[0] - p[0]).hypot(last[1] - p[1]) < 1e-15
            {
                // A corner shared by two straight strips.
                if let Some(lt) = tangents.last_mut() {
                    *lt = [lt[0] + t[0], lt[1] + t[1]];
                }
                continue;
            }
            out.push(p);
            tangents.push(t);
        }
    }
    let normals = tangents
        .iter()
        .map(|t| {
            let len = t[0].hypot(t[1]).max(1e-300);
            [-t[1] / len, t[0] / len]
        })
        .collect();
    (out, normals)
}

/// The lower Cholesky factor of σ²·exp(−Δs²/(2ℓ²)) on `arc`, with the
/// least diagonal jitter that makes it factor (a smooth kernel on close
/// points is numerically singular; the jitter is far below σ²).
fn covariance_factor(arc: &[f64], sigma: f64, correlation: f64) -> DMatrix<f64> {
    let n = arc.len();
    let kernel = DMatrix::from_fn(n, n, |i, j| {
        let d = (arc[i] - arc[j]) / correlation;
        sigma * sigma * (-0.5 * d * d).exp()
    });
    let mut jitter = 1e-10;
    loop {
        let m = &kernel + DMatrix::identity(n, n) * (jitter * sigma * sigma);
        if let Some(c) = m.cholesky() {
            return c.l();
        }
        jitter *= 10.0;
        if jitter > 1e-2 {
            // Unreachable for a kernel matrix; white noise of the same σ
            // rather than a panic.
            return DMatrix::identity(n, n) * sigma;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand_chacha::ChaCha8Rng;
    use rand_chacha::rand_core::{RngCore, SeedableRng};

    use crate::sampling::standard_normal;

    fn spot() -> Scene {
        lucerna_scene::parse_scene(
            include_str!("../../../assets/luminaires/parabolic_spot.toml"),
            std::path::Path::new("spot.toml"),
        )
        .expect("the example reads")
    }

    #[test]
    fn its_samples_have_the_stated_sigma_and_correlation() {
        let scene = spot();
        let (sigma, corr) = (0.05e-3, 10e-3);
        let model = FormErrorModel::new(
            &scene,
            &FormError {
                part: 0,
                part_name: "reflector".to_owned(),
                sigma_m: sigma,
                correlation_length_m: corr,
            },
        )
        .expect("a paraboloid converts");
        let n = model.dimension();
        assert!(
            model
                .arc_m
                .windows(2)
                .all(|w| w[1] - w[0] <= corr / 4.0 + 1e-9)
        );
        let mut rng = ChaCha8Rng::seed_from_u64(7);
        let draws = 4000;
        let samples: Vec<Vec<f64>> = (0..draws)
            .map(|_| {
                let z: Vec<f64> = (0..n).map(|_| standard_normal(rng.next_u64())).collect();
                // The deviations measured on the deformed points, as
                // built: the distance moved along the normal.
                let deformed = model.deformed(&model.deviations(&z));
                deformed
                    .iter()
                    .zip(&model.points)
                    .zip(&model.normals)
                    .map(|((q, p), nrm)| (q[0] - p[0]) * nrm[0] + (q[1] - p[1]) * nrm[1])
                    .collect()
            })
            .collect();
        // σ at every point (the axis point of a revolved profile moves
        // along its normal, which is the axis).
        for i in 0..n {
            let var = samples.iter().map(|s| s[i] * s[i]).sum::<f64>() / draws as f64;
            let ratio = var.sqrt() / sigma;
            assert!((ratio - 1.0).abs() < 0.06, "point {i}: σ ratio {ratio}");
        }
        // The correlation at a lag of about ℓ is e^(−1/2) of the distance
        // actually between the points.
        let i = n / 4;
        let j = (i..n)
            .min_by(|&a, &b| {
                let da = (model.arc_m[a] - model.arc_m[i] - corr).abs();
                let db = (model.arc_m[b] - model.arc_m[i] - corr).abs();
                da.total_cmp(&db)
            })
            .expect("points");
        let lag = model.arc_m[j] - model.arc_m[i];
        let want = (-0.5 * (lag / corr).powi(2)).exp();
        let cov = samples.iter().map(|s| s[i] * s[j]).sum::<f64>() / draws as f64;
        let got = cov / (sigma * sigma);
        assert!(
            (got - want).abs() < 0.05,
            "correlation {got} at lag {lag}, want {want}"
        );
        // Far apart: uncorrelated.
        let far = samples.iter().map(|s| s[0] * s[n - 1]).sum::<f64>() / draws as f64;
        assert!((far / (sigma * sigma)).abs() < 0.06);
    }

    #[test]
    fn a_profile_with_corners_keeps_them() {
        let mut scene = spot();
        scene.parts[0].shape = Shape::Revolved(Revolved {
            profile: vec![[0.0, 0.0], [0.02, 0.0], [0.03, 0.02]],
            interpolation: Interpolation::Linear,
            segments_around: 64,
            segments_per_span: 4,
            faceted: false,
        });
        let model = FormErrorModel::new(
            &scene,
            &FormError {
                part: 0,
                part_name: "reflector".to_owned(),
                sigma_m: 1e-5,
                correlation_length_m: 5e-3,
            },
        )
        .expect("a profile");
        assert!(model.points.contains(&[0.02, 0.0]));
        let zero = model.deformed(&vec![0.0; model.dimension()]);
        assert_eq!(zero, model.points);
    }
}
