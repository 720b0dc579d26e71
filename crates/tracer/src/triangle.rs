//! The triangle record both hierarchies store, and the constants their
//! traversals share: a module of its own so that the BVH2
//! (`bvh`) and the wide BVH (`wide_bvh`) both build on it
//! without importing each other.

use bytemuck::{Pod, Zeroable};
use glam::{Vec3, Vec3A};

/// A triangle ready for Möller–Trumbore: a vertex and two edges.
#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable, PartialEq)]
pub struct BvhTriangle {
    pub v0: [f32; 3],
    pub _pad0: u32,
    pub e1: [f32; 3],
    pub _pad1: u32,
    pub e2: [f32; 3],
    pub _pad2: u32,
}
const _: () = assert!(std::mem::size_of::<BvhTriangle>() == 48);

/// Size of the luminaire in BVH units.
pub const BVH_EXTENT: f32 = 1000.0;

/// Tag bit of a triangle photons pass through unchanged (an index-matched,
/// non-absorbing surface: a clear emitter's disk, IOR 1): `Bvh::intersect`
/// ignores it, `Bvh::intersect_any_surface` (picking) sees it. The
/// physics is the same — Fresnel reflectance 0, refraction straight on —
/// without a ray and a shading step per crossing (5.5 % of the bench cup's
/// photons crossed its emitter).
pub const PASS_THROUGH_TAG: u32 = 1 << 30;

impl BvhTriangle {
    /// The triangle of corners `a, b, c` (BVH units).
    pub fn new([a, b, c]: [Vec3; 3]) -> BvhTriangle {
        BvhTriangle {
            v0: a.to_array(),
            _pad0: 0,
            e1: (b - a).to_array(),
            _pad1: 0,
            e2: (c - a).to_array(),
            _pad2: 0,
        }
    }
}

/// The unit normal `e1 × e2` of a triangle's edges, zero if degenerate.
#[inline(always)]
pub fn unit_normal(e1: Vec3A, e2: Vec3A) -> Vec3A {
    e1.cross(e2).normalize_or_zero()
}
