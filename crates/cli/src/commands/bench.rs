//! `lucerna bench`: photons/s, rays/s and bounces per photon for every
//! example luminaire on every available backend, in one run, plus BVH
//! build times.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result};
use lucerna_photometry::CubeMapLayout;
use lucerna_scene::shapes::Revolved;
use lucerna_scene::{Interpolation, Shape};
use lucerna_tracer::bvh::{Bvh, CpuTraversal};
use lucerna_tracer::gpu::GpuTracer;
use lucerna_tracer::{Backend, PreparedScene, Tally, TraceSettings};

#[derive(Debug, clap::Args)]
pub struct BenchArgs {
    /// Luminaires to measure (default: every file in assets/luminaires).
    pub scenes: Vec<PathBuf>,
    /// Photons per measurement.
    #[arg(long, default_value_t = 2_000_000)]
    pub photons: u32,
    /// Also time BVH builds of 10k, 100k and 1M triangles.
    #[arg(long)]
    pub bvh_sizes: bool,
    /// Skip the GPU adapter even if there is one.
    #[arg(long)]
    pub cpu_only: bool,
    /// Also measure each finished luminaire with its finishes cut into
    /// the mesh as triangles of at most this edge (mm), and print the
    /// time and memory of building each scene: the finish as BRDF against
    /// the finish as geometry.
    #[arg(long)]
    pub finish_geometry_mm: Option<f64>,
}

/// `scenes`, or every example luminaire when none is given.
pub fn example_scenes(scenes: &[PathBuf]) -> Result<Vec<PathBuf>> {
    if scenes.is_empty() {
        examples()
    } else {
        Ok(scenes.to_vec())
    }
}

fn examples() -> Result<Vec<PathBuf>> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires");
    let mut v: Vec<PathBuf> = std::fs::read_dir(&dir)
        .with_context(|| format!("cannot list {}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    v.sort();
    Ok(v)
}

/// Traces `photons` in batches of at most 2²⁰ (warm-up first).
fn run(
    backend: &Backend,
    prepared: &PreparedScene,
    settings: &TraceSettings,
    photons: u32,
) -> Result<(f64, Tally)> {
    let batch = 1u32 << 20;
    let trace = |iteration: u32, count: u32| -> Result<Tally> {
        Ok(backend.trace(prepared, settings, iteration, 0, count)?)
    };
    trace(u32::MAX, 10_000)?;
    let start = Instant::now();
    let mut total = Tally::new(settings.layout.texel_count());
    let mut done = 0;
    let mut iteration = 0;
    while done < photons {
        let n = batch.min(photons - done);
        let t = trace(iteration, n)?;
        total.emitted += t.emitted;
        total.bounces += t.bounces;
        total.rays += t.rays;
        done += n;
        iteration += 1;
    }
    Ok((start.elapsed().as_secs_f64(), total))
}

pub fn bench(args: &BenchArgs) -> Result<()> {
    let scenes = example_scenes(&args.scenes)?;
    let settings = TraceSettings {
        seed: 1,
        max_bounces: 64,
        layout: CubeMapLayout::new(256),
    };
    let gpu = if args.cpu_only {
        None
    } else {
        lucerna_gpu::open().ok()
    };
    println!("CPU: {} threads", rayon::current_num_threads());
    match &gpu {
        Some(ctx) => println!("GPU: {}", ctx.describe()),
        None => println!("GPU: none"),
    }
    println!();
    println!(
        "{:<26} {:>9} {:>10} {:>10}  {:<34} {:>12} {:>12} {:>9}",
        "luminaire",
        "triangles",
        "CWBVH ms",
        "BVH2 ms",
        "backend",
        "M photons/s",
        "M rays/s",
        "bounces"
    );
    // Each scene, and with --finish-geometry-mm each finished one again
    // with its finishes as triangles.
    let mut cases: Vec<(PathBuf, Option<f64>)> = Vec::new();
    for path in &scenes {
        cases.push((path.clone(), None));
        if let Some(mm) = args.finish_geometry_mm {
            if !(mm.is_finite() && mm > 0.0) {
                anyhow::bail!("--finish-geometry-mm must be a positive length, got {mm}");
            }
            let scene = lucerna_scene::load_scene(path)?;
            if scene.parts.iter().any(|p| p.finish.is_some()) {
                cases.push((path.clone(), Some(mm * 1e-3)));
            }
        }
    }
    let mut builds = Vec::new();
    for (path, geometry_edge) in &cases {
        let start = Instant::now();
        let mut prepared = match geometry_edge {
            None => lucerna_simulation::Luminaire::load(path)?.prepared,
            Some(edge) => {
                let scene = lucerna_scene::load_scene(path)?;
                let dir = path.parent().unwrap_or(Path::new("."));
                let split = lucerna_scene::FinishSplit {
                    geometry_edge: Some(*edge),
                    normals_from: None,
                };
                let t = lucerna_scene::tessellate_with(&scene, dir, split)?;
                PreparedScene::new(&scene, &t, dir)?
            }
        };
        let label = |p: &PathBuf| {
            let stem = p
                .file_stem()
                .map_or(String::new(), |s| s.to_string_lossy().into_owned());
            match geometry_edge {
                None => stem,
                Some(_) => format!("{stem} (finish as triangles)"),
            }
        };
        builds.push((
            label(path),
            start.elapsed().as_secs_f64(),
            prepared.triangle_count(),
            // Triangles, their BVH and shading records (bytes).
            std::mem::size_of_val(prepared.shading.as_slice())
                + std::mem::size_of_val(prepared.bvh.triangles.as_slice()),
        ));
        let best_traversal = prepared.bvh.traversal;
        let mut backends = vec![Backend::Cpu];
        if let Some(ctx) = &gpu {
            backends.push(Backend::Gpu(Box::new(GpuTracer::new(
                ctx.clone(),
                &prepared,
                settings,
            )?)));
        }
        // The CPU tracer with each traversal this CPU runs (the fastest
        // first: it is what `--backend cpu` uses), then the GPU.
        let mut runs: Vec<(&Backend, CpuTraversal)> = vec![(&backends[0], best_traversal)];
        if best_traversal != CpuTraversal::Scalar {
            runs.push((&backends[0], CpuTraversal::Scalar));
        }
        runs.extend(backends[1..].iter().map(|b| (b, best_traversal)));
        for (backend, traversal) in runs {
            prepared.bvh.traversal = traversal;
            let (seconds, tally) = run(backend, &prepared, &settings, args.photons)?;
            let name = match backend {
                Backend::Cpu => format!("CPU tracer ({})", traversal.describe()),
                Backend::Gpu(g) => format!("WGSL on {}", g.context().info.name),
            };
            println!(
                "{:<26} {:>9} {:>10.1} {:>10.1}  {:<34} {:>12.3} {:>12.3} {:>9.3}",
                label(path).chars().take(26).collect::<String>(),
                prepared.triangle_count(),
                prepared.bvh.cwbvh_build_time.as_secs_f64() * 1e3,
                prepared.bvh.bvh2().build_time.as_secs_f64() * 1e3,
                name.chars().take(34).collect::<String>(),
                tally.emitted as f64 / seconds / 1e6,
                tally.rays as f64 / seconds / 1e6,
                tally.bounces as f64 / tally.emitted as f64,
            );
        }
    }
    if args.finish_geometry_mm.is_some() {
        println!();
        println!(
            "{:<44} {:>10} {:>12} {:>16}",
            "scene built", "seconds", "triangles", "MB triangles"
        );
        for (name, seconds, triangles, bytes) in &builds {
            println!(
                "{name:<44} {seconds:>10.2} {triangles:>12} {:>16.1}",
                *bytes as f64 / 1e6
            );
        }
    }
    if args.bvh_sizes {
        println!();
        println!("{:>10} {:>12} {:>12}", "triangles", "CWBVH ms", "BVH2 ms");
        for (around, along) in [(100u32, 50u32), (316, 158), (1000, 500)] {
            let shape = Shape::Revolved(Revolved {
                profile: vec![[0.0, 0.03], [0.02, 0.02], [0.04, 0.0], [0.05, -0.03]],
                interpolation: Interpolation::CatmullRom,
                segments_around: around,
                segments_per_span: along / 3,
                faceted: false,
            });
            let mesh = lucerna_scene::shapes::generate(&shape).context("a generated mesh")?;
            let corners: Vec<[glam::Vec3; 3]> = mesh
                .triangles
                .iter()
                .map(|t| t.map(|i| mesh.positions[i as usize]))
                .collect();
            let bvh = Bvh::build(&corners, &[]);
            println!(
                "{:>10} {:>12.1} {:>12.1}",
                corners.len(),
                bvh.cwbvh_build_time.as_secs_f64() * 1e3,
                bvh.bvh2().build_time.as_secs_f64() * 1e3
            );
        }
    }
    Ok(())
}
