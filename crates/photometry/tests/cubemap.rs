#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! Cube-map layout: exact solid angles, and direction ↔ texel consistency.

use std::f64::consts::PI;

use lucerna_photometry::CubeMapLayout;
use lucerna_photometry::cubemap::{CubeFace, face_coordinates};
use proptest::prelude::*;

#[test]
fn texel_solid_angles_sum_to_four_pi() {
    for n in [1u32, 2, 3, 7, 64, 256, 1024] {
        let layout = CubeMapLayout::new(n);
        // Kahan-free plain sum is enough at 1e-9 for these sizes.
        let total: f64 = layout.solid_angles().iter().sum();
        assert!((total - 4.0 * PI).abs() < 1e-9, "N = {n}: {total}");
    }
}

#[test]
fn solid_angles_vary_about_five_fold_across_a_face() {
    let layout = CubeMapLayout::new(256);
    let omega = layout.solid_angles();
    let (lo, hi) = omega
        .iter()
        .fold((f64::MAX, 0.0f64), |(lo, hi), &w| (lo.min(w), hi.max(w)));
    // Centre texel (2/N)² vs corner (2/N)²/3^{3/2}: ratio 3√3 ≈ 5.2.
    assert!((hi / lo - 3f64.powf(1.5)).abs() < 0.05, "ratio {}", hi / lo);
}

#[test]
fn every_texel_centre_maps_back_to_its_texel() {
    for n in [1u32, 4, 33, 128] {
        let layout = CubeMapLayout::new(n);
        for t in 0..layout.texel_count() {
            assert_eq!(
                layout.texel_of_direction(layout.texel_centre_direction(t)),
                t,
                "N = {n}"
            );
        }
    }
}

#[test]
fn faces_follow_the_webgpu_orientation() {
    // Face centres and the direction of growing u (a) and v (b), from the
    // Vulkan/WebGPU cube-map table (sc, tc, ma).
    let cases = [
        (
            CubeFace::PosX,
            [1.0, 0.0, 0.0],
            [0.0, 0.0, -1.0],
            [0.0, -1.0, 0.0],
        ),
        (
            CubeFace::NegX,
            [-1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, -1.0, 0.0],
        ),
        (
            CubeFace::PosY,
            [0.0, 1.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0],
        ),
        (
            CubeFace::NegY,
            [0.0, -1.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 0.0, -1.0],
        ),
        (
            CubeFace::PosZ,
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 0.0],
            [0.0, -1.0, 0.0],
        ),
        (
            CubeFace::NegZ,
            [0.0, 0.0, -1.0],
            [-1.0, 0.0, 0.0],
            [0.0, -1.0, 0.0],
        ),
    ];
    for (face, centre, u_dir, v_dir) in cases {
        assert_eq!(face.direction(0.0, 0.0), centre, "{face:?}");
        let du: Vec<f64> = (0..3)
            .map(|i| face.direction(0.5, 0.0)[i] - centre[i])
            .collect();
        let dv: Vec<f64> = (0..3)
            .map(|i| face.direction(0.0, 0.5)[i] - centre[i])
            .collect();
        assert_eq!(
            du,
            u_dir.iter().map(|x| x * 0.5).collect::<Vec<_>>(),
            "{face:?} u"
        );
        assert_eq!(
            dv,
            v_dir.iter().map(|x| x * 0.5).collect::<Vec<_>>(),
            "{face:?} v"
        );
        assert_eq!(face_coordinates(centre).0, face);
    }
}

proptest! {
    #[test]
    fn direction_to_texel_to_direction_round_trips(x in -1.0f64..1.0, y in -1.0f64..1.0, z in -1.0f64..1.0, n in 1u32..300) {
        prop_assume!(x * x + y * y + z * z > 1e-6);
        let layout = CubeMapLayout::new(n);
        let (face, a, b) = face_coordinates([x, y, z]);
        // Back through the face plane: the same direction up to scale.
        let d = face.direction(a, b);
        let scale = [x, y, z].iter().map(|v| v.abs()).fold(0.0, f64::max);
        for i in 0..3 { prop_assert!((d[i] * scale - [x, y, z][i]).abs() < 1e-12); }
        // The texel's bounds contain the direction's face coordinates.
        let t = layout.texel_of_direction([x, y, z]);
        let (tface, a0, b0, a1, b1) = layout.texel_bounds(t);
        prop_assert_eq!(tface, face);
        prop_assert!(a >= a0 - 1e-12 && a <= a1 + 1e-12 && b >= b0 - 1e-12 && b <= b1 + 1e-12);
    }
}
