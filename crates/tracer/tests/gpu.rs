#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! The WGSL kernel against the CPU reference, on whatever adapter this
//! machine has (llvmpipe / lavapipe in CI). Set LUCERNA_SKIP_GPU_TESTS=1
//! only on a machine with no adapter at all.

use std::path::Path;

use lucerna_photometry::CubeMapLayout;
use lucerna_photometry::table::angles;
use lucerna_tracer::cpu::{TraceSettings, trace_batch};
use lucerna_tracer::gpu::GpuTracer;
use lucerna_tracer::{PreparedScene, Tally};
use wgpu::util::DeviceExt;

fn context() -> Option<lucerna_gpu::GpuContext> {
    lucerna_gpu::open_for_tests()
}

#[test]
fn rust_and_wgsl_cube_map_mappings_agree() {
    let Some(ctx) = context() else { return };
    let resolution = 97u32;
    let mut rng = lucerna_tracer::rng::PhotonRng::new(11, 0, 0);
    let dirs: Vec<[f32; 4]> = (0..20_000)
        .map(|i| {
            // Random directions plus exact axes and face diagonals.
            let v = match i {
                0..6 => {
                    let mut a = [0.0; 3];
                    a[i / 2] = if i % 2 == 0 { 1.0 } else { -1.0 };
                    a
                }
                _ => [
                    rng.next_f32() * 2.0 - 1.0,
                    rng.next_f32() * 2.0 - 1.0,
                    rng.next_f32() * 2.0 - 1.0,
                ],
            };
            [v[0], v[1], v[2], 0.0]
        })
        .collect();
    let device = &ctx.device;
    let module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
        label: None,
        source: wgpu::ShaderSource::Wgsl(lucerna_gpu::shaders::cubemap_test().into()),
    });
    let pipeline = device.create_compute_pipeline(&wgpu::ComputePipelineDescriptor {
        label: None,
        layout: None,
        module: &module,
        entry_point: Some("map_directions"),
        compilation_options: Default::default(),
        cache: None,
    });
    let params = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents: bytemuck::cast_slice(&[dirs.len() as u32, resolution, 0, 0]),
        usage: wgpu::BufferUsages::UNIFORM,
    });
    let input = device.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: None,
        contents: bytemuck::cast_slice(&dirs),
        usage: wgpu::BufferUsages::STORAGE,
    });
    let size = 4 * dirs.len() as u64;
    let output = device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size,
        usage: wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC,
        mapped_at_creation: false,
    });
    let readback = device.create_buffer(&wgpu::BufferDescriptor {
        label: None,
        size,
        usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
        mapped_at_creation: false,
    });
    let bind = device.create_bind_group(&wgpu::BindGroupDescriptor {
        label: None,
        layout: &pipeline.get_bind_group_layout(0),
        entries: &[
            wgpu::BindGroupEntry {
                binding: 0,
                resource: params.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 1,
                resource: input.as_entire_binding(),
            },
            wgpu::BindGroupEntry {
                binding: 2,
                resource: output.as_entire_binding(),
            },
        ],
    });
    let mut encoder = device.create_command_encoder(&Default::default());
    {
        let mut pass = encoder.begin_compute_pass(&Default::default());
        pass.set_pipeline(&pipeline);
        pass.set_bind_group(0, &bind, &[]);
        pass.dispatch_workgroups((dirs.len() as u32).div_ceil(64), 1, 1);
    }
    encoder.copy_buffer_to_buffer(&output, 0, &readback, 0, None);
    ctx.queue.submit([encoder.finish()]);
    let gpu: Vec<u32> =
        bytemuck::cast_slice(&lucerna_gpu::read_buffer(&ctx, &readback).unwrap()).to_vec();
    let layout = CubeMapLayout::new(resolution);
    let mut disagreements = 0;
    for (d, &g) in dirs.iter().zip(&gpu) {
        let cpu = layout.texel_of_direction([f64::from(d[0]), f64::from(d[1]), f64::from(d[2])]);
        if cpu as u32 != g {
            // Only f32 vs f64 rounding on a texel border may differ: the
            // GPU texel must then neighbour the CPU one.
            let a = layout.texel_centre_direction(cpu);
            let b = layout.texel_centre_direction(g as usize);
            let cos = a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
            assert!(
                cos > (3.0 * 90.0 / f64::from(resolution)).to_radians().cos(),
                "{d:?}: CPU texel {cpu}, GPU {g}"
            );
            disagreements += 1;
        }
    }
    assert!(
        disagreements < 10,
        "{disagreements} directions mapped differently"
    );
}

/// Photons per coarse direction bin: 12 γ bands × 4 C quadrants.
fn coarse(t: &Tally, layout: CubeMapLayout) -> Vec<f64> {
    let mut bins = vec![0.0; 48];
    for (texel, &c) in t.counts.iter().enumerate() {
        let (cp, g) = angles(layout.texel_centre_direction(texel));
        let band = ((g.to_degrees() / 15.0) as usize).min(11);
        let quadrant = ((cp.to_degrees() / 90.0) as usize).min(3);
        bins[band * 4 + quadrant] += f64::from(c);
    }
    bins
}

#[test]
fn gpu_kernel_matches_the_cpu_reference_on_every_example() {
    let Some(ctx) = context() else { return };
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires");
    let mut names: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    names.sort();
    let layout = CubeMapLayout::new(32);
    let settings = TraceSettings {
        seed: 5,
        max_bounces: 32,
        layout,
    };
    let n = 60_000u32;
    for path in names {
        let scene = lucerna_scene::load_scene(&path).unwrap();
        let tessellated = lucerna_scene::tessellate(&scene, &dir).unwrap();
        let prepared = PreparedScene::new(&scene, &tessellated, &dir).unwrap();
        let gpu = GpuTracer::new(ctx.clone(), &prepared, settings).unwrap();
        let g = gpu.trace_batch(0, 0, n).unwrap();
        // Different photons on the CPU (another iteration), same physics.
        let c = trace_batch(&prepared, &settings, 1, 0, n);
        let name = path.file_name().unwrap().to_string_lossy();
        assert_eq!(
            g.escaped() + g.absorbed + g.cut_off,
            u64::from(n),
            "{name}: GPU energy balance"
        );
        // Fates: two-proportion z-test.
        for (what, a, b) in [
            ("escaped", g.escaped(), c.escaped()),
            ("absorbed", g.absorbed, c.absorbed),
        ] {
            let (pa, pb) = (a as f64 / f64::from(n), b as f64 / f64::from(n));
            let p = 0.5 * (pa + pb);
            let sigma = (2.0 * p * (1.0 - p) / f64::from(n)).sqrt().max(1e-9);
            assert!(
                (pa - pb).abs() < 5.0 * sigma + 1e-4,
                "{name}: {what} GPU {pa} vs CPU {pb} (σ {sigma})"
            );
        }
        // Directions: two-sample χ² over coarse bins.
        let (bg, bc) = (coarse(&g, layout), coarse(&c, layout));
        let (mut chi2, mut dof) = (0.0, 0);
        for (x, y) in bg.iter().zip(&bc) {
            if x + y >= 20.0 {
                chi2 += (x - y).powi(2) / (x + y);
                dof += 1;
            }
        }
        let dof = f64::from(dof.max(1));
        assert!(
            chi2 < dof + 5.0 * (2.0 * dof).sqrt(),
            "{name}: χ² {chi2} over {dof} bins"
        );
        eprintln!(
            "{name}: χ² {chi2:.1} / {dof} bins, escaped GPU {} CPU {}",
            g.escaped(),
            c.escaped()
        );
    }
}

#[test]
fn gpu_counts_are_deterministic_and_split_exactly() {
    let Some(ctx) = context() else { return };
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires");
    let path = dir.join("parabolic_spot.toml");
    let scene = lucerna_scene::load_scene(&path).unwrap();
    let prepared = PreparedScene::new(
        &scene,
        &lucerna_scene::tessellate(&scene, &dir).unwrap(),
        &dir,
    )
    .unwrap();
    let settings = TraceSettings {
        seed: 9,
        max_bounces: 16,
        layout: CubeMapLayout::new(16),
    };
    let gpu = GpuTracer::new(ctx, &prepared, settings).unwrap();
    let whole = gpu.trace_batch(2, 0, 20_000).unwrap();
    assert_eq!(whole, gpu.trace_batch(2, 0, 20_000).unwrap());
    let a = gpu.trace_batch(2, 0, 7_000).unwrap();
    let b = gpu.trace_batch(2, 7_000, 13_000).unwrap();
    let summed: Vec<u32> = a.counts.iter().zip(&b.counts).map(|(x, y)| x + y).collect();
    assert_eq!(summed, whole.counts);
}

#[test]
fn gpu_kernel_traces_finishes_as_the_cpu_does() {
    // Dimples, crossed ripples at an angle and a rough conductor with a
    // finish: the kernel's facets against the CPU's, on 2° bands of γ
    // and C quadrants (finer than the examples' test: a finish's
    // plateau and peak are what must agree).
    let Some(ctx) = context() else { return };
    let finishes = [
        (
            "mirror",
            r#"{ type = "dimples", pitch = 0.002, depth = 0.00015, radius = 0.0034 }"#,
        ),
        (
            "mirror",
            r#"{ type = "ripples", waves = [{ amplitude = 0.00001, wavelength = 0.0008, direction_deg = 30.0 }, { amplitude = 0.00002, wavelength = 0.0011, direction_deg = 100.0, shape = "trochoid" }] }"#,
        ),
        (
            "brushed",
            r#"{ type = "slopes", sigma_u = 0.08, sigma_v = 0.03, orientation_deg = 15.0 }"#,
        ),
    ];
    let layout = CubeMapLayout::new(64);
    let settings = TraceSettings {
        seed: 5,
        max_bounces: 16,
        layout,
    };
    let n = 200_000u32;
    for (material, finish) in finishes {
        let text = format!(
            r#"
format_version = 1
name = "finished"
[materials.mirror]
type = "mirror"
reflectance = 0.9
[materials.brushed]
type = "rough_conductor"
reflectance = 0.8
roughness_u = 0.05
roughness_v = 0.02
[[emitter]]
name = "LED"
flux_lm = 1000.0
shape = {{ type = "disk", radius = 0.001 }}
transform = {{ rotate_deg = [180.0, 0.0, 0.0] }}
[[part]]
name = "reflector"
material = "{material}"
shape = {{ type = "paraboloid", focal_length = 0.01, aperture_diameter = 0.04, neck_diameter = 0.006, segments_around = 64, segments_along = 16 }}
finish = {finish}
"#
        );
        let scene = lucerna_scene::parse_scene(&text, Path::new("f.toml")).unwrap();
        let tessellated = lucerna_scene::tessellate(&scene, Path::new(".")).unwrap();
        let prepared = PreparedScene::new(&scene, &tessellated, Path::new(".")).unwrap();
        assert!(prepared.material_finish.iter().any(Option::is_some));
        let gpu = GpuTracer::new(ctx.clone(), &prepared, settings).unwrap();
        let g = gpu.trace_batch(0, 0, n).unwrap();
        let c = trace_batch(&prepared, &settings, 1, 0, n);
        assert_eq!(g.escaped() + g.absorbed + g.cut_off, u64::from(n));
        let fine = |t: &Tally| {
            let mut bins = vec![0.0; 45 * 4];
            for (texel, &k) in t.counts.iter().enumerate() {
                let (cp, gamma) = angles(layout.texel_centre_direction(texel));
                let band = ((gamma.to_degrees() / 2.0) as usize).min(44);
                let quadrant = ((cp.to_degrees() / 90.0) as usize).min(3);
                bins[band * 4 + quadrant] += f64::from(k);
            }
            bins
        };
        let (bg, bc) = (fine(&g), fine(&c));
        let (mut chi2, mut dof) = (0.0, 0);
        for (x, y) in bg.iter().zip(&bc) {
            if x + y >= 20.0 {
                chi2 += (x - y).powi(2) / (x + y);
                dof += 1;
            }
        }
        let dof = f64::from(dof.max(1));
        eprintln!(
            "{finish}: χ² {chi2:.1} / {dof}, escaped GPU {} CPU {}",
            g.escaped(),
            c.escaped()
        );
        assert!(dof > 20.0, "{dof}");
        assert!(
            chi2 < dof + 5.0 * (2.0 * dof).sqrt(),
            "{finish}: χ² {chi2} over {dof} bins"
        );
        let (pg, pc) = (
            g.escaped() as f64 / f64::from(n),
            c.escaped() as f64 / f64::from(n),
        );
        let sigma = (2.0 * pc * (1.0 - pc) / f64::from(n)).sqrt();
        assert!((pg - pc).abs() < 5.0 * sigma, "escaped {pg} vs {pc}");
    }
}
