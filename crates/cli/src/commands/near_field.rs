//! `lucerna near-field-eval`: the evaluation of Luksch et al. 2020,
//! section 6 (Figure 10), on our profiles: each shading rule against the
//! exact quadrature (or Monte Carlo), per profile and height, as a table
//! (RMS difference over the reference's mean and over its RMS, worst point
//! within 1 m of the opening), a CSV, per-point CSVs, and pictures of the
//! illuminance and of the error per profile and height.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::{Context, Result};
use lucerna_room::ProfileGrid;
use lucerna_room::evaluation::{
    HEIGHTS, NearFieldSettings, ORIENTATIONS, Reference, ground_points, mean_normalised_rms, nrms,
    relative_errors, stitched_images,
};
use lucerna_scene::write_atomically;

#[derive(Debug, clap::Args)]
pub struct NearFieldArgs {
    /// IES/LDT files (default: assets/profiles/examples and samples).
    pub profiles: Vec<PathBuf>,
    /// Ground samples per image side, corner to corner of the 5 × 5
    /// region (101: the protocol's 5 cm spacing).
    #[arg(long, default_value_t = 48)]
    pub pixels: usize,
    /// Compare with Monte Carlo (MIS, this many samples per technique and
    /// point) instead of the exact quadrature.
    #[arg(long)]
    pub monte_carlo: Option<usize>,
    /// Output directory for the CSVs and pictures.
    #[arg(long)]
    pub out: PathBuf,
}

fn default_profiles() -> Result<Vec<PathBuf>> {
    let mut out = Vec::new();
    for dir in ["assets/profiles/examples", "assets/profiles/samples"] {
        let mut files: Vec<PathBuf> = std::fs::read_dir(dir)
            .with_context(|| {
                format!("cannot list {dir} (run from the repository root or name the files)")
            })?
            .filter_map(|e| e.ok().map(|e| e.path()))
            .filter(|p| matches!(p.extension().and_then(|e| e.to_str()), Some("ies" | "ldt")))
            .collect();
        files.sort();
        out.extend(files);
    }
    Ok(out)
}

pub fn near_field_eval(args: &NearFieldArgs) -> Result<()> {
    if !(4..=512).contains(&args.pixels) {
        anyhow::bail!("--pixels must be 4..512");
    }
    if let Some(n) = args.monte_carlo
        && !(16..=1_000_000).contains(&n)
    {
        anyhow::bail!("--monte-carlo must be 16..1000000 samples");
    }
    let profiles = if args.profiles.is_empty() {
        default_profiles()?
    } else {
        args.profiles.clone()
    };
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    let reference = match args.monte_carlo {
        Some(samples) => Reference::MonteCarlo { samples },
        None => Reference::Exact { relative: 1e-7 },
    };
    let settings = NearFieldSettings {
        pixels: args.pixels,
        reference,
    };
    let truth = match reference {
        Reference::Exact { .. } => "the exact quadrature".to_string(),
        Reference::MonteCarlo { samples } => format!("Monte Carlo ({samples} samples per point)"),
    };
    // The csv crate quotes a profile name with a comma or a quote in it.
    let mut csv = csv::Writer::from_writer(Vec::new());
    csv.write_record([
        "profile",
        "height",
        "polar_rms_over_mean",
        "polar_rms_over_rms",
        "polar_worst_within_1m",
        "fan_rms_over_mean",
        "fan_rms_over_rms",
        "paper_eq10_rms_over_mean",
        "point_rms_over_mean",
    ])?;
    println!(
        "against {truth}, {}² ground points × 5 tilts per height; RMS difference / mean reference (/ RMS reference), worst point within 1 m",
        args.pixels
    );
    println!(
        "{:44} {:>4} {:>22} {:>8} {:>18} {:>8} {:>8}",
        "profile", "h", "polar", "worst", "fan (prefiltered)", "eq. 10", "point"
    );
    let points = ground_points(args.pixels);
    for path in &profiles {
        let phot = super::input::read_photometry(path)?;
        let grid = Arc::new(ProfileGrid::from_table(&phot.table));
        let name = stem(path);
        for &h in &HEIGHTS {
            let images = stitched_images(&grid, h, settings);
            let r = &images.reference;
            let errors = relative_errors(&images.polar, r);
            let worst = errors
                .iter()
                .zip(&images.distance_m)
                .filter(|(_, d)| **d <= 1.0)
                .map(|(e, _)| *e)
                .fold(0.0, f64::max);
            let values = [
                mean_normalised_rms(&images.polar, r),
                nrms(&images.polar, r),
                worst,
                mean_normalised_rms(&images.prefiltered, r),
                nrms(&images.prefiltered, r),
                mean_normalised_rms(&images.paper, r),
                mean_normalised_rms(&images.point, r),
            ];
            println!(
                "{name:44} {h:>4.1} {:>11.4} ({:>8.4}) {:>8.4} {:>8.4} ({:>7.4}) {:>8.4} {:>8.4}",
                values[0], values[1], values[2], values[3], values[4], values[5], values[6]
            );
            let mut record = vec![name.clone(), h.to_string()];
            record.extend(values.iter().map(|v| format!("{v:.6}")));
            csv.write_record(&record)?;
            write_point_csv(args, &name, h, &points, &images)?;
            let fan_errors = relative_errors(&images.prefiltered, r);
            let pictures = [
                (
                    format!("{name}_h{h}.png"),
                    lucerna_pictures::image_rows_png(
                        &[
                            ("exact", r),
                            ("polar (default)", &images.polar),
                            ("fan cubature", &images.prefiltered),
                            ("point light", &images.point),
                        ],
                        ORIENTATIONS.len(),
                        args.pixels,
                        96,
                        &format!(
                            "{name}: ground illuminance, 1 x 1 opening at h = {h}, tilt π/2 … π (log scale, 3 decades)"
                        ),
                    )?,
                ),
                (
                    format!("{name}_h{h}_error.png"),
                    lucerna_pictures::image_rows_png(
                        &[("fan |error|", &fan_errors), ("polar |error|", &errors)],
                        ORIENTATIONS.len(),
                        args.pixels,
                        96,
                        &format!(
                            "{name}: |E − E_exact| / E_exact (floor 1 % of peak) at h = {h}, tilt π/2 … π (log, 3 decades below the fan's worst)"
                        ),
                    )?,
                ),
            ];
            for (file, png) in pictures {
                let file = args.out.join(file);
                write_atomically(&file, &png)
                    .with_context(|| format!("cannot write {}", file.display()))?;
            }
        }
    }
    let file = args.out.join("near_field_nrms.csv");
    let csv = csv.into_inner().context("cannot write the table as CSV")?;
    write_atomically(&file, &csv).with_context(|| format!("cannot write {}", file.display()))?;
    eprintln!(
        "wrote {}, per-point CSVs and pictures per profile and height",
        file.display()
    );
    Ok(())
}

/// Every point of one profile and height: tilt, position, distance to the
/// opening, the reference and each rule.
fn write_point_csv(
    args: &NearFieldArgs,
    name: &str,
    h: f64,
    points: &[glam::DVec3],
    images: &lucerna_room::evaluation::StitchedImages,
) -> Result<()> {
    let mut csv = csv::Writer::from_writer(Vec::new());
    csv.write_record([
        "tilt_pi",
        "x_m",
        "y_m",
        "distance_m",
        "exact_lx",
        "polar_lx",
        "fan_lx",
        "point_lx",
        "polar_relative_error",
    ])?;
    let errors = relative_errors(&images.polar, &images.reference);
    for (k, &tilt) in ORIENTATIONS.iter().enumerate() {
        for (i, p) in points.iter().enumerate() {
            let at = k * points.len() + i;
            csv.write_record([
                tilt.to_string(),
                format!("{:.4}", p.x),
                format!("{:.4}", p.y),
                format!("{:.4}", images.distance_m[at]),
                format!("{:.9e}", images.reference[at]),
                format!("{:.9e}", images.polar[at]),
                format!("{:.9e}", images.prefiltered[at]),
                format!("{:.9e}", images.point[at]),
                format!("{:.6e}", errors[at]),
            ])?;
        }
    }
    let file = args.out.join(format!("{name}_h{h}_points.csv"));
    let bytes = csv.into_inner().context("cannot write the points as CSV")?;
    write_atomically(&file, &bytes).with_context(|| format!("cannot write {}", file.display()))?;
    Ok(())
}

fn stem(path: &Path) -> String {
    path.file_stem().map_or(String::from("profile"), |s| {
        s.to_string_lossy().into_owned()
    })
}
