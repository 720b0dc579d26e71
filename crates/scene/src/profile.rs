//! 2D profiles (r-z or x-z) sampled into smooth strips for revolution and
//! extrusion.

use glam::DVec2;

use crate::exact::ProfileCurve;
use serde::{Deserialize, Serialize};

/// How a 2D profile is interpolated between its control points.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Interpolation {
    /// Straight segments between control points.
    Linear,
    /// A Catmull-Rom spline through the control points (smooth, editable).
    #[default]
    CatmullRom,
}

/// A point on a profile with its tangent along increasing parameter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ProfileSample {
    /// (r, z) or (x, z), metres.
    pub point: DVec2,
    /// Unit tangent.
    pub tangent: DVec2,
}

/// A piece of profile whose tangent is continuous: shading normals are
/// shared along it; a corner between strips duplicates the vertices.
pub type Strip = Vec<ProfileSample>;

/// Samples a parametric curve `t ∈ [t0, t1]` into `segments + 1` points.
pub fn sample_curve(
    t0: f64,
    t1: f64,
    segments: u32,
    point: impl Fn(f64) -> DVec2,
    derivative: impl Fn(f64) -> DVec2,
) -> Strip {
    (0..=segments)
        .map(|i| {
            let t = t0 + (t1 - t0) * f64::from(i) / f64::from(segments);
            ProfileSample {
                point: point(t),
                tangent: derivative(t).normalize_or_zero(),
            }
        })
        .collect()
}

/// Uniform Catmull-Rom span between `p1` and `p2`: position at `t ∈ [0,1]`.
fn catmull_rom(p: [DVec2; 4], t: f64) -> DVec2 {
    let [p0, p1, p2, p3] = p;
    0.5 * (2.0 * p1
        + (p2 - p0) * t
        + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * t * t
        + (-p0 + 3.0 * p1 - 3.0 * p2 + p3) * t * t * t)
}

/// Derivative of [`catmull_rom`] with respect to `t`.
fn catmull_rom_derivative(p: [DVec2; 4], t: f64) -> DVec2 {
    let [p0, p1, p2, p3] = p;
    0.5 * ((p2 - p0)
        + 2.0 * (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * t
        + 3.0 * (-p0 + 3.0 * p1 - 3.0 * p2 + p3) * t * t)
}

/// The four control points of span `i` (between points i and i+1), with the
/// end points reflected so that the spline passes through every control
/// point and starts and ends along the first and last chord.
fn span_controls(points: &[DVec2], i: usize) -> [DVec2; 4] {
    let n = points.len();
    let before = if i == 0 {
        2.0 * points[0] - points[1]
    } else {
        points[i - 1]
    };
    let after = if i + 2 >= n {
        2.0 * points[n - 1] - points[n - 2]
    } else {
        points[i + 2]
    };
    [before, points[i], points[i + 1], after]
}

/// Point and derivative of a profile at global parameter `s ∈ [0, spans]`.
pub fn evaluate(points: &[DVec2], interpolation: Interpolation, s: f64) -> (DVec2, DVec2) {
    let spans = points.len() - 1;
    let i = (s.floor() as usize).min(spans - 1);
    let t = s - i as f64;
    match interpolation {
        Interpolation::Linear => {
            let d = points[i + 1] - points[i];
            (points[i] + d * t, d)
        }
        Interpolation::CatmullRom => {
            let c = span_controls(points, i);
            (catmull_rom(c, t), catmull_rom_derivative(c, t))
        }
    }
}

/// Samples a control-point profile into strips: one smooth strip for a
/// Catmull-Rom spline, one strip per segment for straight segments (each
/// corner gets its own normals).
pub fn sample_profile(
    points: &[[f64; 2]],
    interpolation: Interpolation,
    segments_per_span: u32,
) -> Vec<Strip> {
    let points: Vec<DVec2> = points.iter().map(|&p| DVec2::from_array(p)).collect();
    let spans = points.len() - 1;
    match interpolation {
        Interpolation::Linear => (0..spans)
            .map(|i| {
                let (a, b) = (points[i], points[i + 1]);
                sample_curve(0.0, 1.0, segments_per_span, |t| a + (b - a) * t, |_| b - a)
            })
            .collect(),
        Interpolation::CatmullRom => {
            let total = spans as u32 * segments_per_span;
            vec![sample_curve(
                0.0,
                spans as f64,
                total,
                |s| evaluate(&points, interpolation, s).0,
                |s| evaluate(&points, interpolation, s).1,
            )]
        }
    }
}

/// The profile as the curves [`sample_profile`] samples: a segment per
/// span for straight segments, a cubic Bézier per span for Catmull-Rom
/// (a uniform Catmull-Rom span is exactly that cubic).
pub fn exact_profile(points: &[[f64; 2]], interpolation: Interpolation) -> Vec<ProfileCurve> {
    let points: Vec<DVec2> = points.iter().map(|&p| DVec2::from_array(p)).collect();
    (0..points.len().saturating_sub(1))
        .map(|i| match interpolation {
            Interpolation::Linear => ProfileCurve::Line {
                from: points[i],
                to: points[i + 1],
            },
            Interpolation::CatmullRom => {
                let [p0, p1, p2, p3] = span_controls(&points, i);
                ProfileCurve::Cubic {
                    points: [p1, p1 + (p2 - p0) / 6.0, p2 - (p3 - p1) / 6.0, p2],
                }
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exact_profile_is_the_sampled_spline() {
        let points = [[0.004, 0.02], [0.01, 0.015], [0.03, 0.0], [0.05, -0.03]];
        let dpoints: Vec<DVec2> = points.iter().map(|&p| DVec2::from_array(p)).collect();
        for interpolation in [Interpolation::Linear, Interpolation::CatmullRom] {
            let curves = exact_profile(&points, interpolation);
            assert_eq!(curves.len(), 3);
            for (i, c) in curves.iter().enumerate() {
                for k in 0..=20 {
                    let t = f64::from(k) / 20.0;
                    let (want, _) = evaluate(&dpoints, interpolation, i as f64 + t);
                    assert!(
                        c.point(t).distance(want) < 1e-15,
                        "{interpolation:?} span {i}"
                    );
                }
            }
        }
    }
}
