#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! The BVH2 in the GPU layout (the CPU's scalar traversal too) and the
//! float wide BVH (where the CPU has AVX2) find the same closest hits as
//! brute force.

use std::path::Path;

use glam::Vec3A;
use lucerna_tracer::bvh::{CpuTraversal, intersect_triangle, unit_normal};
use lucerna_tracer::rng::PhotonRng;

#[test]
fn both_hierarchies_agree_with_brute_force() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires");
    for name in [
        "faceted_downlight.toml",
        "linear_louvre.toml",
        "obj_cone.toml",
        "parabolic_spot.toml",
    ] {
        let scene = lucerna_scene::load_scene(&dir.join(name)).unwrap();
        let t = lucerna_scene::tessellate(&scene, &dir).unwrap();
        let p = lucerna_tracer::PreparedScene::new(&scene, &t, &dir).unwrap();
        let bvh = &p.bvh;
        assert_eq!(bvh.traversal, CpuTraversal::best());
        let mut rng = PhotonRng::new(1, 2, 3);
        let mut hits = 0;
        let mut exact = 0;
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
            // Every fifteenth aims at an edge's midpoint or a vertex, which
            // two or more triangles share: hits that tie in distance.
            match i % 15 {
                0 => d.x = 0.0,
                5 => d.y = 0.0,
                10 => d = Vec3A::new(0.0, 0.0, d.z.signum()),
                3 | 8 => {
                    let tri = &bvh.triangles[(rng.next_u32() as usize) % bvh.triangles.len()];
                    let share = if i % 15 == 3 { 0.5 } else { 0.0 };
                    let target =
                        (Vec3A::from_array(tri.v0) + Vec3A::from_array(tri.e1) * share) / bvh.scale;
                    d = target - o;
                }
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
            let full = bvh.intersect(o, d, f32::INFINITY);
            // A hit carries its triangle's tag and normal, whatever the
            // traversal.
            if let Some(h) = full {
                let tri = &bvh.triangles[h.triangle as usize];
                assert_eq!(h.tag, bvh.tags[h.triangle as usize], "{name}: tag");
                assert_eq!(
                    h.normal,
                    unit_normal(Vec3A::from_array(tri.e1), Vec3A::from_array(tri.e2)),
                    "{name}: normal"
                );
                assert_eq!(
                    h.tag,
                    p.shading[h.triangle as usize].tag(&p.materials),
                    "{name}: tag"
                );
            }
            let cw = full.map(|h| (h.t, h.triangle));
            let b2 = bvh
                .intersect_bvh2(o, d, f32::INFINITY)
                .map(|h| (h.t, h.triangle));
            // Same distance (coincident triangles may tie on the index),
            // within 1e-6 relative or 10 µm: on a sliver triangle (the
            // louvre has some) Möller–Trumbore's own t is off its plane by
            // a few µm, and a box around the true triangle may rightly
            // prefer its neighbour in the same plane.
            let same = |a: Option<(f32, u32)>, b: Option<(f32, u32)>| match (a, b) {
                (Some(a), Some(b)) => (a.0 - b.0).abs() <= (1e-6 * b.0).max(1e-5),
                (None, None) => true,
                _ => false,
            };
            assert!(
                same(cw, brute),
                "{name}: {} {cw:?} vs brute force {brute:?}",
                bvh.traversal.describe()
            );
            // The wide BVH's triangle test is the scalar one's arithmetic
            // lane by lane and ties go to the lower index: brute force's
            // hit, to the bit, but for those slivers.
            if bvh.traversal == CpuTraversal::Avx2 {
                exact += usize::from(
                    cw.map(|h| (h.0.to_bits(), h.1)) == brute.map(|h| (h.0.to_bits(), h.1)),
                );
                if let Some((t, triangle)) = cw {
                    let again =
                        intersect_triangle(&bvh.triangles[triangle as usize], o * bvh.scale, d)
                            .map(|h| h.0 / bvh.scale);
                    assert_eq!(
                        again,
                        Some(t),
                        "{name}: wide BVH reports a hit its triangle does not have"
                    );
                }
            }
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
        if bvh.traversal == CpuTraversal::Avx2 {
            assert!(
                exact >= 2990,
                "{name}: {exact} of 3000 hits are brute force's to the bit"
            );
        }
    }
}

/// A refitted tree (the same triangles moved: a focal length dragged from
/// 25 to 18 mm) finds what a tree built for the moved triangles finds:
/// photon for photon the same counts.
#[test]
fn a_refitted_tree_traces_what_a_fresh_build_does() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires");
    let scene = lucerna_scene::load_scene(&dir.join("parabolic_spot.toml")).unwrap();
    let before = lucerna_tracer::PreparedScene::new(
        &scene,
        &lucerna_scene::tessellate(&scene, &dir).unwrap(),
        &dir,
    )
    .unwrap();
    let mut moved = scene.clone();
    match &mut moved.parts[0].shape {
        lucerna_scene::Shape::Paraboloid(p) => p.focal_length = 0.018,
        other => panic!("the spot's reflector is a paraboloid, not {other:?}"),
    }
    let tessellated = lucerna_scene::tessellate(&moved, &dir).unwrap();
    let Some(refitted) =
        lucerna_tracer::PreparedScene::refitted(&before, &moved, &tessellated, &dir).unwrap()
    else {
        // No wide BVH on this CPU: nothing to refit.
        assert_eq!(before.bvh.traversal, CpuTraversal::Scalar);
        return;
    };
    let fresh = lucerna_tracer::PreparedScene::new(&moved, &tessellated, &dir).unwrap();
    assert_ne!(
        refitted.bvh.triangles, before.bvh.triangles,
        "the triangles moved"
    );
    let settings = lucerna_tracer::TraceSettings {
        seed: 4,
        max_bounces: 64,
        layout: lucerna_photometry::CubeMapLayout::new(32),
    };
    let a = lucerna_tracer::trace_batch(&refitted, &settings, 0, 0, 100_000);
    let b = lucerna_tracer::trace_batch(&fresh, &settings, 0, 0, 100_000);
    assert_eq!(a, b);
    // And another triangulation is not refitted.
    let mut finer = moved.clone();
    if let lucerna_scene::Shape::Paraboloid(p) = &mut finer.parts[0].shape {
        p.segments_around += 8;
    }
    let finer_tessellated = lucerna_scene::tessellate(&finer, &dir).unwrap();
    assert!(
        lucerna_tracer::PreparedScene::refitted(&before, &finer, &finer_tessellated, &dir)
            .unwrap()
            .is_none()
    );
}

/// Photons pass through a pass-through triangle (an index-matched clear
/// surface) on every traversal; picking sees it.
#[test]
fn photons_pass_through_index_matched_surfaces_and_picking_sees_them() {
    use glam::Vec3;
    use lucerna_tracer::bvh::{Bvh, PASS_THROUGH_TAG};
    let square = |z: f32| {
        [
            [
                Vec3::new(-1.0, -1.0, z),
                Vec3::new(1.0, -1.0, z),
                Vec3::new(1.0, 1.0, z),
            ],
            [
                Vec3::new(-1.0, -1.0, z),
                Vec3::new(1.0, 1.0, z),
                Vec3::new(-1.0, 1.0, z),
            ],
        ]
    };
    let corners: Vec<[Vec3; 3]> = [square(-0.1), square(-0.5)].concat();
    let tags = [PASS_THROUGH_TAG | 1, PASS_THROUGH_TAG | 1, 2, 2];
    let mut bvh = Bvh::build(&corners, &tags);
    for traversal in [CpuTraversal::best(), CpuTraversal::Scalar] {
        bvh.traversal = traversal;
        let (o, d) = (Vec3A::new(0.1, 0.2, 0.0), Vec3A::NEG_Z);
        let photon = bvh.intersect(o, d, f32::INFINITY).expect("the far square");
        assert!((photon.t - 0.5).abs() < 1e-6, "{traversal:?}: {photon:?}");
        assert_eq!(photon.tag, 2);
        let pick = bvh
            .intersect_any_surface(o, d, f32::INFINITY)
            .expect("the near square");
        assert!((pick.t - 0.1).abs() < 1e-6, "{traversal:?}: {pick:?}");
        assert_eq!(pick.tag & PASS_THROUGH_TAG, PASS_THROUGH_TAG);
    }
}
