//! A finish where a photon lands: the finish's u and v directions, its
//! normals band tilting the shading normal, and a visible facet of its
//! BRDF band ([`crate::finish_brdf`]). The CPU tracer's; the WGSL kernel
//! has the BRDF band's twin.

use glam::Vec3A;
use lucerna_scene::finish_layout::{FinishLayout, SurfacePoint};

use crate::bvh::Hit;
use crate::finish_brdf::FinishBrdf;
use crate::prepared::{PreparedScene, TraceFinish};
use crate::rng::PhotonRng;
use crate::sampling::basis;

/// The finish's unit directions at a point: u along the profile (as its
/// coordinate grows), v around or along the part.
#[derive(Debug, Clone, Copy)]
pub struct Tangents {
    pub u: Vec3A,
    pub v: Vec3A,
}

/// The finish's directions at `position` on a surface whose own (not
/// facing) shading normal is `n`.
#[inline]
pub fn tangents(f: &TraceFinish, position: Vec3A, n: Vec3A) -> Tangents {
    let v = v_direction(f, position, n);
    let u = v.cross(n).normalize_or_zero() * f.handedness;
    Tangents { u, v }
}

/// The unit v direction at `position` across the normal `n`: the f32
/// twin of `TangentRule::v_direction`, any direction across `n` where
/// the rule has none (on the axis).
#[inline(always)]
fn v_direction(f: &TraceFinish, position: Vec3A, n: Vec3A) -> Vec3A {
    let v = if f.around {
        f.axis.cross(position - f.origin)
    } else {
        f.axis
    };
    let v = v - n * v.dot(n);
    if v.length_squared() > 1e-20 {
        v.normalize()
    } else {
        basis(n).1
    }
}

/// The shading normal tilted by the finish's normals band at the hit:
/// n − s_u·u − s_v·v for the band's slopes s, from the surface
/// coordinates interpolated over the triangle's corners.
#[inline]
pub fn normals_band(
    scene: &PreparedScene,
    f: &TraceFinish,
    hit: &Hit,
    n: Vec3A,
    t: Tangents,
) -> Vec3A {
    let s = &f.surface;
    let Some(band) = &s.normals else {
        return n;
    };
    let Some(corners) = scene.finish_corners.get(hit.triangle as usize) else {
        return n;
    };
    let revolution = matches!(s.layout, FinishLayout::Revolution(_));
    let w = [1.0 - hit.u - hit.v, hit.u, hit.v].map(f64::from);
    let v0 = f64::from(corners[0][1]);
    let mut at = [0.0f64; 3];
    for (k, c) in corners.iter().enumerate() {
        let mut v = f64::from(c[1]);
        if revolution {
            // The same turn as the first corner (a triangle across φ = ±π).
            v = v0 + (v - v0 + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU)
                - std::f64::consts::PI;
        }
        at[0] += w[k] * f64::from(c[0]);
        at[1] += w[k] * v;
        at[2] += w[k] * f64::from(c[2]);
    }
    let point = SurfacePoint {
        u: at[0],
        v: at[1],
        radius: revolution.then_some(at[2]),
    };
    match s.layout.slope(band, point) {
        Some([su, sv]) => (n - t.u * su as f32 - t.v * sv as f32).normalize_or(n),
        None => n,
    }
}

/// A facet of the BRDF band visible from the photon arriving along
/// `dir` on the side of the facing shading normal `ns` (the part's own
/// normal there, or the normals band's tilt of it, `n_own` before it
/// faced the photon); None where none was accepted (the photon is lost).
#[inline(always)]
pub fn facet(
    f: &TraceFinish,
    brdf: &FinishBrdf,
    position: Vec3A,
    n_own: Vec3A,
    ns: Vec3A,
    dir: Vec3A,
    rng: &mut PhotonRng,
) -> Option<Vec3A> {
    // v by the part's rule, made exactly across ns; u = handedness ·
    // v × n_own, which is ± v × ns as ns faces the photon.
    let v = v_direction(f, position, ns);
    let sense = if ns.dot(n_own) >= 0.0 { 1.0 } else { -1.0 };
    let u = v.cross(ns) * (f.handedness * sense);
    let wo = -dir;
    let local = Vec3A::new(wo.dot(u), wo.dot(v), wo.dot(ns));
    if local.z <= 0.0 {
        return None;
    }
    let m = brdf.facet(local, || rng.next_f32())?;
    Some((u * m.x + v * m.y + ns * m.z).normalize())
}
