//! The exact surfaces a shape's tessellation samples, in the part's frame
//! (metres): what a CAD export writes instead of triangles. Each shape
//! states its own ([`crate::ShapeGenerator::exact`]); the curves are the
//! polynomial and rational Bézier forms CAD kernels hold exactly, so a
//! paraboloid is a parabola revolved, not a polygon.

use glam::{DVec2, DVec3};

/// One piece of a profile in the r–z (or x–z) plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ProfileCurve {
    /// A straight segment.
    Line { from: DVec2, to: DVec2 },
    /// A conic arc as a rational quadratic Bézier: a parabola for weight
    /// 1, an ellipse or circle for a weight below 1. `control` is where
    /// the end tangents meet.
    Conic {
        from: DVec2,
        control: DVec2,
        to: DVec2,
        weight: f64,
    },
    /// A cubic Bézier span (one span of a Catmull-Rom profile).
    Cubic { points: [DVec2; 4] },
}

impl ProfileCurve {
    pub fn start(&self) -> DVec2 {
        match *self {
            ProfileCurve::Line { from, .. } | ProfileCurve::Conic { from, .. } => from,
            ProfileCurve::Cubic { points } => points[0],
        }
    }

    pub fn end(&self) -> DVec2 {
        match *self {
            ProfileCurve::Line { to, .. } | ProfileCurve::Conic { to, .. } => to,
            ProfileCurve::Cubic { points } => points[3],
        }
    }

    /// The point at `t ∈ [0, 1]`.
    pub fn point(&self, t: f64) -> DVec2 {
        let s = 1.0 - t;
        match *self {
            ProfileCurve::Line { from, to } => from + (to - from) * t,
            ProfileCurve::Conic {
                from,
                control,
                to,
                weight,
            } => {
                let (b0, b1, b2) = (s * s, 2.0 * s * t * weight, t * t);
                (from * b0 + control * b1 + to * b2) / (b0 + b1 + b2)
            }
            ProfileCurve::Cubic {
                points: [p0, p1, p2, p3],
            } => {
                p0 * (s * s * s)
                    + p1 * (3.0 * s * s * t)
                    + p2 * (3.0 * s * t * t)
                    + p3 * (t * t * t)
            }
        }
    }

    /// The same curve run the other way.
    pub fn reversed(&self) -> ProfileCurve {
        match *self {
            ProfileCurve::Line { from, to } => ProfileCurve::Line { from: to, to: from },
            ProfileCurve::Conic {
                from,
                control,
                to,
                weight,
            } => ProfileCurve::Conic {
                from: to,
                control,
                to: from,
                weight,
            },
            ProfileCurve::Cubic {
                points: [p0, p1, p2, p3],
            } => ProfileCurve::Cubic {
                points: [p3, p2, p1, p0],
            },
        }
    }
}

/// One exact surface of a shape.
#[derive(Debug, Clone, PartialEq)]
pub enum ExactSurface {
    /// A chain of curves in the r–z half plane (x = r ≥ 0, y = z) revolved
    /// a full turn about the z axis.
    Revolution(Vec<ProfileCurve>),
    /// A chain of curves in the x–z plane swept along y from −length/2 to
    /// +length/2; `end_caps` closes each end with the plane region between
    /// the profile and its chord.
    Extrusion {
        profile: Vec<ProfileCurve>,
        length: f64,
        end_caps: bool,
    },
    /// A disk in the plane z = `z`, centred on the axis.
    Disk { radius: f64, z: f64 },
    /// A planar polygon, corners in order.
    Polygon(Vec<DVec3>),
}

/// The parabola z = f − r²/(4f) from radius `r0` to `r1`: a quadratic
/// Bézier is exact, since r runs linearly along it.
pub fn parabola(focal_length: f64, r0: f64, r1: f64) -> ProfileCurve {
    let f = focal_length;
    let z = |r: f64| f - r * r / (4.0 * f);
    ProfileCurve::Conic {
        from: DVec2::new(r0, z(r0)),
        // Where the tangents at r0 and r1 meet.
        control: DVec2::new(0.5 * (r0 + r1), f - r0 * r1 / (4.0 * f)),
        to: DVec2::new(r1, z(r1)),
        weight: 1.0,
    }
}

/// The elliptic arc (r, z) = (b sin t, centre_z + a cos t) for t from `t0`
/// to `t1` (a = b: a circle), in arcs of at most a quarter turn: the
/// affine image of a circle's rational quadratic arcs, which is exact.
pub fn elliptic_arc(centre_z: f64, a: f64, b: f64, t0: f64, t1: f64) -> Vec<ProfileCurve> {
    let pieces = ((t1 - t0).abs() / std::f64::consts::FRAC_PI_2)
        .ceil()
        .max(1.0) as usize;
    let at = |t: f64, scale: f64| DVec2::new(b * t.sin() * scale, centre_z + a * t.cos() * scale);
    (0..pieces)
        .map(|i| {
            let ta = t0 + (t1 - t0) * i as f64 / pieces as f64;
            let tb = t0 + (t1 - t0) * (i + 1) as f64 / pieces as f64;
            let half = 0.5 * (tb - ta);
            let weight = half.cos();
            // The unit circle's tangents at ta and tb meet at 1/cos(half)
            // along the middle direction; the affine map keeps that.
            let control = DVec2::new(
                b * (ta + half).sin() / weight,
                centre_z + a * (ta + half).cos() / weight,
            );
            ProfileCurve::Conic {
                from: at(ta, 1.0),
                control,
                to: at(tb, 1.0),
                weight,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parabola_bezier_lies_on_the_parabola() {
        let (f, r0, r1) = (0.03, 0.004, 0.05);
        let c = parabola(f, r0, r1);
        for i in 0..=100 {
            let p = c.point(f64::from(i) / 100.0);
            assert!((p.y - (f - p.x * p.x / (4.0 * f))).abs() < 1e-15, "{p}");
        }
        assert_eq!(c.start().x, r0);
        assert_eq!(c.end().x, r1);
    }

    #[test]
    fn elliptic_arcs_lie_on_the_ellipse_and_join() {
        let (cz, a, b) = (-0.01, 0.05, 0.03);
        let arcs = elliptic_arc(cz, a, b, 0.2, 2.9);
        assert_eq!(arcs.len(), 2);
        assert!(arcs[0].end().distance(arcs[1].start()) < 1e-15);
        for arc in &arcs {
            for i in 0..=50 {
                let p = arc.point(f64::from(i) / 50.0);
                let e = (p.x / b).powi(2) + ((p.y - cz) / a).powi(2);
                assert!((e - 1.0).abs() < 1e-12, "{e}");
            }
        }
        let (s, e) = (arcs[0].start(), arcs[1].end());
        assert!((s - DVec2::new(b * 0.2f64.sin(), cz + a * 0.2f64.cos())).length() < 1e-15);
        assert!((e - DVec2::new(b * 2.9f64.sin(), cz + a * 2.9f64.cos())).length() < 1e-15);
    }

    #[test]
    fn reversed_runs_backwards() {
        let c = parabola(0.02, 0.0, 0.03);
        let r = c.reversed();
        for i in 0..=10 {
            let t = f64::from(i) / 10.0;
            assert!(c.point(t).distance(r.point(1.0 - t)) < 1e-15);
        }
    }
}
