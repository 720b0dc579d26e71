//! `lucerna render`: light a room with photometric profiles and write the
//! view (tone-mapped or false-colour lux), the work-plane grid and its
//! EN 12464-1 figures; `lucerna render-bench`: frame times per backend.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result, bail};
use lucerna_photometry::Photometry;
use lucerna_room::gpu::GpuRoomRenderer;
use lucerna_room::model::SourceKind;
use lucerna_room::{
    RoomRenderer, RoomScene, RoomSetup, Shading, TASK_TARGETS, TaskTarget, render_cpu, tone_map,
};
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
    /// The EN 12464-1 task area the work plane is judged against: words of
    /// its name ("writing", "corridors", "technical drawing"); by default
    /// the one the room file's name suggests, as the editor picks it.
    #[arg(long)]
    pub task: Option<String>,
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
pub fn load_room_scene(path: &Path, photons: u64) -> Result<(RoomSetup, RoomScene)> {
    let setup = RoomSetup::load(path)?;
    let mut profiles = Vec::new();
    for (i, spec) in setup.file.luminaires.iter().enumerate() {
        let Some((kind, source)) = spec.source_path(setup.base()) else {
            bail!("luminaire[{i}] has no profile");
        };
        let phot = match kind {
            SourceKind::PhotometricFile => super::input::read_photometry(&source)?,
            SourceKind::LuminaireScene => {
                eprintln!("baking {} ({photons} photons)", source.display());
                bake_profile(&source, photons)
                    .with_context(|| format!("cannot bake {}", source.display()))?
            }
        };
        profiles.push(phot);
    }
    let scene = setup.scene_with_profiles(&profiles);
    Ok((setup, scene))
}

/// The task `words` name, or the one the room's file and name suggest.
fn task_target(words: Option<&str>, room: &Path, room_name: &str) -> Result<TaskTarget> {
    match words {
        Some(words) => TaskTarget::find(words).with_context(|| {
            let names: Vec<&str> = TASK_TARGETS.iter().map(|t| t.name).collect();
            format!(
                "no EN 12464-1 task area named like '{words}'; the task areas are: {}",
                names.join("; ")
            )
        }),
        None => Ok(TASK_TARGETS[TaskTarget::for_room(&format!("{} {room_name}", room.display()))]),
    }
}

pub fn render(args: &RenderArgs) -> Result<()> {
    // A task asked for by name is checked before any baking.
    let asked = args
        .task
        .as_deref()
        .map(|words| task_target(Some(words), &args.room, ""));
    let asked = asked.transpose()?;
    let (setup, scene) = load_room_scene(&args.room, args.photons)?;
    let target = match asked {
        Some(t) => t,
        None => task_target(None, &args.room, &setup.file.name)?,
    };
    let (w, h) = args.size;
    let shading = if args.point_lights {
        Shading::PointLight
    } else {
        Shading::Cubature
    };
    let mut renderer = RoomRenderer::open(args.backend);
    if args.backend == BackendRequest::Gpu && !renderer.is_gpu() {
        bail!("--backend gpu: {}", renderer.description());
    }
    let start = Instant::now();
    // The view and the work-plane grid, both by the same renderer.
    let Some(lit) = renderer.light(&scene, [w, h], shading, &|| false) else {
        bail!("the render was given up");
    };
    eprintln!(
        "rendered {w}x{h}, {} luminaires, on {} in {:.0} ms",
        scene.lights.len(),
        lit.backend,
        start.elapsed().as_secs_f64() * 1e3
    );
    let (frame, grid, f, indirect) = (&lit.frame, &lit.grid, lit.figures, lit.indirect_lux);
    let light = if indirect > 0.0 {
        format!("direct + {indirect:.1} lx uniform indirect")
    } else {
        "direct light only".to_owned()
    };
    println!(
        "{}",
        figures_line(grid, &f, scene.work_plane.border_m, &light)
    );
    println!(
        "EN 12464-1 {} (Em {:.0} lx, U0 {:.2}): {}",
        target.name,
        target.e_m_lx,
        target.u0,
        if target.met_by(&f) { "meets" } else { "fails" }
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
        lucerna_pictures::room_view_png(w, h, &tone_map(frame), &caption)?
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

/// The work plane's figures as `lucerna render` prints them (a test
/// compares them with the editor's preview of the same room and table).
pub fn figures_line(
    grid: &lucerna_room::WorkPlaneGrid,
    f: &lucerna_room::IlluminanceFigures,
    border_m: f64,
    light: &str,
) -> String {
    format!(
        "work plane at {:.2} m, {} points ({border_m:.2} m border): Emin {:.1} lx, Eavg {:.1} lx, Emax {:.1} lx, U0 = Emin/Eavg {:.2} ({light})",
        grid.height_m, f.points, f.e_min_lx, f.e_avg_lx, f.e_max_lx, f.u0
    )
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

/// Milliseconds per frame for 1, 4 and 16 luminaires, the polar rule, its
/// draft (the editor's room while a drag runs) and the point-light
/// baseline, on each backend.
pub fn render_bench(args: &RenderBenchArgs) -> Result<()> {
    let (_, base) = load_room_scene(&args.room, 2_000_000)?;
    let Some(first) = base.lights.first().cloned() else {
        bail!("the room has no luminaire");
    };
    let (w, h) = args.size;
    let gpu = lucerna_gpu::open()
        .ok()
        .and_then(|ctx| GpuRoomRenderer::new(ctx).ok());
    println!("frame times at {w}x{h} (ms per frame, best of 3; GPU: kernel submit to completion)");
    println!(
        "backend                                  lights  cubature   draft   point  ratio  draft ratio"
    );
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
            let mut best = [f64::INFINITY; 3];
            for (k, shading) in [Shading::Cubature, Shading::Draft, Shading::PointLight]
                .into_iter()
                .enumerate()
            {
                for _ in 0..3 {
                    let (_, t) = r.render(&scene, &uploaded, w, h, shading)?;
                    best[k] = best[k].min(t.as_secs_f64() * 1e3);
                }
            }
            println!(
                "{:40} {count:6}  {:8.2}  {:6.2}  {:6.2}  {:5.2}  {:11.2}",
                r.context().describe(),
                best[0],
                best[1],
                best[2],
                best[0] / best[2],
                best[1] / best[2]
            );
        }
        if !args.gpu_only {
            let mut t = [0.0; 3];
            for (k, shading) in [Shading::Cubature, Shading::Draft, Shading::PointLight]
                .into_iter()
                .enumerate()
            {
                // Best of 3, as on the GPU: this machine is shared.
                t[k] = f64::INFINITY;
                for _ in 0..3 {
                    let start = Instant::now();
                    let _ = render_cpu(&scene, w, h, shading);
                    t[k] = t[k].min(start.elapsed().as_secs_f64() * 1e3);
                }
            }
            println!(
                "{:40} {count:6}  {:8.2}  {:6.2}  {:6.2}  {:5.2}  {:11.2}",
                format!("CPU ({} threads)", rayon::current_num_threads()),
                t[0],
                t[1],
                t[2],
                t[0] / t[2],
                t[1] / t[2]
            );
        }
    }
    Ok(())
}
