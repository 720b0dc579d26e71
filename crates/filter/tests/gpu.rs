#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! The WGSL filter against the CPU reference on the software adapter.

mod common;

use common::photons;
use lucerna_filter::gpu::GpuFilter;
use lucerna_filter::{FilterSettings, Threshold, filter, filter_symmetric};
use lucerna_photometry::{AxialSymmetry, CubeMapLayout, TexelSymmetry};

fn context() -> Option<lucerna_gpu::GpuContext> {
    lucerna_gpu::open_for_tests()
}

#[test]
fn gpu_filter_matches_the_cpu_reference() {
    let Some(ctx) = context() else { return };
    for resolution in [1u32, 5, 32, 64] {
        let layout = CubeMapLayout::new(resolution);
        let gpu = GpuFilter::new(ctx.clone(), layout).unwrap();
        let counts = photons(layout, 20 * layout.texel_count(), 7, |d| {
            let lit = if d[0] > 0.3 { 1.0 } else { 0.15 };
            lit * (0.5 + 0.5 * d[2].abs())
        });
        for threshold in [
            Threshold::Automatic,
            Threshold::Fixed(100.0),
            Threshold::Fixed(30.0),
            Threshold::Poisson { cap: 512.0, z: 3.0 },
        ] {
            let settings = FilterSettings {
                threshold,
                ..Default::default()
            };
            let cpu = filter(layout, &counts, &settings);
            let g = gpu.filter(&counts, &settings).unwrap();
            // The automatic mode chooses the same candidate on both.
            assert_eq!(g.settings, cpu.settings, "N {resolution} {threshold:?}");
            // f32 on the GPU, f64 on the CPU: values agree to float
            // tolerance; a decision on a test's very edge may flip.
            let mut differing = 0;
            for t in 0..counts.len() {
                let (a, b) = (g.photons_per_sr[t], cpu.photons_per_sr[t]);
                if (a - b).abs() > 1e-3 * b.abs().max(1.0) || g.replaced[t] != cpu.replaced[t] {
                    differing += 1;
                }
            }
            assert!(
                differing * 1000 <= counts.len(),
                "N {resolution} {threshold:?}: {differing} of {} texels differ",
                counts.len()
            );
            assert!(
                (g.renormalisation - cpu.renormalisation).abs() < 1e-3,
                "{} vs {}",
                g.renormalisation,
                cpu.renormalisation
            );
        }
    }
}

#[test]
fn gpu_filter_with_a_symmetry_matches_the_cpu_reference() {
    let Some(ctx) = context() else { return };
    let layout = CubeMapLayout::new(32);
    let gpu = GpuFilter::new(ctx, layout).unwrap();
    let sym = TexelSymmetry::new(layout, AxialSymmetry::Square);
    let counts = photons(layout, 4 * layout.texel_count(), 9, |d| {
        if d[2] > 0.5 {
            0.5 + 0.5 * (d[0] * d[1]).abs()
        } else {
            0.05
        }
    });
    for threshold in [Threshold::Automatic, Threshold::Fixed(100.0)] {
        let settings = FilterSettings {
            threshold,
            ..Default::default()
        };
        let cpu = filter_symmetric(&counts, &settings, &sym);
        let g = gpu.filter_symmetric(&counts, &settings, &sym).unwrap();
        assert_eq!(g.settings, cpu.settings, "{threshold:?}");
        assert_eq!(g.symmetry, AxialSymmetry::Square);
        let differing = (0..counts.len())
            .filter(|&t| {
                let (a, b) = (g.photons_per_sr[t], cpu.photons_per_sr[t]);
                (a - b).abs() > 1e-3 * b.abs().max(1.0) || g.replaced[t] != cpu.replaced[t]
            })
            .count();
        assert!(
            differing * 1000 <= counts.len(),
            "{threshold:?}: {differing} of {} texels differ",
            counts.len()
        );
    }
}
