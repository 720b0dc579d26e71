//! `lucerna near-field-eval`: the evaluation of Luksch et al. 2020,
//! section 6 (Figure 10), on our profiles: NRMS of each shading method
//! against Monte Carlo integration, per profile and height, as a table,
//! a CSV, and a picture per profile.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::{Context, Result};
use lucerna_room::ProfileGrid;
use lucerna_room::evaluation::{HEIGHTS, NearFieldSettings, ORIENTATIONS, nrms, stitched_images};
use lucerna_scene::write_atomically;

#[derive(Debug, clap::Args)]
pub struct NearFieldArgs {
    /// IES/LDT files (default: assets/profiles/examples and samples).
    pub profiles: Vec<PathBuf>,
    /// Ground samples per image side.
    #[arg(long, default_value_t = 48)]
    pub pixels: usize,
    /// Reference samples per technique (points on the opening, directions
    /// from the profile) per ground sample.
    #[arg(long, default_value_t = 4096)]
    pub samples: usize,
    /// Output directory for the CSV and pictures.
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
    if !(4..=512).contains(&args.pixels) || !(16..=1_000_000).contains(&args.samples) {
        anyhow::bail!("--pixels must be 4..512 and --samples 16..1000000");
    }
    let profiles = if args.profiles.is_empty() {
        default_profiles()?
    } else {
        args.profiles.clone()
    };
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    let settings = NearFieldSettings {
        pixels: args.pixels,
        reference_samples: args.samples,
    };
    // The csv crate quotes a profile name with a comma or a quote in it.
    let mut csv = csv::Writer::from_writer(Vec::new());
    csv.write_record([
        "profile",
        "height",
        "nrms_prefiltered",
        "nrms_exact_cosine",
        "nrms_paper_eq10",
        "nrms_point",
    ])?;
    println!(
        "NRMS against Monte Carlo ({} samples per point), {}² ground samples × 5 orientations per height",
        args.samples, args.pixels
    );
    println!(
        "{:44} {:>6} {:>11} {:>11} {:>11} {:>11}",
        "profile", "h", "prefiltered", "exact-cos", "eq. 10", "point"
    );
    for path in &profiles {
        let phot = super::info::read(path)?;
        let grid = Arc::new(ProfileGrid::from_table(&phot.table));
        let name = stem(path);
        for &h in &HEIGHTS {
            let images = stitched_images(&grid, h, settings);
            let values = [
                nrms(&images.prefiltered, &images.reference),
                nrms(&images.exact_cosine, &images.reference),
                nrms(&images.paper, &images.reference),
                nrms(&images.point, &images.reference),
            ];
            println!(
                "{name:44} {h:>6.1} {:>11.4} {:>11.4} {:>11.4} {:>11.4}",
                values[0], values[1], values[2], values[3]
            );
            let mut record = vec![name.clone(), h.to_string()];
            record.extend(values.iter().map(|v| format!("{v:.6}")));
            csv.write_record(&record)?;
            if h == HEIGHTS[0] {
                let png = lucerna_pictures::image_rows_png(
                    &[
                        ("Monte Carlo", &images.reference),
                        ("cubature", &images.prefiltered),
                        ("paper eq. 10", &images.paper),
                        ("point light", &images.point),
                    ],
                    ORIENTATIONS.len(),
                    args.pixels,
                    96,
                    &format!(
                        "{name}: ground illuminance, 1 x 1 opening at h = {h}, tilt π/2 … π (log scale, 3 decades)"
                    ),
                )?;
                let file = args.out.join(format!("{name}_h{h}.png"));
                write_atomically(&file, &png)
                    .with_context(|| format!("cannot write {}", file.display()))?;
            }
        }
    }
    let file = args.out.join("near_field_nrms.csv");
    let csv = csv
        .into_inner()
        .context("cannot write the NRMS table as CSV")?;
    write_atomically(&file, &csv).with_context(|| format!("cannot write {}", file.display()))?;
    eprintln!("wrote {} and a picture per profile", file.display());
    Ok(())
}

fn stem(path: &Path) -> String {
    path.file_stem().map_or(String::from("profile"), |s| {
        s.to_string_lossy().into_owned()
    })
}
