#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! A TM-25 ray-file emitter: photons are the file's rays, chosen in
//! proportion to their flux and placed by the emitter's transform, on the
//! CPU and in the WGSL kernel alike.

use std::path::{Path, PathBuf};

use lucerna_photometry::AxialSymmetry;
use lucerna_photometry::CubeMapLayout;
use lucerna_photometry::tm25::read_ray_file;
use lucerna_photometry::tm25::{RayFileHeader, RaySet, write_ray_file};
use lucerna_tracer::cpu::{TraceSettings, trace_batch};
use lucerna_tracer::gpu::GpuTracer;
use lucerna_tracer::{PreparedScene, RayReuse, luminaire_symmetry, prepared_luminaire_symmetry};

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
    let mut prepared = PreparedScene::new(&scene, &tessellated, &dir).unwrap();
    // The rays as they are (interpolated rays are tested below).
    prepared.set_ray_reuse(RayReuse::Loop);
    // Unchecked, a ray file breaks every symmetry; checked, the synthetic
    // LED (a Lambertian disk) and the square plate have all eight.
    let unchecked = luminaire_symmetry(&scene, &tessellated);
    assert!(unchecked.limited_by.unwrap().contains("ray file"));
    let checked = prepared_luminaire_symmetry(&scene, &tessellated, &prepared);
    assert_eq!(checked.symmetry, AxialSymmetry::Square, "{checked:?}");
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

/// A Lambertian disk of radius 1 mm emitting along +z, as `rays` rays of
/// equal flux, but those going towards +x carry `plus_x` times as much.
fn disk_rays(rays: usize, plus_x: f32) -> RaySet {
    lambertian_disk(rays, 1.0, 1.0, plus_x)
}

/// A Lambertian disk of `radius_mm` emitting along `z_sign` z, as `rays`
/// rays of equal flux, but those going towards +x carry `plus_x` times as
/// much; drawn from a fixed stream (SplitMix64).
fn lambertian_disk(rays: usize, radius_mm: f64, z_sign: f64, plus_x: f32) -> RaySet {
    let mut state = 0x1234_5678_9abc_def0u64;
    let mut uniform = || {
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut records = Vec::with_capacity(7 * rays);
    let mut fluxes = Vec::with_capacity(rays);
    for _ in 0..rays {
        let (r, a) = (uniform().sqrt(), std::f64::consts::TAU * uniform());
        let (s, b) = (uniform().sqrt(), std::f64::consts::TAU * uniform());
        let d = [s * b.cos(), s * b.sin(), z_sign * (1.0 - s * s).sqrt()];
        let f = if d[0] > 0.0 { plus_x } else { 1.0 };
        records.extend([
            (radius_mm * r * a.cos()) as f32,
            (radius_mm * r * a.sin()) as f32,
            0.0,
            d[0] as f32,
            d[1] as f32,
            d[2] as f32,
            f,
        ]);
        fluxes.push(f);
    }
    let total: f32 = fluxes.iter().sum();
    RaySet {
        header: RayFileHeader::luminous(rays as u64, total),
        records,
        luminous_flux_lm: fluxes,
    }
}

/// The symmetry a scene finds with `rays` as its emitter, placed by
/// `transform` (TOML), over a square absorbing plate.
fn symmetry_with(rays: &RaySet, transform: &str) -> lucerna_tracer::LuminaireSymmetry {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("led.tm25ray"), write_ray_file(rays)).unwrap();
    let text = format!(
        r#"
format_version = 1
name = "checked rays"

[materials.black]
type = "absorber"

[[emitter]]
name = "LED"
flux_lm = 100.0
shape = {{ type = "ray_file", path = "led.tm25ray" }}
transform = {transform}

[[part]]
name = "plate"
material = "black"
shape = {{ type = "plate", width = 0.05, depth = 0.05 }}
transform = {{ translate = [0.0, 0.0, -0.02] }}
"#
    );
    let scene = lucerna_scene::parse_scene(&text, &dir.path().join("s.toml")).unwrap();
    let tessellated = lucerna_scene::tessellate(&scene, dir.path()).unwrap();
    let prepared = PreparedScene::new(&scene, &tessellated, dir.path()).unwrap();
    prepared_luminaire_symmetry(&scene, &tessellated, &prepared)
}

#[test]
fn a_ray_files_symmetry_is_checked_not_assumed() {
    let on_axis = "{ translate = [0.0, 0.0, 0.0] }";
    // A symmetric set within its own noise: all eight.
    let fair = disk_rays(200_000, 1.0);
    assert_eq!(
        symmetry_with(&fair, on_axis).symmetry,
        AxialSymmetry::Square
    );
    // 10 % more light towards +x: only the mirror that keeps x.
    let tilted = disk_rays(200_000, 1.1);
    let found = symmetry_with(&tilted, on_axis);
    assert_eq!(found.symmetry, AxialSymmetry::AboutC0C180, "{found:?}");
    assert!(found.limited_by.unwrap().contains("ray file"));
    // The fair set placed 0.5 mm off the axis along y: only the mirror
    // that keeps y.
    let off_axis = "{ translate = [0.0, 0.0005, 0.0] }";
    assert_eq!(
        symmetry_with(&fair, off_axis).symmetry,
        AxialSymmetry::AboutC90C270
    );
    // Turned 5° about x (its beam leans towards −y): the same.
    let turned = "{ rotate_deg = [5.0, 0.0, 0.0] }";
    assert_eq!(
        symmetry_with(&fair, turned).symmetry,
        AxialSymmetry::AboutC90C270
    );
}

/// Ideal emitter equivalence: the parabolic spot's 3 mm Lambertian LED
/// written as a ray file (1 M rays of our own generator) in place of its
/// disk bakes the same distribution as the native disk, within the Monte
/// Carlo floor: a two-sample χ² over the texels, each count's variance
/// Poisson for the disk and Poisson times (1 + photons / rays) for the
/// file (its rays are themselves a sample).
#[test]
fn a_lambertian_disk_as_a_ray_file_bakes_as_the_native_disk() {
    // The file's rays as they are, fewer photons than rays.
    disk_file_against_native(1_000_000, 400_000, RayReuse::Loop);
    // Twenty photons a ray, each a ray moved by the file's kernel: within
    // the file's own noise of the native disk.
    disk_file_against_native(100_000, 2_000_000, RayReuse::Interpolate);
}

fn disk_file_against_native(rays: usize, photons: u32, reuse: RayReuse) {
    let spot =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires/parabolic_spot.toml");
    let native = lucerna_scene::load_scene(&spot).unwrap();
    let lucerna_scene::EmitterShape::Disk { radius } = native.emitters[0].shape else {
        panic!("the spot's LED is a disk");
    };
    let dir = tempfile::tempdir().unwrap();
    // The native disk emits along its own −z.
    let file = lambertian_disk(rays, radius * 1e3, -1.0, 1.0);
    std::fs::write(dir.path().join("disk.tm25ray"), write_ray_file(&file)).unwrap();
    let mut with_file = native.clone();
    with_file.emitters[0].shape = lucerna_scene::EmitterShape::RayFile {
        path: "disk.tm25ray".to_owned(),
    };
    // Texels of 0.35°: the spot's 7° beam over a few hundred of them.
    let layout = CubeMapLayout::new(256);
    let counts = |scene: &lucerna_scene::Scene, folder: &Path, seed: u32| {
        let tessellated = lucerna_scene::tessellate(scene, folder).unwrap();
        let mut prepared = PreparedScene::new(scene, &tessellated, folder).unwrap();
        prepared.set_ray_reuse(reuse);
        let settings = TraceSettings {
            seed,
            max_bounces: 64,
            layout,
        };
        trace_batch(&prepared, &settings, 0, 0, photons).counts
    };
    let spot_dir = spot.parent().unwrap();
    let a = counts(&native, spot_dir, 1);
    let b = counts(&with_file, dir.path(), 2);
    let c = counts(&native, spot_dir, 3);
    let inflation = 1.0 + f64::from(photons) / rays as f64;
    let chi2 = |x: &[u32], y: &[u32], vy: f64| -> (f64, f64) {
        let (mut s, mut dof) = (0.0, 0.0);
        for (&p, &q) in x.iter().zip(y) {
            let (p, q) = (f64::from(p), f64::from(q));
            if p + q >= 40.0 {
                s += (p - q).powi(2) / (p + vy * q);
                dof += 1.0;
            }
        }
        (s, dof)
    };
    let (s, dof) = chi2(&a, &b, inflation);
    assert!(dof > 50.0, "{dof} texels");
    assert!(
        s < dof + 5.0 * (2.0 * dof).sqrt(),
        "ray file vs disk: χ² {s} over {dof}"
    );
    // The floor: the native disk against itself with another seed.
    let (s0, dof0) = chi2(&a, &c, 1.0);
    assert!(
        s0 < dof0 + 5.0 * (2.0 * dof0).sqrt(),
        "floor: χ² {s0} over {dof0}"
    );
    // It can fail: the file's LED 0.5 mm off the focus is another light.
    let mut moved = with_file.clone();
    moved.emitters[0].transform.translate[2] += 0.0005;
    let m = counts(&moved, dir.path(), 2);
    let (sm, dofm) = chi2(&a, &m, inflation);
    assert!(
        sm > dofm + 10.0 * (2.0 * dofm).sqrt(),
        "moved: χ² {sm} over {dofm}"
    );
    eprintln!(
        "{rays} rays, {photons} photons, {reuse:?}: χ²/dof: ray file {:.3}, floor {:.3}, moved {:.3}",
        s / dof,
        s0 / dof0,
        sm / dofm
    );
}

/// A bare LED file: intensity per texel of a bake of `photons`, in
/// candela for 1 lm, with its rays reused as `reuse` says.
fn bare_led_intensity(
    rays: &RaySet,
    layout: CubeMapLayout,
    photons: u32,
    reuse: RayReuse,
    gpu: bool,
) -> Option<Vec<f64>> {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("led.tm25ray"), write_ray_file(rays)).unwrap();
    let text = r#"
format_version = 1
name = "bare LED"

[materials.black]
type = "absorber"

[[emitter]]
name = "LED"
flux_lm = 1.0
shape = { type = "ray_file", path = "led.tm25ray" }

[[part]]
name = "plate"
material = "black"
shape = { type = "plate", width = 0.01, depth = 0.01 }
transform = { translate = [0.0, 0.0, 0.05] }
"#;
    let scene = lucerna_scene::parse_scene(text, &dir.path().join("s.toml")).unwrap();
    let tessellated = lucerna_scene::tessellate(&scene, dir.path()).unwrap();
    let mut prepared = PreparedScene::new(&scene, &tessellated, dir.path()).unwrap();
    prepared.set_ray_reuse(reuse);
    let settings = TraceSettings {
        seed: 5,
        max_bounces: 4,
        layout,
    };
    let counts = if gpu {
        let ctx = lucerna_gpu::open_for_tests()?;
        let tracer = GpuTracer::new(ctx, &prepared, settings).unwrap();
        let mut total = vec![0u64; layout.texel_count()];
        let batch = 1u32 << 20;
        for k in 0..photons.div_ceil(batch) {
            let n = batch.min(photons - k * batch);
            let b = tracer.trace_batch(k, 0, n).unwrap();
            total
                .iter_mut()
                .zip(&b.counts)
                .for_each(|(t, c)| *t += u64::from(*c));
        }
        total
    } else {
        let batch = 1u32 << 21;
        let mut total = vec![0u64; layout.texel_count()];
        for k in 0..photons.div_ceil(batch) {
            let n = batch.min(photons - k * batch);
            let b = trace_batch(&prepared, &settings, k, 0, n);
            total
                .iter_mut()
                .zip(&b.counts)
                .for_each(|(t, c)| *t += u64::from(*c));
        }
        total
    };
    Some(
        counts
            .iter()
            .enumerate()
            .map(|(t, &c)| c as f64 / f64::from(photons) / layout.texel_solid_angle(t))
            .collect(),
    )
}

/// Intensity (cd per lm) against γ from −z in rings of `step` degrees:
/// each ring's flux over its solid angle.
fn rings(directions: impl Iterator<Item = ([f64; 3], f64)>, step: f64) -> Vec<f64> {
    let n = (90.0 / step) as usize;
    let mut flux = vec![0.0; n];
    for (d, w) in directions {
        let g = (-d[2]).clamp(-1.0, 1.0).acos().to_degrees();
        if g < 90.0 {
            flux[(g / step) as usize] += w;
        }
    }
    (0..n)
        .map(|k| {
            let (a, b) = (
                (k as f64 * step).to_radians(),
                ((k + 1) as f64 * step).to_radians(),
            );
            flux[k] / (std::f64::consts::TAU * (a.cos() - b.cos()))
        })
        .collect()
}

/// Issue 53: a 100 k-ray LED baked with 20 M photons. Looped, each ray's
/// 200 photons land on its own texel and the table's peak is a spike;
/// interpolated, the peak is the rays' own (binned in 10° rings, where
/// each ring holds thousands of rays), within 5 %, and the far field
/// keeps within twice the file's own noise of the rays' binning.
#[test]
fn interpolated_rays_bake_without_spikes() {
    let rays = lambertian_disk(100_000, 1.0, -1.0, 1.0);
    let total = rays.total_luminous_flux_lm();
    let own = rings(
        (0..rays.len()).map(|i| {
            let d = rays.direction(i).map(f64::from);
            let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            (
                d.map(|x| x / l),
                f64::from(rays.luminous_flux_lm[i]) / total,
            )
        }),
        10.0,
    );
    let own_peak = own.iter().copied().fold(0.0, f64::max);
    // Texels of 2.8°: 15 000 photons in each of the peak's.
    let layout = CubeMapLayout::new(32);
    let photons = 20_000_000;
    let peak = |i: &[f64]| i.iter().copied().fold(0.0, f64::max);
    let looped = bare_led_intensity(&rays, layout, photons, RayReuse::Loop, false).unwrap();
    let moved = bare_led_intensity(&rays, layout, photons, RayReuse::Interpolate, false).unwrap();
    let texel_rings = |i: &[f64]| {
        rings(
            (0..layout.texel_count()).map(|t| {
                let d = layout.texel_centre_direction(t);
                (d, i[t] * layout.texel_solid_angle(t))
            }),
            10.0,
        )
    };
    eprintln!(
        "peak cd/lm: rays {own_peak:.4}, looped {:.4}, interpolated {:.4}",
        peak(&looped),
        peak(&moved)
    );
    assert!(
        peak(&looped) > 1.2 * own_peak,
        "looped rays make spikes: {} vs {own_peak}",
        peak(&looped)
    );
    assert!(
        (peak(&moved) / own_peak - 1.0).abs() < 0.05,
        "interpolated peak {} vs the rays' {own_peak}",
        peak(&moved)
    );
    // Ring by ring, the interpolated bake against the rays' own binning:
    // within twice the rays' noise (a ring of m rays: 1/√m).
    // The rays binned on the same texels, so both rings have the same
    // texel edges.
    let mut binned = vec![0.0; layout.texel_count()];
    for i in 0..rays.len() {
        let d = rays.direction(i).map(f64::from);
        let t = layout.texel_of_direction(d);
        binned[t] += f64::from(rays.luminous_flux_lm[i]) / total / layout.texel_solid_angle(t);
    }
    let own = texel_rings(&binned);
    let moved_rings = texel_rings(&moved);
    for k in 0..8 {
        let (a, b) = (
            (k as f64 * 10.0).to_radians(),
            ((k + 1) as f64 * 10.0).to_radians(),
        );
        let share = a.cos().powi(2) - b.cos().powi(2);
        let noise = 1.0 / (share * rays.len() as f64).sqrt();
        let rel = moved_rings[k] / own[k] - 1.0;
        eprintln!("ring {k}: {rel:+.4} (noise {noise:.4})");
        assert!(
            rel.abs() < 2.0 * noise + 0.01,
            "ring {k}: {rel:+.4} (noise {noise:.4})"
        );
    }
    // The WGSL kernel draws the same kernel: its peak within 2 % of the
    // CPU's.
    if let Some(g) = bare_led_intensity(&rays, layout, 4_000_000, RayReuse::Interpolate, true) {
        let gr = texel_rings(&g);
        for k in 0..8 {
            let rel = gr[k] / moved_rings[k] - 1.0;
            assert!(rel.abs() < 0.02, "GPU ring {k}: {rel:+.4}");
        }
        assert!(
            peak(&g) < 1.15 * own_peak,
            "GPU peak {} vs {own_peak}",
            peak(&g)
        );
    }
}
