//! Closest-hit traversal of obvhs' CWBVH with all eight child boxes of a
//! node tested at once in AVX2 registers, chosen at run time when the CPU
//! has AVX2 and FMA (every x86-64 CPU since about 2013).
//!
//! obvhs' own node test handles four children at a time in SSE and
//! converts the quantised box planes byte by byte; here each plane row is
//! one 8-byte load widened to eight floats, the near/far planes are picked
//! once per ray (by the direction's signs) instead of per node, the slab
//! test is fused multiply-add, and the children's traversal bits are
//! shifted and OR-reduced in registers without a branch per child.
//! The traversal order, stack and leaf handling are obvhs' `traverse!`.
//! Same hits as obvhs' traversal (tested on random rays in `tests/bvh.rs`).

use glam::Vec3A;

/// Whether this CPU runs [`closest_hit`].
pub fn available() -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        std::arch::is_x86_feature_detected!("avx2")
            && std::arch::is_x86_feature_detected!("fma")
            && std::arch::is_x86_feature_detected!("lzcnt")
            && std::arch::is_x86_feature_detected!("popcnt")
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        false
    }
}

/// Closest hit in BVH units: (t, leaf slot, u, v), t in (0, t_max).
///
/// # Safety
/// The CPU must have AVX2, FMA, LZCNT and POPCNT ([`available`]).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,lzcnt,popcnt")]
pub unsafe fn closest_hit(
    cwbvh: &obvhs::cwbvh::CwBvh,
    slot_triangles: &[crate::bvh::BvhTriangle],
    origin: Vec3A,
    dir: Vec3A,
    t_max: f32,
) -> Option<(f32, u32, f32, f32)> {
    use glam::UVec2;
    use obvhs::cwbvh::node::CwBvhNode;
    use std::mem::offset_of;

    if cwbvh.nodes.is_empty() {
        return None;
    }
    let ray = obvhs::ray::Ray::new(origin, dir, 0.0, t_max);
    // Byte offsets of the near and far plane rows for this ray: a negative
    // direction component enters a box through its max plane.
    let rows = |min: usize, negative: bool| {
        // `child_max_*` directly follows `child_min_*` (8 bytes).
        if negative {
            (min + 8, min)
        } else {
            (min, min + 8)
        }
    };
    let (near_x, far_x) = rows(offset_of!(CwBvhNode, child_min_x), dir.x < 0.0);
    let (near_y, far_y) = rows(offset_of!(CwBvhNode, child_min_y), dir.y < 0.0);
    let (near_z, far_z) = rows(offset_of!(CwBvhNode, child_min_z), dir.z < 0.0);
    let planes = PlaneRows {
        near: [near_x, near_y, near_z],
        far: [far_x, far_y, far_z],
    };

    let mut t_best = t_max;
    let mut best: Option<(f32, u32, f32, f32)> = None;
    let mut state = cwbvh.new_traversal(dir);
    let mut node: &CwBvhNode;
    obvhs::traverse!(
        cwbvh,
        node,
        state,
        // SAFETY: the caller guarantees the target features.
        unsafe { node_hits(node, &ray, &planes, t_best, state.oct_inv4) },
        {
            let slot = state.primitive_id;
            if let Some((t, u, v)) =
                crate::bvh::intersect_triangle(&slot_triangles[slot as usize], origin, dir)
                && t < t_best
            {
                t_best = t;
                best = Some((t, slot, u, v));
            }
        }
    );
    best
}

/// Off x86-64 there is no AVX2 traversal ([`available`] is false).
///
/// # Safety
/// Never to be called: it panics.
#[cfg(not(target_arch = "x86_64"))]
pub unsafe fn closest_hit(
    _: &obvhs::cwbvh::CwBvh,
    _: &[crate::bvh::BvhTriangle],
    _: Vec3A,
    _: Vec3A,
    _: f32,
) -> Option<(f32, u32, f32, f32)> {
    unreachable!("wide_traversal::available() is false off x86-64")
}

/// Byte offsets in a node of the quantised planes a ray enters and leaves
/// each axis through.
#[cfg(target_arch = "x86_64")]
struct PlaneRows {
    near: [usize; 3],
    far: [usize; 3],
}

/// The node's children hit before `t_max`, as obvhs' hit mask: internal
/// children set bit 24 + their traversal priority, leaves their unary
/// triangle count at their triangle offset.
#[cfg(target_arch = "x86_64")]
#[inline]
#[target_feature(enable = "avx2,fma")]
unsafe fn node_hits(
    node: &obvhs::cwbvh::node::CwBvhNode,
    ray: &obvhs::ray::Ray,
    planes: &PlaneRows,
    t_max: f32,
    oct_inv4: u32,
) -> u32 {
    use std::arch::x86_64::*;

    /// Eight quantised planes (bytes at `offset`) as floats.
    #[inline(always)]
    unsafe fn row(base: *const u8, offset: usize) -> __m256 {
        // SAFETY: offsets come from `offset_of!` on 8-byte fields of the node.
        unsafe {
            let bytes = _mm_loadl_epi64(base.add(offset).cast::<__m128i>());
            _mm256_cvtepi32_ps(_mm256_cvtepu8_epi32(bytes))
        }
    }

    // Ray in the node's quantised grid: t = q · extent / d + (p − o) / d.
    let scale = node.compute_extent() * ray.inv_direction;
    let offset = (Vec3A::from(node.p) - ray.origin) * ray.inv_direction;
    let base = std::ptr::from_ref(node).cast::<u8>();
    // SAFETY: AVX2/FMA are enabled on this function; loads stay in `node`.
    unsafe {
        let slab = |axis: usize, s: f32, o: f32| {
            let s = _mm256_set1_ps(s);
            let o = _mm256_set1_ps(o);
            (
                _mm256_fmadd_ps(row(base, planes.near[axis]), s, o),
                _mm256_fmadd_ps(row(base, planes.far[axis]), s, o),
            )
        };
        let (near_x, far_x) = slab(0, scale.x, offset.x);
        let (near_y, far_y) = slab(1, scale.y, offset.y);
        let (near_z, far_z) = slab(2, scale.z, offset.z);
        // obvhs culls boxes entered closer than its EPSILON (1e-4 units).
        let near = _mm256_max_ps(
            _mm256_max_ps(near_x, near_y),
            _mm256_max_ps(near_z, _mm256_set1_ps(1e-4)),
        );
        let far = _mm256_min_ps(
            _mm256_min_ps(far_x, far_y),
            _mm256_min_ps(far_z, _mm256_set1_ps(t_max)),
        );
        let hit = _mm256_castps_si256(_mm256_cmp_ps::<_CMP_LE_OQ>(near, far));

        let (child_bits8, bit_index8) = node.get_child_and_index_bits(oct_inv4);
        let child_bits = _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(child_bits8 as i64));
        let bit_index = _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(bit_index8 as i64));
        let bits = _mm256_and_si256(_mm256_sllv_epi32(child_bits, bit_index), hit);
        let half = _mm_or_si128(
            _mm256_castsi256_si128(bits),
            _mm256_extracti128_si256::<1>(bits),
        );
        let quarter = _mm_or_si128(half, _mm_shuffle_epi32::<0b01_00_11_10>(half));
        let one = _mm_or_si128(quarter, _mm_shuffle_epi32::<0b10_11_00_01>(quarter));
        _mm_cvtsi128_si32(one) as u32
    }
}

/// Runs `work` compiled for AVX2 and FMA where this CPU has them (its
/// inlined callees too: the photon loop's vector maths, sampling and the
/// traversal), else as it is.
#[inline]
pub fn with_best_features<R>(work: impl FnOnce() -> R) -> R {
    #[cfg(target_arch = "x86_64")]
    if available() {
        // SAFETY: the CPU has the features (`available`).
        return unsafe { with_avx2(work) };
    }
    work()
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,fma,lzcnt,popcnt")]
unsafe fn with_avx2<R>(work: impl FnOnce() -> R) -> R {
    work()
}
