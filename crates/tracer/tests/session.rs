#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! The progressive session: accumulation, restart, time budget, noise.

use std::path::Path;
use std::time::Duration;

use lucerna_photometry::{AxialSymmetry, CubeMapLayout, TexelSymmetry};
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
    use lucerna_tracer::session::next_iteration_size;
    let ms = Duration::from_millis;
    // 100 000 photons took 50 ms: a 100 ms budget doubles the next batch.
    assert_eq!(next_iteration_size(100_000, ms(50), ms(100)), 200_000);
    // Far off: at most 4× per step, either way.
    assert_eq!(next_iteration_size(100_000, ms(1), ms(100)), 400_000);
    assert_eq!(next_iteration_size(100_000, ms(1000), ms(40)), 25_000);
    // Bounded below and above.
    assert_eq!(next_iteration_size(1000, ms(1000), ms(1)), 1024);
    assert_eq!(next_iteration_size(1 << 30, ms(1), ms(1000)), 1 << 30);
    // Converges: a tracer of 10 M photons/s settles at the budget's worth.
    let mut n = 65_536u32;
    for _ in 0..12 {
        let elapsed = Duration::from_secs_f64(f64::from(n) / 10e6);
        n = next_iteration_size(n, elapsed, ms(40));
    }
    assert!((n as f64 - 400_000.0).abs() < 1000.0, "{n}");
}

#[test]
fn peak_error_compares_blocks_per_steradian() {
    use lucerna_photometry::IntensityMap;
    use lucerna_tracer::session::peak_relative_error;
    // 64² per face: blocks of 8×8 texels. A corner block has ~3.7× less
    // solid angle than a centre block, so fewer photons there can still be
    // the brighter direction.
    let layout = CubeMapLayout::new(64);
    let block_omega = |bx: u32, by: u32| -> f64 {
        (0..8)
            .flat_map(|y| (0..8).map(move |x| (x, y)))
            .map(|(x, y)| {
                layout.texel_solid_angle(layout.texel_index(
                    lucerna_photometry::CubeFace::NegZ,
                    bx * 8 + x,
                    by * 8 + y,
                ))
            })
            .sum()
    };
    let (centre, corner) = (block_omega(3, 3), block_omega(0, 0));
    assert!(centre / corner > 3.0);
    let mut map = IntensityMap::new(layout, 1.0);
    let fill = |map: &mut IntensityMap, bx: u32, by: u32, per_texel: u64| {
        for y in 0..8 {
            for x in 0..8 {
                map.counts[layout.texel_index(
                    lucerna_photometry::CubeFace::NegZ,
                    bx * 8 + x,
                    by * 8 + y,
                )] = per_texel;
            }
        }
    };
    fill(&mut map, 3, 3, 100); // 6400 photons over the larger solid angle
    fill(&mut map, 0, 0, 50); // 3200 photons, but brighter per steradian
    assert!(3200.0 / corner > 6400.0 / centre);
    map.photons_emitted = map.photons_escaped();
    let none = TexelSymmetry::none(layout);
    assert!((peak_relative_error(&map, &none) - 1.0 / 3200f64.sqrt()).abs() < 1e-12);
    // Pooled over the square's symmetry, the corner block's images are the
    // face's four corner blocks (the diagonal mirror keeps it in place):
    // their photons count once each.
    let square = TexelSymmetry::new(layout, AxialSymmetry::Square);
    assert!((peak_relative_error(&map, &square) - 1.0 / 3200f64.sqrt()).abs() < 1e-12);
    fill(&mut map, 7, 0, 50);
    fill(&mut map, 0, 7, 50);
    fill(&mut map, 7, 7, 50);
    map.photons_emitted = map.photons_escaped();
    assert!((peak_relative_error(&map, &none) - 1.0 / 3200f64.sqrt()).abs() < 1e-12);
    assert!((peak_relative_error(&map, &square) - 1.0 / 12800f64.sqrt()).abs() < 1e-12);
}

/// An iteration given up (an edit made it stale) adds nothing, and leaves
/// no partial counts in the reused per-thread buffers: the next iteration
/// counts exactly what a fresh session's first does, on a scene a bake
/// would build with another BVH (the hits do not depend on the tree).
#[test]
fn a_stopped_iteration_adds_nothing_and_leaves_no_counts_behind() {
    use std::sync::atomic::{AtomicU32, Ordering};
    let settings = TraceSettings {
        seed: 3,
        max_bounces: 32,
        layout: CubeMapLayout::new(32),
    };
    let mut stopped = Session::start(prepared("faceted_downlight.toml"), settings);
    stopped.set_next_iteration_photons(200_000);
    // Stops after a few chunks were traced into the buffers.
    let asked = AtomicU32::new(0);
    let report = stopped
        .iterate_at_most_unless(u64::MAX, &|| asked.fetch_add(1, Ordering::Relaxed) > 4)
        .unwrap();
    assert!(report.is_none());
    assert_eq!(stopped.map().photons_emitted, 0);
    assert!(stopped.map().counts.iter().all(|&c| c == 0));
    stopped.set_next_iteration_photons(50_000);
    stopped.iterate().unwrap();

    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires");
    let scene = lucerna_scene::load_scene(&dir.join("faceted_downlight.toml")).unwrap();
    let preview = PreparedScene::with_quality(
        &scene,
        &lucerna_scene::tessellate(&scene, &dir).unwrap(),
        &dir,
        lucerna_tracer::bvh::BvhQuality::Preview,
    )
    .unwrap();
    let mut fresh = Session::start(preview, settings);
    fresh.set_next_iteration_photons(50_000);
    fresh.iterate().unwrap();
    assert_eq!(stopped.map().photons_emitted, 50_000);
    assert_eq!(stopped.map().counts, fresh.map().counts);
}
