//! Tracer micro-benchmark, one thread:
//! `cargo run --release -p lucerna-tracer --example speed -- SCENE [photons]`.
//! Times closest-hit queries of the rays real photons cast (their paths'
//! segments) on each CPU traversal, and whole photons; with `photons`, only
//! prints the best of three photon rates (M photons/s), for A/B scripts.
#![allow(clippy::expect_used)] // reason: a benchmark may panic on bad input

use glam::Vec3A;
use lucerna_tracer::bvh::CpuTraversal;
use lucerna_tracer::rng::PhotonRng;
use lucerna_tracer::{Fate, cpu, cpu_features};

fn main() {
    let path = std::path::PathBuf::from(std::env::args().nth(1).expect("scene path"));
    let only_photons = std::env::args().nth(2).as_deref() == Some("photons");
    let scene = lucerna_scene::load_scene(&path).expect("scene");
    let dir = path.parent().expect("dir");
    let t = lucerna_scene::tessellate(&scene, dir).expect("tessellate");
    let mut p = lucerna_tracer::PreparedScene::new(&scene, &t, dir).expect("prepare");
    let photons = 1_000_000u32;
    let photon_rate = |p: &lucerna_tracer::PreparedScene| {
        (0..3u32)
            .map(|rep| {
                let start = std::time::Instant::now();
                let escaped = cpu_features::with_best_features(|| {
                    (0..photons)
                        .filter(|&k| {
                            let mut rng = PhotonRng::new(1, rep, k);
                            matches!(cpu::trace_photon(p, 64, &mut rng).0, Fate::Escaped(_))
                        })
                        .count()
                });
                std::hint::black_box(escaped);
                f64::from(photons) / start.elapsed().as_secs_f64() / 1e6
            })
            .fold(0.0, f64::max)
    };
    if only_photons {
        println!("{:.3}", photon_rate(&p));
        return;
    }
    if let Some(w) = &p.bvh.wide {
        let lanes: usize = w
            .blocks
            .iter()
            .map(|b| b.triangle.iter().filter(|&&t| t != u32::MAX).count())
            .sum();
        println!(
            "wide BVH: {} nodes, {} blocks, {:.2} triangles per block, depth {}",
            w.nodes.len(),
            w.blocks.len(),
            lanes as f64 / w.blocks.len() as f64,
            w.depth
        );
    }
    // The rays of 300 000 photons: each segment of each path.
    let mut rays: Vec<(Vec3A, Vec3A)> = Vec::new();
    for k in 0..300_000u32 {
        let mut rng = PhotonRng::new(1, 0, k);
        let mut points = Vec::new();
        let (fate, _, _) = cpu::trace_photon_recorded(&p, 64, &mut rng, |x| points.push(x));
        rays.extend(points.windows(2).map(|w| (w[0], (w[1] - w[0]).normalize())));
        if let (Fate::Escaped(d), Some(&last)) = (fate, points.last()) {
            rays.push((last + d * p.epsilon * 2.0, d));
        }
    }
    for traversal in [CpuTraversal::best(), CpuTraversal::Scalar] {
        p.bvh.traversal = traversal;
        let start = std::time::Instant::now();
        let hits = cpu_features::with_best_features(|| {
            rays.iter()
                .filter(|&&(o, d)| p.bvh.intersect(o, d, f32::INFINITY).is_some())
                .count()
        });
        println!(
            "{}: {:.0} ns/ray, {hits} hits of {} photon rays",
            traversal.describe(),
            start.elapsed().as_secs_f64() * 1e9 / rays.len() as f64,
            rays.len()
        );
        println!("  {:.3} M photons/s", photon_rate(&p));
    }
}
