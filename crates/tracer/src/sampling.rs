//! Direction sampling and the optics of each material, shared by the CPU
//! tracer (and mirrored in WGSL).

use std::f32::consts::TAU;

use glam::Vec3A;
use lucerna_photometry::CandelaTable;

/// Orthonormal basis (t, b, n) around a unit normal (Duff et al. 2017).
#[inline]
pub fn basis(n: Vec3A) -> (Vec3A, Vec3A) {
    let sign = 1.0f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        Vec3A::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        Vec3A::new(b, sign + n.y * n.y * a, -n.y),
    )
}

/// Cosine-weighted direction about `n` (pdf cos θ / π).
#[inline]
pub fn cosine_hemisphere(n: Vec3A, u1: f32, u2: f32) -> Vec3A {
    let r = u1.sqrt();
    let phi = TAU * u2;
    let (t, b) = basis(n);
    let z = (1.0 - u1).max(0.0).sqrt();
    (t * (r * phi.cos()) + b * (r * phi.sin()) + n * z).normalize()
}

/// Mirror reflection of `d` about unit `n`.
#[inline]
pub fn reflect(d: Vec3A, n: Vec3A) -> Vec3A {
    d - n * (2.0 * d.dot(n))
}

/// Unpolarised Fresnel reflectance of a smooth dielectric interface for
/// incidence cosine `cos_i` (> 0) and relative index `eta = n_i / n_t`;
/// 1 under total internal reflection. Also returns cos θ_t.
#[inline]
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> (f32, f32) {
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin2_t >= 1.0 {
        return (1.0, 0.0);
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    (0.5 * (rs * rs + rp * rp), cos_t)
}

/// GGX Smith Λ for a direction in the local frame (z = normal).
#[inline]
pub fn ggx_lambda(w: Vec3A, ax: f32, ay: f32) -> f32 {
    let z2 = w.z * w.z;
    if z2 <= 0.0 {
        return f32::INFINITY;
    }
    let a2 = (ax * ax * w.x * w.x + ay * ay * w.y * w.y) / z2;
    0.5 * (-1.0 + (1.0 + a2).sqrt())
}

/// A GGX microfacet normal sampled from the distribution of normals visible
/// from `wo` (Heitz 2018, "Sampling the GGX Distribution of Visible
/// Normals"), local frame.
#[inline]
pub fn sample_ggx_vndf(wo: Vec3A, ax: f32, ay: f32, u1: f32, u2: f32) -> Vec3A {
    let vh = Vec3A::new(ax * wo.x, ay * wo.y, wo.z).normalize();
    let len2 = vh.x * vh.x + vh.y * vh.y;
    let t1 = if len2 > 0.0 {
        Vec3A::new(-vh.y, vh.x, 0.0) / len2.sqrt()
    } else {
        Vec3A::X
    };
    let t2 = vh.cross(t1);
    let r = u1.sqrt();
    let phi = TAU * u2;
    let p1 = r * phi.cos();
    let s = 0.5 * (1.0 + vh.z);
    let p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * r * phi.sin();
    let nh = t1 * p1 + t2 * p2 + vh * (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt();
    Vec3A::new(ax * nh.x, ay * nh.y, nh.z.max(1e-7)).normalize()
}

/// Importance sampling of a measured emission profile: a piecewise-constant
/// density over the table's cells (C-plane × γ cell), each weighted by its
/// intensity times its solid angle; within a cell, uniform in solid angle.
#[derive(Debug, Clone)]
pub struct ProfileSampler {
    /// Cell C bounds (radians), one pair per C-plane.
    c_bounds: Vec<(f32, f32)>,
    /// Cell cos γ bounds, one pair per γ angle (cos decreasing).
    cos_bounds: Vec<(f32, f32)>,
    /// Cumulative probability over cells, c-major.
    cdf: Vec<f32>,
}

impl ProfileSampler {
    /// `None` when the table carries no flux at all.
    pub fn new(table: &CandelaTable) -> Option<ProfileSampler> {
        let c = &table.c_planes_deg;
        let g = &table.gammas_deg;
        let c_bounds: Vec<(f32, f32)> = if c.len() == 1 {
            vec![(0.0, TAU)]
        } else {
            (0..c.len())
                .map(|i| {
                    let prev = (c[i] - c[(i + c.len() - 1) % c.len()]).rem_euclid(360.0);
                    let next = (c[(i + 1) % c.len()] - c[i]).rem_euclid(360.0);
                    (
                        (c[i] - 0.5 * prev).to_radians() as f32,
                        (c[i] + 0.5 * next).to_radians() as f32,
                    )
                })
                .collect()
        };
        let mut edges = vec![g[0]];
        edges.extend(g.windows(2).map(|w| 0.5 * (w[0] + w[1])));
        edges.push(g[g.len() - 1]);
        let cos_bounds: Vec<(f32, f32)> = (0..g.len())
            .map(|j| {
                (
                    edges[j].to_radians().cos() as f32,
                    edges[j + 1].to_radians().cos() as f32,
                )
            })
            .collect();
        let mut cdf = Vec::with_capacity(c.len() * g.len());
        let mut total = 0.0f64;
        for (i, (c0, c1)) in c_bounds.iter().enumerate() {
            for (j, (z0, z1)) in cos_bounds.iter().enumerate() {
                let omega = f64::from(c1 - c0) * f64::from(z0 - z1);
                total += table.candela[i * g.len() + j] * omega.max(0.0);
                cdf.push(total as f32);
            }
        }
        if total <= 0.0 {
            return None;
        }
        for v in &mut cdf {
            *v /= total as f32;
        }
        Some(ProfileSampler {
            c_bounds,
            cos_bounds,
            cdf,
        })
    }

    /// The sampler as the WGSL kernel reads it: C bounds (2 per plane),
    /// cos γ bounds (2 per angle), CDF (planes × angles).
    pub fn packed(&self) -> (u32, u32, Vec<f32>) {
        let mut v = Vec::with_capacity(
            2 * self.c_bounds.len() + 2 * self.cos_bounds.len() + self.cdf.len(),
        );
        v.extend(self.c_bounds.iter().flat_map(|&(a, b)| [a, b]));
        v.extend(self.cos_bounds.iter().flat_map(|&(a, b)| [a, b]));
        v.extend_from_slice(&self.cdf);
        (self.c_bounds.len() as u32, self.cos_bounds.len() as u32, v)
    }

    /// Number of cells (for tests binning samples by cell).
    pub fn cell_count(&self) -> usize {
        self.cdf.len()
    }

    /// Probability of cell `k`.
    pub fn cell_probability(&self, k: usize) -> f32 {
        self.cdf[k] - if k == 0 { 0.0 } else { self.cdf[k - 1] }
    }

    /// The cell a local direction falls in.
    pub fn cell_of(&self, d: Vec3A) -> usize {
        let cos_g = -d.z;
        let c = d.y.atan2(d.x).rem_euclid(TAU);
        let ng = self.cos_bounds.len();
        let j = self
            .cos_bounds
            .iter()
            .position(|&(z0, z1)| cos_g <= z0 && cos_g >= z1)
            .unwrap_or(ng - 1);
        let i = self
            .c_bounds
            .iter()
            .position(|&(c0, c1)| {
                let x = (c - c0).rem_euclid(TAU);
                x < c1 - c0
            })
            .unwrap_or(0);
        i * ng + j
    }

    /// A direction in the emitter's local frame (nadir −z).
    pub fn sample(&self, u_cell: f32, u1: f32, u2: f32) -> Vec3A {
        let k = self
            .cdf
            .partition_point(|&p| p <= u_cell)
            .min(self.cdf.len() - 1);
        let ng = self.cos_bounds.len();
        let (c0, c1) = self.c_bounds[k / ng];
        let (z0, z1) = self.cos_bounds[k % ng];
        let c = c0 + (c1 - c0) * u1;
        let cos_g = z0 + (z1 - z0) * u2;
        let sin_g = (1.0 - cos_g * cos_g).max(0.0).sqrt();
        Vec3A::new(sin_g * c.cos(), sin_g * c.sin(), -cos_g)
    }
}

/// Photons from a TM-25 ray file: a ray chosen in proportion to its
/// luminous flux by Walker's alias method (constant time per photon), its
/// start and direction as the file gives them. The file's rays are held
/// once, here.
#[derive(Debug)]
pub struct RaySampler {
    pub rays: lucerna_photometry::tm25::RaySet,
    /// Per ray: the probability of keeping it, and the ray taken instead.
    alias: Vec<(f32, u32)>,
    /// The rays' luminous flux summed once (lm): a panel showing it every
    /// frame must not add up 20 M rays each time.
    pub total_lm: f64,
    /// The phase-space kernel new rays are drawn with, cross-validated
    /// once on first use (about a second) and kept with the rays.
    kernel: std::sync::OnceLock<Option<crate::ray_kernel::RayKernel>>,
}

/// Walker's alias table of `probabilities` (summing to 1) by Vose's
/// construction: per entry, the probability of keeping it and the entry
/// taken otherwise, so one uniform entry and one uniform keep test draw
/// an entry in proportion in constant time.
pub fn alias_table(probabilities: impl IntoIterator<Item = f64>) -> Vec<(f32, u32)> {
    let mut scaled: Vec<f64> = probabilities.into_iter().collect();
    let n = scaled.len();
    scaled.iter_mut().for_each(|p| *p *= n as f64);
    let mut alias: Vec<(f32, u32)> = (0..n as u32).map(|i| (1.0, i)).collect();
    let (mut small, mut large): (Vec<u32>, Vec<u32>) =
        (0..n as u32).partition(|&i| scaled[i as usize] < 1.0);
    while let (Some(s), Some(&l)) = (small.pop(), large.last()) {
        alias[s as usize] = (scaled[s as usize] as f32, l);
        scaled[l as usize] -= 1.0 - scaled[s as usize];
        if scaled[l as usize] < 1.0 {
            large.pop();
            small.push(l);
        }
    }
    alias
}

impl RaySampler {
    /// `None` when the rays carry no flux.
    pub fn new(rays: lucerna_photometry::tm25::RaySet) -> Option<RaySampler> {
        let n = rays.len();
        let total = rays.total_luminous_flux_lm();
        if n == 0 || !(total > 0.0) {
            return None;
        }
        let alias = alias_table(rays.luminous_flux_lm.iter().map(|&f| f64::from(f) / total));
        Some(RaySampler {
            rays,
            alias,
            total_lm: total,
            kernel: std::sync::OnceLock::new(),
        })
    }

    /// The file's cross-validated kernel ([`crate::ray_kernel`]).
    pub fn kernel(&self) -> Option<crate::ray_kernel::RayKernel> {
        *self
            .kernel
            .get_or_init(|| crate::ray_kernel::cross_validated(&self.rays))
    }

    /// A ray as [`RaySampler::sample`] gives it, its direction turned by
    /// `kernel` with two more uniforms (a Box–Muller pair), as the WGSL
    /// kernel draws them.
    #[inline(always)]
    pub fn sample_turned(
        &self,
        column: u32,
        u: f32,
        kernel: &crate::ray_kernel::RayKernel,
        more: [f32; 2],
    ) -> (Vec3A, Vec3A) {
        use crate::ray_kernel::{normal_pair, turned};
        let (p, d) = self.sample(column, u);
        let (n0, n1) = normal_pair(more[0], more[1]);
        let w = kernel.direction_rad;
        (p, turned(d, (n0 * w, n1 * w)))
    }

    /// The ray for a uniform `column` (all 32 bits: a 20 M-ray file needs
    /// more than a float's 24) and uniform `u` (keep or alias): start (m)
    /// and unit direction, the file's frame.
    #[inline(always)]
    pub fn sample(&self, column: u32, u: f32) -> (Vec3A, Vec3A) {
        let n = self.alias.len();
        let i = ((u64::from(column) * n as u64) >> 32) as usize;
        let (keep, other) = self.alias[i];
        let k = if u < keep { i } else { other as usize };
        let p = self.rays.position_mm(k);
        let d = self.rays.direction(k);
        (
            Vec3A::from_array(p) * 1e-3,
            Vec3A::from_array(d).normalize(),
        )
    }

    /// Per ray, for the GPU: start (m), unit direction, keep probability
    /// and alias (its bits as f32).
    pub fn packed(&self) -> Vec<f32> {
        let mut out = Vec::with_capacity(8 * self.alias.len());
        for (i, &(keep, other)) in self.alias.iter().enumerate() {
            let p = Vec3A::from_array(self.rays.position_mm(i)) * 1e-3;
            let d = Vec3A::from_array(self.rays.direction(i)).normalize();
            out.extend([p.x, p.y, p.z, d.x, d.y, d.z, keep, f32::from_bits(other)]);
        }
        out
    }
}

#[cfg(test)]
mod ray_sampler_tests {
    use super::*;
    use lucerna_photometry::tm25::{RayFileHeader, RaySet};

    #[test]
    fn rays_are_chosen_in_proportion_to_their_flux() {
        // Fluxes 1, 2, 3, 4 (and a dark ray): chosen 10, 20, 30, 40 %.
        let fluxes = [1.0f32, 0.0, 2.0, 3.0, 4.0];
        let mut records = Vec::new();
        for (i, f) in fluxes.iter().enumerate() {
            records.extend([i as f32, 0.0, 0.0, 0.0, 0.0, -2.0, *f]);
        }
        let rays = RaySet {
            header: RayFileHeader::luminous(5, 10.0),
            records,
            luminous_flux_lm: fluxes.to_vec(),
        };
        let sampler = RaySampler::new(rays).unwrap();
        let mut counts = [0u32; 5];
        let n = 100_000;
        let mut rng = crate::rng::PhotonRng::new(3, 0, 0);
        for _ in 0..n {
            let (p, d) = sampler.sample(rng.next_u32(), rng.next_f32());
            assert_eq!(d, Vec3A::NEG_Z);
            counts[(p.x * 1000.0).round() as usize] += 1;
        }
        assert_eq!(counts[1], 0);
        for (i, want) in [(0, 0.1), (2, 0.2), (3, 0.3), (4, 0.4)] {
            let got = f64::from(counts[i]) / f64::from(n);
            assert!((got - want).abs() < 0.005, "ray {i}: {got} vs {want}");
        }
    }
}
