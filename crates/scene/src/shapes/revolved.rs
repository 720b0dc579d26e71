//! A drawn profile revolved about the axis (custom reflectors, cones).

use serde::{Deserialize, Serialize};

use super::ShapeGenerator;
use crate::check::{Checker, FieldPath};
use crate::exact::ExactSurface;
use crate::generators::{revolution_triangle_count, revolve};
use crate::mesh::TriangleMesh;
use crate::profile::Interpolation;
use crate::profile::{exact_profile, sample_profile};

/// A profile `[r, z]` (metres, r ≥ 0) revolved about the z axis.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Revolved {
    /// Control points `[r, z]` (m).
    pub profile: Vec<[f64; 2]>,
    #[serde(default)]
    pub interpolation: Interpolation,
    #[serde(default = "crate::shapes::defaults::default_around")]
    pub segments_around: u32,
    /// Segments per span between two control points.
    #[serde(default = "crate::shapes::defaults::default_per_span")]
    pub segments_per_span: u32,
    /// Flat facets instead of a smooth surface.
    #[serde(default, skip_serializing_if = "crate::shapes::defaults::is_false")]
    pub faceted: bool,
}

impl ShapeGenerator for Revolved {
    fn kind(&self) -> &'static str {
        "revolved"
    }

    fn segments_around(&self) -> Option<u32> {
        Some(self.segments_around)
    }

    fn validate(&self, at: &FieldPath, check: &mut Checker<'_>) {
        let negative_radius = |p: [f64; 2]| {
            (p[0] < 0.0)
                .then(|| format!("radius r must be ≥ 0 in a revolved profile, got {}", p[0]))
        };
        if check.profile(at, &self.profile, negative_radius) {
            // A span lying on the axis revolves into nothing.
            let profile = &self.profile;
            for i in 1..profile.len() {
                if profile[i][0] == 0.0 && profile[i - 1][0] == 0.0 {
                    check.fail(
                        at.key("profile").index(i),
                        "two consecutive points on the axis (r = 0) give a zero-area surface",
                    );
                }
            }
        }
        check.segments(at, "segments_around", self.segments_around, 3);
        check.profile_segments(at, self.profile.len(), self.segments_per_span);
    }

    fn triangle_count(&self) -> Option<u64> {
        let spans = self.profile.len().saturating_sub(1) as u64;
        Some(revolution_triangle_count(
            self.segments_around,
            spans.saturating_mul(u64::from(self.segments_per_span)),
        ))
    }

    fn generate(&self) -> Option<TriangleMesh> {
        Some(revolve(
            &sample_profile(&self.profile, self.interpolation, self.segments_per_span),
            self.segments_around,
            self.faceted,
        ))
    }

    fn exact(&self) -> Option<Vec<ExactSurface>> {
        (!self.faceted).then(|| {
            vec![ExactSurface::Revolution(exact_profile(
                &self.profile,
                self.interpolation,
            ))]
        })
    }
}

/// The most control points a converted profile gets; a surface that needs
/// more is not converted.
const MAX_CONVERTED_POINTS: usize = 129;

/// `shape` as an editable revolved profile: a Catmull-Rom spline through
/// points on its exact meridian, with points added until the spline lies
/// within `tolerance_m` of the meridian everywhere (both ways: no point
/// of either is farther from the other). Its segments around, and about
/// as many along, as the shape had. `None` for a shape that is not one
/// smooth surface of revolution (faceted, capped, flat, not round), or
/// that would need more than 129 points.
pub fn editable_revolution(shape: &super::Shape, tolerance_m: f64) -> Option<Revolved> {
    use super::Shape;
    let segments_along = match shape {
        Shape::Paraboloid(s) => s.segments_along,
        Shape::Ellipsoid(s) => s.segments_along,
        Shape::Dome(s) => s.segments_along,
        Shape::Cylinder(_) => 1,
        _ => return None,
    };
    let segments_around = shape.generator().segments_around()?;
    let surfaces = shape.generator().exact()?;
    let [ExactSurface::Revolution(curves)] = surfaces.as_slice() else {
        return None;
    };
    let parameters = curve_parameters(curves.len());
    let meridian = dense(curves);
    let lengths = cumulative_lengths(&meridian);
    let total = *lengths.last()?;
    if !(total > 0.0 && tolerance_m > 0.0) {
        return None;
    }
    // A point `length` along the meridian, on the curve itself (its
    // parameter interpolated between the samples either side).
    let on_curve = |length: f64| -> glam::DVec2 {
        let k = lengths
            .partition_point(|&l| l < length)
            .clamp(1, meridian.len() - 1);
        let span = lengths[k] - lengths[k - 1];
        let f = if span > 0.0 {
            ((length - lengths[k - 1]) / span).clamp(0.0, 1.0)
        } else {
            0.0
        };
        let (curve, t1) = parameters[k];
        let t0 = if parameters[k - 1].0 == curve {
            parameters[k - 1].1
        } else {
            0.0
        };
        curves[curve].point(t0 + (t1 - t0) * f)
    };
    let mut count = 5;
    while count <= MAX_CONVERTED_POINTS {
        let profile: Vec<[f64; 2]> = (0..count)
            .map(|k| on_curve(total * k as f64 / (count - 1) as f64))
            .map(|p| [p.x.max(0.0), p.y])
            .collect();
        let spans = (count - 1) as u32;
        let candidate = Revolved {
            segments_around,
            segments_per_span: segments_along.div_ceil(spans).max(2),
            faceted: false,
            interpolation: Interpolation::CatmullRom,
            profile,
        };
        let spline = dense(&exact_profile(&candidate.profile, candidate.interpolation));
        if hausdorff(&spline, &meridian) <= tolerance_m {
            return Some(candidate);
        }
        count = 2 * count - 1;
    }
    None
}

/// Samples a curve of a meridian is measured by.
const PER_CURVE: usize = 256;

/// Points along a chain of profile curves, [`PER_CURVE`] a curve.
fn dense(curves: &[crate::exact::ProfileCurve]) -> Vec<glam::DVec2> {
    curve_parameters(curves.len())
        .into_iter()
        .map(|(i, t)| curves[i].point(t))
        .collect()
}

fn cumulative_lengths(points: &[glam::DVec2]) -> Vec<f64> {
    let mut lengths = Vec::with_capacity(points.len());
    let mut total = 0.0;
    for (i, p) in points.iter().enumerate() {
        if i > 0 {
            total += p.distance(points[i - 1]);
        }
        lengths.push(total);
    }
    lengths
}

/// The (curve, parameter) of each point [`dense`] gives.
fn curve_parameters(curves: usize) -> Vec<(usize, f64)> {
    let mut parameters = Vec::with_capacity(curves * PER_CURVE + 1);
    for i in 0..curves {
        let start = usize::from(i > 0);
        parameters.extend((start..=PER_CURVE).map(|k| (i, k as f64 / PER_CURVE as f64)));
    }
    parameters
}

/// The larger of the two one-sided distances between polylines.
fn hausdorff(a: &[glam::DVec2], b: &[glam::DVec2]) -> f64 {
    one_sided(a, b).max(one_sided(b, a))
}

/// How far the farthest point of `a` lies from the polyline `b`.
fn one_sided(a: &[glam::DVec2], b: &[glam::DVec2]) -> f64 {
    a.iter()
        .map(|&p| {
            b.windows(2)
                .map(|s| {
                    let d = s[1] - s[0];
                    let t = if d.length_squared() > 0.0 {
                        ((p - s[0]).dot(d) / d.length_squared()).clamp(0.0, 1.0)
                    } else {
                        0.0
                    };
                    p.distance(s[0] + d * t)
                })
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shapes::Shape;

    fn parsed(toml: &str) -> Shape {
        #[derive(serde::Deserialize)]
        struct Holder {
            shape: Shape,
        }
        toml::from_str::<Holder>(toml).expect("shape").shape
    }

    #[test]
    fn parametric_reflectors_become_profiles_within_the_tolerance() {
        for text in [
            r#"shape = { type = "paraboloid", focal_length = 0.025, aperture_diameter = 0.1, segments_around = 192, segments_along = 48 }"#,
            r#"shape = { type = "paraboloid", focal_length = 0.01, aperture_diameter = 0.12, neck_diameter = 0.01 }"#,
            r#"shape = { type = "ellipsoid", focal_distance = 0.08, vertex_distance = 0.02, cut_below_focus = 0.01 }"#,
            r#"shape = { type = "dome", radius = 0.05, height = 0.03 }"#,
        ] {
            let shape = parsed(text);
            let revolved = editable_revolution(&shape, 0.02e-3).expect("converts");
            // Checked against the original's own meridian, more finely
            // than the conversion did: within 0.05 mm.
            let surfaces = shape.generator().exact().expect("exact surfaces");
            let [ExactSurface::Revolution(original)] = surfaces.as_slice() else {
                panic!("one surface of revolution");
            };
            let fine = |curves: &[crate::exact::ProfileCurve]| -> Vec<glam::DVec2> {
                curves
                    .iter()
                    .flat_map(|c| (0..=600).map(move |k| c.point(f64::from(k) / 600.0)))
                    .collect()
            };
            let spline = exact_profile(&revolved.profile, revolved.interpolation);
            let gap = hausdorff(&fine(&spline), &fine(original));
            assert!(gap < 0.05e-3, "{text}: {:.4} mm", gap * 1e3);
            // The ends are the shape's: neck and rim stay where they were.
            let ends = |c: &[crate::exact::ProfileCurve]| [c[0].start(), c[c.len() - 1].end()];
            for (a, b) in ends(&spline).iter().zip(ends(original)) {
                assert!(a.distance(b) < 1e-12, "{text}: end {a} vs {b}");
            }
            assert_eq!(
                Some(revolved.segments_around),
                shape.generator().segments_around()
            );
        }
    }

    #[test]
    fn shapes_without_one_smooth_meridian_are_not_converted() {
        for text in [
            r#"shape = { type = "paraboloid", focal_length = 0.025, aperture_diameter = 0.1, faceted = true }"#,
            r#"shape = { type = "box", size = [0.1, 0.1, 0.1] }"#,
            r#"shape = { type = "disk", radius = 0.05 }"#,
        ] {
            assert!(
                editable_revolution(&parsed(text), 0.02e-3).is_none(),
                "{text}"
            );
        }
        // A tolerance no spline of 129 points meets.
        let spot = parsed(
            r#"shape = { type = "paraboloid", focal_length = 0.025, aperture_diameter = 0.1 }"#,
        );
        assert!(editable_revolution(&spot, 1e-12).is_none());
    }
}
