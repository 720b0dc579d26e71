//! Traversal micro-benchmark: `cargo run --release -p lucerna-tracer --example speed -- SCENE`.
use glam::Vec3A;
fn main() {
    let path = std::path::PathBuf::from(std::env::args().nth(1).expect("scene path"));
    let scene = lucerna_scene::load_scene(&path).expect("scene");
    let dir = path.parent().expect("dir");
    let t = lucerna_scene::tessellate(&scene, dir).expect("tessellate");
    let mut p = lucerna_tracer::PreparedScene::new(&scene, &t, dir).expect("prepare");
    let mut rng = lucerna_tracer::rng::PhotonRng::new(1, 1, 1);
    let rays: Vec<(Vec3A, Vec3A)> = (0..1_000_000)
        .map(|_| {
            let d = lucerna_tracer::sampling::cosine_hemisphere(
                Vec3A::Z,
                rng.next_f32(),
                rng.next_f32(),
            );
            (Vec3A::new(0.0, 0.0, 0.0001), d)
        })
        .collect();
    for name in ["cwbvh obvhs", "cwbvh avx2", "bvh2"] {
        p.bvh.traversal = if name == "cwbvh avx2" {
            lucerna_tracer::bvh::CpuTraversal::Avx2
        } else {
            lucerna_tracer::bvh::CpuTraversal::Obvhs
        };
        let start = std::time::Instant::now();
        let mut hits = 0;
        for &(o, d) in &rays {
            let h = if name.starts_with("cwbvh") {
                p.bvh.intersect(o, d, f32::INFINITY)
            } else {
                p.bvh.intersect_bvh2(o, d, f32::INFINITY)
            };
            hits += usize::from(h.is_some());
        }
        let s = start.elapsed().as_secs_f64();
        println!(
            "{name}: {:.0} ns/ray single-threaded, {hits} hits",
            s * 1e9 / rays.len() as f64
        );
    }
    let mut tests = 0usize;
    for &(o, d) in rays.iter().take(100_000) {
        let ray = obvhs::ray::Ray::new(o * p.bvh.scale, d, 0.0, f32::INFINITY);
        let mut hit = obvhs::ray::RayHit::none();
        p.bvh.cwbvh.ray_traverse(ray, &mut hit, |r, slot| {
            tests += 1;
            let i = p.bvh.cwbvh_leaf_triangles[slot];
            lucerna_tracer::bvh::intersect_triangle(
                &p.bvh.triangles[i as usize],
                o * p.bvh.scale,
                d,
            )
            .map_or(f32::INFINITY, |h| {
                if h.0 < r.tmax { h.0 } else { f32::INFINITY }
            })
        });
    }
    println!("triangle tests per ray: {:.1}", tests as f64 / 100_000.0);
    let start = std::time::Instant::now();
    let mut acc = 0usize;
    for &(_, d) in &rays {
        acc += lucerna_photometry::CubeMapLayout::new(256).texel_of_direction([
            f64::from(d.x),
            f64::from(d.y),
            f64::from(d.z),
        ]);
    }
    println!(
        "texel_of_direction: {:.0} ns ({acc})",
        start.elapsed().as_secs_f64() * 1e9 / rays.len() as f64
    );
}
#[allow(dead_code)]
fn unused() {}
