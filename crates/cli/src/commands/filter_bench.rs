//! `lucerna filter-bench`: the Litemaker paper's Figure 8a protocol on our
//! scenes: RMSE against a high-photon reference (each image scaled by its
//! mean) of the raw map and of the filter with fixed and automatic
//! thresholds, over photon counts; CSV, PNG plot, filter timings.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result};
use lucerna_filter::{FilterSettings, Threshold, filter};
use lucerna_photometry::CubeMapLayout;
use lucerna_pictures::chart::{Series, log_log_chart_png};
use lucerna_scene::write_atomically;
use lucerna_tracer::{PreparedScene, TraceSettings, trace_batch};

#[derive(Debug, clap::Args)]
pub struct FilterBenchArgs {
    /// Luminaires (default: the opal bell and the faceted downlight).
    pub scenes: Vec<PathBuf>,
    /// Texels per cube-face edge.
    #[arg(long, default_value_t = 128)]
    pub resolution: u32,
    /// Photons of the reference.
    #[arg(long, default_value_t = 200_000_000)]
    pub reference_photons: u64,
    /// Largest photon count evaluated (powers of ten from 10⁵).
    #[arg(long, default_value_t = 100_000_000)]
    pub max_photons: u64,
    /// Output directory for the CSV and PNG files.
    #[arg(long, default_value = "target/filter-bench")]
    pub out: PathBuf,
}

const BATCH: u64 = 1 << 20;
const FIXED: [f64; 4] = [50.0, 100.0, 150.0, 250.0];

/// Accumulates photons `done .. target` of a run into `counts`.
fn trace_to(
    prepared: &PreparedScene,
    settings: &TraceSettings,
    counts: &mut [u64],
    done: &mut u64,
    target: u64,
) {
    while *done < target {
        let iteration = (*done / BATCH) as u32;
        let first = (*done % BATCH) as u32;
        let n = (BATCH - u64::from(first)).min(target - *done) as u32;
        let t = trace_batch(prepared, settings, iteration, first, n);
        for (a, b) in counts.iter_mut().zip(&t.counts) {
            *a += u64::from(*b);
        }
        *done += u64::from(n);
    }
}

/// Intensity per steradian of raw counts.
fn raw_intensity(layout: CubeMapLayout, counts: &[u64]) -> Vec<f64> {
    counts
        .iter()
        .enumerate()
        .map(|(t, &c)| c as f64 / layout.texel_solid_angle(t))
        .collect()
}

/// RMSE of two images each scaled by its own mean (the paper's measure).
pub fn rmse_mean_scaled(a: &[f64], b: &[f64]) -> f64 {
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len() as f64;
    let (ma, mb) = (mean(a), mean(b));
    if ma <= 0.0 || mb <= 0.0 {
        return f64::INFINITY;
    }
    (a.iter()
        .zip(b)
        .map(|(x, y)| (x / ma - y / mb).powi(2))
        .sum::<f64>()
        / a.len() as f64)
        .sqrt()
}

/// The part of a mean-scaled MSE against the reference that is the
/// reference's own Poisson noise: mean over texels of var(r_t) / mean(r)²
/// with var(r_t) = c_t / Ω_t² (an estimate independent of the reference
/// sees it added to its true error).
pub fn reference_noise_mse(layout: CubeMapLayout, counts: &[u64]) -> f64 {
    let intensity = raw_intensity(layout, counts);
    let mean = intensity.iter().sum::<f64>() / intensity.len() as f64;
    if mean <= 0.0 {
        return 0.0;
    }
    counts
        .iter()
        .enumerate()
        .map(|(t, &c)| c as f64 / layout.texel_solid_angle(t).powi(2))
        .sum::<f64>()
        / counts.len() as f64
        / (mean * mean)
}

/// The RMSE with the reference's noise taken out (0 when the measured
/// error is all reference noise).
fn corrected(rmse: f64, reference_noise_mse: f64) -> f64 {
    (rmse * rmse - reference_noise_mse).max(0.0).sqrt()
}

pub fn filter_bench(args: &FilterBenchArgs) -> Result<()> {
    let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires");
    let scenes = if args.scenes.is_empty() {
        vec![
            assets.join("opal_bell.toml"),
            assets.join("faceted_downlight.toml"),
        ]
    } else {
        args.scenes.clone()
    };
    std::fs::create_dir_all(&args.out)?;
    let layout = CubeMapLayout::new(args.resolution);
    let mut csv = String::from(
        "scene,resolution,photons,method,rule,rmse,rmse_reference_noise_removed,filter_ms,estimated_rmse\n",
    );
    let mut summary = String::new();
    for path in &scenes {
        let name = path
            .file_stem()
            .map_or(String::new(), |s| s.to_string_lossy().into_owned());
        let (_, _, prepared) = super::bake::load_luminaire(path)?;
        let start = Instant::now();
        let reference_settings = TraceSettings {
            seed: 1_000_003,
            max_bounces: 64,
            layout,
        };
        let mut reference = vec![0u64; layout.texel_count()];
        let mut done = 0;
        trace_to(
            &prepared,
            &reference_settings,
            &mut reference,
            &mut done,
            args.reference_photons,
        );
        let noise = reference_noise_mse(layout, &reference);
        let reference = raw_intensity(layout, &reference);
        eprintln!(
            "{name}: reference of {} photons in {:.0} s",
            args.reference_photons,
            start.elapsed().as_secs_f64()
        );
        let settings = TraceSettings {
            seed: 1,
            max_bounces: 64,
            layout,
        };
        let mut counts = vec![0u64; layout.texel_count()];
        let mut done = 0;
        let mut series: Vec<Series> = std::iter::once("raw".to_owned())
            .chain(FIXED.iter().map(|t| format!("T = {t}")))
            .chain(std::iter::once("automatic".to_owned()))
            .map(|name| Series {
                name,
                points: Vec::new(),
            })
            .collect();
        // The same errors with the reference's own noise removed.
        let mut corrected_points: Vec<Vec<f64>> = vec![Vec::new(); series.len()];
        // The rule the automatic mode chose at each photon count, and the
        // error it estimated for it.
        let mut chosen = Vec::new();
        let mut estimated = Vec::new();
        let mut n = 100_000u64;
        while n <= args.max_photons {
            trace_to(&prepared, &settings, &mut counts, &mut done, n);
            let raw = rmse_mean_scaled(&raw_intensity(layout, &counts), &reference);
            series[0].points.push((n as f64, raw));
            corrected_points[0].push(corrected(raw, noise));
            let _ = writeln!(
                csv,
                "{name},{},{n},raw,,{raw:.6},{:.6},,",
                args.resolution,
                corrected(raw, noise)
            );
            let thresholds = FIXED
                .iter()
                .map(|&t| Threshold::Fixed(t))
                .chain(std::iter::once(Threshold::Automatic));
            for (k, threshold) in thresholds.enumerate() {
                let t0 = Instant::now();
                let f = filter(
                    layout,
                    &counts,
                    &FilterSettings {
                        threshold,
                        ..Default::default()
                    },
                );
                let ms = t0.elapsed().as_secs_f64() * 1e3;
                let e = rmse_mean_scaled(&f.photons_per_sr, &reference);
                series[k + 1].points.push((n as f64, e));
                corrected_points[k + 1].push(corrected(e, noise));
                let method = if threshold == Threshold::Automatic {
                    "automatic"
                } else {
                    "fixed"
                };
                // The rule's description holds commas: quoted.
                let _ = writeln!(
                    csv,
                    "{name},{},{n},{method},\"{}\",{e:.6},{:.6},{ms:.1},{}",
                    args.resolution,
                    f.settings,
                    corrected(e, noise),
                    f.automatic
                        .map_or(String::new(), |a| format!("{:.6}", a.estimated_rmse))
                );
                if let Some(a) = f.automatic {
                    chosen.push(f.settings);
                    estimated.push(a.estimated_rmse);
                }
            }
            eprintln!(
                "{name}: {n} photons done ({:.0} s)",
                start.elapsed().as_secs_f64()
            );
            n *= 10;
        }
        // Targets: filtered(N) ≤ raw(10 N); automatic within 10 % of the
        // best fixed threshold. Both as measured and with the reference's
        // noise (√MSE {noise}) taken out.
        let _ = writeln!(
            summary,
            "{name} {}²: reference noise alone gives RMSE {:.4}",
            args.resolution,
            noise.sqrt()
        );
        for (label, values) in [
            (
                "measured",
                series
                    .iter()
                    .map(|s| s.points.iter().map(|p| p.1).collect::<Vec<_>>())
                    .collect::<Vec<_>>(),
            ),
            ("reference noise removed", corrected_points.clone()),
        ] {
            let raw = &values[0];
            for i in 0..raw.len() {
                let best_fixed = (1..=FIXED.len())
                    .map(|k| values[k][i])
                    .fold(f64::INFINITY, f64::min);
                let auto = values[FIXED.len() + 1][i];
                let raw_10n = raw.get(i + 1).copied();
                let _ = writeln!(
                    summary,
                    "{name} {}² N = {:.0e} ({label}): raw {:.4}, raw(10N) {}, best fixed {:.4}, automatic {:.4} ({:+.1} % vs best, {}; estimated {}) {}",
                    args.resolution,
                    series[0].points[i].0,
                    raw[i],
                    raw_10n.map_or("—".to_owned(), |v| format!("{v:.4}")),
                    best_fixed,
                    auto,
                    100.0 * (auto / best_fixed - 1.0),
                    chosen.get(i).map_or(String::new(), ToString::to_string),
                    estimated
                        .get(i)
                        .map_or(String::new(), |e| format!("{e:.4}")),
                    match raw_10n {
                        Some(r) if auto <= r => "filtered(N) ≤ raw(10N): yes",
                        Some(_) => "filtered(N) ≤ raw(10N): NO",
                        None => "",
                    }
                );
            }
        }
        let png = log_log_chart_png(
            &series,
            &format!(
                "{name} {}x{} per face: RMSE vs reference",
                args.resolution, args.resolution
            ),
            "photons",
            "RMSE (mean-scaled)",
            900,
            560,
        )?;
        write_atomically(
            &args.out.join(format!("{name}_{}.png", args.resolution)),
            &png,
        )?;
    }
    // Filter time per map size and backend (the GPU time includes the
    // upload of the counts and the read-back of the result): one pass with
    // a given rule (what a preview pays per frame once the rule is
    // chosen), and the automatic mode (cross-validation of every candidate
    // on two halves, then the pass).
    let gpu = lucerna_gpu::open().ok();
    let one_pass = FilterSettings {
        threshold: lucerna_filter::AUTOMATIC_FALLBACK,
        ..Default::default()
    };
    let automatic = FilterSettings::default();
    for n in [256u32, 1024] {
        let layout = CubeMapLayout::new(n);
        let counts: Vec<u64> = (0..layout.texel_count() as u64)
            .map(|t| (t * 2_654_435_761) % 97)
            .collect();
        // Mean milliseconds of `runs` calls (the results are dropped).
        let time =
            |f: &mut dyn FnMut() -> Result<lucerna_filter::Filtered>, runs: u32| -> Result<f64> {
                let t0 = Instant::now();
                for _ in 0..runs {
                    f()?;
                }
                Ok(t0.elapsed().as_secs_f64() * 1e3 / f64::from(runs))
            };
        let cpu_pass = time(&mut || Ok(filter(layout, &counts, &one_pass)), 1)?;
        let cpu_auto = time(&mut || Ok(filter(layout, &counts, &automatic)), 1)?;
        let _ = writeln!(
            summary,
            "filter time 6×{n}²: CPU reference ({} threads) {cpu_pass:.0} ms per pass, {cpu_auto:.0} ms automatic",
            rayon::current_num_threads()
        );
        if let Some(ctx) = &gpu {
            let g = lucerna_filter::gpu::GpuFilter::new(ctx.clone(), layout)?;
            g.filter(&counts, &one_pass)?;
            let gpu_pass = time(&mut || Ok(g.filter(&counts, &one_pass)?), 3)?;
            let gpu_auto = time(&mut || Ok(g.filter(&counts, &automatic)?), 1)?;
            let _ = writeln!(
                summary,
                "filter time 6×{n}²: WGSL on {} {gpu_pass:.0} ms per pass, {gpu_auto:.0} ms automatic",
                ctx.describe()
            );
        }
    }
    let csv_path = args
        .out
        .join(format!("filter_rmse_{}.csv", args.resolution));
    write_atomically(&csv_path, csv.as_bytes())
        .with_context(|| format!("cannot write {}", csv_path.display()))?;
    print!("{summary}");
    println!(
        "wrote {} and the PNG plots in {}",
        csv_path.display(),
        args.out.display()
    );
    Ok(())
}
