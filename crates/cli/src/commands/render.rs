//! `lucerna render`: light a room with photometric profiles and write the
//! view (tone-mapped or false-colour lux), the work-plane grid and its
//! EN 12464-1 figures; `lucerna render-bench`: frame times per backend.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use lucerna_photometry::Photometry;
use lucerna_room::gpu::GpuRoomRenderer;
use lucerna_room::model::{SourceKind, load_room};
use lucerna_room::{RoomScene, Shading, render_cpu, tone_map, work_plane_cpu};
use lucerna_scene::write_atomically;
use lucerna_simulation::{
    BackendRequest, ExportOptions, FilterChoice, Luminaire, SimulationSettings, StoppingRule,
};

#[derive(Debug, clap::Args)]
pub struct RenderArgs {
    /// The room (TOML).
    pub room: PathBuf,
    /// Output PNG.
    #[arg(long)]
    pub out: PathBuf,
    /// Show illuminance (lx) in false colour instead of the tone-mapped view.
    #[arg(long)]
    pub false_colour: bool,
    /// Write the work-plane illuminance grid as CSV.
    #[arg(long)]
    pub lux_grid: Option<PathBuf>,
    /// Write a top view of the work-plane grid (false colour, lux per
    /// cell, figures) as PNG.
    #[arg(long)]
    pub work_plane_png: Option<PathBuf>,
    /// Image size, WIDTHxHEIGHT.
    #[arg(long, default_value = "1280x720", value_parser = parse_size)]
    pub size: (u32, u32),
    /// gpu (the WGSL renderer, a software adapter included), cpu, or auto:
    /// a hardware GPU if one opens, else the CPU (which renders faster than
    /// a software adapter: `lucerna render-bench` measures both).
    #[arg(long, default_value = "auto")]
    pub backend: BackendRequest,
    /// Shade as point lights (far-field photometry) instead of the cubature.
    #[arg(long)]
    pub point_lights: bool,
    /// Photons per luminaire given as a scene to bake.
    #[arg(long, default_value_t = 2_000_000)]
    pub photons: u64,
}

/// "1280x720".
pub fn parse_size(s: &str) -> Result<(u32, u32), String> {
    let (w, h) = s
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("'{s}' is not WIDTHxHEIGHT"))?;
    let w: u32 = w
        .trim()
        .parse()
        .map_err(|_| format!("bad width in '{s}'"))?;
    let h: u32 = h
        .trim()
        .parse()
        .map_err(|_| format!("bad height in '{s}'"))?;
    if !(8..=8192).contains(&w) || !(8..=8192).contains(&h) {
        return Err(format!("size {w}x{h} outside 8..8192"));
    }
    Ok((w, h))
}

/// Traces a luminaire scene into photometry (auto backend, filtered map
/// pooled over the luminaire's symmetry).
fn bake_profile(path: &Path, photons: u64) -> Result<Photometry> {
    let luminaire = std::sync::Arc::new(Luminaire::load(path)?);
    let settings = SimulationSettings {
        resolution: 128,
        filter: FilterChoice::Automatic,
        stop: StoppingRule {
            photons: Some(photons),
            ..Default::default()
        },
        ..Default::default()
    };
    let snapshot = lucerna_simulation::bake(luminaire, settings)?;
    let options = ExportOptions {
        symmetrise: None,
        date: String::new(),
        seed: settings.seed,
        scene_file: path.display().to_string(),

        labels: None,
    };
    Ok(lucerna_simulation::photometry(&snapshot, &options))
}

/// Loads the room and every luminaire's profile.
pub fn load_room_scene(path: &Path, photons: u64) -> Result<RoomScene> {
    let room = load_room(path)?;
    let base = path.parent().unwrap_or(Path::new("."));
    let mut profiles = Vec::new();
    for (i, spec) in room.luminaires.iter().enumerate() {
        let Some((kind, source)) = spec.source_path(base) else {
            bail!("luminaire[{i}] has no profile");
        };
        let phot = match kind {
            SourceKind::PhotometricFile => super::info::read(&source)?,
            SourceKind::LuminaireScene => {
                eprintln!("baking {} ({photons} photons)", source.display());
                bake_profile(&source, photons)
                    .with_context(|| format!("cannot bake {}", source.display()))?
            }
        };
        profiles.push(phot);
    }
    let mut scene = RoomScene::new(&room, &profiles);
    scene.mesh = lucerna_room::scene::load_room_mesh(&room, base)?;
    Ok(scene)
}

pub fn render(args: &RenderArgs) -> Result<()> {
    let scene = load_room_scene(&args.room, args.photons)?;
    let (w, h) = args.size;
    let shading = if args.point_lights {
        Shading::PointLight
    } else {
        Shading::Cubature
    };
    let gpu = match args.backend {
        BackendRequest::Cpu => None,
        BackendRequest::Gpu => Some(GpuRoomRenderer::new(lucerna_gpu::open()?)?),
        BackendRequest::Auto => lucerna_gpu::open()
            .ok()
            .filter(|ctx| !ctx.is_software())
            .and_then(|ctx| GpuRoomRenderer::new(ctx).ok()),
    };
    let start = Instant::now();
    // The view and the work-plane grid, both by the same backend.
    let (frame, mut grid, backend) = match &gpu {
        Some(r) => {
            let uploaded = r.upload(&scene)?;
            let (frame, _) = r.render(&scene, &uploaded, w, h, shading)?;
            let grid = r.work_plane(&scene, &uploaded, shading)?;
            (frame, grid, r.context().describe())
        }
        None => (
            render_cpu(&scene, w, h, shading),
            work_plane_cpu(&scene, shading),
            "CPU".to_owned(),
        ),
    };
    eprintln!(
        "rendered {w}x{h}, {} luminaires, on {backend} in {:.0} ms",
        scene.lights.len(),
        start.elapsed().as_secs_f64() * 1e3
    );
    let indirect = scene.indirect_lux();
    for e in &mut grid.lux {
        *e += indirect;
    }
    let f = grid.figures();
    let light = if indirect > 0.0 {
        format!("direct + {indirect:.1} lx uniform indirect")
    } else {
        "direct light only".to_owned()
    };
    println!(
        "work plane at {:.2} m, {} points ({:.2} m border): Emin {:.1} lx, Eavg {:.1} lx, Emax {:.1} lx, U0 = Emin/Eavg {:.2} ({light})",
        grid.height_m,
        f.points,
        scene.work_plane.border_m,
        f.e_min_lx,
        f.e_avg_lx,
        f.e_max_lx,
        f.u0
    );
    let name = args
        .room
        .file_stem()
        .map_or(String::new(), |s| s.to_string_lossy().into_owned());
    let caption = format!(
        "{name}: Eavg {:.0} lx, Emin {:.0} lx, U0 {:.2} on the work plane ({})",
        f.e_avg_lx,
        f.e_min_lx,
        f.u0,
        if args.point_lights {
            "point lights"
        } else {
            "cubature"
        }
    );
    let png = if args.false_colour {
        lucerna_pictures::illuminance_png(w, h, &frame.illuminance, &caption)?
    } else {
        lucerna_pictures::room_view_png(w, h, &tone_map(&frame), &caption)?
    };
    write_atomically(&args.out, &png)
        .with_context(|| format!("cannot write {}", args.out.display()))?;
    eprintln!("wrote {}", args.out.display());
    if let Some(path) = &args.work_plane_png {
        let caption = format!(
            "{name}: work plane {:.2} m, Emin {:.0} lx, Eavg {:.0} lx, Emax {:.0} lx, U0 {:.2}",
            grid.height_m, f.e_min_lx, f.e_avg_lx, f.e_max_lx, f.u0
        );
        let png = lucerna_pictures::work_plane_png(
            &grid.xs,
            &grid.ys,
            &grid.lux,
            (scene.size.x, scene.size.y),
            &scene
                .lights
                .iter()
                .map(|l| (l.position.x, l.position.y))
                .collect::<Vec<_>>(),
            &caption,
        )?;
        write_atomically(path, &png).with_context(|| format!("cannot write {}", path.display()))?;
        eprintln!("wrote {}", path.display());
    }
    if let Some(csv) = &args.lux_grid {
        write_atomically(csv, &grid.csv()?)
            .with_context(|| format!("cannot write {}", csv.display()))?;
        eprintln!("wrote {}", csv.display());
    }
    Ok(())
}

#[derive(Debug, clap::Args)]
pub struct RenderBenchArgs {
    /// The room whose first luminaire is repeated 1, 4 and 16 times.
    #[arg(default_value = "assets/rooms/office.toml")]
    pub room: PathBuf,
    /// Image size, WIDTHxHEIGHT.
    #[arg(long, default_value = "1280x720", value_parser = parse_size)]
    pub size: (u32, u32),
    /// Skip the CPU renderer (slow at 1280x720 with 16 luminaires).
    #[arg(long)]
    pub gpu_only: bool,
}

/// Milliseconds per frame for 1, 4 and 16 luminaires, cubature and the
/// point-light baseline, on each backend.
pub fn render_bench(args: &RenderBenchArgs) -> Result<()> {
    let base = load_room_scene(&args.room, 2_000_000)?;
    let Some(first) = base.lights.first().cloned() else {
        bail!("the room has no luminaire");
    };
    let (w, h) = args.size;
    let gpu = lucerna_gpu::open()
        .ok()
        .and_then(|ctx| GpuRoomRenderer::new(ctx).ok());
    println!("frame times at {w}x{h} (ms per frame; GPU: kernel submit to completion, best of 3)");
    println!("backend                                  lights  cubature  point  ratio");
    for count in [1usize, 4, 16] {
        let mut scene = base.clone();
        scene.lights = (0..count)
            .map(|i| {
                let mut l = first.clone();
                let (gx, gy) = ((i % 4) as f64, (i / 4) as f64);
                l.position.x = scene.size.x * (gx + 0.5) / 4.0;
                l.position.y = scene.size.y * (gy + 0.5) / 4.0;
                l
            })
            .collect();
        if let Some(r) = &gpu {
            let uploaded = r.upload(&scene)?;
            let mut best = [f64::INFINITY; 2];
            for (k, shading) in [Shading::Cubature, Shading::PointLight]
                .into_iter()
                .enumerate()
            {
                for _ in 0..3 {
                    let (_, t) = r.render(&scene, &uploaded, w, h, shading)?;
                    best[k] = best[k].min(t.as_secs_f64() * 1e3);
                }
            }
            println!(
                "{:40} {count:6}  {:8.2}  {:6.2}  {:5.2}",
                r.context().describe(),
                best[0],
                best[1],
                best[0] / best[1]
            );
        }
        if !args.gpu_only {
            let mut t = [0.0; 2];
            for (k, shading) in [Shading::Cubature, Shading::PointLight]
                .into_iter()
                .enumerate()
            {
                let start = Instant::now();
                let _ = render_cpu(&scene, w, h, shading);
                t[k] = start.elapsed().as_secs_f64() * 1e3;
            }
            println!(
                "{:40} {count:6}  {:8.2}  {:6.2}  {:5.2}",
                format!("CPU ({} threads)", rayon::current_num_threads()),
                t[0],
                t[1],
                t[0] / t[1]
            );
        }
    }
    Ok(())
}
