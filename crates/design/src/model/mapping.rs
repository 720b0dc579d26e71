//! The energy-balance mapping of a revolved mirror for a point source on
//! its axis, meeting both of its fixed ends.
//!
//! The source's flux between the mirror's first end and a ray angle θ is
//! sent, reflected, into the same share of the wanted light, counted
//! along a signed output angle γₛ (negative: the reflected ray crosses
//! the axis). In polar form about the source, P(θ) = S + ρ(θ)·u(θ), the
//! law of reflection makes the surface perpendicular to u − v, which for
//! meridional rays is
//!
//! d ln ρ / dθ = −cot((θ − γₛ(θ)) / 2),
//!
//! so the profile is a quadrature, and where it lands is a function of
//! the mapping alone. The mapping has free constants that leave the
//! folded output (the light against |γₛ|) unchanged: the sweep (γₛ rising
//! or falling from the first end to the last) and the share of the
//! reflected flux sent across the axis. For each sweep that share is
//! solved for so that the profile lands on the other end. Where no share
//! can, the wanted light is stretched in angle (a second constant) until
//! it does; where nothing closes, the nearest is blended onto the end and
//! the miss reported.

use glam::DVec2;

/// Source angles the quadrature takes between the two ends.
const STEPS: usize = 2000;
/// Steps of the bisection on a free constant.
const BISECTIONS: usize = 60;
/// Samples of a free constant searched for a bracket of the closure.
const BRACKET_SAMPLES: usize = 24;
/// The closest a reflected ray may come to its incident ray's direction
/// (radians, half a degree): the surface would be tangent to the ray.
const GRAZING: f64 = 0.5 * std::f64::consts::PI / 180.0;

/// A point source on the axis of the part's r-z half-plane.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PointSource {
    /// Its height on the axis (m).
    pub z: f64,
    /// Whether it emits towards −z.
    pub facing_down: bool,
}

impl PointSource {
    /// θ (from the source's facing direction, towards +r) and ρ of a point.
    pub fn polar(&self, p: [f64; 2]) -> (f64, f64) {
        let along = self.along(p[1] - self.z);
        (p[0].atan2(along), p[0].hypot(along))
    }

    /// The point at θ, ρ.
    pub fn point(&self, theta: f64, rho: f64) -> [f64; 2] {
        [rho * theta.sin(), self.z + self.along(rho * theta.cos())]
    }

    /// A height difference in the source's facing direction, and back.
    fn along(&self, dz: f64) -> f64 {
        if self.facing_down { -dz } else { dz }
    }

    /// The source's relative flux per unit θ at θ: Lambertian, cos θ
    /// around the axis (sin θ).
    fn flux_density(theta: f64) -> f64 {
        (theta.cos() * theta.sin()).max(0.0)
    }
}

/// The light the mirror is to make: relative intensity against γ (from
/// the source's facing direction) on equal steps from 0 to 180°.
#[derive(Debug, Clone, PartialEq)]
pub struct Wanted {
    pub step_deg: f64,
    pub intensity: Vec<f64>,
}

impl Wanted {
    /// `intensity(γ°)` sampled on `step_deg` steps.
    pub fn sampled(step_deg: f64, intensity: impl Fn(f64) -> f64) -> Wanted {
        let n = (180.0 / step_deg).round() as usize;
        Wanted {
            step_deg,
            intensity: (0..=n)
                .map(|k| intensity(k as f64 * step_deg).max(0.0))
                .collect(),
        }
    }

    /// The intensity at γ (degrees), linear between samples.
    pub fn at(&self, gamma_deg: f64) -> f64 {
        let n = self.intensity.len() - 1;
        let x = (gamma_deg / self.step_deg).clamp(0.0, n as f64);
        let i = (x.floor() as usize).min(n - 1);
        let t = x - i as f64;
        self.intensity[i] * (1.0 - t) + self.intensity[i + 1] * t
    }

    /// The cumulative flux from γ = 0 at each sample, as shares of the
    /// whole (None: no light).
    fn cumulative(&self) -> Option<Vec<f64>> {
        let h = self.step_deg.to_radians();
        let density = |k: usize| self.intensity[k] * (k as f64 * h).sin();
        let mut c = vec![0.0; self.intensity.len()];
        for k in 1..c.len() {
            c[k] = c[k - 1] + 0.5 * (density(k - 1) + density(k)) * h;
        }
        let total = c[c.len() - 1];
        if !(total > 0.0) || !total.is_finite() {
            return None;
        }
        c.iter_mut().for_each(|x| *x /= total);
        Some(c)
    }
}

/// Which way the output angle runs along the mirror.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Sweep {
    /// γₛ rises from the profile's first end to its last.
    Rising,
    /// γₛ falls from the first end to the last.
    Falling,
}

/// How a mapped profile closes onto its far end.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Closure {
    /// The crossing share alone lands it on the end.
    Exact,
    /// The wanted light was stretched in angle by this factor as well.
    Stretched(f64),
    /// Nothing closes: the nearest profile, moved onto the end along its
    /// length by this much (m) at most.
    Blended(f64),
}

/// A profile mapped from one end to the other.
#[derive(Debug, Clone, PartialEq)]
pub struct MappedProfile {
    /// Points from the first end to the last (r, z), [`STEPS`] + 1 of them.
    pub points: Vec<[f64; 2]>,
    pub sweep: Sweep,
    /// The share of the reflected flux sent across the axis.
    pub crossing_share: f64,
    pub closure: Closure,
}

/// The mapping's fixed data between two ends.
struct Mapper {
    thetas: Vec<f64>,
    /// The source's cumulative flux from the first end at each θ (shares).
    source_share: Vec<f64>,
    wanted_cumulative: Vec<f64>,
    wanted_step: f64,
    /// ln ρ at the first end, and the closure's goal: ln(ρ_last / ρ_first).
    log_rho_first: f64,
    goal: f64,
}

impl Mapper {
    fn new(source: &PointSource, ends: [[f64; 2]; 2], wanted: &Wanted) -> Option<Mapper> {
        let (ta, ra) = source.polar(ends[0]);
        let (tb, rb) = source.polar(ends[1]);
        if !(ra > 0.0 && rb > 0.0 && (ta - tb).abs() > 1e-3) {
            return None;
        }
        let thetas: Vec<f64> = (0..=STEPS)
            .map(|i| ta + (tb - ta) * i as f64 / STEPS as f64)
            .collect();
        let mut share = vec![0.0; STEPS + 1];
        for i in 1..=STEPS {
            share[i] = share[i - 1]
                + 0.5
                    * (PointSource::flux_density(thetas[i - 1])
                        + PointSource::flux_density(thetas[i]))
                    * (thetas[i] - thetas[i - 1]).abs();
        }
        let total = share[STEPS];
        if !(total > 0.0) {
            return None;
        }
        share.iter_mut().for_each(|x| *x /= total);
        Some(Mapper {
            thetas,
            source_share: share,
            wanted_cumulative: wanted.cumulative()?,
            wanted_step: wanted.step_deg.to_radians(),
            log_rho_first: ra.ln(),
            goal: (rb / ra).ln(),
        })
    }

    /// γ (radians) below which a share `c` of the wanted flux lies.
    fn gamma_of_share(&self, c: f64) -> f64 {
        let cum = &self.wanted_cumulative;
        let j = cum.partition_point(|&x| x < c).clamp(1, cum.len() - 1);
        let (c0, c1) = (cum[j - 1], cum[j]);
        let t = if c1 > c0 { (c - c0) / (c1 - c0) } else { 0.0 };
        (j as f64 - 1.0 + t) * self.wanted_step
    }

    /// The signed output angle of the source ray at index i.
    fn output(&self, i: usize, sweep: Sweep, crossing: f64, stretch: f64) -> f64 {
        let q = match sweep {
            Sweep::Rising => self.source_share[i],
            Sweep::Falling => 1.0 - self.source_share[i],
        };
        // The signed CDF: the crossing share on γₛ < 0 (its wide edge
        // first), the rest on γₛ > 0.
        let gamma = if q < crossing {
            -self.gamma_of_share(1.0 - q / crossing)
        } else if crossing < 1.0 {
            self.gamma_of_share((q - crossing) / (1.0 - crossing))
        } else {
            0.0
        };
        (gamma * stretch).clamp(-std::f64::consts::PI, std::f64::consts::PI)
    }

    /// d ln ρ / dθ at every source angle. A reflected ray may not leave
    /// beyond its own incident direction (the surface would face away
    /// from the source): an output angle past θ less [`GRAZING`] is
    /// taken as that (the ray grazes the surface near the aperture's rim,
    /// where a wide target's edge is made).
    fn slopes(&self, sweep: Sweep, crossing: f64, stretch: f64) -> Option<Vec<f64>> {
        Some(
            (0..=STEPS)
                .map(|i| {
                    let theta = self.thetas[i];
                    let half = (0.5 * (theta - self.output(i, sweep, crossing, stretch)))
                        .clamp(0.5 * GRAZING, std::f64::consts::PI - 0.5 * GRAZING);
                    -1.0 / half.tan()
                })
                .collect(),
        )
    }

    /// ln(ρ_last/ρ_first) of the mapping less the goal (None: invalid).
    fn miss(&self, sweep: Sweep, crossing: f64, stretch: f64) -> Option<f64> {
        let s = self.slopes(sweep, crossing, stretch)?;
        let h = (self.thetas[STEPS] - self.thetas[0]) / STEPS as f64;
        let integral: f64 = s.windows(2).map(|w| 0.5 * (w[0] + w[1]) * h).sum();
        Some(integral - self.goal)
    }

    /// The profile of a mapping, moved onto the far end along its length.
    fn profile(
        &self,
        source: &PointSource,
        end: [f64; 2],
        sweep: Sweep,
        crossing: f64,
        stretch: f64,
    ) -> Option<(Vec<[f64; 2]>, f64)> {
        let s = self.slopes(sweep, crossing, stretch)?;
        let h = (self.thetas[STEPS] - self.thetas[0]) / STEPS as f64;
        let mut log_rho = self.log_rho_first;
        let mut curve = Vec::with_capacity(STEPS + 1);
        for i in 0..=STEPS {
            if i > 0 {
                log_rho += 0.5 * (s[i - 1] + s[i]) * h;
            }
            if !log_rho.is_finite() || log_rho > 10.0 {
                return None;
            }
            curve.push(DVec2::from_array(
                source.point(self.thetas[i], log_rho.exp()),
            ));
        }
        let lengths: Vec<f64> = std::iter::once(0.0)
            .chain(curve.windows(2).scan(0.0, |acc, w| {
                *acc += (w[1] - w[0]).length();
                Some(*acc)
            }))
            .collect();
        let length = lengths[STEPS];
        if !(length > 0.0) {
            return None;
        }
        let miss = DVec2::from_array(end) - curve[STEPS];
        let points = curve
            .iter()
            .zip(&lengths)
            .map(|(p, l)| (*p + miss * (l / length)).to_array())
            .collect();
        Some((points, miss.length()))
    }
}

/// The profile from `ends[0]` to `ends[1]` whose reflection of `source`
/// makes `wanted`, for one sweep; None where no valid mapping exists.
pub fn map_profile(
    source: &PointSource,
    ends: [[f64; 2]; 2],
    wanted: &Wanted,
    sweep: Sweep,
) -> Option<MappedProfile> {
    let m = Mapper::new(source, ends, wanted)?;
    // The crossing share first: a bracket of the closure on a few
    // samples, then bisection.
    let shares: Vec<f64> = (0..=BRACKET_SAMPLES)
        .map(|k| k as f64 / BRACKET_SAMPLES as f64)
        .collect();
    let by_share: Vec<Option<f64>> = shares.iter().map(|&a| m.miss(sweep, a, 1.0)).collect();
    if let Some(a) = root_in(&shares, &by_share, |a| m.miss(sweep, a, 1.0)) {
        let (points, _) = m.profile(source, ends[1], sweep, a, 1.0)?;
        return Some(MappedProfile {
            points,
            sweep,
            crossing_share: a,
            closure: Closure::Exact,
        });
    }
    // Then the stretch, at the share whose miss was least.
    let (share, _) = shares
        .iter()
        .zip(&by_share)
        .filter_map(|(&a, m)| m.map(|m| (a, m.abs())))
        .min_by(|x, y| x.1.total_cmp(&y.1))?;
    let stretches: Vec<f64> = (0..=BRACKET_SAMPLES)
        .map(|k| 4f64.powf(2.0 * k as f64 / BRACKET_SAMPLES as f64 - 1.0))
        .collect();
    let by_stretch: Vec<Option<f64>> = stretches.iter().map(|&b| m.miss(sweep, share, b)).collect();
    if let Some(b) = root_in(&stretches, &by_stretch, |b| m.miss(sweep, share, b)) {
        let (points, _) = m.profile(source, ends[1], sweep, share, b)?;
        return Some(MappedProfile {
            points,
            sweep,
            crossing_share: share,
            closure: Closure::Stretched(b),
        });
    }
    let (stretch, _) = stretches
        .iter()
        .zip(&by_stretch)
        .filter_map(|(&b, m)| m.map(|m| (b, m.abs())))
        .min_by(|x, y| x.1.total_cmp(&y.1))?;
    let (points, miss) = m.profile(source, ends[1], sweep, share, stretch)?;
    Some(MappedProfile {
        points,
        sweep,
        crossing_share: share,
        closure: Closure::Blended(miss),
    })
}

/// The profile of given constants (a crossing share and a stretch),
/// moved onto the far end along its length where it misses it.
pub fn map_profile_at(
    source: &PointSource,
    ends: [[f64; 2]; 2],
    wanted: &Wanted,
    sweep: Sweep,
    crossing_share: f64,
    stretch: f64,
) -> Option<MappedProfile> {
    let m = Mapper::new(source, ends, wanted)?;
    let (points, miss) = m.profile(source, ends[1], sweep, crossing_share, stretch)?;
    Some(MappedProfile {
        points,
        sweep,
        crossing_share,
        closure: if miss < CLOSED_M {
            if stretch == 1.0 {
                Closure::Exact
            } else {
                Closure::Stretched(stretch)
            }
        } else {
            Closure::Blended(miss)
        },
    })
}

/// A landing this close to the far end counts as meeting it (m).
const CLOSED_M: f64 = 1e-6;

/// The crossing shares and stretches a family of mappings samples: the
/// shares over their whole range, the stretches a factor 1.6 either way.
const FAMILY_SHARES: [f64; 5] = [0.0, 0.25, 0.5, 0.75, 1.0];
const FAMILY_STRETCHES: [f64; 5] = [0.625, 0.8, 1.0, 1.25, 1.6];

/// The mapping's whole family between the ends: for each sweep the
/// profile that closes (where one does), then the free constants sampled
/// over their range (each moved onto the end where it misses it). The
/// folded light of each is the wanted light, or a stretch of it, for a
/// point source; which of them an extended source's light is nearest is
/// for a model to say.
pub fn mapping_family(
    source: &PointSource,
    ends: [[f64; 2]; 2],
    wanted: &Wanted,
) -> Vec<MappedProfile> {
    let mut out = Vec::new();
    for sweep in [Sweep::Rising, Sweep::Falling] {
        out.extend(map_profile(source, ends, wanted, sweep));
        for share in FAMILY_SHARES {
            for stretch in FAMILY_STRETCHES {
                out.extend(map_profile_at(source, ends, wanted, sweep, share, stretch));
            }
        }
    }
    out
}

/// The first root of `f` between neighbouring samples whose values
/// change sign, by bisection.
fn root_in(xs: &[f64], values: &[Option<f64>], f: impl Fn(f64) -> Option<f64>) -> Option<f64> {
    for k in 1..xs.len() {
        let (Some(fa), Some(fb)) = (values[k - 1], values[k]) else {
            continue;
        };
        if fa == 0.0 {
            return Some(xs[k - 1]);
        }
        if fa.signum() == fb.signum() {
            continue;
        }
        let (mut a, mut b, mut va) = (xs[k - 1], xs[k], fa);
        for _ in 0..BISECTIONS {
            let mid = 0.5 * (a + b);
            let Some(vm) = f(mid) else {
                break;
            };
            if vm.signum() == va.signum() {
                a = mid;
                va = vm;
            } else {
                b = mid;
            }
        }
        return Some(0.5 * (a + b));
    }
    None
}

/// `count` control points on `curve` at equal shares of its length, the
/// first and last its ends: a Catmull-Rom spline through them follows the
/// curve.
pub fn control_points(curve: &[[f64; 2]], count: usize) -> Vec<[f64; 2]> {
    let pts: Vec<DVec2> = curve.iter().map(|&p| DVec2::from_array(p)).collect();
    let mut lengths = vec![0.0];
    for w in pts.windows(2) {
        lengths.push(lengths[lengths.len() - 1] + (w[1] - w[0]).length());
    }
    let total = lengths[lengths.len() - 1];
    (0..count)
        .map(|k| {
            if k == 0 {
                return curve[0];
            }
            if k + 1 == count {
                return curve[curve.len() - 1];
            }
            let goal = total * k as f64 / (count - 1) as f64;
            let j = lengths
                .partition_point(|&s| s < goal)
                .clamp(1, lengths.len() - 1);
            let (s0, s1) = (lengths[j - 1], lengths[j]);
            let t = if s1 > s0 {
                (goal - s0) / (s1 - s0)
            } else {
                0.0
            };
            (pts[j - 1] + t * (pts[j] - pts[j - 1])).to_array()
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    const SOURCE: PointSource = PointSource {
        z: 0.0,
        facing_down: true,
    };

    /// A paraboloid focused at the source, collimating along −z: ρ = p /
    /// (1 − cos θ).
    fn on_paraboloid(p: f64, theta_deg: f64) -> [f64; 2] {
        let t = theta_deg.to_radians();
        SOURCE.point(t, p / (1.0 - t.cos()))
    }

    /// A collimated target: all the light within 0.002° of nadir.
    fn collimated() -> Wanted {
        Wanted::sampled(0.001, |g| if g <= 0.002 { 1.0 } else { 0.0 })
    }

    #[test]
    fn a_collimating_target_gives_the_paraboloid_through_the_ends() {
        let p = 0.012;
        let ends = [on_paraboloid(p, 100.0), on_paraboloid(p, 30.0)];
        for sweep in [Sweep::Rising, Sweep::Falling] {
            let mapped = map_profile(&SOURCE, ends, &collimated(), sweep).expect("a mapping");
            let worst = mapped
                .points
                .iter()
                .map(|&q| {
                    let (theta, _) = SOURCE.polar(q);
                    let on = SOURCE.point(theta, p / (1.0 - theta.cos()));
                    (DVec2::from_array(q) - DVec2::from_array(on)).length()
                })
                .fold(0.0, f64::max);
            assert!(worst < 0.05e-3, "{sweep:?}: {:.4} mm off", worst * 1e3);
            let last = mapped.points[mapped.points.len() - 1];
            assert!((DVec2::from_array(last) - DVec2::from_array(ends[1])).length() < 1e-9);
        }
    }

    #[test]
    fn a_focus_off_the_paraboloid_is_not_met_by_the_collimating_mapping() {
        // The test above can fail: a rim 5 mm off the paraboloid is not
        // reached by collimated light, and the mapping says so.
        let p = 0.012;
        let mut rim = on_paraboloid(p, 30.0);
        rim[0] += 0.005;
        let mapped = map_profile(
            &SOURCE,
            [on_paraboloid(p, 100.0), rim],
            &collimated(),
            Sweep::Rising,
        )
        .expect("a mapping");
        assert!(!matches!(mapped.closure, Closure::Exact));
    }

    /// A 30° beam, flat-topped.
    fn beam() -> Wanted {
        Wanted::sampled(0.05, |g| if g <= 15.0 { 1.0 } else { 0.0 })
    }

    #[test]
    fn both_sweeps_meet_the_aperture_point() {
        // The revolved reflector's neck and aperture.
        let ends = [[0.006, 0.0], [0.04, -0.06]];
        for sweep in [Sweep::Rising, Sweep::Falling] {
            let mapped = map_profile(&SOURCE, ends, &beam(), sweep).expect("a mapping");
            assert!(
                matches!(mapped.closure, Closure::Exact | Closure::Stretched(_)),
                "{sweep:?}: {:?}",
                mapped.closure
            );
            let n = mapped.points.len();
            // Before the blend onto the end: the quadrature's own landing.
            let m = Mapper::new(&SOURCE, ends, &beam()).expect("a mapper");
            let stretch = match mapped.closure {
                Closure::Stretched(b) => b,
                _ => 1.0,
            };
            let (free, miss) = m
                .profile(&SOURCE, ends[1], sweep, mapped.crossing_share, stretch)
                .expect("a profile");
            assert!(miss < 0.01e-3, "{sweep:?}: lands {:.4} mm off", miss * 1e3);
            assert!((DVec2::from_array(free[n - 1]) - DVec2::from_array(ends[1])).length() < 1e-12);
            assert!(
                (DVec2::from_array(mapped.points[0]) - DVec2::from_array(ends[0])).length() < 1e-12
            );
        }
    }

    #[test]
    fn the_mapped_rays_leave_at_the_angles_the_energy_balance_gives() {
        // Reflect the source's rays off the mapped profile (its
        // polyline's own normals) and bin the flux: the folded output is
        // the wanted beam, whatever the sweep.
        let ends = [[0.006, 0.0], [0.04, -0.06]];
        for sweep in [Sweep::Rising, Sweep::Falling] {
            let mapped = map_profile(&SOURCE, ends, &beam(), sweep).expect("a mapping");
            // Where the crossing share alone could not close it, the
            // beam was stretched to close it: the stretched beam is made.
            let edge =
                15.0 * match mapped.closure {
                    Closure::Stretched(b) => b,
                    _ => 1.0,
                } + 0.05;
            let pts: Vec<DVec2> = mapped
                .points
                .iter()
                .map(|&p| DVec2::from_array(p))
                .collect();
            let (mut inside, mut total) = (0.0, 0.0);
            for w in pts.windows(2) {
                let mid = 0.5 * (w[0] + w[1]);
                let (theta, _) = SOURCE.polar(mid.to_array());
                let (t0, _) = SOURCE.polar(w[0].to_array());
                let (t1, _) = SOURCE.polar(w[1].to_array());
                let flux = PointSource::flux_density(theta) * (t1 - t0).abs();
                let u = DVec2::new(theta.sin(), -theta.cos());
                let tangent = (w[1] - w[0]).normalize();
                let n = DVec2::new(-tangent.y, tangent.x);
                let v = u - 2.0 * u.dot(n) * n;
                let gamma = v.x.abs().atan2(-v.y).to_degrees();
                total += flux;
                if gamma <= edge {
                    inside += flux;
                }
            }
            assert!(
                inside / total > 0.995,
                "{sweep:?}: {:.4} inside",
                inside / total
            );
        }
    }

    #[test]
    fn control_points_lie_on_the_curve_at_equal_lengths() {
        let curve: Vec<[f64; 2]> = (0..=1000)
            .map(|i| {
                let t = i as f64 / 1000.0 * std::f64::consts::FRAC_PI_2;
                [t.cos(), t.sin()]
            })
            .collect();
        let cps = control_points(&curve, 5);
        for (k, p) in cps.iter().enumerate() {
            let angle = p[1].atan2(p[0]);
            assert!((angle - k as f64 / 4.0 * std::f64::consts::FRAC_PI_2).abs() < 1e-5);
        }
    }
}
