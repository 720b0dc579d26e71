#![allow(clippy::unwrap_used, clippy::expect_used)]
//! Shadow borders on a traced scene: a 0.5 mm Lambertian disk at the top
//! of an 80 mm black tube of 20 mm radius, the simplest louvre with a
//! hard cut-off (fully lit below γ = 13.7°, dark beyond 14.4°). The
//! filtered map's 10 %–90 % edge width must stay within 2 texels of a
//! high-photon reference's.

use std::path::Path;

use lucerna_filter::{FilterSettings, Threshold, filter, filter_symmetric};
use lucerna_photometry::{AxialSymmetry, CubeMapLayout, IntensityMap, TexelSymmetry};
use lucerna_scene::{parse_scene, tessellate};
use lucerna_tracer::{Backend, PreparedScene, Session, TraceSettings, luminaire_symmetry};

const SCENE: &str = r#"
format_version = 1
name = "Cut-off tube"

[materials.black]
type = "absorber"

[materials.white]
type = "lambertian"
albedo = 0.8

[[emitter]]
name = "LED"
flux_lm = 100.0
material = "white"
shape = { type = "disk", radius = 0.0005 }

[[part]]
name = "tube"
material = "black"
shape = { type = "cylinder", radius = 0.02, height = 0.08, cap_top = false, cap_bottom = false, segments_around = 256 }
transform = { translate = [0.0, 0.0, -0.0401] }
"#;

fn trace(photons: u64, seed: u32, layout: CubeMapLayout) -> IntensityMap {
    let scene = parse_scene(SCENE, Path::new("tube.toml")).unwrap();
    let tessellated = tessellate(&scene, Path::new(".")).unwrap();
    let prepared = PreparedScene::new(&scene, &tessellated, Path::new(".")).unwrap();
    let settings = TraceSettings {
        seed,
        max_bounces: 8,
        layout,
    };
    let mut session = Session::with_backend(prepared, settings, Backend::Cpu);
    while session.map().photons_emitted < photons {
        let left = photons - session.map().photons_emitted;
        session.iterate_at_most(left).unwrap();
    }
    session.snapshot()
}

/// Mean of I / cos γ (photons per steradian over cos γ: flat inside the
/// cone for a Lambertian source) in 0.1° bins of γ over the nadir face.
fn radial_profile(layout: CubeMapLayout, photons_per_sr: &[f64]) -> Vec<f64> {
    let bins = 300; // 0 – 30°
    let mut sum = vec![0.0; bins];
    let mut n = vec![0u32; bins];
    for t in 0..layout.texel_count() {
        let d = layout.texel_centre_direction(t);
        let len = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let cos = -d[2] / len;
        if cos <= 0.0 {
            continue;
        }
        let gamma = cos.acos().to_degrees();
        let b = (gamma * 10.0) as usize;
        if b < bins {
            sum[b] += photons_per_sr[t] / cos;
            n[b] += 1;
        }
    }
    sum.iter()
        .zip(&n)
        .map(|(s, &k)| if k > 0 { s / f64::from(k) } else { f64::NAN })
        .collect()
}

/// The edge: γ (degrees) where the profile first falls below 10 % of the
/// plateau (mean over 4°–10°) beyond 10°, and the last γ before it where
/// it falls below 90 % (so noise on the plateau does not count as edge),
/// each by linear interpolation between 0.1° bins.
fn edge(profile: &[f64]) -> (f64, f64) {
    let plateau: Vec<f64> = profile[40..100]
        .iter()
        .copied()
        .filter(|v| v.is_finite())
        .collect();
    let level = plateau.iter().sum::<f64>() / plateau.len() as f64;
    let valid: Vec<(f64, f64)> = profile
        .iter()
        .enumerate()
        .filter(|(_, v)| v.is_finite())
        .map(|(b, &v)| ((b as f64 + 0.5) / 10.0, v))
        .collect();
    let fall = |w: &[(f64, f64)], target: f64| {
        let ((g0, v0), (g1, v1)) = (w[0], w[1]);
        (v0 >= target && v1 < target).then(|| g0 + (v0 - target) / (v0 - v1) * (g1 - g0))
    };
    let Some(k10) = (0..valid.len() - 1)
        .find(|&k| valid[k].0 >= 10.0 && fall(&valid[k..k + 2], 0.1 * level).is_some())
    else {
        return (f64::NAN, f64::NAN);
    };
    let g10 = fall(&valid[k10..k10 + 2], 0.1 * level).unwrap_or(f64::NAN);
    let g90 = (0..=k10)
        .rev()
        .find_map(|k| fall(&valid[k..k + 2], 0.9 * level))
        .unwrap_or(f64::NAN);
    (g90, g10)
}

/// Width of the fall from 90 % to 10 % of the plateau, in texels of the
/// nadir face at the cut-off (dγ = cos²γ · 2 / resolution rad).
fn edge_width_texels(layout: CubeMapLayout, photons_per_sr: &[f64]) -> f64 {
    let (g90, g10) = edge(&radial_profile(layout, photons_per_sr));
    let texel_deg =
        (14f64.to_radians().cos().powi(2) * 2.0 / f64::from(layout.resolution)).to_degrees();
    (g10 - g90) / texel_deg
}

fn raw(map: &IntensityMap) -> Vec<f64> {
    let omega = map.layout.solid_angles();
    map.counts
        .iter()
        .zip(&omega)
        .map(|(&c, w)| c as f64 / w)
        .collect()
}

#[test]
fn a_traced_cut_off_stays_sharp_after_filtering() {
    let layout = CubeMapLayout::new(128);
    let reference = trace(20_000_000, 1, layout);
    let w_ref = edge_width_texels(layout, &raw(&reference));
    eprintln!("reference (2·10⁷ photons): edge {w_ref:.2} texels");
    assert!(
        w_ref.is_finite() && w_ref < 4.0,
        "the scene's own edge is {w_ref} texels"
    );
    // The tube is round: all eight of the square's symmetries.
    let scene = parse_scene(SCENE, Path::new("tube.toml")).unwrap();
    let found = luminaire_symmetry(&scene, &tessellate(&scene, Path::new(".")).unwrap());
    assert_eq!(found.symmetry, AxialSymmetry::Square);
    let symmetry = TexelSymmetry::new(layout, found.symmetry);
    let mut failures = Vec::new();
    for photons in [100_000u64, 1_000_000, 10_000_000] {
        let map = trace(photons, 7, layout);
        let automatic = filter(layout, &map.counts, &FilterSettings::default());
        let pooled = filter_symmetric(&map.counts, &FilterSettings::default(), &symmetry);
        let fixed = filter(
            layout,
            &map.counts,
            &FilterSettings {
                threshold: Threshold::Fixed(100.0),
                ..Default::default()
            },
        );
        let (w_raw, w_auto, w_fixed, w_pooled) = (
            edge_width_texels(layout, &raw(&map)),
            edge_width_texels(layout, &automatic.photons_per_sr),
            edge_width_texels(layout, &fixed.photons_per_sr),
            edge_width_texels(layout, &pooled.photons_per_sr),
        );
        eprintln!(
            "{photons} photons: edge raw {w_raw:.2}, automatic {w_auto:.2}, automatic with the symmetry {w_pooled:.2}, fixed 100 {w_fixed:.2} texels (reference {w_ref:.2})"
        );
        for (name, w) in [
            ("automatic", w_auto),
            ("automatic with the symmetry", w_pooled),
        ] {
            if w.is_nan() || w > w_ref + 2.0 {
                failures.push(format!("{photons}: {name} {w:.2} vs reference {w_ref:.2}"));
            }
        }
        // The paper's fixed threshold (100 photons) blurs the border at
        // these counts (NaN: no fall to 10 % within 10°–30° at all), which
        // is what the automatic mode's Poisson test is for.
        if photons <= 1_000_000 && w_fixed <= w_auto {
            failures.push(format!(
                "{photons}: fixed {w_fixed:.2} not wider than automatic {w_auto:.2}"
            ));
        }
    }
    assert!(failures.is_empty(), "{failures:?}");
}
