//! The direct design of a revolved reflector for a point source: the
//! reflector's meridian tailored by energy balance, so that the source's
//! flux between two ray angles lands, reflected, in the target's flux
//! between two output angles (what the reflector design literature calls
//! the ray mapping; the profile then follows from the law of reflection
//! as an ODE in the source angle). In polar form about the source,
//! P(θ) = S + ρ(θ)·u(θ), the surface is perpendicular to u − v, where u is
//! the source ray and v the reflected one, so
//! ρ'/ρ = (∂u/∂θ · v) / (1 − u · v).
//!
//! Milliseconds for a start; the tracer in the loop then corrects it for
//! the real, extended source, the package and the end points the designer
//! fixed. Four mappings are made (the reflector's near end to the beam's
//! centre or its edge, rays crossing the axis or not) and the caller keeps
//! the one the tracer likes best.

use glam::{DQuat, DVec2, DVec3};
use lucerna_photometry::CandelaTable;
use lucerna_scene::{Emission, EmitterShape, Interpolation, Material, Scene, Shape};

use crate::model::meridian::MeridianModel;
use crate::target::Target;
use crate::variables::{Place, Variable};

/// Source angles the ODE is integrated over (RK4 steps).
const STEPS: usize = 2000;

/// The direct designs of the revolved profile `variables` vary (interior
/// points, both coordinates), each as the variables' values; empty where
/// none applies (not a revolved profile with fixed ends, no Lambertian
/// emitter on the axis facing along it, a target that is not a
/// distribution the same in every C-plane).
pub fn designs(start: &Scene, variables: &[Variable], target: &Target) -> Vec<Vec<f64>> {
    let Some(setup) = Setup::new(start, variables, target) else {
        return Vec::new();
    };
    let mut out = Vec::new();
    for centre_first in [true, false] {
        for crossing in [false, true] {
            if let Some(points) = setup.profile(centre_first, crossing) {
                out.push(
                    variables
                        .iter()
                        .map(|v| match v.place {
                            Place::ProfilePoint { point, coord, .. } => points[point][coord],
                            Place::Field { .. } => v.start,
                        })
                        .collect(),
                );
            }
        }
    }
    out
}

/// The meridian model of the revolved mirror `variables` vary, and its
/// start profile (r, z control points), where a direct design applies
/// and the mirror is specular (a mirror or a rough conductor, whose
/// roughness the model leaves out).
pub fn meridian_model(
    start: &Scene,
    variables: &[Variable],
    target: &Target,
) -> Option<(MeridianModel, Vec<[f64; 2]>)> {
    let setup = Setup::new(start, variables, target)?;
    let part = &start.parts[setup.part];
    let reflectance = match start.materials.get(&part.material)? {
        Material::Mirror { reflectance } => *reflectance,
        Material::RoughConductor { reflectance, .. } => *reflectance,
        _ => return None,
    };
    let Shape::Revolved(shape) = &part.shape else {
        return None;
    };
    Some((
        MeridianModel {
            source_z: setup.source_z,
            source_radius: setup.source_radius,
            facing_down: setup.facing_down,
            reflectance,
            interpolation: shape.interpolation,
            segments_per_span: shape.segments_per_span,
            gammas_deg: match target {
                Target::Distribution { table, .. } => table.gammas_deg.clone(),
                Target::Spec(_) => Vec::new(),
            },
        },
        setup.points,
    ))
}

/// What a direct design works from, in the part's r-z half-plane.
struct Setup {
    /// The varied part.
    part: usize,
    /// The source on the axis (z, metres) and its radius (a rectangle's:
    /// the disk of its area).
    source_z: f64,
    source_radius: f64,
    /// +1 for a source emitting towards −z (down), −1 towards +z.
    facing_down: bool,
    /// The profile's control points and its two fixed ends.
    points: Vec<[f64; 2]>,
    /// The target's intensity against γ (degrees), averaged over C.
    target: CandelaTable,
}

impl Setup {
    fn new(start: &Scene, variables: &[Variable], target: &Target) -> Option<Setup> {
        let Target::Distribution { table, .. } = target else {
            return None;
        };
        if !target.rotationally_symmetric() {
            return None;
        }
        // One revolved part, its interior points varied (both coordinates),
        // nothing else.
        let part = match variables.first()?.place {
            Place::ProfilePoint { part, .. } => part,
            Place::Field { .. } => return None,
        };
        let varied_ends = variables.iter().any(|v| match v.place {
            Place::ProfilePoint { part: p, point, .. } => {
                p != part
                    || point == 0
                    || matches!(&start.parts[part].shape, Shape::Revolved(s) if point + 1 == s.profile.len())
            }
            Place::Field { .. } => true,
        });
        if varied_ends {
            return None;
        }
        let Shape::Revolved(shape) = &start.parts[part].shape else {
            return None;
        };
        if shape.interpolation != Interpolation::CatmullRom || shape.profile.len() < 3 {
            return None;
        }
        let t = &start.parts[part].transform;
        if t.translate[0] != 0.0
            || t.translate[1] != 0.0
            || t.rotate_deg != [0.0; 3]
            || t.scale != [1.0; 3]
        {
            return None;
        }
        // One Lambertian emitter on the axis, facing along it.
        let emitters: Vec<_> = start.emitters.iter().filter(|e| e.enabled).collect();
        let [emitter] = emitters.as_slice() else {
            return None;
        };
        if emitter.emission != Emission::Lambertian
            || !matches!(
                emitter.shape,
                EmitterShape::Disk { .. } | EmitterShape::Rectangle { .. }
            )
        {
            return None;
        }
        let et = &emitter.transform;
        if et.translate[0].abs() > 1e-9 || et.translate[1].abs() > 1e-9 {
            return None;
        }
        let [rx, ry, rz] = et.rotate_deg.map(f64::to_radians);
        let normal = DQuat::from_euler(glam::EulerRot::ZYX, rz, ry, rx) * DVec3::NEG_Z;
        if normal.x.abs() > 1e-6 || normal.y.abs() > 1e-6 {
            return None;
        }
        let target = axial_profile(table);
        let scale = et.scale[0].abs().max(et.scale[1].abs());
        let source_radius = scale
            * match emitter.shape {
                EmitterShape::Disk { radius } => radius,
                EmitterShape::Rectangle { width, depth } => {
                    (width * depth / std::f64::consts::PI).sqrt()
                }
                _ => return None,
            };
        Some(Setup {
            part,
            source_radius,
            source_z: et.translate[2] - t.translate[2],
            facing_down: normal.z < 0.0,
            points: shape.profile.clone(),
            target,
        })
    }

    /// The source's intensity (relative) at θ from nadir.
    fn source(&self, theta: f64) -> f64 {
        let c = if self.facing_down {
            theta.cos()
        } else {
            -theta.cos()
        };
        c.max(0.0)
    }

    /// θ (from nadir, radians) of a point of the half-plane seen from the
    /// source.
    fn theta_of(&self, p: [f64; 2]) -> f64 {
        p[0].atan2(-(p[1] - self.source_z))
    }

    /// The profile of a design: `centre_first` sends the rays that meet
    /// the reflector nearest the axis of the source's beam (the smaller
    /// θ) to the target's centre; `crossing` reflects them across the
    /// axis.
    fn profile(&self, centre_first: bool, crossing: bool) -> Option<Vec<[f64; 2]>> {
        let n = self.points.len();
        let (first, last) = (self.points[0], self.points[n - 1]);
        let (ta, tb) = (self.theta_of(first), self.theta_of(last));
        // Integrate from the end further from nadir (the neck, usually)
        // towards the other; blend onto the other end afterwards.
        let (start_point, end_point, t_start, t_end) = if ta > tb {
            (first, last, ta, tb)
        } else {
            (last, first, tb, ta)
        };
        let (lo, hi) = (t_end.min(t_start), t_end.max(t_start));
        if !(hi - lo > 1e-3) {
            return None;
        }
        // Source flux on the reflector, cumulative from `lo` (∝ I sin θ).
        let k = STEPS;
        let thetas: Vec<f64> = (0..=k)
            .map(|i| lo + (hi - lo) * i as f64 / k as f64)
            .collect();
        let mut source_cdf = vec![0.0; k + 1];
        for i in 1..=k {
            let f = |t: f64| self.source(t) * t.sin();
            source_cdf[i] =
                source_cdf[i - 1] + 0.5 * (f(thetas[i - 1]) + f(thetas[i])) * (hi - lo) / k as f64;
        }
        let reflected = source_cdf[k];
        if !(reflected > 0.0) {
            return None;
        }
        // The direct light (θ below the reflector's lower edge) leaves as
        // it is; the reflector must make the rest of the target.
        let direct = |g: f64| if g < lo { self.source(g) } else { 0.0 };
        let gammas: Vec<f64> = (0..=1800).map(|i| (i as f64 * 0.1).to_radians()).collect();
        let target_raw: Vec<f64> = gammas
            .iter()
            .map(|g| self.target.intensity(0.0, g.to_degrees()))
            .collect();
        let flux = |v: &dyn Fn(usize) -> f64| {
            (1..gammas.len())
                .map(|i| {
                    0.5 * (v(i - 1) * gammas[i - 1].sin() + v(i) * gammas[i].sin())
                        * (gammas[i] - gammas[i - 1])
                })
                .sum::<f64>()
        };
        let direct_flux = flux(&|i| direct(gammas[i]));
        let target_flux = flux(&|i| target_raw[i]);
        if !(target_flux > 0.0) {
            return None;
        }
        let scale = (direct_flux + reflected) / target_flux;
        let wanted: Vec<f64> = (0..gammas.len())
            .map(|i| (scale * target_raw[i] - direct(gammas[i])).max(0.0))
            .collect();
        let mut target_cdf = vec![0.0; gammas.len()];
        for i in 1..gammas.len() {
            target_cdf[i] = target_cdf[i - 1]
                + 0.5
                    * (wanted[i - 1] * gammas[i - 1].sin() + wanted[i] * gammas[i].sin())
                    * (gammas[i] - gammas[i - 1]);
        }
        let total = target_cdf[gammas.len() - 1];
        if !(total > 0.0) {
            return None;
        }
        // γ of the source ray at θ: equal shares of the two fluxes.
        let gamma_of = |theta: f64| -> f64 {
            let x = ((theta - lo) / (hi - lo) * k as f64).clamp(0.0, k as f64);
            let i = (x as usize).min(k - 1);
            let share =
                (source_cdf[i] + (x - i as f64) * (source_cdf[i + 1] - source_cdf[i])) / reflected;
            let share = if centre_first { share } else { 1.0 - share };
            let goal = share * total;
            let j = target_cdf
                .partition_point(|&c| c < goal)
                .clamp(1, gammas.len() - 1);
            let (c0, c1) = (target_cdf[j - 1], target_cdf[j]);
            let t = if c1 > c0 {
                (goal - c0) / (c1 - c0)
            } else {
                0.0
            };
            gammas[j - 1] + t * (gammas[j] - gammas[j - 1])
        };
        let sign = if crossing { -1.0 } else { 1.0 };
        let derivative = |theta: f64, rho: f64| -> f64 {
            let u = DVec2::new(theta.sin(), -theta.cos());
            let u_theta = DVec2::new(theta.cos(), theta.sin());
            let g = gamma_of(theta);
            let v = DVec2::new(sign * g.sin(), -g.cos());
            let denominator = 1.0 - u.dot(v);
            if denominator.abs() < 1e-9 {
                return f64::NAN;
            }
            rho * u_theta.dot(v) / denominator
        };
        // RK4 from the start end towards the other.
        let source = DVec2::new(0.0, self.source_z);
        let mut rho = (DVec2::from_array(start_point) - source).length();
        let h = (t_end - t_start) / k as f64;
        let mut curve = vec![DVec2::from_array(start_point)];
        let mut theta = t_start;
        for _ in 0..k {
            let k1 = derivative(theta, rho);
            let k2 = derivative(theta + 0.5 * h, rho + 0.5 * h * k1);
            let k3 = derivative(theta + 0.5 * h, rho + 0.5 * h * k2);
            let k4 = derivative(theta + h, rho + h * k3);
            rho += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
            theta += h;
            if !(rho.is_finite() && rho > 0.0 && rho < 100.0) {
                return None;
            }
            curve.push(source + rho * DVec2::new(theta.sin(), -theta.cos()));
        }
        // Blend onto the fixed far end, in proportion to arc length.
        let lengths: Vec<f64> = std::iter::once(0.0)
            .chain(curve.windows(2).scan(0.0, |s, w| {
                *s += (w[1] - w[0]).length();
                Some(*s)
            }))
            .collect();
        let length = lengths[lengths.len() - 1];
        if !(length > 0.0) {
            return None;
        }
        let miss = DVec2::from_array(end_point) - curve[curve.len() - 1];
        let blended: Vec<DVec2> = curve
            .iter()
            .zip(&lengths)
            .map(|(p, s)| *p + miss * (s / length))
            .collect();
        // The interior control points at the start profile's arc-length
        // shares along it.
        let start_shares = shares(&self.points);
        let at = |share: f64| -> DVec2 {
            let goal = share * length;
            let j = lengths
                .partition_point(|&s| s < goal)
                .clamp(1, lengths.len() - 1);
            let (s0, s1) = (lengths[j - 1], lengths[j]);
            let t = if s1 > s0 {
                (goal - s0) / (s1 - s0)
            } else {
                0.0
            };
            blended[j - 1] + t * (blended[j] - blended[j - 1])
        };
        let mut out = self.points.clone();
        let from_first = ta > tb;
        for i in 1..n - 1 {
            let share = if from_first {
                start_shares[i]
            } else {
                1.0 - start_shares[i]
            };
            let p = at(share);
            if p.x < 0.0 {
                return None;
            }
            out[i] = [p.x, p.y];
        }
        Some(out)
    }
}

/// Each control point's share of the polyline's length through them.
fn shares(points: &[[f64; 2]]) -> Vec<f64> {
    let mut s = vec![0.0];
    for w in points.windows(2) {
        let d = (DVec2::from_array(w[1]) - DVec2::from_array(w[0])).length();
        s.push(s[s.len() - 1] + d);
    }
    let total = s[s.len() - 1].max(1e-300);
    s.iter().map(|x| x / total).collect()
}

/// The table averaged over C (one plane), on its own γ angles.
fn axial_profile(table: &CandelaTable) -> CandelaTable {
    let n = table.gammas_deg.len();
    let planes = table.c_planes_deg.len() as f64;
    let candela = (0..n)
        .map(|j| {
            (0..table.c_planes_deg.len())
                .map(|i| table.candela[i * n + j])
                .sum::<f64>()
                / planes
        })
        .collect();
    CandelaTable {
        c_planes_deg: vec![0.0],
        gammas_deg: table.gammas_deg.clone(),
        candela,
    }
}
