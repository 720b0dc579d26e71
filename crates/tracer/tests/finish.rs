#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! Finishes traced as their BRDF against the same finishes cut into the
//! mesh as triangles: the far fields agree within the noise floor, a
//! Gaussian of the same slope variance does not, the split between
//! normals and BRDF moves without a jump, and a finished mirror loses
//! exactly its computed shadowing.

use std::path::Path;

use glam::Vec3A;
use lucerna_scene::{FinishSplit, parse_scene, tessellate_with};
use lucerna_tracer::PreparedScene;
use lucerna_tracer::cpu::{Fate, trace_photon};
use lucerna_tracer::rng::PhotonRng;
use rayon::prelude::*;

/// A small parabolic spot (f = 10 mm, 40 mm aperture, 6 mm neck) with a
/// 2 mm LED at the focus facing the vertex, its reflector finished by
/// `finish` (a TOML inline table, or empty).
fn spot(finish: &str) -> String {
    finished_scene(
        "reflector",
        "{ type = \"paraboloid\", focal_length = 0.01, aperture_diameter = 0.024, neck_diameter = 0.006, segments_around = 96, segments_along = 16 }",
        finish,
    )
}

/// A trough: a parabolic profile (f = 10 mm, 40 mm wide) extruded 20 mm
/// along y, the same LED at its focal line facing the vertex.
fn trough(finish: &str) -> String {
    let f: f64 = 0.01;
    let points: Vec<String> = (0..=16)
        .map(|i| {
            let x = -0.02 + 0.04 * f64::from(i) / 16.0;
            format!("[{x}, {}]", f - x * x / (4.0 * f))
        })
        .collect();
    let shape = format!(
        "{{ type = \"extruded\", profile = [{}], length = 0.02, end_caps = false, segments_per_span = 4 }}",
        points.join(", ")
    );
    finished_scene("trough", &shape, finish)
}

/// One mirror part `name` of `shape` (a TOML inline table) around a 2 mm
/// LED facing −z at the origin, finished by `finish` (or not, if empty).
fn finished_scene(name: &str, shape: &str, finish: &str) -> String {
    let finish = if finish.is_empty() {
        String::new()
    } else {
        format!("finish = {finish}")
    };
    format!(
        r#"
format_version = 1
name = "finished {name}"
[materials.alu]
type = "mirror"
reflectance = 0.9
[[emitter]]
name = "LED"
flux_lm = 1000.0
shape = {{ type = "disk", radius = 0.001 }}
transform = {{ rotate_deg = [180.0, 0.0, 0.0] }}
[[part]]
name = "{name}"
material = "alu"
shape = {shape}
{finish}
"#
    )
}

fn prepare(toml: &str, split: FinishSplit) -> PreparedScene {
    let scene = parse_scene(toml, Path::new("test.toml")).unwrap_or_else(|e| panic!("{e}"));
    let problems = lucerna_scene::validate(&scene);
    assert!(problems.is_empty(), "{problems:?}");
    let t = tessellate_with(&scene, Path::new("."), split).unwrap();
    PreparedScene::new(&scene, &t, Path::new(".")).unwrap()
}

/// Cut into the mesh at triangles of at most `edge` (m).
fn as_geometry(edge: f64) -> FinishSplit {
    FinishSplit {
        geometry_edge: Some(edge),
        ..FinishSplit::default()
    }
}

/// Escaped photons' directions binned by `bin` (a bin index or none).
fn histogram(
    scene: &PreparedScene,
    photons: u32,
    seed: u32,
    bins: usize,
    bin: impl Fn(Vec3A) -> Option<usize> + Sync,
) -> Vec<f64> {
    let chunks = 64u32;
    let per = photons / chunks;
    (0..chunks)
        .into_par_iter()
        .map(|c| {
            let mut h = vec![0.0; bins];
            for i in c * per..(c + 1) * per {
                let mut rng = PhotonRng::new(seed, 0, i);
                if let (Fate::Escaped(d), _, _) = trace_photon(scene, 16, &mut rng)
                    && let Some(k) = bin(d)
                {
                    h[k] += 1.0;
                }
            }
            h
        })
        .reduce(
            || vec![0.0; bins],
            |mut a, b| {
                a.iter_mut().zip(b).for_each(|(x, y)| *x += y);
                a
            },
        )
}

/// Bins of γ (from the downward axis) this wide, out to [`GAMMA_MAX`].
const GAMMA_BIN_DEG: f64 = 0.5;
const GAMMA_MAX: f64 = 60.0;

/// Intensity (photons per steradian) in bins of γ.
fn intensity_by_gamma(scene: &PreparedScene, photons: u32, seed: u32) -> Vec<f64> {
    let bins = (GAMMA_MAX / GAMMA_BIN_DEG) as usize;
    let h = histogram(scene, photons, seed, bins, |d| {
        let gamma = (-d.z).clamp(-1.0, 1.0).acos().to_degrees() as f64;
        let k = (gamma / GAMMA_BIN_DEG) as usize;
        (k < bins).then_some(k)
    });
    h.iter()
        .enumerate()
        .map(|(k, n)| {
            let (a, b) = (
                (k as f64 * GAMMA_BIN_DEG).to_radians(),
                ((k + 1) as f64 * GAMMA_BIN_DEG).to_radians(),
            );
            n / (std::f64::consts::TAU * (a.cos() - b.cos()))
        })
        .collect()
}

/// ‖a − b‖ / ‖b‖ over the bins, each weighted by `w`.
fn relative_l2(a: &[f64], b: &[f64], w: &[f64]) -> f64 {
    let num: f64 = a
        .iter()
        .zip(b)
        .zip(w)
        .map(|((x, y), w)| w * (x - y).powi(2))
        .sum();
    let den: f64 = b.iter().zip(w).map(|(y, w)| w * y * y).sum();
    (num / den).sqrt()
}

/// The solid angle of each γ bin: the L2 of intensities over the sphere.
fn gamma_weights() -> Vec<f64> {
    let bins = (GAMMA_MAX / GAMMA_BIN_DEG) as usize;
    (0..bins)
        .map(|k| {
            let (a, b) = (
                (k as f64 * GAMMA_BIN_DEG).to_radians(),
                ((k + 1) as f64 * GAMMA_BIN_DEG).to_radians(),
            );
            a.cos() - b.cos()
        })
        .collect()
}

/// The full angle (degrees) where the intensity falls to half its
/// peak, interpolated between bins. The peak is the mean intensity
/// within γ < 2° (by solid angle: the bins nearest the axis hold too
/// few photons to stand alone).
fn beam_angle(i: &[f64]) -> f64 {
    let near = (2.0 / GAMMA_BIN_DEG) as usize;
    let w = gamma_weights();
    let peak = (0..near).map(|k| i[k] * w[k]).sum::<f64>() / w[..near].iter().sum::<f64>();
    for k in 1..i.len() {
        if i[k] < 0.5 * peak {
            let (a, b) = (i[k - 1], i[k]);
            let t = (a - 0.5 * peak) / (a - b);
            return 2.0 * ((k as f64 - 0.5 + t) * GAMMA_BIN_DEG);
        }
    }
    2.0 * GAMMA_MAX
}

const PHOTONS: u32 = 1 << 21;

const DIMPLES: &str = r#"{ type = "dimples", pitch = 0.002, depth = 0.00015, radius = 0.0034, pattern = "hexagonal" }"#;

/// The test's criterion: within max(0.01, 2 × the floor).
fn agrees(l2: f64, floor: f64) -> bool {
    l2 <= 0.01f64.max(2.0 * floor)
}

#[test]
fn hammered_dimples_as_brdf_match_the_dimples_as_triangles() {
    let brdf = prepare(&spot(DIMPLES), FinishSplit::default());
    let w = gamma_weights();
    let b = intensity_by_gamma(&brdf, PHOTONS, 2);
    // The floor: the same BRDF scene traced with another seed.
    let floor = relative_l2(&intensity_by_gamma(&brdf, PHOTONS, 3), &b, &w);
    // The triangles' chords cut the dimples' rims and flatten their
    // steepest slopes, an error linear in the edge: traced at two edges
    // and extrapolated to edge 0 (Richardson), as a far field is linear
    // in its photons.
    let coarse = prepare(&spot(DIMPLES), as_geometry(0.1e-3));
    let fine = prepare(&spot(DIMPLES), as_geometry(0.05e-3));
    assert!(
        fine.triangle_count() > 100 * brdf.triangle_count(),
        "{} vs {}",
        fine.triangle_count(),
        brdf.triangle_count()
    );
    let gc = intensity_by_gamma(&coarse, PHOTONS, 5);
    let gf = intensity_by_gamma(&fine, PHOTONS, 1);
    let g: Vec<f64> = gf.iter().zip(&gc).map(|(f, c)| 2.0 * f - c).collect();
    // The extrapolation's own noise: √5 times one trace's.
    let floor_g = floor * 5f64.sqrt();
    let l2 = relative_l2(&b, &g, &w);
    let (l2_fine, l2_coarse) = (relative_l2(&b, &gf, &w), relative_l2(&b, &gc, &w));
    let (beam_g, beam_b) = (beam_angle(&g), beam_angle(&b));
    eprintln!(
        "dimples: L2 {l2:.4} (floor {floor_g:.4}; 0.1 mm {l2_coarse:.4}, 0.05 mm {l2_fine:.4}), beam {beam_g:.2}° vs {beam_b:.2}°"
    );
    assert!(agrees(l2, floor_g), "L2 {l2} floor {floor_g}");
    assert!(l2_fine < l2_coarse, "{l2_fine} vs {l2_coarse}");
    assert!((beam_g - beam_b).abs() <= 0.2, "{beam_g} vs {beam_b}");

    // A Gaussian of the same slope covariance fails the same test.
    let stats = match &brdf.material_finish.iter().flatten().next() {
        Some(f) => f.surface.brdf_statistics.clone().unwrap(),
        None => panic!("no finish"),
    };
    let c = stats.covariance;
    let gaussian = format!(
        r#"{{ type = "slopes", sigma_u = {}, sigma_v = {} }}"#,
        c[0].sqrt(),
        c[2].sqrt()
    );
    let gauss = prepare(&spot(&gaussian), FinishSplit::default());
    let n = intensity_by_gamma(&gauss, PHOTONS, 2);
    let l2_gauss = relative_l2(&n, &g, &w);
    eprintln!(
        "Gaussian of the same variance: L2 {l2_gauss:.3}, beam {:.2}° vs {beam_g:.2}°",
        beam_angle(&n)
    );
    assert!(
        !agrees(l2_gauss, floor_g) && l2_gauss > 5.0 * l2,
        "{l2_gauss}"
    );
}

#[test]
fn flat_facets_as_brdf_match_the_facets_as_triangles() {
    // 3 mm facets on the small spot: each turns the reflection by up to
    // ±curvature × 1.5 mm; as triangles at 0.1 and 0.05 mm extrapolated
    // to edge 0 (the facets' edges are kinks, as the dimples' rims).
    let facets = r#"{ type = "facets", size_along = 0.003, size_around = 0.003 }"#;
    let brdf = prepare(&spot(facets), FinishSplit::default());
    let smooth = prepare(&spot(""), FinishSplit::default());
    let w = gamma_weights();
    let b = intensity_by_gamma(&brdf, PHOTONS, 2);
    let floor = relative_l2(&intensity_by_gamma(&brdf, PHOTONS, 3), &b, &w);
    let gc = intensity_by_gamma(&prepare(&spot(facets), as_geometry(0.1e-3)), PHOTONS, 5);
    let gf = intensity_by_gamma(&prepare(&spot(facets), as_geometry(0.05e-3)), PHOTONS, 1);
    let g: Vec<f64> = gf.iter().zip(&gc).map(|(f, c)| 2.0 * f - c).collect();
    let floor_g = floor * 5f64.sqrt();
    let l2 = relative_l2(&b, &g, &w);
    let s = intensity_by_gamma(&smooth, PHOTONS, 1);
    let (beam_g, beam_b, beam_s) = (beam_angle(&g), beam_angle(&b), beam_angle(&s));
    eprintln!(
        "facets: L2 {l2:.4} (floor {floor_g:.4}; 0.05 mm alone {:.4}), beam {beam_g:.2}° vs {beam_b:.2}° (smooth {beam_s:.2}°)",
        relative_l2(&b, &gf, &w)
    );
    assert!(agrees(l2, floor_g), "L2 {l2} floor {floor_g}");
    assert!((beam_g - beam_b).abs() <= 0.2, "{beam_g} vs {beam_b}");
    assert!(beam_b > beam_s + 1.0, "the facets widen the beam");
}

/// Ripples along the profile (2π·a/λ = 0.084: ±9.6° of slope). A wave
/// of 1.5 mm on this 24 mm reflector is coarse enough that where it lies
/// shows: as normals (or triangles) its beam is 0.15° narrower than as
/// the BRDF, which holds once the wave is 0.3 mm (within the floor).
/// The BRDF is the limit of features small against the part.
const RIPPLES_ALONG: &str = r#"{ type = "ripples", waves = [{ amplitude = 0.0000076, wavelength = 0.0006, direction_deg = 0.0 }] }"#;

#[test]
fn ripples_along_a_revolved_profile_as_brdf_match_them_as_triangles() {
    let brdf = prepare(&spot(RIPPLES_ALONG), FinishSplit::default());
    let geometry = prepare(&spot(RIPPLES_ALONG), as_geometry(0.05e-3));
    let smooth = prepare(&spot(""), FinishSplit::default());
    let w = gamma_weights();
    // Four traces of each: a beam angle of this wide, soft-edged beam
    // scatters by ±0.07° from one trace of 2 M photons to the next.
    let mean = |scene: &PreparedScene, seeds: [u32; 4]| {
        let runs: Vec<Vec<f64>> = seeds
            .iter()
            .map(|&s| intensity_by_gamma(scene, PHOTONS, s))
            .collect();
        let n = runs[0].len();
        let mean: Vec<f64> = (0..n)
            .map(|k| runs.iter().map(|r| r[k]).sum::<f64>() / 4.0)
            .collect();
        (mean, runs)
    };
    let (b, runs) = mean(&brdf, [2, 3, 4, 5]);
    let (g, _) = mean(&geometry, [6, 7, 8, 9]);
    // The floor of a mean of four: two of its traces against the other
    // two, halved (a mean of four has half the noise of one).
    let half = |r: &[Vec<f64>], k: [usize; 2]| -> Vec<f64> {
        (0..r[0].len())
            .map(|i| 0.5 * (r[k[0]][i] + r[k[1]][i]))
            .collect()
    };
    let floor = relative_l2(&half(&runs, [0, 1]), &half(&runs, [2, 3]), &w) / 2f64.sqrt();
    let s = intensity_by_gamma(&smooth, PHOTONS, 1);
    let l2 = relative_l2(&b, &g, &w);
    let (beam_g, beam_b, beam_s) = (beam_angle(&g), beam_angle(&b), beam_angle(&s));
    eprintln!(
        "ripples along: L2 {l2:.4} (floor {floor:.4}), beam {beam_g:.2}° vs {beam_b:.2}° (smooth {beam_s:.2}°)"
    );
    assert!(agrees(l2, floor), "L2 {l2} floor {floor}");
    assert!((beam_g - beam_b).abs() <= 0.2, "{beam_g} vs {beam_b}");
    assert!(beam_b > beam_s + 2.0, "the ripples widen the beam");
}

/// Cells of the plane-angle grid, each way, over ±30° (2° cells).
const PLANE_CELLS: usize = 30;

/// Photons on a grid of the angles in the x–z and y–z planes.
fn intensity_by_planes(scene: &PreparedScene, photons: u32, seed: u32) -> Vec<f64> {
    let n = PLANE_CELLS;
    let cell = 60.0 / n as f64;
    histogram(scene, photons, seed, n * n, |d| {
        if d.z >= 0.0 {
            return None;
        }
        let a = (f64::from((d.x / -d.z).atan().to_degrees()) + 30.0) / cell;
        let b = (f64::from((d.y / -d.z).atan().to_degrees()) + 30.0) / cell;
        (a >= 0.0 && b >= 0.0 && a < n as f64 && b < n as f64).then(|| b as usize * n + a as usize)
    })
}

/// The rms angle (degrees) of the grid's counts along x–z and y–z.
fn spreads(h: &[f64]) -> [f64; 2] {
    let n = PLANE_CELLS;
    let cell = 60.0 / n as f64;
    let (mut sx, mut sy, mut t) = (0.0, 0.0, 0.0);
    for j in 0..n {
        for i in 0..n {
            let c = h[j * n + i];
            let centre = |k: usize| (k as f64 + 0.5) * cell - 30.0;
            sx += c * centre(i).powi(2);
            sy += c * centre(j).powi(2);
            t += c;
        }
    }
    [(sx / t).sqrt(), (sy / t).sqrt()]
}

#[test]
fn ripples_across_an_extruded_part_widen_one_plane_only_as_the_triangles_do() {
    let brdf = prepare(&trough(RIPPLES_ALONG), FinishSplit::default());
    let geometry = prepare(&trough(RIPPLES_ALONG), as_geometry(0.15e-3));
    let smooth = prepare(&trough(""), FinishSplit::default());
    let w = vec![1.0; PLANE_CELLS * PLANE_CELLS];
    let b = intensity_by_planes(&brdf, PHOTONS, 2);
    let floor = relative_l2(&intensity_by_planes(&brdf, PHOTONS, 3), &b, &w);
    let g = intensity_by_planes(&geometry, PHOTONS, 1);
    let s = intensity_by_planes(&smooth, PHOTONS, 1);
    let l2 = relative_l2(&b, &g, &w);
    let (sb, sg, ss) = (spreads(&b), spreads(&g), spreads(&s));
    eprintln!(
        "trough: L2 {l2:.4} (floor {floor:.4}); rms x–z, y–z: brdf {sb:.2?}, triangles {sg:.2?}, smooth {ss:.2?}"
    );
    assert!(agrees(l2, floor), "L2 {l2} floor {floor}");
    // Widened across the trough (x–z), not along it (y–z).
    assert!(sb[0] > ss[0] + 1.0, "{sb:?} vs {ss:?}");
    assert!((sb[1] - ss[1]).abs() < 0.05 * ss[1], "{sb:?} vs {ss:?}");
}

#[test]
fn moving_the_cut_between_normals_and_brdf_or_refining_the_mesh_changes_nothing() {
    // Dimples on the trough: all BRDF; all normals (cut below the
    // pitch); cut above it (BRDF again) with the mesh refined 4 ×.
    let w = vec![1.0; PLANE_CELLS * PLANE_CELLS];
    let brdf = prepare(&trough(DIMPLES), FinishSplit::default());
    let b = intensity_by_planes(&brdf, PHOTONS, 2);
    let floor = relative_l2(&intensity_by_planes(&brdf, PHOTONS, 3), &b, &w);
    for (name, toml, split) in [
        (
            "normals from 0.5 mm",
            trough(DIMPLES),
            FinishSplit {
                normals_from: Some(0.5e-3),
                ..FinishSplit::default()
            },
        ),
        (
            "normals from 4 mm, mesh 4 × finer",
            trough(DIMPLES).replace("segments_per_span = 4", "segments_per_span = 16"),
            FinishSplit {
                normals_from: Some(4e-3),
                ..FinishSplit::default()
            },
        ),
    ] {
        let other = prepare(&toml, split);
        let o = intensity_by_planes(&other, PHOTONS, 4);
        let l2 = relative_l2(&o, &b, &w);
        eprintln!("{name}: L2 {l2:.4} (floor {floor:.4})");
        assert!(agrees(l2, floor), "{name}: L2 {l2} floor {floor}");
    }
}
