#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! The BVH2 in the GPU layout and both CPU traversals of the CWBVH (obvhs'
//! and the AVX2 one, where the CPU has it) find the same closest hits as
//! brute force.

use std::path::Path;

use glam::Vec3A;
use lucerna_tracer::bvh::{CpuTraversal, intersect_triangle};
use lucerna_tracer::rng::PhotonRng;

#[test]
fn both_hierarchies_agree_with_brute_force() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires");
    for name in [
        "faceted_downlight.toml",
        "linear_louvre.toml",
        "obj_cone.toml",
    ] {
        let scene = lucerna_scene::load_scene(&dir.join(name)).unwrap();
        let t = lucerna_scene::tessellate(&scene, &dir).unwrap();
        let p = lucerna_tracer::PreparedScene::new(&scene, &t, &dir).unwrap();
        let mut obvhs_traversal = p.bvh.clone();
        obvhs_traversal.traversal = CpuTraversal::Obvhs;
        let bvh = &p.bvh;
        assert_eq!(bvh.traversal, CpuTraversal::best());
        let mut rng = PhotonRng::new(1, 2, 3);
        let mut hits = 0;
        for i in 0..3000 {
            let o = Vec3A::new(
                rng.next_f32() - 0.5,
                rng.next_f32() - 0.5,
                rng.next_f32() - 0.5,
            ) * 0.1;
            let mut d = Vec3A::new(
                rng.next_f32() - 0.5,
                rng.next_f32() - 0.5,
                rng.next_f32() - 0.5,
            );
            // Every fifth ray lies in a coordinate plane or along an axis
            // (zero direction components: the slab test's 1/0 case).
            match i % 15 {
                0 => d.x = 0.0,
                5 => d.y = 0.0,
                10 => d = Vec3A::new(0.0, 0.0, d.z.signum()),
                _ => {}
            }
            let d = d.normalize();
            let brute = bvh
                .triangles
                .iter()
                .enumerate()
                .filter_map(|(i, tri)| {
                    intersect_triangle(tri, o * bvh.scale, d).map(|h| (h.0 / bvh.scale, i as u32))
                })
                .min_by(|a, b| a.0.total_cmp(&b.0));
            let cw = bvh
                .intersect(o, d, f32::INFINITY)
                .map(|h| (h.t, h.triangle));
            let cw_obvhs = obvhs_traversal
                .intersect(o, d, f32::INFINITY)
                .map(|h| (h.t, h.triangle));
            let b2 = bvh
                .intersect_bvh2(o, d, f32::INFINITY)
                .map(|h| (h.t, h.triangle));
            // Same distance (coincident triangles may tie on the index).
            let same = |a: Option<(f32, u32)>, b: Option<(f32, u32)>| match (a, b) {
                (Some(a), Some(b)) => (a.0 - b.0).abs() <= 1e-6 * b.0.max(1e-3),
                (None, None) => true,
                _ => false,
            };
            assert!(
                same(cw, brute),
                "{name}: CWBVH ({}) {cw:?} vs brute force {brute:?}",
                bvh.traversal.describe()
            );
            assert!(
                same(cw_obvhs, brute),
                "{name}: CWBVH (obvhs) {cw_obvhs:?} vs brute force {brute:?}"
            );
            assert!(
                same(b2, brute),
                "{name}: BVH2 {b2:?} vs brute force {brute:?}"
            );
            hits += usize::from(brute.is_some());
        }
        assert!(
            hits > 300,
            "{name}: the test rays must hit something ({hits})"
        );
    }
}
