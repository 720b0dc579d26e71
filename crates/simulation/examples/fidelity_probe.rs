use lucerna_photometry::CubeMapLayout;
use lucerna_photometry::fidelity::{BeamFigures, FidelityTargets, TableFidelity};
use lucerna_photometry::resample::{AUTOMATIC_GAMMA_STEPS_DEG, GammaGrid, TableResampler};
use lucerna_photometry::table::{angles, uniform_c_planes};
use std::sync::Arc;

fn report(layout: CubeMapLayout, candela: &[f64]) {
    let t0 = std::time::Instant::now();
    let map = BeamFigures::of_map(layout, candela);
    println!("map figures {:?} in {:?}", map, t0.elapsed());
    let mut r = TableResampler::new();
    for step in [5.0].iter().chain(AUTOMATIC_GAMMA_STEPS_DEG.iter()) {
        let t0 = std::time::Instant::now();
        let table = r
            .table(
                layout,
                candela,
                &uniform_c_planes(5.0),
                GammaGrid::Step(*step, FidelityTargets::default()),
            )
            .table;
        let f = TableFidelity::new(*step, false, map, &table, FidelityTargets::default());
        println!("step {step}: {:?} | {}", t0.elapsed(), f.summary());
        println!(
            "   table beam {:?} field {:?} cones {:?}",
            f.table.beam_angle_deg, f.table.field_angle_deg, f.table.cone_flux_lm
        );
        for s in f.shortfalls() {
            println!("   - {s}");
        }
    }
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args[1] == "constant" {
        constant_check();
        return;
    }
    if args[1] == "synthetic" {
        let res: u32 = args[2].parse().unwrap();
        let fwhm: f64 = args[3].parse().unwrap();
        let layout = CubeMapLayout::new(res);
        let sub = 8;
        let candela: Vec<f64> = (0..layout.texel_count())
            .map(|t| {
                let (face, a0, b0, a1, b1) = layout.texel_bounds(t);
                let mut s = 0.0;
                let mut w = 0.0;
                for i in 0..sub {
                    for j in 0..sub {
                        let a = a0 + (a1 - a0) * (i as f64 + 0.5) / sub as f64;
                        let b = b0 + (b1 - b0) * (j as f64 + 0.5) / sub as f64;
                        let d = face.direction(a, b);
                        let l = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
                        let (_, g) = angles([d[0] / l, d[1] / l, d[2] / l]);
                        let g = g.to_degrees();
                        let wgt = 1.0 / l.powi(3);
                        s +=
                            wgt * (1e5 * (-(2.0f64.ln()) * (g / (0.5 * fwhm)).powi(2)).exp() + 1.0);
                        w += wgt;
                    }
                }
                s / w
            })
            .collect();
        report(layout, &candela);
    } else {
        let photons: u64 = args[2].parse().unwrap();
        let lum =
            Arc::new(lucerna_simulation::Luminaire::load(std::path::Path::new(&args[1])).unwrap());
        let mut settings = lucerna_simulation::SimulationSettings::default();
        settings.stop.photons = Some(photons);
        if let Some(f) = args.get(3) {
            if f == "auto" {
                settings.filter = lucerna_simulation::FilterChoice::Automatic;
            }
        }
        let snap = lucerna_simulation::bake(lum, settings).unwrap();
        println!(
            "photons {} chosen table step {:?}",
            snap.photons,
            snap.table.uniform_gamma_step()
        );
        report(snap.map.layout, &snap.candela);
    }
}
#[allow(dead_code)]
pub fn constant_check() {
    for res in [64u32, 256] {
        let layout = CubeMapLayout::new(res);
        let ones = vec![1.0; layout.texel_count()];
        let c = lucerna_photometry::resample::cone_flux_lm(layout, &ones, [2.0, 5.0, 10.0, 30.0]);
        let truth = [2.0f64, 5.0, 10.0, 30.0]
            .map(|g| 2.0 * std::f64::consts::PI * (1.0 - g.to_radians().cos()));
        println!(
            "res {res}: {:?}",
            c.iter()
                .zip(truth)
                .map(|(a, b)| a / b - 1.0)
                .collect::<Vec<_>>()
        );
    }
}
