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

use crate::triangle::BvhTriangle;

/// A child reference with this bit set names a [`TriangleBlock`].
pub(crate) const LEAF: u32 = 1 << 31;
/// An empty child slot (its box is empty too, so it is never hit).
pub(crate) const EMPTY: u32 = u32::MAX;

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
pub(crate) const BLOCK_LANES: usize = 4;

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
