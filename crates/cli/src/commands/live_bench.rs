//! `lucerna live-bench`: what a live preview pays per snapshot at a live
//! run's schedule: the candela table and figures (first table of a layout,
//! then cached) and the automatic filter on the live path (one pass per
//! snapshot; the rule re-chosen by cross-validation on a background thread
//! whenever the photons have doubled), beside one in-line choice.

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use anyhow::Result;
use lucerna_filter::Threshold;
use lucerna_photometry::fidelity::FidelityTargets;
use lucerna_photometry::gamma_grid::PhotonNoise;
use lucerna_photometry::table::uniform_c_planes;
use lucerna_photometry::tabulate::{CPooling, GammaGrid, TableResampler};
use lucerna_photometry::{AxialSymmetry, TexelSymmetry, figures};
use lucerna_simulation::{
    BackendRequest, LiveFilter, Luminaire, Run, SimulationSettings, StoppingRule,
};

#[derive(Debug, clap::Args)]
pub struct LiveBenchArgs {
    /// Luminaire scenes (default: every example).
    pub scenes: Vec<PathBuf>,
    /// Texels per cube-face edge.
    #[arg(long, default_value_t = 256)]
    pub resolution: u32,
    /// Snapshots of the live schedule, one every `--snapshot-photons`.
    #[arg(long, default_value_t = 50)]
    pub snapshots: u64,
    /// Photons between snapshots (a live run at 2 M photons/s and five
    /// snapshots a second).
    #[arg(long, default_value_t = 400_000)]
    pub snapshot_photons: u64,
}

pub fn live_bench(args: &LiveBenchArgs) -> Result<()> {
    let scenes = super::bench::example_scenes(&args.scenes)?;
    println!(
        "{:<20} {:>10} {:>10} {:>9} {:>9} {:>12} {:>12} {:>10} {:>12}",
        "scene",
        "table 1st",
        "table+fig",
        "γ angles",
        "flux err",
        "filter/snap",
        "max/snap",
        "choices",
        "in-line CV"
    );
    for path in &scenes {
        let name = path
            .file_stem()
            .map_or(String::new(), |s| s.to_string_lossy().into_owned());
        let luminaire = Arc::new(Luminaire::load(path)?);
        let settings = SimulationSettings {
            resolution: args.resolution,
            backend: BackendRequest::Cpu,
            stop: StoppingRule {
                photons: Some(args.snapshots * args.snapshot_photons),
                ..Default::default()
            },
            ..Default::default()
        };
        let symmetry = TexelSymmetry::new(
            settings_layout(&settings),
            if settings.pool_symmetry {
                luminaire.find_symmetry().symmetry
            } else {
                AxialSymmetry::None
            },
        );
        let mut run = Run::new(luminaire, settings)?;
        let mut resampler = TableResampler::new();
        let mut filter = LiveFilter::new();
        let c_planes = uniform_c_planes(settings.table.c_step_deg);
        let (mut first_table_ms, mut table_ms, mut table_count) = (0.0, 0.0, 0u32);
        let (mut filter_ms, mut filter_max_ms, mut choices) = (0.0, 0.0f64, 0u32);
        let (mut angles, mut flux_error) = (0usize, 0.0);
        for k in 1..=args.snapshots {
            let target = k * args.snapshot_photons;
            while run.session().map().photons_emitted < target {
                run.step()?;
            }
            let map = run.session().map();
            // The live filter's cost at this snapshot (a background choice
            // may be running beside it, and beside the tracing).
            let was_choosing = filter.is_choosing();
            let start = Instant::now();
            let (candela, _) = filter.filter(map, Threshold::Automatic, &symmetry, true);
            let ms = start.elapsed().as_secs_f64() * 1e3;
            if filter.is_choosing() && !was_choosing {
                choices += 1;
            }
            filter_ms += ms;
            filter_max_ms = filter_max_ms.max(ms);
            // The table and figures of the exported map.
            let traced = map.escaped_flux_lm();
            let start = Instant::now();
            let table = resampler
                .table(
                    map.layout,
                    &candela,
                    &c_planes,
                    GammaGrid::Automatic(FidelityTargets::default()),
                    Some(PhotonNoise {
                        lm_per_photon: map.flux_per_photon_lm(),
                        pooled_images: symmetry.order() as f64,
                    }),
                    CPooling::Separate,
                )
                .table;
            let fig = figures(&table, Some(map.emitter_flux_lm));
            let ms = start.elapsed().as_secs_f64() * 1e3;
            if k == 1 {
                first_table_ms = ms;
            } else {
                table_ms += ms;
                table_count += 1;
            }
            angles = table.gammas_deg.len();
            flux_error = fig.flux_lm / traced - 1.0;
        }
        // One choice in line at the last snapshot, for comparison.
        filter.wait_for_choice();
        let start = Instant::now();
        filter.filter(run.session().map(), Threshold::Automatic, &symmetry, false);
        let in_line_ms = start.elapsed().as_secs_f64() * 1e3;
        println!(
            "{:<20} {:>8.1}ms {:>8.1}ms {:>9} {:>8.3}% {:>10.1}ms {:>10.1}ms {:>10} {:>10.0}ms",
            name,
            first_table_ms,
            table_ms / f64::from(table_count.max(1)),
            angles,
            100.0 * flux_error,
            filter_ms / args.snapshots as f64,
            filter_max_ms,
            format!("{choices}/{}", args.snapshots),
            in_line_ms
        );
    }
    Ok(())
}

fn settings_layout(settings: &SimulationSettings) -> lucerna_photometry::CubeMapLayout {
    lucerna_photometry::CubeMapLayout::new(settings.resolution)
}
