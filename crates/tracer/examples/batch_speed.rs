#![allow(clippy::expect_used)]
fn main() {
    let path = std::path::PathBuf::from(std::env::args().nth(1).expect("scene path"));
    let scene = lucerna_scene::load_scene(&path).expect("scene");
    let dir = path.parent().expect("dir");
    let t = lucerna_scene::tessellate(&scene, dir).expect("tessellate");
    let p = lucerna_tracer::PreparedScene::new(&scene, &t, dir).expect("prepare");
    let settings = lucerna_tracer::TraceSettings { seed: 1, max_bounces: 64, layout: lucerna_photometry::CubeMapLayout::new(256) };
    let buffers = lucerna_tracer::CountBuffers::default();
    let mut counts = vec![0u64; settings.layout.texel_count()];
    let n = 1u32 << 20;
    let mut best = 0.0f64;
    for rep in 0..4 {
        let start = std::time::Instant::now();
        lucerna_tracer::trace_batch_into(&p, &settings, rep, 0, n, &buffers, &mut counts);
        best = best.max(f64::from(n) / start.elapsed().as_secs_f64() / 1e6);
    }
    println!("{best:.3}");
}
