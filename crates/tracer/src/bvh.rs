//! Bounding-volume hierarchies, built by obvhs (PLOC + reinsertion):
//! - a compressed 8-wide BVH (CWBVH), converted for the CPU into float
//!   eight-wide nodes with four-wide triangle blocks ([`crate::wide_bvh`]),
//!   traversed in AVX2 where the CPU has it;
//! - a BVH2 flattened into 32-byte nodes for the WGSL kernel, traversed on
//!   the CPU too by [`Bvh::intersect_bvh2`], so tests check the GPU layout
//!   and CPUs without AVX2 (or with another architecture) trace with it.
//!
//! Triangles are stored once, in the scene's order; the leaves of both
//! hierarchies reach them through slot → triangle tables, so spatial
//! pre-splits (one triangle in several leaves) cost no duplicate records.
//!
//! Geometry is stored scaled so the luminaire is about [`BVH_EXTENT`] units
//! across: obvhs' CWBVH culls boxes closer than 1e-4 units, which in metres
//! would lose hits within 0.1 mm of a ray's origin (creases, thin gaps).

use bytemuck::{Pod, Zeroable};
use glam::{Vec3, Vec3A};

pub use crate::triangle::{BVH_EXTENT, BvhTriangle, PASS_THROUGH_TAG, unit_normal};

/// One BVH2 node. Inner node: `count == 0`, children at `first` and
/// `first + 1`. Leaf: triangles `first .. first + count` of the reordered
/// triangle array.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable, PartialEq)]
pub struct BvhNode {
    pub min: [f32; 3],
    pub first: u32,
    pub max: [f32; 3],
    pub count: u32,
}
const _: () = assert!(std::mem::size_of::<BvhNode>() == 32);

#[derive(Debug, Clone)]
pub struct Bvh {
    /// BVH units per metre.
    pub scale: f32,
    /// obvhs' CWBVH converted to float boxes and triangle blocks, for
    /// [`CpuTraversal::Avx2`]; `None` off AVX2 or for a tree too deep for
    /// its stack (then the BVH2 is traversed).
    pub wide: Option<crate::wide_bvh::WideBvh>,
    /// The BVH2 for the GPU, built the first time it is asked for: a run
    /// on the CPU (every edit on a machine without a GPU) never pays for it.
    bvh2: std::sync::OnceLock<Bvh2>,
    /// Triangles in the scene's order.
    pub triangles: Vec<BvhTriangle>,
    /// A tag per triangle, handed back with its hits.
    pub tags: Vec<u32>,
    /// Time obvhs took to build the CWBVH (or a refit took).
    pub cwbvh_build_time: std::time::Duration,
    /// How the CPU traverses the CWBVH; the fastest this CPU runs, by
    /// default.
    pub traversal: CpuTraversal,
}

/// The BVH2 in the GPU layout.
#[derive(Debug, Clone)]
pub struct Bvh2 {
    /// Nodes (leaves index `leaf_triangles`).
    pub nodes: Vec<BvhNode>,
    /// For each leaf slot, the index into [`Bvh::triangles`].
    pub leaf_triangles: Vec<u32>,
    pub build_time: std::time::Duration,
}

/// How much a build spends on the tree. The hits do not depend on it
/// (ties go to the lower triangle index), only how fast they are found:
/// a preview of an edit in progress builds quickly and traces a little
/// slower.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BvhQuality {
    /// obvhs' `fast_build`: PLOC, a little reinsertion, no spatial splits.
    Preview,
    /// obvhs' `very_slow_build`: spatial pre-splits, PLOC, full
    /// reinsertion, leaf collapse.
    Final,
}

impl BvhQuality {
    fn params(self) -> obvhs::BvhBuildParams {
        match self {
            BvhQuality::Preview => obvhs::BvhBuildParams::fast_build(),
            BvhQuality::Final => obvhs::BvhBuildParams::very_slow_build(),
        }
    }
}

/// How the CPU finds closest hits.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum CpuTraversal {
    /// The BVH2 of the GPU layout, one box at a time: any CPU. (obvhs' own
    /// CWBVH traversal is not used: its quantised boxes cannot be widened,
    /// and it lost hits on rays through shared edges.)
    Scalar,
    /// The float eight-wide BVH in AVX2 ([`crate::wide_bvh`]); only where
    /// [`crate::cpu_features::available`].
    Avx2,
}

impl CpuTraversal {
    /// The fastest traversal this CPU runs.
    pub fn best() -> CpuTraversal {
        if crate::cpu_features::available() {
            CpuTraversal::Avx2
        } else {
            CpuTraversal::Scalar
        }
    }

    pub fn describe(self) -> &'static str {
        match self {
            CpuTraversal::Scalar => "scalar BVH2",
            CpuTraversal::Avx2 => "AVX2 8-wide float BVH",
        }
    }
}

/// A ray hit: distance, scene triangle index, barycentrics (u, v), and
/// what the tracer needs of the triangle without reading another record:
/// its tag and unit geometric normal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Hit {
    pub t: f32,
    pub triangle: u32,
    pub u: f32,
    pub v: f32,
    /// The tag given to [`Bvh::build`] for the triangle.
    pub tag: u32,
    /// `e1 × e2` normalised (zero for a degenerate triangle): the same
    /// arithmetic on every traversal.
    pub normal: Vec3A,
}

/// BVH units per metre for a luminaire between `lo` and `hi` (m).
fn scale_for(lo: Vec3, hi: Vec3) -> f32 {
    let extent = (hi - lo).max_element();
    if extent.is_finite() && extent > 0.0 {
        BVH_EXTENT / extent
    } else {
        1.0
    }
}

impl Bvh {
    /// Builds both hierarchies at [`BvhQuality::Final`]; corners in
    /// luminaire coordinates (m), and a tag per triangle (zeros if `tags`
    /// is shorter) that hits carry.
    pub fn build(corners: &[[Vec3; 3]], tags: &[u32]) -> Bvh {
        Bvh::build_with(corners, tags, BvhQuality::Final)
    }

    /// [`Bvh::build`] at a chosen quality.
    pub fn build_with(corners: &[[Vec3; 3]], tags: &[u32], quality: BvhQuality) -> Bvh {
        let tags: Vec<u32> = (0..corners.len())
            .map(|i| tags.get(i).copied().unwrap_or(0))
            .collect();
        use std::time::Instant;
        let (lo, hi) = corners.iter().flatten().fold(
            (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        let scale = scale_for(lo, hi);
        let corners: Vec<[Vec3; 3]> = corners.iter().map(|c| c.map(|p| p * scale)).collect();
        let tris: Vec<obvhs::triangle::Triangle> = corners
            .iter()
            .map(|c| obvhs::triangle::Triangle {
                v0: c[0].into(),
                v1: c[1].into(),
                v2: c[2].into(),
            })
            .collect();
        let mut core = std::time::Duration::ZERO;
        let params = quality.params();
        let start = Instant::now();
        let cwbvh = obvhs::cwbvh::builder::build_cwbvh_from_tris(&tris, params, &mut core);
        let cwbvh_build_time = start.elapsed();
        let triangles: Vec<BvhTriangle> = corners.iter().map(|&c| BvhTriangle::new(c)).collect();
        let traversal = CpuTraversal::best();
        let wide = if traversal == CpuTraversal::Avx2 {
            let slot_triangles: Vec<BvhTriangle> = cwbvh
                .primitive_indices
                .iter()
                .map(|&i| triangles[i as usize])
                .collect();
            crate::wide_bvh::WideBvh::from_cwbvh(
                &cwbvh,
                &slot_triangles,
                &cwbvh.primitive_indices,
                &tags,
            )
        } else {
            None
        };
        let traversal = if wide.is_some() {
            traversal
        } else {
            CpuTraversal::Scalar
        };
        Bvh {
            wide,
            scale,
            bvh2: std::sync::OnceLock::new(),
            triangles,
            tags,
            cwbvh_build_time,
            traversal,
        }
    }

    /// This tree over moved corners: the same triangles in the same order
    /// (a drag that changes a focal length moves every vertex of a
    /// reflector and keeps its triangulation), its boxes recomputed
    /// bottom-up in 1–2 ms where a build of the 18k-triangle spot takes
    /// 20–40. The hits are those of a fresh build (they do not depend on
    /// the tree), found a little slower as the tree drifts from the
    /// geometry. `None` where there is nothing to refit (no wide BVH, or
    /// another triangle count): build instead.
    pub fn refit(&self, corners: &[[Vec3; 3]], tags: &[u32]) -> Option<Bvh> {
        let wide = self.wide.as_ref()?;
        if corners.len() != self.triangles.len() || tags.len() != corners.len() {
            return None;
        }
        let start = std::time::Instant::now();
        let (lo, hi) = corners.iter().flatten().fold(
            (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(lo, hi), p| (lo.min(*p), hi.max(*p)),
        );
        let scale = scale_for(lo, hi);
        let triangles: Vec<BvhTriangle> = corners
            .iter()
            .map(|c| BvhTriangle::new(c.map(|p| p * scale)))
            .collect();
        let wide = wide.refitted(&triangles, tags)?;
        Some(Bvh {
            scale,
            wide: Some(wide),
            bvh2: std::sync::OnceLock::new(),
            triangles,
            tags: tags.to_vec(),
            cwbvh_build_time: start.elapsed(),
            traversal: self.traversal,
        })
    }

    /// The BVH2 for the GPU kernel, built on first use at
    /// [`BvhQuality::Final`].
    pub fn bvh2(&self) -> &Bvh2 {
        self.bvh2.get_or_init(|| {
            use std::time::Instant;
            let tris: Vec<obvhs::triangle::Triangle> = self
                .triangles
                .iter()
                .map(|t| {
                    let v0 = Vec3::from_array(t.v0);
                    obvhs::triangle::Triangle {
                        v0: v0.into(),
                        v1: (v0 + Vec3::from_array(t.e1)).into(),
                        v2: (v0 + Vec3::from_array(t.e2)).into(),
                    }
                })
                .collect();
            let mut core = std::time::Duration::ZERO;
            let start = Instant::now();
            let bvh2 = obvhs::bvh2::builder::build_bvh2_from_tris(
                &tris,
                obvhs::BvhBuildParams::very_slow_build(),
                &mut core,
            );
            let nodes = bvh2
                .nodes
                .iter()
                .map(|n| BvhNode {
                    // Widened as the CPU's wide BVH is, so that neither
                    // culls a hit Möller–Trumbore puts just off its
                    // triangle's plane.
                    min: n
                        .aabb()
                        .min
                        .to_array()
                        .map(|x| crate::wide_bvh::outward_down(f64::from(x))),
                    first: n.first_index,
                    max: n
                        .aabb()
                        .max
                        .to_array()
                        .map(|x| crate::wide_bvh::outward_up(f64::from(x))),
                    count: n.prim_count,
                })
                .collect();
            Bvh2 {
                nodes,
                leaf_triangles: bvh2.primitive_indices.clone(),
                build_time: start.elapsed(),
            }
        })
    }

    /// Closest hit along `origin + t·dir` (metres, unit `dir`), t in
    /// (0, t_max), of a surface photons interact with: by the wide BVH in
    /// AVX2 where it is, else by the BVH2.
    #[inline]
    pub fn intersect(&self, origin: Vec3A, dir: Vec3A, t_max: f32) -> Option<Hit> {
        self.closest(
            origin,
            dir,
            t_max,
            crate::wide_traversal::Surfaces::ForPhotons,
        )
    }

    /// [`Bvh::intersect`] of two rays, their traversals interleaved where
    /// the wide BVH runs (each hides the other's waits for memory).
    #[inline]
    pub fn intersect_pair(&self, rays: [(Vec3A, Vec3A); 2], t_max: f32) -> [Option<Hit>; 2] {
        if !self.triangles.is_empty()
            && self.traversal == CpuTraversal::Avx2
            && let Some(wide) = &self.wide
            && crate::cpu_features::available()
        {
            let rays = rays.map(|(o, d)| (o * self.scale, d));
            // SAFETY: the CPU has the features, checked just above.
            #[allow(unsafe_code)]
            let hits = unsafe {
                crate::wide_traversal::closest_hit_pair(
                    wide,
                    rays,
                    t_max * self.scale,
                    crate::wide_traversal::Surfaces::ForPhotons,
                )
            };
            return hits.map(|h| {
                h.map(|h| Hit {
                    t: h.t / self.scale,
                    triangle: h.triangle,
                    u: h.u,
                    v: h.v,
                    tag: h.tag,
                    normal: h.normal,
                })
            });
        }
        rays.map(|(o, d)| self.intersect(o, d, t_max))
    }

    /// [`Bvh::intersect`] of every surface, pass-through ones too (what a
    /// click in the 3D view picks).
    pub fn intersect_any_surface(&self, origin: Vec3A, dir: Vec3A, t_max: f32) -> Option<Hit> {
        self.closest(origin, dir, t_max, crate::wide_traversal::Surfaces::All)
    }

    #[inline(always)]
    fn closest(
        &self,
        origin: Vec3A,
        dir: Vec3A,
        t_max: f32,
        surfaces: crate::wide_traversal::Surfaces,
    ) -> Option<Hit> {
        if self.triangles.is_empty() {
            return None;
        }
        if self.traversal == CpuTraversal::Avx2
            && let Some(wide) = &self.wide
            && crate::cpu_features::available()
        {
            let origin = origin * self.scale;
            // SAFETY: the CPU has the features, checked just above (a
            // cached atomic load).
            #[allow(unsafe_code)]
            let hit = unsafe {
                crate::wide_traversal::closest_hit(wide, origin, dir, t_max * self.scale, surfaces)
            }?;
            return Some(Hit {
                t: hit.t / self.scale,
                triangle: hit.triangle,
                u: hit.u,
                v: hit.v,
                tag: hit.tag,
                normal: hit.normal,
            });
        }
        self.bvh2_closest(origin, dir, t_max, surfaces)
    }

    /// Closest hit of a surface photons interact with by the BVH2 in the
    /// GPU layout: the same stack traversal as the WGSL kernel (nearer
    /// child first).
    pub fn intersect_bvh2(&self, origin: Vec3A, dir: Vec3A, t_max: f32) -> Option<Hit> {
        self.bvh2_closest(
            origin,
            dir,
            t_max,
            crate::wide_traversal::Surfaces::ForPhotons,
        )
    }

    fn bvh2_closest(
        &self,
        origin: Vec3A,
        dir: Vec3A,
        t_max: f32,
        surfaces: crate::wide_traversal::Surfaces,
    ) -> Option<Hit> {
        if self.triangles.is_empty() {
            return None;
        }
        let Bvh2 {
            nodes,
            leaf_triangles,
            ..
        } = self.bvh2();
        if nodes.is_empty() {
            return None;
        }
        let origin = origin * self.scale;
        let t_max = t_max * self.scale;
        let inv = dir.recip();
        let mut best = Hit {
            t: t_max,
            triangle: u32::MAX,
            u: 0.0,
            v: 0.0,
            tag: 0,
            normal: Vec3A::ZERO,
        };
        let mut stack = [0u32; 64];
        let mut top = 0usize;
        let mut node = 0u32;
        slab(&nodes[0], origin, inv, best.t)?;
        loop {
            let n = &nodes[node as usize];
            if n.count > 0 {
                for slot in n.first..n.first + n.count {
                    let i = leaf_triangles[slot as usize];
                    if surfaces == crate::wide_traversal::Surfaces::ForPhotons
                        && self.tags[i as usize] & PASS_THROUGH_TAG != 0
                    {
                        continue;
                    }
                    if let Some((t, u, v)) =
                        intersect_triangle(&self.triangles[i as usize], origin, dir)
                        && (t < best.t || (t == best.t && i < best.triangle))
                    {
                        best = Hit {
                            t,
                            triangle: i,
                            u,
                            v,
                            tag: 0,
                            normal: Vec3A::ZERO,
                        };
                    }
                }
            } else {
                let (a, b) = (n.first, n.first + 1);
                let ta = slab(&nodes[a as usize], origin, inv, best.t);
                let tb = slab(&nodes[b as usize], origin, inv, best.t);
                match (ta, tb) {
                    (Some(ta), Some(tb)) => {
                        let (near, far) = if ta <= tb { (a, b) } else { (b, a) };
                        if top < stack.len() {
                            stack[top] = far;
                            top += 1;
                        }
                        node = near;
                        continue;
                    }
                    (Some(_), None) => {
                        node = a;
                        continue;
                    }
                    (None, Some(_)) => {
                        node = b;
                        continue;
                    }
                    (None, None) => {}
                }
            }
            if top == 0 {
                break;
            }
            top -= 1;
            node = stack[top];
        }
        (best.triangle != u32::MAX).then(|| {
            let tri = &self.triangles[best.triangle as usize];
            Hit {
                t: best.t / self.scale,
                tag: self.tags[best.triangle as usize],
                normal: unit_normal(Vec3A::from_array(tri.e1), Vec3A::from_array(tri.e2)),
                ..best
            }
        })
    }
}

/// Entry distance into a node's box, if it is entered before `t_max`.
#[inline(always)]
fn slab(n: &BvhNode, origin: Vec3A, inv: Vec3A, t_max: f32) -> Option<f32> {
    let t0 = (Vec3A::from_array(n.min) - origin) * inv;
    let t1 = (Vec3A::from_array(n.max) - origin) * inv;
    let near = t0.min(t1).max_element().max(0.0);
    let far = t0.max(t1).min_element().min(t_max);
    (near <= far).then_some(near)
}

/// Möller–Trumbore; returns (t, u, v) for t > 0.
#[inline(always)]
pub fn intersect_triangle(tri: &BvhTriangle, origin: Vec3A, dir: Vec3A) -> Option<(f32, f32, f32)> {
    let e1 = Vec3A::from_array(tri.e1);
    let e2 = Vec3A::from_array(tri.e2);
    let p = dir.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-20 {
        return None;
    }
    let inv_det = 1.0 / det;
    let s = origin - Vec3A::from_array(tri.v0);
    let u = s.dot(p) * inv_det;
    if !(0.0..=1.0).contains(&u) {
        return None;
    }
    let q = s.cross(e1);
    let v = dir.dot(q) * inv_det;
    if v < 0.0 || u + v > 1.0 {
        return None;
    }
    let t = e2.dot(q) * inv_det;
    (t > 0.0).then_some((t, u, v))
}
