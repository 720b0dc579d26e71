#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! The CPU tracer against closed forms: Lambert's cosine law, exact energy
//! balance, a white box, a paraboloid's beam, Fresnel at a glass slab, total
//! internal reflection, profile importance sampling (χ²), determinism.

use std::f64::consts::PI;
use std::path::Path;

use lucerna_photometry::CubeMapLayout;
use lucerna_photometry::table::angles;
use lucerna_scene::{parse_scene, tessellate};
use lucerna_tracer::cpu::{TraceSettings, trace_batch};
use lucerna_tracer::sampling::{ProfileSampler, fresnel_dielectric};
use lucerna_tracer::{PreparedScene, Tally};

fn prepare(toml: &str, dir: &Path) -> PreparedScene {
    let scene = parse_scene(toml, Path::new("test.toml")).unwrap_or_else(|e| panic!("{e}"));
    let t = tessellate(&scene, dir).unwrap();
    PreparedScene::new(&scene, &t, dir).unwrap()
}

fn settings(resolution: u32, max_bounces: u32) -> TraceSettings {
    TraceSettings {
        seed: 7,
        max_bounces,
        layout: CubeMapLayout::new(resolution),
    }
}

/// γ (degrees) of every texel centre.
fn texel_gammas(layout: CubeMapLayout) -> Vec<f64> {
    (0..layout.texel_count())
        .map(|t| angles(layout.texel_centre_direction(t)).1.to_degrees())
        .collect()
}

const BARE_DISK: &str = r#"
format_version = 1
name = "bare disk"
[[emitter]]
name = "LED"
flux_lm = 1000.0
shape = { type = "disk", radius = 0.001 }
"#;

#[test]
fn a_bare_lambertian_disk_follows_the_cosine_law() {
    let scene = prepare(BARE_DISK, Path::new("."));
    let s = settings(64, 8);
    let n = 2_000_000u32;
    let tally = trace_batch(&scene, &s, 0, 0, n);
    assert_eq!(
        tally.escaped(),
        u64::from(n),
        "nothing to hit: every photon escapes"
    );
    // Bands of 5° in γ: expected probability of a cosine law is
    // sin²b − sin²a. Each band within 5σ of its binomial expectation.
    let gammas = texel_gammas(s.layout);
    let mut observed = [0u64; 36];
    for (t, &c) in tally.counts.iter().enumerate() {
        observed[((gammas[t] / 5.0) as usize).min(35)] += u64::from(c);
    }
    // Texels straddle band edges; use each texel's own expected share so
    // the comparison is exact up to noise.
    let mut expected = [0f64; 36];
    for t in 0..s.layout.texel_count() {
        let g = gammas[t].to_radians();
        expected[((gammas[t] / 5.0) as usize).min(35)] +=
            f64::from(n) * (g.cos().max(0.0) / PI) * s.layout.texel_solid_angle(t);
    }
    for band in 0..36 {
        let (o, e) = (observed[band] as f64, expected[band]);
        let sigma = e.max(1.0).sqrt();
        assert!(
            (o - e).abs() <= 5.0 * sigma + 2.0,
            "band {band}: {o} photons, expected {e:.0} ± {sigma:.0}"
        );
    }
    assert_eq!(observed[18..].iter().sum::<u64>(), 0, "no photon goes up");
    // In candela: I(γ) = Φ/π cos γ.
    let mut map = lucerna_photometry::IntensityMap::new(s.layout, scene.total_flux_lm);
    for (a, &b) in map.counts.iter_mut().zip(&tally.counts) {
        *a = u64::from(b);
    }
    map.photons_emitted = u64::from(n);
    // One C-plane (rotational), 1° γ cells: ~30 000 photons per cell at
    // γ 30°, so 3 % is 5σ.
    let gammas_deg: Vec<f64> = (0..=90).map(f64::from).collect();
    let table =
        lucerna_photometry::table_from_cube_map(s.layout, &map.candela(), &[0.0], &gammas_deg);
    for g in [10.0f64, 30.0, 60.0] {
        let expected = 1000.0 / PI * g.to_radians().cos();
        let got = table.intensity(0.0, g);
        assert!(
            (got - expected).abs() < 0.03 * expected,
            "γ {g}: {got} cd vs {expected}"
        );
    }
}

fn balanced(t: &Tally) -> bool {
    t.escaped() + t.absorbed + t.cut_off == t.emitted
}

#[test]
fn energy_balance_is_exact_on_every_example() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires");
    for entry in std::fs::read_dir(&dir).unwrap() {
        let path = entry.unwrap().path();
        let scene = lucerna_scene::load_scene(&path).unwrap();
        let t = tessellate(&scene, &dir).unwrap();
        let prepared = PreparedScene::new(&scene, &t, &dir).unwrap();
        let tally = trace_batch(&prepared, &settings(32, 16), 3, 0, 20_000);
        assert_eq!(tally.emitted, 20_000);
        assert!(balanced(&tally), "{}: {tally:?}", path.display());
        assert!(tally.escaped() > 0, "{}", path.display());
    }
}

#[test]
fn a_white_box_with_one_opening_lets_every_photon_out() {
    let toml = r#"
format_version = 1
name = "white box"
[materials.white]
type = "lambertian"
albedo = 1.0
[[emitter]]
name = "LED"
flux_lm = 100.0
material = "white"
shape = { type = "sphere", radius = 0.005 }
[[part]]
name = "box"
material = "white"
shape = { type = "box", size = [0.1, 0.1, 0.1], open_bottom = true }
"#;
    let scene = prepare(toml, Path::new("."));
    let tally = trace_batch(&scene, &settings(16, 1000), 0, 0, 50_000);
    assert!(balanced(&tally));
    assert_eq!(tally.absorbed, 0, "albedo 1 absorbs nothing");
    assert!(tally.cut_off < 50, "cut off {}", tally.cut_off);
    assert_eq!(tally.escaped() + tally.cut_off, 50_000);
    // It escapes downwards only, through the opening.
    let gammas = texel_gammas(CubeMapLayout::new(16));
    let up: u64 = tally
        .counts
        .iter()
        .enumerate()
        .filter(|(t, _)| gammas[*t] > 90.5)
        .map(|(_, &c)| u64::from(c))
        .sum();
    assert_eq!(up, 0);
}

/// Fraction of escaped photons within `gamma_deg` of nadir, and the γ
/// containing `fraction` of them.
fn beam(tally: &Tally, layout: CubeMapLayout, gamma_deg: f64, fraction: f64) -> (f64, f64) {
    let gammas = texel_gammas(layout);
    let total = tally.escaped() as f64;
    let mut by_gamma: Vec<(f64, u32)> = gammas
        .iter()
        .copied()
        .zip(tally.counts.iter().copied())
        .filter(|(_, c)| *c > 0)
        .collect();
    by_gamma.sort_by(|a, b| a.0.total_cmp(&b.0));
    let within: u64 = by_gamma
        .iter()
        .filter(|(g, _)| *g <= gamma_deg)
        .map(|(_, c)| u64::from(*c))
        .sum();
    let mut acc = 0.0;
    let mut containing = 180.0;
    for (g, c) in &by_gamma {
        acc += f64::from(*c);
        if acc >= fraction * total {
            containing = *g;
            break;
        }
    }
    (within as f64 / total, containing)
}

fn spot(source_z: f64) -> String {
    format!(
        r#"
format_version = 1
name = "spot"
[materials.mirror]
type = "mirror"
reflectance = 0.9
[[emitter]]
name = "LED"
flux_lm = 100.0
shape = {{ type = "disk", radius = 0.0015 }}
transform = {{ translate = [0.0, 0.0, {source_z}], rotate_deg = [180.0, 0.0, 0.0] }}
[[part]]
name = "reflector"
material = "mirror"
shape = {{ type = "paraboloid", focal_length = 0.025, aperture_diameter = 0.1, segments_around = 256, segments_along = 64 }}
"#
    )
}

#[test]
fn a_paraboloid_collimates_a_source_at_its_focus() {
    let layout = CubeMapLayout::new(512);
    let s = settings(512, 8);
    let focused = trace_batch(&prepare(&spot(0.0), Path::new(".")), &s, 0, 0, 300_000);
    assert!(balanced(&focused));
    // Geometric prediction: a source of radius a seen from the reflector at
    // distance ρ ≥ f subtends at most a/ρ ≤ a/f = 3.4°; every reflected
    // photon leaves within it (plus a texel, 0.18°). Facets of the
    // tessellation add a little.
    let half_angle = (0.0015f64 / 0.025).atan().to_degrees();
    let (within, containing_90) = beam(&focused, layout, half_angle + 0.5, 0.9);
    assert!(
        within > 0.995,
        "only {within} of the flux within {half_angle:.2}°"
    );
    // Reflectance 0.9 with one bounce: 90 % escapes.
    let escaped = focused.escaped() as f64 / 300_000.0;
    assert!((escaped - 0.9).abs() < 0.005, "escaped {escaped}");
    // Off focus (5 mm towards the vertex) the beam widens.
    let defocused = trace_batch(&prepare(&spot(0.005), Path::new(".")), &s, 0, 0, 300_000);
    let (_, containing_90_off) = beam(&defocused, layout, half_angle, 0.9);
    assert!(
        containing_90_off > 2.0 * containing_90 && containing_90_off > half_angle,
        "90 % cone {containing_90_off}° off focus vs {containing_90}° at focus"
    );
}

/// An IES profile that emits only within `cone_deg` of nadir.
fn collimated_profile(dir: &Path, cone_deg: f64) -> String {
    let path = dir.join("collimated.ies");
    let text = format!(
        "IESNA:LM-63-2002\n[TEST] t\n[MANUFAC] m\nTILT=NONE\n1 1000 1 3 1 1 2 0 0 0\n1 1 1\n0 {} {}\n0\n1000 1000 0\n",
        cone_deg,
        2.0 * cone_deg
    );
    std::fs::write(&path, text).unwrap();
    "collimated.ies".to_owned()
}

#[test]
fn a_glass_slab_reflects_what_fresnel_predicts() {
    let dir = tempfile::tempdir().unwrap();
    let profile = collimated_profile(dir.path(), 0.2);
    let toml = format!(
        r#"
format_version = 1
name = "slab"
[materials.glass]
type = "dielectric"
ior = 1.5
[[emitter]]
name = "beam"
flux_lm = 100.0
shape = {{ type = "disk", radius = 0.001 }}
emission = {{ profile = "{profile}" }}
[[part]]
name = "slab"
material = "glass"
shape = {{ type = "box", size = [2.0, 2.0, 0.01] }}
transform = {{ translate = [0.0, 0.0, -0.05] }}
"#
    );
    let scene = prepare(&toml, dir.path());
    let n = 400_000u32;
    let tally = trace_batch(&scene, &settings(32, 200), 0, 0, n);
    assert!(balanced(&tally));
    // Photons reflected back up hit the emitter's (absorbing) back or
    // escape upwards: count both as reflected. Two interfaces, incoherent:
    // R_total = 2R / (1 + R), R = ((n − 1)/(n + 1))².
    let r = ((1.5f64 - 1.0) / 2.5).powi(2);
    let expected = 2.0 * r / (1.0 + r);
    let gammas = texel_gammas(CubeMapLayout::new(32));
    let up: u64 = tally
        .counts
        .iter()
        .enumerate()
        .filter(|(t, _)| gammas[*t] > 90.0)
        .map(|(_, &c)| u64::from(c))
        .sum();
    let reflected = (up + tally.absorbed) as f64 / f64::from(n);
    let sigma = (expected * (1.0 - expected) / f64::from(n)).sqrt();
    assert!(
        (reflected - expected).abs() < 5.0 * sigma + 1e-3,
        "reflected {reflected}, Fresnel {expected} ± {sigma}"
    );
}

#[test]
fn total_internal_reflection_traps_what_it_must() {
    // An isotropic source at the centre of a glass cube, one interaction
    // allowed: a photon escapes only if it meets the face inside the
    // critical cone and passes Fresnel. The incidence angle is the angle to
    // the direction's major axis.
    let toml = r#"
format_version = 1
name = "cube"
[materials.glass]
type = "dielectric"
ior = 1.5
[[emitter]]
name = "bulb"
flux_lm = 100.0
shape = { type = "sphere", radius = 0.0005 }
[[part]]
name = "cube"
material = "glass"
shape = { type = "box", size = [0.1, 0.1, 0.1] }
"#;
    let scene = prepare(toml, Path::new("."));
    let n = 400_000u32;
    let tally = trace_batch(&scene, &settings(16, 1), 0, 0, n);
    assert!(balanced(&tally));
    let mut expected = 0.0;
    let steps = 400;
    let mut total_weight = 0.0;
    for i in 0..steps {
        for j in 0..2 * steps {
            let theta = PI * (i as f64 + 0.5) / steps as f64;
            let phi = 2.0 * PI * (j as f64 + 0.5) / (2 * steps) as f64;
            let d = [
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            ];
            let w = theta.sin();
            let cos_i = d.iter().map(|x| x.abs()).fold(0.0, f64::max);
            let (f, _) = fresnel_dielectric(cos_i as f32, 1.5);
            expected += w * (1.0 - f64::from(f));
            total_weight += w;
        }
    }
    expected /= total_weight;
    let escaped = tally.escaped() as f64 / f64::from(n);
    let sigma = (expected * (1.0 - expected) / f64::from(n)).sqrt();
    assert!(
        (escaped - expected).abs() < 5.0 * sigma + 2e-3,
        "escaped {escaped}, expected {expected}"
    );
    let trapped = tally.cut_off as f64 / f64::from(n);
    assert!(trapped > 0.25, "TIR and Fresnel keep {trapped} inside");
    assert_eq!(
        fresnel_dielectric(0.5, 1.5).0,
        1.0,
        "beyond the critical angle"
    );
    assert!((fresnel_dielectric(1.0, 1.0 / 1.5).0 - 0.04).abs() < 1e-6);
}

#[test]
fn profile_sampling_follows_the_profile() {
    let bytes = std::fs::read(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../assets/profiles/samples/rab_roadway1_2002_quadrant.ies"),
    )
    .unwrap();
    let p = lucerna_photometry::read_photometry(&bytes).unwrap();
    let sampler = ProfileSampler::new(&p.table).unwrap();
    let mut rng = lucerna_tracer::rng::PhotonRng::new(3, 0, 0);
    let n = 2_000_000usize;
    let mut counts = vec![0u64; sampler.cell_count()];
    for _ in 0..n {
        let d = sampler.sample(rng.next_f32(), rng.next_f32(), rng.next_f32());
        counts[sampler.cell_of(d)] += 1;
    }
    // Pearson χ² over cells expecting at least 5 samples.
    let (mut chi2, mut dof) = (0.0, 0usize);
    for (k, &o) in counts.iter().enumerate() {
        let e = f64::from(sampler.cell_probability(k)) * n as f64;
        if e >= 5.0 {
            chi2 += (o as f64 - e).powi(2) / e;
            dof += 1;
        }
    }
    let dof = (dof - 1) as f64;
    assert!(
        chi2 < dof + 5.0 * (2.0 * dof).sqrt(),
        "χ² = {chi2} for {dof} degrees of freedom"
    );
}

#[test]
fn tracing_is_deterministic_and_splits_add_up() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires/opal_bell.toml");
    let scene = lucerna_scene::load_scene(&path).unwrap();
    let dir = path.parent().unwrap();
    let prepared = PreparedScene::new(&scene, &tessellate(&scene, dir).unwrap(), dir).unwrap();
    let s = settings(16, 32);
    let whole = trace_batch(&prepared, &s, 5, 0, 30_000);
    assert_eq!(whole, trace_batch(&prepared, &s, 5, 0, 30_000));
    let a = trace_batch(&prepared, &s, 5, 0, 12_345);
    let b = trace_batch(&prepared, &s, 5, 12_345, 30_000 - 12_345);
    let summed: Vec<u32> = a.counts.iter().zip(&b.counts).map(|(x, y)| x + y).collect();
    assert_eq!(summed, whole.counts);
    assert_eq!(a.absorbed + b.absorbed, whole.absorbed);
    let other_seed = trace_batch(&prepared, &TraceSettings { seed: 8, ..s }, 5, 0, 30_000);
    assert_ne!(other_seed.counts, whole.counts);
}
