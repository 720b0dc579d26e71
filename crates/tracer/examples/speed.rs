//! Quick CPU speed probe: `cargo run --release -p lucerna-tracer --example speed -- SCENE`.
fn main() {
    let path = std::path::PathBuf::from(std::env::args().nth(1).expect("scene path"));
    let scene = lucerna_scene::load_scene(&path).expect("scene");
    let dir = path.parent().expect("dir");
    let t = lucerna_scene::tessellate(&scene, dir).expect("tessellate");
    let p = lucerna_tracer::PreparedScene::new(&scene, &t, dir).expect("prepare");
    let s = lucerna_tracer::TraceSettings::default();
    let n = 2_000_000;
    let start = std::time::Instant::now();
    let tally = lucerna_tracer::trace_batch(&p, &s, 0, 0, n);
    let secs = start.elapsed().as_secs_f64();
    println!(
        "{} tris, bvh {:?}: {:.2} M photons/s, {:.2} M rays/s, {:.2} bounces",
        p.triangle_count(),
        p.bvh_build_time,
        n as f64 / secs / 1e6,
        tally.rays as f64 / secs / 1e6,
        tally.bounces as f64 / n as f64
    );
}
