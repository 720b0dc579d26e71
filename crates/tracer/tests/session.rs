#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! The progressive session: accumulation, restart, time budget, noise.

use std::path::Path;
use std::time::Duration;

use lucerna_photometry::CubeMapLayout;
use lucerna_tracer::{PreparedScene, Session, TraceSettings};

fn prepared(name: &str) -> PreparedScene {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires");
    let scene = lucerna_scene::load_scene(&dir.join(name)).unwrap();
    PreparedScene::new(
        &scene,
        &lucerna_scene::tessellate(&scene, &dir).unwrap(),
        &dir,
    )
    .unwrap()
}

#[test]
fn iterations_accumulate_and_noise_falls() {
    let settings = TraceSettings {
        seed: 1,
        max_bounces: 32,
        layout: CubeMapLayout::new(32),
    };
    let mut s = Session::start(prepared("faceted_downlight.toml"), settings);
    s.target_iteration_time = Duration::from_millis(20);
    let first = s.iterate().unwrap();
    let mut last = first;
    for _ in 0..8 {
        last = s.iterate().unwrap();
    }
    let map = s.snapshot();
    assert_eq!(map.photons_emitted, last.photons_total);
    assert!(map.is_balanced());
    assert!(last.photons_total > first.photons_total);
    assert!(
        last.peak_relative_error < first.peak_relative_error,
        "{} !< {}",
        last.peak_relative_error,
        first.peak_relative_error
    );
    assert!(last.flux_relative_error < first.flux_relative_error);
    // Restart drops everything.
    s.restart(prepared("parabolic_spot.toml"));
    assert_eq!(s.map().photons_emitted, 0);
    let r = s.iterate().unwrap();
    assert_eq!(s.map().photons_emitted, r.photons);
    assert!(
        (s.map().emitter_flux_lm - 800.0).abs() < 1e-9,
        "the new scene's flux"
    );
}

#[test]
fn iteration_size_follows_the_time_budget() {
    let settings = TraceSettings {
        seed: 1,
        max_bounces: 32,
        layout: CubeMapLayout::new(16),
    };
    let mut fast = Session::start(prepared("parabolic_spot.toml"), settings);
    fast.target_iteration_time = Duration::from_millis(5);
    let mut slow = Session::start(prepared("parabolic_spot.toml"), settings);
    slow.target_iteration_time = Duration::from_millis(80);
    let (mut a, mut b) = (0, 0);
    for _ in 0..6 {
        a = fast.iterate().unwrap().photons;
        b = slow.iterate().unwrap().photons;
    }
    assert!(
        b > 4 * a,
        "an 80 ms budget traces more per iteration than 5 ms: {b} vs {a}"
    );
}
