//! `lucerna filter-bench`: the Litemaker paper's Figure 8a protocol on our
//! scenes: RMSE against a high-photon reference (each image scaled by its
//! mean) of the raw map and of the filter with fixed and automatic
//! thresholds, over photon counts; CSV, PNG plot, filter timings.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, Result};
use lucerna_filter::evaluation::{
    mean_scaled_rmse, raw_photons_per_sr, reference_noise_mse, rmse_without_reference_noise,
};
use lucerna_filter::{FilterSettings, Threshold, filter, filter_symmetric};
use lucerna_photometry::{CubeMapLayout, TexelSymmetry};
use lucerna_pictures::chart::{Series, log_log_chart_png};
use lucerna_scene::write_atomically;
use lucerna_simulation::Luminaire;
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

/// One way of turning counts into an intensity map.
struct Method {
    /// Series name in the CSV and plot.
    label: String,
    /// Filter rule, or none for the raw map.
    threshold: Option<Threshold>,
    /// Pool the photons over the luminaire's symmetry.
    symmetric: bool,
    /// Drawn in the plot (the CSV has every method).
    plotted: bool,
}

/// Errors of one method at each photon count.
#[derive(Default)]
struct Errors {
    measured: Vec<f64>,
    corrected: Vec<f64>,
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
        "scene,resolution,photons,method,symmetry,rule,rmse,rmse_reference_noise_removed,filter_ms,estimated_rmse\n",
    );
    let mut summary = String::new();
    for path in &scenes {
        let name = path
            .file_stem()
            .map_or(String::new(), |s| s.to_string_lossy().into_owned());
        let luminaire = Luminaire::load(path)?;
        let found = luminaire.find_symmetry().clone();
        let prepared = luminaire.prepared;
        let symmetry = TexelSymmetry::new(layout, found.symmetry);
        let none = TexelSymmetry::none(layout);
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
        // The reference is pooled over the luminaire's symmetry too: its
        // noise drops by √order, every comparison gets sharper.
        let reference = symmetry.pool(&reference);
        let noise = reference_noise_mse(layout, &reference, &symmetry);
        let reference = raw_photons_per_sr(layout, &reference);
        eprintln!(
            "{name}: symmetry {}; reference of {} photons in {:.0} s",
            found.symmetry,
            args.reference_photons,
            start.elapsed().as_secs_f64()
        );
        let settings = TraceSettings {
            seed: 1,
            max_bounces: 64,
            layout,
        };
        let mut methods = Vec::new();
        for symmetric in [false, true] {
            let tag = if symmetric { ", symmetry" } else { "" };
            methods.push(Method {
                label: format!("raw{tag}"),
                threshold: None,
                symmetric,
                plotted: true,
            });
            for t in FIXED {
                methods.push(Method {
                    label: format!("T = {t}{tag}"),
                    threshold: Some(Threshold::Fixed(t)),
                    symmetric,
                    plotted: t == 100.0,
                });
            }
            methods.push(Method {
                label: format!("automatic{tag}"),
                threshold: Some(Threshold::Automatic),
                symmetric,
                plotted: true,
            });
        }
        let mut errors: Vec<Errors> = methods.iter().map(|_| Errors::default()).collect();
        // The rules the automatic modes chose at each photon count, and the
        // errors they estimated.
        let mut chosen: Vec<Vec<String>> = vec![Vec::new(); methods.len()];
        let mut counts = vec![0u64; layout.texel_count()];
        let mut done = 0;
        let mut photon_counts = Vec::new();
        let mut n = 100_000u64;
        while n <= args.max_photons {
            trace_to(&prepared, &settings, &mut counts, &mut done, n);
            photon_counts.push(n);
            for (k, method) in methods.iter().enumerate() {
                let sym = if method.symmetric { &symmetry } else { &none };
                let t0 = Instant::now();
                let (intensity, rule, estimate) = match method.threshold {
                    None => {
                        let pooled = sym.pool(&counts);
                        let order = sym.order() as f64;
                        let mut v = raw_photons_per_sr(layout, &pooled);
                        v.iter_mut().for_each(|x| *x /= order);
                        (v, String::new(), None)
                    }
                    Some(threshold) => {
                        let f = filter_symmetric(
                            &counts,
                            &FilterSettings {
                                threshold,
                                ..Default::default()
                            },
                            sym,
                        );
                        let estimate = f.automatic.map(|a| a.estimated_rmse);
                        (f.photons_per_sr, f.settings.to_string(), estimate)
                    }
                };
                let ms = t0.elapsed().as_secs_f64() * 1e3;
                let e = mean_scaled_rmse(&intensity, &reference);
                errors[k].measured.push(e);
                errors[k]
                    .corrected
                    .push(rmse_without_reference_noise(e, noise));
                if let Some(estimate) = estimate {
                    chosen[k].push(format!("{rule}; estimated {estimate:.4}"));
                }
                // The rule's description holds commas: quoted.
                let _ = writeln!(
                    csv,
                    "{name},{},{n},{},{},\"{rule}\",{e:.6},{:.6},{},{}",
                    args.resolution,
                    match method.threshold {
                        None => "raw",
                        Some(Threshold::Automatic) => "automatic",
                        Some(_) => "fixed",
                    },
                    if method.symmetric {
                        found.symmetry.order()
                    } else {
                        1
                    },
                    rmse_without_reference_noise(e, noise),
                    if method.threshold.is_some() {
                        format!("{ms:.1}")
                    } else {
                        String::new()
                    },
                    estimate.map_or(String::new(), |e| format!("{e:.6}"))
                );
            }
            eprintln!(
                "{name}: {n} photons done ({:.0} s)",
                start.elapsed().as_secs_f64()
            );
            n *= 10;
        }
        // Targets: filtered(N) ≤ raw(10 N); automatic within 10 % of the
        // best fixed threshold. Both as measured and with the reference's
        // noise taken out; without and with the symmetry.
        let _ = writeln!(
            summary,
            "{name} {}²: symmetry {} ({}); reference of {} photons pooled, its noise alone gives RMSE {:.4}",
            args.resolution,
            found.symmetry,
            found
                .limited_by
                .as_deref()
                .unwrap_or("found from the geometry"),
            args.reference_photons,
            noise.sqrt()
        );
        let index = |label: &str| methods.iter().position(|m| m.label == label);
        for corrected_errors in [false, true] {
            let label = if corrected_errors {
                "reference noise removed"
            } else {
                "measured"
            };
            let of = |k: usize| {
                if corrected_errors {
                    &errors[k].corrected
                } else {
                    &errors[k].measured
                }
            };
            for symmetric in [false, true] {
                if symmetric && found.symmetry.order() == 1 {
                    continue;
                }
                let tag = if symmetric { ", symmetry" } else { "" };
                let (Some(raw_k), Some(sym_raw_k), Some(auto_k)) = (
                    index("raw"),
                    index(&format!("raw{tag}")),
                    index(&format!("automatic{tag}")),
                ) else {
                    continue;
                };
                for (i, &n) in photon_counts.iter().enumerate() {
                    let best_fixed = methods
                        .iter()
                        .enumerate()
                        .filter(|(_, m)| {
                            m.symmetric == symmetric
                                && matches!(m.threshold, Some(Threshold::Fixed(_)))
                        })
                        .map(|(k, _)| of(k)[i])
                        .fold(f64::INFINITY, f64::min);
                    let auto = of(auto_k)[i];
                    let raw_10n = of(raw_k).get(i + 1).copied();
                    let _ = writeln!(
                        summary,
                        "{name} {}² N = {n:.0e} ({label}{tag}): raw {:.4}, raw(10N) {}, best fixed {best_fixed:.4}, automatic {auto:.4} ({:+.1} % vs best; {}) {}",
                        args.resolution,
                        of(sym_raw_k)[i],
                        raw_10n.map_or("—".to_owned(), |v| format!("{v:.4}")),
                        100.0 * (auto / best_fixed - 1.0),
                        chosen[auto_k].get(i).map_or("", String::as_str),
                        match raw_10n {
                            Some(r) if auto <= r => "filtered(N) ≤ raw(10N): yes",
                            Some(_) => "filtered(N) ≤ raw(10N): NO",
                            None => "",
                        }
                    );
                }
            }
        }
        let series: Vec<Series> = methods
            .iter()
            .zip(&errors)
            .filter(|(m, _)| m.plotted && (!m.symmetric || found.symmetry.order() > 1))
            .map(|(m, e)| Series {
                name: m.label.clone(),
                points: photon_counts
                    .iter()
                    .zip(&e.measured)
                    .map(|(&n, &e)| (n as f64, e))
                    .collect(),
            })
            .collect();
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
