#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! A TM-25 ray-file emitter: photons are the file's rays, chosen in
//! proportion to their flux and placed by the emitter's transform, on the
//! CPU and in the WGSL kernel alike.

use std::path::{Path, PathBuf};

use lucerna_photometry::CubeMapLayout;
use lucerna_photometry::tm25::read_ray_file;
use lucerna_tracer::cpu::{TraceSettings, trace_batch};
use lucerna_tracer::gpu::GpuTracer;
use lucerna_tracer::{PreparedScene, luminaire_symmetry};

fn rayfiles() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/rayfiles")
}

/// The synthetic LED turned over (180° about x: it emits along −z), 1 cm
/// below an absorbing plate it never reaches.
fn scene() -> lucerna_scene::Scene {
    let text = r#"
format_version = 1
name = "ray-file LED"

[materials.black]
type = "absorber"

[[emitter]]
name = "LED"
flux_lm = 100.0
shape = { type = "ray_file", path = "synthetic_led.tm25ray" }
transform = { rotate_deg = [180.0, 0.0, 0.0], translate = [0.0, 0.0, 0.005] }

[[part]]
name = "plate"
material = "black"
shape = { type = "plate", width = 0.05, depth = 0.05 }
transform = { translate = [0.0, 0.0, 0.02] }
"#;
    lucerna_scene::parse_scene(text, &rayfiles().join("led.toml")).unwrap()
}

/// Expected escapes per texel: every ray's share of the flux, its
/// direction turned over as the transform turns it.
fn expected(layout: CubeMapLayout, photons: f64) -> Vec<f64> {
    let rays = read_ray_file(&rayfiles().join("synthetic_led.tm25ray")).unwrap();
    let total = rays.total_luminous_flux_lm();
    let mut e = vec![0.0; layout.texel_count()];
    for i in 0..rays.len() {
        let [x, y, z] = rays.direction(i).map(f64::from);
        e[layout.texel_of_direction([x, -y, -z])] +=
            photons * f64::from(rays.luminous_flux_lm[i]) / total;
    }
    e
}

/// χ² of observed counts against their expectation, over texels expecting
/// at least 20, and its degrees of freedom.
fn chi2(counts: &[u32], expected: &[f64]) -> (f64, f64) {
    let (mut chi2, mut dof) = (0.0, 0.0);
    for (&c, &e) in counts.iter().zip(expected) {
        if e >= 20.0 {
            chi2 += (f64::from(c) - e).powi(2) / e;
            dof += 1.0;
        }
    }
    (chi2, dof)
}

#[test]
fn photons_are_the_files_rays_on_the_cpu_and_the_gpu() {
    let scene = scene();
    let dir = rayfiles();
    let tessellated = lucerna_scene::tessellate(&scene, &dir).unwrap();
    // No surface for the emitter: only the plate's two triangles.
    assert_eq!(tessellated.triangle_count(), 2);
    let prepared = PreparedScene::new(&scene, &tessellated, &dir).unwrap();
    let symmetry = luminaire_symmetry(&scene, &tessellated);
    assert!(symmetry.limited_by.unwrap().contains("ray file"));
    let layout = CubeMapLayout::new(8);
    let settings = TraceSettings {
        seed: 9,
        max_bounces: 8,
        layout,
    };
    let n = 200_000u32;
    let want = expected(layout, f64::from(n));
    let cpu = trace_batch(&prepared, &settings, 0, 0, n);
    // Every photon leaves downwards: none reaches the plate above.
    assert_eq!(cpu.escaped(), u64::from(n));
    let (c2, dof) = chi2(&cpu.counts, &want);
    assert!(
        c2 < dof + 5.0 * (2.0 * dof).sqrt(),
        "CPU: χ² {c2} over {dof}"
    );
    if let Some(ctx) = lucerna_gpu::open_for_tests() {
        let gpu = GpuTracer::new(ctx, &prepared, settings).unwrap();
        let g = gpu.trace_batch(0, 0, n).unwrap();
        assert_eq!(g.escaped(), u64::from(n));
        let (c2, dof) = chi2(&g.counts, &want);
        assert!(
            c2 < dof + 5.0 * (2.0 * dof).sqrt(),
            "GPU: χ² {c2} over {dof}"
        );
    }
}

#[test]
fn a_missing_or_broken_ray_file_is_a_clear_error() {
    let mut scene = scene();
    scene.emitters[0].shape = lucerna_scene::EmitterShape::RayFile {
        path: "missing.tm25ray".to_owned(),
    };
    let dir = rayfiles();
    let tessellated = lucerna_scene::tessellate(&scene, &dir).unwrap();
    let e = PreparedScene::new(&scene, &tessellated, &dir).unwrap_err();
    let chain = format!("{e}: {}", std::error::Error::source(&e).unwrap());
    assert!(
        chain.contains("LED") && chain.contains("missing.tm25ray"),
        "{chain}"
    );
}
