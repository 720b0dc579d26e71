//! New rays drawn from a ray file's phase-space density, so a bake of
//! more photons than the file has rays gets no spikes from rays used
//! again and again.
//!
//! A maker ships 10⁵–10⁶ rays; a final bake traces 10⁸ and more. Looping
//! over the file puts each ray's photons on the same texel: a 100 k-ray
//! LED baked with 2 M photons peaks at three times its rays' own peak.
//! Instead each photon takes a ray (by its flux) and turns its direction
//! by a Gaussian kernel: the smoothed bootstrap of a kernel density
//! estimate, as JMO's InterpolateRaySet moves toward a nearest neighbour.
//! The kernel's width is the rays' own spread of direction times a factor
//! β chosen by likelihood cross-validation on the file's rays in phase
//! space (position × direction, each axis over its spread): the β under
//! which held-out rays are likeliest given the rest. Data decide, no
//! constant tuned to a file.
//!
//! The start stays where the file puts it. A start moved by the same β
//! leaves the source's surfaces (a 3 mm die's rays start up to 0.3 mm
//! outside it), and a parabolic spot images its source: its beam then
//! differs from the native disk's by 3.4 times the file's own noise
//! (χ²/dof, `tests/ray_file.rs`), against 0.6 with the starts kept. A
//! turned direction from a kept start is a ray the source could send, and
//! already makes every photon a distinct ray.
//!
//! The kernel cannot add information: a table baked from it keeps the
//! file's own noise, which is why the bake's uncertainty counts distinct
//! rays ([`effective_photons`]).

use rayon::prelude::*;

use lucerna_photometry::tm25::RaySet;

/// What a bake does when it wants more photons than the file has rays.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum RayReuse {
    /// Each photon a ray whose direction is turned by the file's
    /// cross-validated kernel.
    #[default]
    Interpolate,
    /// Each photon exactly a ray of the file (rays used again as they are).
    Loop,
}

/// The kernel's width: a Gaussian standard deviation of the direction
/// across the ray (radians, each of two tangent axes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RayKernel {
    pub direction_rad: f32,
    /// The factor β the cross-validation chose, carried to the number
    /// of rays the file has.
    pub beta: f64,
    /// How many rays the cross-validation held out.
    pub held_out: usize,
}

impl RayKernel {
    /// The angular width in degrees, for reports.
    pub fn direction_deg(&self) -> f64 {
        f64::from(self.direction_rad).to_degrees()
    }
}

/// At most this many rays form the reference set the held-out rays are
/// scored against, and at most this many are held out: enough to place β
/// within a few per cent (its log-likelihood is smooth in β), small
/// enough to take about a second on two cores for any file.
const REFERENCE_RAYS: usize = 10_000;
const HELD_OUT_RAYS: usize = 1_000;
/// Candidates for β: geometric between these, this many.
const BETA_MIN: f64 = 1e-3;
const BETA_MAX: f64 = 1.0;
const BETA_STEPS: usize = 31;
/// A position axis whose spread is below this share of the largest is
/// flat (rays leaving a plane): it gets no kernel and no dimension.
const FLAT_AXIS: f64 = 1e-6;

/// Per ray: normalised coordinates (positions over their spreads, the
/// direction over its spread), with the flat axes left out.
struct Normalised {
    dims: usize,
    coords: Vec<[f64; 6]>,
    weights: Vec<f64>,
    spread_dir: f64,
}

fn normalised(rays: &RaySet) -> Option<Normalised> {
    let n = rays.len();
    let w: Vec<f64> = rays
        .luminous_flux_lm
        .iter()
        .map(|&f| f64::from(f))
        .collect();
    let total: f64 = w.iter().sum();
    if n < 2 || !(total > 0.0) {
        return None;
    }
    let mut mean = [0.0f64; 6];
    for (i, wi) in w.iter().enumerate() {
        let p = rays.position_mm(i);
        let d = unit(rays.direction(i));
        for k in 0..3 {
            mean[k] += wi * f64::from(p[k]);
            mean[3 + k] += wi * d[k];
        }
    }
    mean.iter_mut().for_each(|m| *m /= total);
    let mut var = [0.0f64; 6];
    for (i, wi) in w.iter().enumerate() {
        let p = rays.position_mm(i);
        let d = unit(rays.direction(i));
        for k in 0..3 {
            var[k] += wi * (f64::from(p[k]) - mean[k]).powi(2);
            var[3 + k] += wi * (d[k] - mean[3 + k]).powi(2);
        }
    }
    var.iter_mut().for_each(|v| *v /= total);
    let spread_mm = [var[0].sqrt(), var[1].sqrt(), var[2].sqrt()];
    // The direction's spread per tangent axis: the mean squared distance
    // from the mean direction shared over the sphere's two dimensions.
    let spread_dir = ((var[3] + var[4] + var[5]) / 2.0).sqrt();
    let largest = spread_mm.iter().copied().fold(0.0, f64::max);
    let position_axes: Vec<usize> = (0..3)
        .filter(|&k| spread_mm[k] > FLAT_AXIS * largest.max(1e-12))
        .collect();
    if !(spread_dir > 0.0) {
        return None;
    }
    let coords = (0..n)
        .map(|i| {
            let p = rays.position_mm(i);
            let d = unit(rays.direction(i));
            let mut c = [0.0; 6];
            for (slot, &k) in position_axes.iter().enumerate() {
                c[slot] = f64::from(p[k]) / spread_mm[k];
            }
            let at = position_axes.len();
            for k in 0..3 {
                c[at + k] = d[k] / spread_dir;
            }
            c
        })
        .collect();
    Some(Normalised {
        // The direction lies on a sphere: two dimensions of the three.
        dims: position_axes.len() + 2,
        coords,
        weights: w,
        spread_dir,
    })
}

fn unit(d: [f32; 3]) -> [f64; 3] {
    let d = d.map(f64::from);
    let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    d.map(|x| x / l)
}

/// The kernel cross-validation chooses for `rays`; None for a set with
/// fewer than two rays or no spread of direction (nothing to smooth).
///
/// Held out: every k-th ray (up to [`HELD_OUT_RAYS`]); reference: a
/// stride of the rest (up to [`REFERENCE_RAYS`]). β maximises the
/// held-out rays' flux-weighted mean log density under the reference
/// rays' kernel estimate; the β so found suits a set of the reference's
/// size, and is carried to the file's by the kernel estimate's rate,
/// n^(−1/(d+4)).
pub fn cross_validated(rays: &RaySet) -> Option<RayKernel> {
    let set = normalised(rays)?;
    let n = set.coords.len();
    let held_stride = (n / HELD_OUT_RAYS.min(n / 2).max(1)).max(2);
    let held: Vec<usize> = (0..n).step_by(held_stride).collect();
    let rest: Vec<usize> = (0..n).filter(|i| i % held_stride != 0).collect();
    let ref_stride = rest.len().div_ceil(REFERENCE_RAYS).max(1);
    let reference: Vec<usize> = rest.iter().copied().step_by(ref_stride).collect();
    let betas: Vec<f64> = (0..BETA_STEPS)
        .map(|k| BETA_MIN * (BETA_MAX / BETA_MIN).powf(k as f64 / (BETA_STEPS - 1) as f64))
        .collect();
    let dims = set.dims as f64;
    // Per held-out ray, its log density (up to a constant) at each β.
    let scores: Vec<(f64, Vec<f64>)> = held
        .par_iter()
        .map(|&i| {
            let ci = &set.coords[i];
            let q: Vec<(f64, f64)> = reference
                .iter()
                .map(|&j| {
                    let cj = &set.coords[j];
                    let d2: f64 = (0..6).map(|k| (ci[k] - cj[k]).powi(2)).sum();
                    (d2, set.weights[j])
                })
                .collect();
            let q_min = q.iter().map(|x| x.0).fold(f64::INFINITY, f64::min);
            let per_beta = betas
                .iter()
                .map(|&b| {
                    let s = 0.5 / (b * b);
                    let sum: f64 = q
                        .iter()
                        .filter(|(d2, _)| (d2 - q_min) * s < 40.0)
                        .map(|(d2, w)| w * (-(d2 - q_min) * s).exp())
                        .sum();
                    -q_min * s + sum.max(1e-300).ln() - dims * b.ln()
                })
                .collect();
            (set.weights[i], per_beta)
        })
        .collect();
    let total_w: f64 = scores.iter().map(|s| s.0).sum();
    if !(total_w > 0.0) {
        return None;
    }
    let mean = |k: usize| scores.iter().map(|(w, s)| w * s[k]).sum::<f64>() / total_w;
    let (best, _) = (0..betas.len())
        .map(|k| (k, mean(k)))
        .fold((0, f64::NEG_INFINITY), |a, b| if b.1 > a.1 { b } else { a });
    let beta_ref = betas[best];
    let beta = beta_ref * (reference.len() as f64 / n as f64).powf(1.0 / (dims + 4.0));
    Some(RayKernel {
        direction_rad: (beta * set.spread_dir) as f32,
        beta,
        held_out: held.len(),
    })
}

/// `d` (unit) turned by `across` radians along each of two axes across
/// it, `t1` and `t2` of the same orthonormal basis the WGSL kernel builds
/// (Duff et al. 2017).
#[inline(always)]
pub fn turned(d: glam::Vec3A, across: (f32, f32)) -> glam::Vec3A {
    let sign = 1.0f32.copysign(d.z);
    let a = -1.0 / (sign + d.z);
    let b = d.x * d.y * a;
    let t1 = glam::Vec3A::new(1.0 + sign * d.x * d.x * a, sign * b, -sign * d.x);
    let t2 = glam::Vec3A::new(b, sign + d.y * d.y * a, -d.y);
    (d + t1 * across.0 + t2 * across.1).normalize()
}

/// Two standard normal deviates from two uniforms in [0, 1) (Box–Muller,
/// in f32 as the WGSL kernel computes them).
#[inline(always)]
pub fn normal_pair(u1: f32, u2: f32) -> (f32, f32) {
    let r = (-2.0 * (1.0 - u1).ln()).sqrt();
    let a = std::f32::consts::TAU * u2;
    (r * a.cos(), r * a.sin())
}

/// The effective number of independent photons of a bake that draws
/// `photons` from a set of `rays`: the rays are themselves a sample, so
/// a figure's relative variance is about 1/photons + 1/rays, whether the
/// rays are looped or interpolated.
pub fn effective_photons(photons: f64, rays: f64) -> f64 {
    if rays > 0.0 && photons > 0.0 {
        1.0 / (1.0 / photons + 1.0 / rays)
    } else {
        photons
    }
}

/// How much a ray file's reuse widens a relative error counted from
/// `photons`: √(photons / effective), 1 without rays.
pub fn noise_inflation(photons: f64, rays: Option<u64>) -> f64 {
    let Some(rays) = rays else {
        return 1.0;
    };
    let effective = effective_photons(photons, rays as f64);
    if effective > 0.0 {
        (photons / effective).sqrt()
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)] // reason: tests may panic
    use super::*;
    use lucerna_photometry::tm25::RayFileHeader;

    fn gaussian_set(n: usize, sigma_mm: f64, sigma_rad: f64) -> RaySet {
        let mut state = 7u64;
        let mut uniform = || {
            state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            ((z ^ (z >> 31)) >> 11) as f32 / (1u64 << 53) as f32
        };
        let mut records = Vec::new();
        for _ in 0..n {
            let (a, b) = normal_pair(uniform(), uniform());
            let (c, d) = normal_pair(uniform(), uniform());
            records.extend([
                a * sigma_mm as f32,
                b * sigma_mm as f32,
                0.0,
                c * sigma_rad as f32,
                d * sigma_rad as f32,
                -1.0,
                1.0,
            ]);
        }
        RaySet {
            header: RayFileHeader::luminous(n as u64, n as f32),
            records,
            luminous_flux_lm: vec![1.0; n],
        }
    }

    #[test]
    fn the_chosen_bandwidth_follows_the_kernel_estimates_rate() {
        // For a Gaussian density the best bandwidth is known in closed
        // form: β = (4 / (d + 2))^(1/(d+4)) n^(−1/(d+4)) for the
        // mean-integrated-squared error; likelihood cross-validation
        // lands near it (within a factor of two), and a set 16 times as
        // large gets a β smaller by 16^(1/(d+4)).
        let d: f64 = 4.0; // x, y and the direction's two
        let rule = |n: f64| (4.0 / (d + 2.0)).powf(1.0 / (d + 4.0)) * n.powf(-1.0 / (d + 4.0));
        let small = cross_validated(&gaussian_set(4_000, 1.0, 0.05)).unwrap();
        let large = cross_validated(&gaussian_set(64_000, 1.0, 0.05)).unwrap();
        for (k, n) in [(small, 4_000.0), (large, 64_000.0)] {
            let ratio = k.beta / rule(n);
            assert!(
                (0.5..2.0).contains(&ratio),
                "n {n}: β {} vs {}",
                k.beta,
                rule(n)
            );
        }
        let shrink = small.beta / large.beta;
        assert!(
            (1.2..2.2).contains(&shrink),
            "16× the rays: β {} → {}",
            small.beta,
            large.beta
        );
        // The direction's width is β times its spread (0.05 rad).
        let k = small;
        let want = k.beta * 0.05;
        assert!((f64::from(k.direction_rad) / want - 1.0).abs() < 0.1);
    }

    #[test]
    fn distinct_rays_bound_the_effective_photons() {
        assert_eq!(effective_photons(1e6, 0.0), 1e6);
        let e = effective_photons(2e6, 1e5);
        assert!(e < 1e5 && e > 0.95e5, "{e}");
        assert!((effective_photons(1e5, 1e5) - 5e4).abs() < 1e-6);
        assert_eq!(noise_inflation(1e6, None), 1.0);
        assert!((noise_inflation(1e5, Some(100_000)) - 2f64.sqrt()).abs() < 1e-12);
    }

    #[test]
    fn box_muller_gives_unit_normals() {
        let mut sum = (0.0f64, 0.0f64);
        let n = 200;
        for i in 0..n {
            for j in 0..n {
                let (a, b) = normal_pair((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                sum.0 += f64::from(a * a + b * b);
                sum.1 += f64::from(a + b);
            }
        }
        let m = (n * n) as f64;
        assert!(
            (sum.0 / (2.0 * m) - 1.0).abs() < 0.02,
            "{}",
            sum.0 / (2.0 * m)
        );
        assert!((sum.1 / m).abs() < 1e-3);
    }
}
