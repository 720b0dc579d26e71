#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! The noise estimates a snapshot shows beside its figures against the
//! scatter of the figures over independent runs (different seeds): an
//! estimate that is off by more than a factor of two fails.

use std::path::Path;
use std::sync::Arc;

use lucerna_photometry::figures::ZONES_DEG;
use lucerna_simulation::{Luminaire, SimulationSettings, Snapshot, StoppingRule, bake};

fn runs(name: &str, photons: u64, count: u32) -> Vec<Snapshot> {
    runs_pooled(name, photons, count, false)
}

fn runs_pooled(name: &str, photons: u64, count: u32, pool_symmetry: bool) -> Vec<Snapshot> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets/luminaires")
        .join(name);
    let luminaire = Arc::new(Luminaire::load(&path).unwrap());
    (0..count)
        .map(|seed| {
            let settings = SimulationSettings {
                resolution: 32,
                seed: 100 + seed,
                pool_symmetry,
                stop: StoppingRule {
                    photons: Some(photons),
                    ..StoppingRule::default()
                },
                ..SimulationSettings::default()
            };
            bake(luminaire.clone(), settings).unwrap()
        })
        .collect()
}

/// Sample standard deviation.
fn scatter(values: &[f64]) -> f64 {
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    (values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
}

fn mean(values: &[f64]) -> f64 {
    values.iter().sum::<f64>() / values.len() as f64
}

fn assert_within_factor_two(what: &str, estimated: f64, observed: f64) {
    let ratio = estimated / observed;
    assert!(
        (0.5..=2.0).contains(&ratio),
        "{what}: estimated {estimated:.4e}, observed {observed:.4e} (ratio {ratio:.2})"
    );
}

#[test]
fn zonal_flux_noise_matches_the_scatter_over_seeds() {
    let snapshots = runs("opal_bell.toml", 20_000, 24);
    for (k, zone) in ZONES_DEG.iter().enumerate() {
        let fluxes: Vec<f64> = snapshots
            .iter()
            .map(|s| s.figures.zonal_flux_lm[k])
            .collect();
        let observed = scatter(&fluxes) / mean(&fluxes);
        let estimated = mean(
            &snapshots
                .iter()
                .map(|s| s.noise.zonal_relative[k])
                .collect::<Vec<_>>(),
        );
        assert_within_factor_two(&format!("zone {zone:?}"), estimated, observed);
    }
}

#[test]
fn beam_angle_noise_matches_the_scatter_over_seeds() {
    // Unpooled, then pooled over the luminaire's symmetry: the estimate
    // counts the photons of every image.
    for pooled in [false, true] {
        beam_angle_noise_matches(
            runs_pooled("faceted_downlight.toml", 50_000, 24, pooled),
            pooled,
        );
    }
}

fn beam_angle_noise_matches(snapshots: Vec<Snapshot>, pooled: bool) {
    for plane in 0..2 {
        let angles: Vec<f64> = snapshots
            .iter()
            .map(|s| s.figures.beam_angle_deg[plane].unwrap())
            .collect();
        let observed = scatter(&angles);
        let estimated = mean(
            &snapshots
                .iter()
                .map(|s| s.noise.beam_angle_deg[plane].unwrap())
                .collect::<Vec<_>>(),
        );
        eprintln!(
            "pooled {pooled} plane {plane}: estimated {estimated:.3}°, observed {observed:.3}°"
        );
        assert_within_factor_two(
            &format!("beam angle, plane {plane}, pooled {pooled}"),
            estimated,
            observed,
        );
    }
}

/// A ray file's photons are no more certain than its distinct rays: the
/// same luminaire baked from a 20 000-ray file with 200 000 and with
/// 2 000 000 photons shows a peak noise that falls as √(1/N + 1/R), by a
/// factor 1.044, not by the photons' √10.
#[test]
fn a_ray_files_noise_counts_its_distinct_rays() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets/rayfiles/parabolic_spot_ray_file_led.toml");
    let luminaire = std::sync::Arc::new(lucerna_simulation::Luminaire::load(&path).unwrap());
    let noise = |photons: u64| {
        let settings = lucerna_simulation::SimulationSettings {
            resolution: 32,
            backend: lucerna_simulation::BackendRequest::Cpu,
            stop: lucerna_simulation::StoppingRule {
                photons: Some(photons),
                ..Default::default()
            },
            ..Default::default()
        };
        lucerna_simulation::bake(luminaire.clone(), settings)
            .unwrap()
            .noise
            .peak_relative
    };
    let (few, many) = (noise(200_000), noise(2_000_000));
    let ratio = few / many;
    let want = ((1.0f64 / 2e5 + 1.0 / 2e4) / (1.0 / 2e6 + 1.0 / 2e4)).sqrt();
    assert!(
        (ratio / want - 1.0).abs() < 0.03,
        "peak noise {few} at 200 k photons, {many} at 2 M: {ratio}× against {want}× (photons alone: 3.2×)"
    );
}
