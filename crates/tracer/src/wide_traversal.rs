//! Closest-hit traversal of the [`crate::wide_bvh`] layout on AVX2/FMA:
//! nearest child first with distance culling, ties to the lower triangle
//! index, two rays interleaved a step at a time.

use glam::Vec3A;

use crate::wide_bvh::*;

/// 1/x, with zero components of a direction made tiny instead (the slab
/// test then sees a huge but finite reciprocal).
#[inline(always)]
fn safe_reciprocal(x: f32) -> f32 {
    const TINY: f32 = 1e-20;
    if x.abs() < TINY {
        1.0 / TINY.copysign(x)
    } else {
        1.0 / x
    }
}

/// Which surfaces a query sees.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Surfaces {
    /// Those that scatter photons: not [`crate::triangle::PASS_THROUGH_TAG`].
    ForPhotons,
    /// All of them (picking in the editor).
    All,
}

/// A closest hit in BVH units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WideHit {
    pub t: f32,
    /// Scene triangle index.
    pub triangle: u32,
    pub u: f32,
    pub v: f32,
    pub tag: u32,
    /// Unit geometric normal, [`crate::triangle::unit_normal`] of its edges.
    pub normal: Vec3A,
}

/// Closest hit in BVH units, t in (0, t_max).
///
/// # Safety
/// The CPU must have AVX2 and FMA ([`crate::cpu_features::available`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,bmi1")]
pub unsafe fn closest_hit(
    bvh: &WideBvh,
    origin: Vec3A,
    dir: Vec3A,
    t_max: f32,
    surfaces: Surfaces,
) -> Option<WideHit> {
    // SAFETY: the caller guarantees the features.
    unsafe {
        let mut ray = RayTraversal::new(origin, dir, t_max, surfaces);
        while ray.step(bvh) {}
        ray.hit(bvh)
    }
}

/// [`closest_hit`] of two rays at once, their traversals interleaved a
/// node or leaf at a time: one ray's wait for memory (a node, a block)
/// overlaps the other's work, where one ray alone stalls.
///
/// # Safety
/// The CPU must have AVX2 and FMA ([`crate::cpu_features::available`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,bmi1")]
pub unsafe fn closest_hit_pair(
    bvh: &WideBvh,
    rays: [(Vec3A, Vec3A); 2],
    t_max: f32,
    surfaces: Surfaces,
) -> [Option<WideHit>; 2] {
    // SAFETY: the caller guarantees the features.
    unsafe {
        let mut a = RayTraversal::new(rays[0].0, rays[0].1, t_max, surfaces);
        let mut b = RayTraversal::new(rays[1].0, rays[1].1, t_max, surfaces);
        loop {
            let more_a = a.step(bvh);
            let more_b = b.step(bvh);
            if !more_a {
                while b.step(bvh) {}
                break;
            }
            if !more_b {
                while a.step(bvh) {}
                break;
            }
        }
        [a.hit(bvh), b.hit(bvh)]
    }
}

/// One ray's closest-hit traversal, advanced a node or a leaf at a time.
#[cfg(target_arch = "x86_64")]
struct RayTraversal {
    origin: Vec3A,
    dir: Vec3A,
    surfaces: Surfaces,
    /// 1/d and o/d per axis, in all eight lanes.
    inv: [std::arch::x86_64::__m256; 3],
    origin_inv: [std::arch::x86_64::__m256; 3],
    /// Rows of the planes the ray enters and leaves each axis through (a
    /// negative direction component enters through the max plane).
    near: [usize; 3],
    far: [usize; 3],
    t_best: f32,
    /// (t, triangle, u, v) of the closest hit so far, and its block and
    /// lane.
    best: Option<(f32, u32, f32, f32)>,
    best_at: (usize, usize),
    /// The node or leaf the next step visits.
    current: u32,
    sp: usize,
    /// Entries are written before they are read (`sp` counts them).
    stack_ref: [std::mem::MaybeUninit<u32>; STACK_ENTRIES],
    stack_dist: [std::mem::MaybeUninit<f32>; STACK_ENTRIES],
}

#[cfg(target_arch = "x86_64")]
impl RayTraversal {
    /// Inlined into [`closest_hit`] and [`closest_hit_pair`], which enable
    /// the features its intrinsics need: a call per step would cost more
    /// than the interleaving gains.
    #[inline(always)]
    unsafe fn new(origin: Vec3A, dir: Vec3A, t_max: f32, surfaces: Surfaces) -> RayTraversal {
        use std::arch::x86_64::*;
        use std::mem::MaybeUninit;
        let inv = Vec3A::new(
            safe_reciprocal(dir.x),
            safe_reciprocal(dir.y),
            safe_reciprocal(dir.z),
        );
        let origin_inv = origin * inv;
        let near = [
            usize::from(inv.x < 0.0),
            2 + usize::from(inv.y < 0.0),
            4 + usize::from(inv.z < 0.0),
        ];
        // SAFETY: the caller's function enables AVX.
        unsafe {
            RayTraversal {
                origin,
                dir,
                surfaces,
                inv: [
                    _mm256_set1_ps(inv.x),
                    _mm256_set1_ps(inv.y),
                    _mm256_set1_ps(inv.z),
                ],
                origin_inv: [
                    _mm256_set1_ps(origin_inv.x),
                    _mm256_set1_ps(origin_inv.y),
                    _mm256_set1_ps(origin_inv.z),
                ],
                near,
                far: [near[0] ^ 1, near[1] ^ 1, near[2] ^ 1],
                t_best: t_max,
                best: None,
                best_at: (0, 0),
                current: 0,
                sp: 0,
                stack_ref: [MaybeUninit::uninit(); STACK_ENTRIES],
                stack_dist: [MaybeUninit::uninit(); STACK_ENTRIES],
            }
        }
    }

    #[inline(always)]
    unsafe fn push(&mut self, reference: u32, distance: f32) {
        // SAFETY: at most 7·depth + 1 ≤ STACK_ENTRIES entries (checked
        // when the tree was built).
        unsafe {
            self.stack_ref.get_unchecked_mut(self.sp).write(reference);
            self.stack_dist.get_unchecked_mut(self.sp).write(distance);
        }
        self.sp += 1;
    }

    /// Moves to the next stacked entry that can still hold a closer hit;
    /// false when there is none.
    #[inline(always)]
    unsafe fn pop(&mut self) -> bool {
        while self.sp > 0 {
            self.sp -= 1;
            // SAFETY: entries below `sp` were written.
            unsafe {
                if self.stack_dist.get_unchecked(self.sp).assume_init() <= self.t_best {
                    self.current = self.stack_ref.get_unchecked(self.sp).assume_init();
                    return true;
                }
            }
        }
        false
    }

    /// Visits the current node (its hit children, nearest next) or leaf;
    /// false when the traversal has ended. Inlined like
    /// [`RayTraversal::new`].
    #[inline(always)]
    unsafe fn step(&mut self, bvh: &WideBvh) -> bool {
        use std::arch::x86_64::*;
        // SAFETY: the caller's function enables the features; node and
        // block indices come from the converter, which checked them.
        unsafe {
            if self.current & LEAF != 0 {
                if self.current != EMPTY {
                    let index = (self.current & !LEAF) as usize;
                    let block = bvh.blocks.get_unchecked(index);
                    let lanes = match self.surfaces {
                        Surfaces::ForPhotons => block.photon_lanes,
                        Surfaces::All => block.all_lanes,
                    };
                    if let Some((t, lane, u, v)) =
                        block_hit(block, self.origin, self.dir, self.t_best, lanes)
                    {
                        let triangle = *block.triangle.get_unchecked(lane);
                        // Equal distances (a ray through a shared edge) go
                        // to the lower triangle index, whatever the
                        // visiting order: the hit is brute force's.
                        if self
                            .best
                            .is_none_or(|(bt, bi, _, _)| t < bt || triangle < bi)
                        {
                            self.t_best = t;
                            self.best = Some((t, triangle, u, v));
                            self.best_at = (index, lane);
                        }
                    }
                }
                return self.pop();
            }
            let node = bvh.nodes.get_unchecked(self.current as usize);
            let row = |r: usize| _mm256_load_ps(node.planes.get_unchecked(r).as_ptr());
            let [inv_x, inv_y, inv_z] = self.inv;
            let [oi_x, oi_y, oi_z] = self.origin_inv;
            let t_near = _mm256_max_ps(
                _mm256_max_ps(
                    _mm256_fmsub_ps(row(self.near[0]), inv_x, oi_x),
                    _mm256_fmsub_ps(row(self.near[1]), inv_y, oi_y),
                ),
                _mm256_max_ps(
                    _mm256_fmsub_ps(row(self.near[2]), inv_z, oi_z),
                    _mm256_setzero_ps(),
                ),
            );
            let t_far = _mm256_min_ps(
                _mm256_min_ps(
                    _mm256_fmsub_ps(row(self.far[0]), inv_x, oi_x),
                    _mm256_fmsub_ps(row(self.far[1]), inv_y, oi_y),
                ),
                _mm256_min_ps(
                    _mm256_fmsub_ps(row(self.far[2]), inv_z, oi_z),
                    _mm256_set1_ps(self.t_best),
                ),
            );
            let mut mask = _mm256_movemask_ps(_mm256_cmp_ps::<_CMP_LE_OQ>(t_near, t_far)) as u32;
            if mask == 0 {
                return self.pop();
            }
            let mut distances = [0.0f32; 8];
            _mm256_storeu_ps(distances.as_mut_ptr(), t_near);
            let a = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            if mask == 0 {
                self.current = *node.children.get_unchecked(a);
                return true;
            }
            let b = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            let (da, db) = (distances[a], distances[b]);
            if mask == 0 {
                let (near_child, far_child, far_dist) =
                    if da <= db { (a, b, db) } else { (b, a, da) };
                self.push(*node.children.get_unchecked(far_child), far_dist);
                self.current = *node.children.get_unchecked(near_child);
                return true;
            }
            // Three or more: push them all, sorted so that the nearest
            // ends on top (insertion sort of at most eight).
            let base = self.sp;
            self.push(*node.children.get_unchecked(a), da);
            self.push(*node.children.get_unchecked(b), db);
            while mask != 0 {
                let c = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                self.push(*node.children.get_unchecked(c), distances[c]);
            }
            for i in base + 1..self.sp {
                let r = self.stack_ref.get_unchecked(i).assume_init();
                let d = self.stack_dist.get_unchecked(i).assume_init();
                let mut j = i;
                while j > base && self.stack_dist.get_unchecked(j - 1).assume_init() < d {
                    let prev_r = self.stack_ref.get_unchecked(j - 1).assume_init();
                    let prev_d = self.stack_dist.get_unchecked(j - 1).assume_init();
                    self.stack_ref.get_unchecked_mut(j).write(prev_r);
                    self.stack_dist.get_unchecked_mut(j).write(prev_d);
                    j -= 1;
                }
                self.stack_ref.get_unchecked_mut(j).write(r);
                self.stack_dist.get_unchecked_mut(j).write(d);
            }
            self.sp -= 1;
            self.current = self.stack_ref.get_unchecked(self.sp).assume_init();
            true
        }
    }

    /// The closest hit found, with its tag and normal (from the block the
    /// test just read).
    #[inline(always)]
    unsafe fn hit(&self, bvh: &WideBvh) -> Option<WideHit> {
        let (t, triangle, u, v) = self.best?;
        let (block, lane) = self.best_at;
        // SAFETY: the block and lane were those of a hit.
        unsafe {
            let block = bvh.blocks.get_unchecked(block);
            let edge = |r: usize| {
                Vec3A::new(
                    *block.rows.get_unchecked(r).get_unchecked(lane),
                    *block.rows.get_unchecked(r + 1).get_unchecked(lane),
                    *block.rows.get_unchecked(r + 2).get_unchecked(lane),
                )
            };
            Some(WideHit {
                t,
                triangle,
                u,
                v,
                tag: *block.tag.get_unchecked(lane),
                normal: crate::triangle::unit_normal(edge(3), edge(6)),
            })
        }
    }
}

/// The nearest of a block's triangles hit at or before `t_best`, the lower
/// triangle index on a tie: (t, lane, u, v). Möller–Trumbore on four
/// lanes, with the scalar test's conditions
/// ([`crate::bvh::intersect_triangle`]).
#[cfg(target_arch = "x86_64")]
#[inline]
#[target_feature(enable = "avx2,fma,bmi1")]
unsafe fn block_hit(
    block: &TriangleBlock,
    origin: Vec3A,
    dir: Vec3A,
    t_best: f32,
    lanes: u32,
) -> Option<(f32, usize, f32, f32)> {
    use std::arch::x86_64::*;
    // SAFETY: the features are enabled on this function; rows are
    // 16-byte aligned within the 32-byte aligned block.
    unsafe {
        let row = |r: usize| _mm_load_ps(block.rows.get_unchecked(r).as_ptr());
        let (v0x, v0y, v0z) = (row(0), row(1), row(2));
        let (e1x, e1y, e1z) = (row(3), row(4), row(5));
        let (e2x, e2y, e2z) = (row(6), row(7), row(8));
        let dx = _mm_set1_ps(dir.x);
        let dy = _mm_set1_ps(dir.y);
        let dz = _mm_set1_ps(dir.z);
        // The scalar test's operations in its order (glam's SSE cross and
        // dot: products rounded, then (x + y) + z), so a hit's t, u and v
        // are the scalar test's to the bit and a seed's counts do not
        // depend on the traversal.
        let cross = |ax, ay, az, bx, by, bz| {
            (
                _mm_sub_ps(_mm_mul_ps(ay, bz), _mm_mul_ps(by, az)),
                _mm_sub_ps(_mm_mul_ps(az, bx), _mm_mul_ps(bz, ax)),
                _mm_sub_ps(_mm_mul_ps(ax, by), _mm_mul_ps(bx, ay)),
            )
        };
        let dot = |ax, ay, az, bx, by, bz| {
            _mm_add_ps(
                _mm_add_ps(_mm_mul_ps(ax, bx), _mm_mul_ps(ay, by)),
                _mm_mul_ps(az, bz),
            )
        };
        let (px, py, pz) = cross(dx, dy, dz, e2x, e2y, e2z);
        let det = dot(e1x, e1y, e1z, px, py, pz);
        let inv_det = _mm_div_ps(_mm_set1_ps(1.0), det);
        let sx = _mm_sub_ps(_mm_set1_ps(origin.x), v0x);
        let sy = _mm_sub_ps(_mm_set1_ps(origin.y), v0y);
        let sz = _mm_sub_ps(_mm_set1_ps(origin.z), v0z);
        let u = _mm_mul_ps(dot(sx, sy, sz, px, py, pz), inv_det);
        let (qx, qy, qz) = cross(sx, sy, sz, e1x, e1y, e1z);
        let v = _mm_mul_ps(dot(dx, dy, dz, qx, qy, qz), inv_det);
        let t = _mm_mul_ps(dot(e2x, e2y, e2z, qx, qy, qz), inv_det);
        let abs_det = _mm_andnot_ps(_mm_set1_ps(-0.0), det);
        let zero = _mm_setzero_ps();
        let one = _mm_set1_ps(1.0);
        let ok = _mm_and_ps(
            _mm_and_ps(
                _mm_cmpge_ps(abs_det, _mm_set1_ps(1e-20)),
                _mm_and_ps(_mm_cmpge_ps(u, zero), _mm_cmple_ps(u, one)),
            ),
            _mm_and_ps(
                _mm_and_ps(_mm_cmpge_ps(v, zero), _mm_cmple_ps(_mm_add_ps(u, v), one)),
                _mm_and_ps(_mm_cmpgt_ps(t, zero), _mm_cmple_ps(t, _mm_set1_ps(t_best))),
            ),
        );
        let mut mask = _mm_movemask_ps(ok) as u32 & lanes;
        if mask == 0 {
            return None;
        }
        let mut ts = [0.0f32; 4];
        let mut us = [0.0f32; 4];
        let mut vs = [0.0f32; 4];
        _mm_storeu_ps(ts.as_mut_ptr(), t);
        _mm_storeu_ps(us.as_mut_ptr(), u);
        _mm_storeu_ps(vs.as_mut_ptr(), v);
        let mut lane = mask.trailing_zeros() as usize;
        mask &= mask - 1;
        while mask != 0 {
            let l = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            if ts[l] < ts[lane] || (ts[l] == ts[lane] && block.triangle[l] < block.triangle[lane]) {
                lane = l;
            }
        }
        Some((ts[lane], lane, us[lane], vs[lane]))
    }
}

/// Off x86-64 there is no wide traversal ([`crate::cpu_features::available`]
/// is false).
///
/// # Safety
/// Never to be called: it panics.
#[cfg(not(target_arch = "x86_64"))]
pub unsafe fn closest_hit(_: &WideBvh, _: Vec3A, _: Vec3A, _: f32, _: Surfaces) -> Option<WideHit> {
    unreachable!("cpu_features::available() is false off x86-64")
}
