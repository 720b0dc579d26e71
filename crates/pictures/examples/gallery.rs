//! Every picture this crate draws, from a sample profile and made-up data,
//! written into one folder so a person can look at the labels:
//! `cargo run -p lucerna-pictures --example gallery -- target/gallery`.

use std::error::Error;
use std::path::PathBuf;

use lucerna_photometry::{CubeMapLayout, read_photometry, table};
use lucerna_pictures::chart::{Series, log_log_chart_png};

fn main() -> Result<(), Box<dyn Error>> {
    let out = PathBuf::from(
        std::env::args()
            .nth(1)
            .unwrap_or_else(|| "target/gallery".to_owned()),
    );
    std::fs::create_dir_all(&out)?;
    let write = |name: &str, png: Vec<u8>| -> Result<(), Box<dyn Error>> {
        let path = out.join(name);
        std::fs::write(&path, png)?;
        println!("wrote {}", path.display());
        Ok(())
    };
    let assets = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../assets/profiles");

    // A real asymmetric profile for the polar diagram.
    let sample = assets.join("samples/ledvance_fl_max_900w_asym_isym0.ldt");
    let phot = read_photometry(&std::fs::read(&sample)?)?;
    let per_klm = 1000.0 / phot.table.flux_lm();
    write(
        "polar.png",
        lucerna_pictures::polar_png(
            &phot.table,
            per_klm,
            640,
            "ledvance_fl_max_900w_asym - 20000000 photons",
        )?,
    )?;
    // As small as a test draws it.
    write(
        "polar_300.png",
        lucerna_pictures::polar_png(&phot.table, per_klm, 300, "ledvance_fl_max_900w_asym")?,
    )?;
    let spot = assets.join("examples/parabolic_spot.ies");
    let spot = read_photometry(&std::fs::read(&spot)?)?;
    write(
        "polar_spot.png",
        lucerna_pictures::polar_png(
            &spot.table,
            1000.0 / spot.table.flux_lm(),
            640,
            "parabolic_spot - 5000000 photons",
        )?,
    )?;

    // The cube map of that profile, texel by texel.
    let layout = CubeMapLayout::new(64);
    let candela: Vec<f64> = (0..layout.texel_count())
        .map(|t| {
            let (c, gamma) = table::angles(layout.texel_centre_direction(t));
            phot.table.intensity(c.to_degrees(), gamma.to_degrees())
        })
        .collect();
    write(
        "cube.png",
        lucerna_pictures::cube_map_png(
            layout,
            &candela,
            200,
            "ledvance_fl_max_900w_asym - 20000000 photons",
        )?,
    )?;

    // RMSE against photons as filter-bench plots it.
    let labels = [
        "raw",
        "T = 100",
        "T = 250",
        "automatic",
        "raw, symmetry",
        "automatic, symmetry",
    ];
    let series: Vec<Series> = labels
        .iter()
        .enumerate()
        .map(|(k, name)| Series {
            name: (*name).to_owned(),
            points: (0..6)
                .map(|i| {
                    let n = 1e5 * 4f64.powi(i);
                    (n, (0.8 / (k as f64 + 1.0)) * (1e5 / n).sqrt())
                })
                .collect(),
        })
        .collect();
    write(
        "chart.png",
        log_log_chart_png(
            &series,
            "parabolic_spot 128x128 per face: RMSE vs reference",
            "photons",
            "RMSE (mean-scaled)",
            900,
            560,
        )?,
    )?;

    // The room pictures with a made-up lux field.
    let (w, h) = (640u32, 360u32);
    let lux: Vec<f32> = (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f32 / w as f32, (i / w) as f32 / h as f32);
            if (x - 0.5).abs() < 0.04 && y < 0.03 {
                -1.0
            } else {
                800.0 * (-((x - 0.5).powi(2) + (y - 0.6).powi(2)) * 6.0).exp()
            }
        })
        .collect();
    let caption = "office: Eavg 512 lx, Emin 301 lx, U0 0.59 on the work plane (cubature)";
    write(
        "room_lux.png",
        lucerna_pictures::illuminance_png(w, h, &lux, caption)?,
    )?;
    let rgb: Vec<u8> = lux
        .iter()
        .flat_map(|&v| {
            let g = (v.max(0.0) / 800.0 * 230.0 + 20.0) as u8;
            [g, g, g.saturating_sub(10)]
        })
        .collect();
    write(
        "room_view.png",
        lucerna_pictures::room_view_png(w, h, &rgb, caption)?,
    )?;
    // The end-to-end test's 160x90 view: the caption must be cut short.
    let small: Vec<f32> = (0..160 * 90).map(|i| (i % 160) as f32 * 5.0).collect();
    write(
        "room_lux_small.png",
        lucerna_pictures::illuminance_png(160, 90, &small, caption)?,
    )?;
    let xs: Vec<f64> = (0..20).map(|i| 0.375 + 0.25 * f64::from(i)).collect();
    let ys: Vec<f64> = (0..15).map(|j| 0.5 + 0.2 * f64::from(j)).collect();
    let grid: Vec<f64> = ys
        .iter()
        .flat_map(|&y| {
            xs.iter()
                .map(move |&x| 600.0 * (-((x - 2.75).powi(2) + (y - 2.0).powi(2)) / 4.0).exp())
        })
        .collect();
    write(
        "work_plane.png",
        lucerna_pictures::work_plane_png(
            &xs,
            &ys,
            &grid,
            (5.5, 4.0),
            &[(1.5, 2.0), (4.0, 2.0)],
            "office: work plane 0.80 m, Emin 120 lx, Eavg 350 lx, Emax 600 lx, U0 0.34",
        )?,
    )?;
    let side = 16usize;
    let image: Vec<f64> = (0..5 * side * side)
        .map(|i| {
            let (x, y) = ((i % side) as f64, ((i / side) % side) as f64);
            100.0 / (1.0 + (x - 8.0).powi(2) + (y - 8.0).powi(2))
        })
        .collect();
    write(
        "image_rows.png",
        lucerna_pictures::image_rows_png(
            &[
                ("Monte Carlo", &image),
                ("cubature", &image),
                ("paper eq. 10", &image),
                ("point light", &image),
            ],
            5,
            side,
            96,
            "rab_indoor3_2002_full360: ground illuminance, 1 x 1 opening at h = 0.1, tilt pi/2 .. pi (log scale, 3 decades)",
        )?,
    )?;
    Ok(())
}
