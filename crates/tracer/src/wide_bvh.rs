//! The CPU tracer's own BVH layout over obvhs' build: the CWBVH's
//! topology (obvhs' SAH collapse of its PLOC BVH2 into eight-wide nodes,
//! leaves of at most three triangles) with the child boxes decompressed to
//! floats and tightened bottom-up, and each leaf's triangles packed into
//! one four-wide SoA block.
//!
//! Layout (deviations from the CWBVH paper, Ylitie et al. 2017, which is
//! built for GPUs' memory bandwidth, not for a CPU's latency):
//! - [`WideNode`], 224 bytes: six rows of eight `f32` planes (min x, max x,
//!   min y, max y, min z, max z) and eight child references. A ray picks
//!   its near and far row per axis once, by the signs of its direction,
//!   so a node test is six fused multiply-adds, four min/max and one
//!   compare on eight lanes, with no byte unpacking.
//! - [`TriangleBlock`], 192 bytes: up to four triangles as vertex and two
//!   edges in SoA rows, tested at once by Möller–Trumbore in four lanes
//!   (unused lanes are degenerate, zero edges, and never hit), then their
//!   scene indices and tags (the tracer's material and flat-shading flag)
//!   in the block's last cache line: the hit's geometric normal (from its
//!   edges) and tag come from lines the test has just read, where a
//!   separate shading record per triangle cost a cache miss per bounce.
//!
//! Traversal is closest-hit with a stack of (reference, entry distance):
//! hit children are visited nearest first (the farther ones pushed in
//! descending order), and a popped entry farther than the closest hit so
//! far is dropped without loading its node. The CWBVH traversal of obvhs
//! orders children by ray octant instead and has no distances to cull by.
//! Ties in distance go to the lower triangle index, so the hit is the one
//! brute force finds, to the bit, whatever the tree (`tests/bvh.rs`).
//!
//! Measured on the bench scenes (`examples/speed.rs`, BENCHMARKS.md).

use glam::Vec3A;

use crate::triangle::BvhTriangle;

/// A child reference with this bit set names a [`TriangleBlock`].
const LEAF: u32 = 1 << 31;
/// An empty child slot (its box is empty too, so it is never hit).
const EMPTY: u32 = u32::MAX;

/// One eight-wide node: child boxes in SoA rows and child references.
#[repr(C, align(32))]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WideNode {
    /// Rows min x, max x, min y, max y, min z, max z (BVH units).
    pub planes: [[f32; 8]; 6],
    /// Inner node index, `LEAF | block index`, or `EMPTY`.
    pub children: [u32; 8],
}
const _: () = assert!(std::mem::size_of::<WideNode>() == 224);

/// Up to four triangles of one leaf, SoA.
#[repr(C, align(64))]
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriangleBlock {
    /// Rows v0 x, y, z; e1 x, y, z; e2 x, y, z.
    pub rows: [[f32; 4]; 9],
    /// Scene triangle index per lane (`u32::MAX` in unused lanes).
    pub triangle: [u32; 4],
    /// The tag [`crate::bvh::Bvh::build`] was given per triangle.
    pub tag: [u32; 4],
    /// Lanes photons can hit: used, and not
    /// [`crate::triangle::PASS_THROUGH_TAG`] (bit `l` for lane `l`).
    pub photon_lanes: u32,
    /// Lanes in use.
    pub all_lanes: u32,
}
const _: () = assert!(std::mem::size_of::<TriangleBlock>() == 192);

/// The float eight-wide BVH the CPU traverses.
#[derive(Debug, Clone, Default)]
pub struct WideBvh {
    pub nodes: Vec<WideNode>,
    pub blocks: Vec<TriangleBlock>,
    /// Longest root-to-leaf path in nodes: bounds the traversal stack.
    pub depth: usize,
}

/// Entries the traversal stack holds: a node visit pushes at most seven
/// net, so a tree of depth `d` needs at most `7d + 1`.
pub const STACK_ENTRIES: usize = 256;

/// Box of nothing: never hit (+∞ near plane, −∞ far plane).
const EMPTY_BOX: ([f32; 3], [f32; 3]) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);

/// An axis-aligned box (min, max) in BVH units.
type Aabb = ([f32; 3], [f32; 3]);

/// What a child slot of an output node holds while converting.
#[derive(Debug, Clone)]
enum Child {
    Inner(u32),
    /// Leaf slots (indices into the slot triangles), at most four distinct
    /// triangles.
    Leaf(Vec<u32>),
}

/// Leaf blocks hold four triangles: a subtree of at most this many is
/// tested as one block instead of being descended.
const BLOCK_LANES: usize = 4;

impl WideBvh {
    /// Converts obvhs' CWBVH; `slot_triangles[s]` is leaf slot `s`'s
    /// triangle and `slot_scene_triangle[s]` its index in the scene.
    /// `None` if the tree is too deep for the fixed traversal stack (then
    /// obvhs' traversal is used).
    ///
    /// Besides decompressing the boxes this fills the four-wide blocks
    /// (obvhs' SAH collapse leaves 1.5 triangles per leaf on the bench's
    /// paraboloid, but a block tests four for the price of one): a
    /// subtree of at most four triangles becomes one leaf, and sibling
    /// leaves merge while their union box has no more area than the two
    /// apart (the chance a ray enters it is no larger). Nodes are written
    /// in depth-first order, so a ray's path through the tree is close in
    /// memory.
    pub fn from_cwbvh(
        cwbvh: &obvhs::cwbvh::CwBvh,
        slot_triangles: &[BvhTriangle],
        slot_scene_triangle: &[u32],
        tags: &[u32],
    ) -> Option<WideBvh> {
        let count = cwbvh.nodes.len();
        if count == 0 || slot_triangles.len() != slot_scene_triangle.len() {
            return None;
        }
        // Post-order: each node's children as (box, content), their boxes
        // tightened by what they hold; and the node's own leaf slots if
        // its subtree has at most four distinct triangles.
        let mut children: Vec<Vec<(Aabb, Child)>> = vec![Vec::new(); count];
        let mut bounds: Vec<Option<Aabb>> = vec![None; count];
        let mut small: Vec<Option<Vec<u32>>> = vec![None; count];
        let mut order = vec![(0u32, false)];
        while let Some((index, children_done)) = order.pop() {
            let node = cwbvh.nodes.get(index as usize)?;
            if !children_done {
                order.push((index, true));
                for child in 0..8 {
                    if node.child_meta[child] != 0 && !node.is_leaf(child) {
                        let c = node.child_node_index(child);
                        // Children come after their parent in obvhs'
                        // layout; anything else would be a cycle.
                        if c <= index || c as usize >= count {
                            return None;
                        }
                        order.push((c, false));
                    }
                }
                continue;
            }
            let mut own: Vec<(Aabb, Child)> = Vec::new();
            let mut union = EMPTY_BOX;
            let mut subtree_slots: Option<Vec<u32>> = Some(Vec::new());
            for child in 0..8 {
                if node.child_meta[child] == 0 {
                    continue;
                }
                let quantised = quantised_child_box(node, child);
                let (content, child_box, slots) = if node.is_leaf(child) {
                    let (first, n) = node.child_primitives(child);
                    let slots: Vec<u32> = (first..first + n).collect();
                    let content = slots_box(slot_triangles, &slots)?;
                    (Child::Leaf(slots.clone()), content, Some(slots))
                } else {
                    let c = node.child_node_index(child);
                    (
                        Child::Inner(c),
                        bounds[c as usize]?,
                        small[c as usize].clone(),
                    )
                };
                let b = intersect_boxes(quantised, child_box);
                union = union_boxes(union, b);
                subtree_slots = match (subtree_slots, slots) {
                    (Some(mut all), Some(more)) => {
                        all.extend(more);
                        dedup_triangles(&mut all, slot_scene_triangle);
                        (all.len() <= BLOCK_LANES).then_some(all)
                    }
                    _ => None,
                };
                own.push((b, content));
            }
            bounds[index as usize] = Some(union);
            small[index as usize] = subtree_slots;
            children[index as usize] = own;
        }

        // Pre-order: write the output nodes, small subtrees as leaves and
        // sibling leaves merged.
        let mut bvh = WideBvh::default();
        let mut pending = vec![(0u32, None::<(usize, usize)>, 1usize)];
        while let Some((index, parent_slot, depth)) = pending.pop() {
            let out_index = bvh.nodes.len() as u32;
            if let Some((parent, slot)) = parent_slot {
                bvh.nodes[parent].children[slot] = out_index;
            }
            bvh.depth = bvh.depth.max(depth);
            let mut slots: Vec<(Aabb, Child)> = children[index as usize]
                .iter()
                .map(|(b, c)| match c {
                    Child::Inner(i) => match &small[*i as usize] {
                        Some(leaf) => (*b, Child::Leaf(leaf.clone())),
                        None => (*b, c.clone()),
                    },
                    leaf => (*b, leaf.clone()),
                })
                .collect();
            merge_sibling_leaves(&mut slots, slot_scene_triangle);
            let mut wide = WideNode {
                planes: [[0.0; 8]; 6],
                children: [EMPTY; 8],
            };
            for slot in 0..8 {
                let (lo, hi) = slots.get(slot).map_or(EMPTY_BOX, |(b, _)| *b);
                for axis in 0..3 {
                    wide.planes[2 * axis][slot] = lo[axis];
                    wide.planes[2 * axis + 1][slot] = hi[axis];
                }
            }
            bvh.nodes.push(wide);
            // Inner children pushed so that the first is written next.
            for (slot, (_, content)) in slots.iter().enumerate().rev() {
                match content {
                    Child::Inner(c) => {
                        pending.push((*c, Some((out_index as usize, slot)), depth + 1));
                    }
                    Child::Leaf(leaf) => {
                        let block = pack_block(slot_triangles, slot_scene_triangle, tags, leaf)?;
                        bvh.blocks.push(block);
                        bvh.nodes[out_index as usize].children[slot] =
                            LEAF | (bvh.blocks.len() as u32 - 1);
                    }
                }
            }
        }
        if bvh.blocks.len() >= LEAF as usize || 7 * bvh.depth + 1 > STACK_ENTRIES {
            return None;
        }
        Some(bvh)
    }
}

impl TriangleBlock {
    fn set_photon_lanes(&mut self) {
        self.photon_lanes = (0..4)
            .filter(|&l| {
                self.all_lanes & (1 << l) != 0
                    && self.tag[l] & crate::triangle::PASS_THROUGH_TAG == 0
            })
            .fold(0, |m, l| m | (1 << l));
    }
}

impl WideBvh {
    /// The same tree over new triangles (`triangles` and `tags` per scene
    /// triangle, as the blocks name them): blocks filled again, boxes
    /// recomputed from the leaves up (nodes are in depth-first order, so a
    /// node's children come after it). A leaf's box is now its triangles'
    /// whole box, where a spatial split had clipped it: looser, never
    /// wrong. `None` if a block names a triangle `triangles` lacks.
    pub fn refitted(&self, triangles: &[BvhTriangle], tags: &[u32]) -> Option<WideBvh> {
        let mut out = self.clone();
        let mut block_boxes = Vec::with_capacity(out.blocks.len());
        for block in &mut out.blocks {
            let lanes: Vec<u32> = block
                .triangle
                .iter()
                .copied()
                .filter(|&t| t != u32::MAX)
                .collect();
            for (lane, &t) in lanes.iter().enumerate() {
                let tri = triangles.get(t as usize)?;
                for axis in 0..3 {
                    block.rows[axis][lane] = tri.v0[axis];
                    block.rows[3 + axis][lane] = tri.e1[axis];
                    block.rows[6 + axis][lane] = tri.e2[axis];
                }
                block.tag[lane] = *tags.get(t as usize)?;
            }
            block.set_photon_lanes();
            let b = lanes
                .iter()
                .map(|&t| slots_box(std::slice::from_ref(&triangles[t as usize]), &[0]))
                .try_fold(EMPTY_BOX, |acc, b| Some(union_boxes(acc, b?)))?;
            block_boxes.push(b);
        }
        let mut node_boxes = vec![EMPTY_BOX; out.nodes.len()];
        for index in (0..out.nodes.len()).rev() {
            let mut union = EMPTY_BOX;
            for slot in 0..8 {
                let child = out.nodes[index].children[slot];
                let (lo, hi) = if child == EMPTY {
                    EMPTY_BOX
                } else if child & LEAF != 0 {
                    *block_boxes.get((child & !LEAF) as usize)?
                } else {
                    // A child before its parent would be a cycle.
                    if child as usize <= index {
                        return None;
                    }
                    *node_boxes.get(child as usize)?
                };
                let node = &mut out.nodes[index];
                for axis in 0..3 {
                    node.planes[2 * axis][slot] = lo[axis];
                    node.planes[2 * axis + 1][slot] = hi[axis];
                }
                union = union_boxes(union, (lo, hi));
            }
            node_boxes[index] = union;
        }
        Some(out)
    }
}

/// Drops slots that name a triangle already in the list (spatial splits
/// put one triangle in several leaves).
fn dedup_triangles(slots: &mut Vec<u32>, slot_scene_triangle: &[u32]) {
    let mut seen: Vec<u32> = Vec::with_capacity(slots.len());
    slots.retain(|&s| {
        let t = slot_scene_triangle[s as usize];
        if seen.contains(&t) {
            false
        } else {
            seen.push(t);
            true
        }
    });
}

/// Merges pairs of leaf children while their triangles fit one block and
/// the union box's area is at most the sum of the two (best pair first).
fn merge_sibling_leaves(slots: &mut Vec<(Aabb, Child)>, slot_scene_triangle: &[u32]) {
    loop {
        let mut best: Option<(usize, usize, f32, Vec<u32>)> = None;
        for i in 0..slots.len() {
            let Child::Leaf(a) = &slots[i].1 else {
                continue;
            };
            for j in i + 1..slots.len() {
                let Child::Leaf(b) = &slots[j].1 else {
                    continue;
                };
                let mut merged = a.clone();
                merged.extend(b);
                dedup_triangles(&mut merged, slot_scene_triangle);
                if merged.len() > BLOCK_LANES {
                    continue;
                }
                let gain = half_area(slots[i].0) + half_area(slots[j].0)
                    - half_area(union_boxes(slots[i].0, slots[j].0));
                if gain >= 0.0 && best.as_ref().is_none_or(|b| gain > b.2) {
                    best = Some((i, j, gain, merged));
                }
            }
        }
        let Some((i, j, _, merged)) = best else {
            return;
        };
        let union = union_boxes(slots[i].0, slots[j].0);
        slots[i] = (union, Child::Leaf(merged));
        slots.remove(j);
    }
}

fn half_area((lo, hi): Aabb) -> f32 {
    let d = [hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]].map(|x| x.max(0.0));
    d[0] * d[1] + d[1] * d[2] + d[2] * d[0]
}

fn union_boxes(a: Aabb, b: Aabb) -> Aabb {
    let mut out = a;
    for axis in 0..3 {
        out.0[axis] = a.0[axis].min(b.0[axis]);
        out.1[axis] = a.1[axis].max(b.1[axis]);
    }
    out
}

/// The bounding box of slots' triangles (vertices as the triangle test
/// sees them: v0, v0 + e1, v0 + e2), rounded outwards.
fn slots_box(slot_triangles: &[BvhTriangle], slots: &[u32]) -> Option<Aabb> {
    let mut b = EMPTY_BOX;
    for &s in slots {
        let t = slot_triangles.get(s as usize)?;
        for axis in 0..3 {
            let v0 = f64::from(t.v0[axis]);
            for v in [v0, v0 + f64::from(t.e1[axis]), v0 + f64::from(t.e2[axis])] {
                b.0[axis] = b.0[axis].min(outward_down(v));
                b.1[axis] = b.1[axis].max(outward_up(v));
            }
        }
    }
    Some(b)
}

/// A child's box from the node's 8-bit planes, rounded outwards.
fn quantised_child_box(node: &obvhs::cwbvh::node::CwBvhNode, child: usize) -> ([f32; 3], [f32; 3]) {
    let extent = node.compute_extent();
    let q_lo = [
        node.child_min_x[child],
        node.child_min_y[child],
        node.child_min_z[child],
    ];
    let q_hi = [
        node.child_max_x[child],
        node.child_max_y[child],
        node.child_max_z[child],
    ];
    let mut lo = [0.0; 3];
    let mut hi = [0.0; 3];
    for axis in 0..3 {
        let p = f64::from(node.p[axis]);
        let e = f64::from(extent[axis]);
        lo[axis] = outward_down(p + e * f64::from(q_lo[axis]));
        hi[axis] = outward_up(p + e * f64::from(q_hi[axis]));
    }
    (lo, hi)
}

fn intersect_boxes(a: ([f32; 3], [f32; 3]), b: ([f32; 3], [f32; 3])) -> ([f32; 3], [f32; 3]) {
    let mut out = a;
    for axis in 0..3 {
        out.0[axis] = a.0[axis].max(b.0[axis]);
        out.1[axis] = a.1[axis].min(b.1[axis]);
    }
    out
}

/// Margin that absorbs the slab test's rounding (a few ulps of the
/// coordinate) and Möller–Trumbore's error in t, which puts the computed
/// hit point off a small, distant triangle's plane (1e-4 units seen on the
/// faceted downlight's fan apex): 1e-6 of the luminaire's size in BVH
/// units. A box that tight around its triangles would cull such hits.
pub(crate) fn margin(x: f64) -> f64 {
    x.abs() * 4.0 * f64::from(f32::EPSILON) + 1e-6 * f64::from(crate::triangle::BVH_EXTENT)
}

pub(crate) fn outward_down(x: f64) -> f32 {
    (x - margin(x)) as f32
}

pub(crate) fn outward_up(x: f64) -> f32 {
    (x + margin(x)) as f32
}

/// Packs leaf slots (at most four) into a block; `tags` are per scene
/// triangle.
fn pack_block(
    slot_triangles: &[BvhTriangle],
    slot_scene_triangle: &[u32],
    tags: &[u32],
    slots: &[u32],
) -> Option<TriangleBlock> {
    if slots.is_empty() || slots.len() > BLOCK_LANES {
        return None;
    }
    let mut block = TriangleBlock {
        rows: [[0.0; 4]; 9],
        triangle: [u32::MAX; 4],
        tag: [0; 4],
        photon_lanes: 0,
        all_lanes: 0,
    };
    for (lane, &slot) in slots.iter().enumerate() {
        let t = slot_triangles.get(slot as usize)?;
        for axis in 0..3 {
            block.rows[axis][lane] = t.v0[axis];
            block.rows[3 + axis][lane] = t.e1[axis];
            block.rows[6 + axis][lane] = t.e2[axis];
        }
        let triangle = *slot_scene_triangle.get(slot as usize)?;
        block.triangle[lane] = triangle;
        block.tag[lane] = *tags.get(triangle as usize)?;
        block.all_lanes |= 1 << lane;
    }
    block.set_photon_lanes();
    Some(block)
}

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
/// The CPU must have AVX2 and FMA ([`crate::wide_traversal::available`]).
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
/// The CPU must have AVX2 and FMA ([`crate::wide_traversal::available`]).
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

/// Off x86-64 there is no wide traversal ([`crate::wide_traversal::available`]
/// is false).
///
/// # Safety
/// Never to be called: it panics.
#[cfg(not(target_arch = "x86_64"))]
pub unsafe fn closest_hit(_: &WideBvh, _: Vec3A, _: Vec3A, _: f32, _: Surfaces) -> Option<WideHit> {
    unreachable!("wide_traversal::available() is false off x86-64")
}
