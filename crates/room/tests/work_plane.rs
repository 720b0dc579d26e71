#![allow(clippy::unwrap_used, clippy::expect_used)]
//! Work-plane figures (Emin, Eavg, Emax, U0) of the example rooms: the
//! cubature against the Monte Carlo reference, the GPU against the CPU.

mod common;

use lucerna_room::gpu::GpuRoomRenderer;
use lucerna_room::work_plane::work_plane_reference;
use lucerna_room::{IlluminanceFigures, RoomScene, Shading, work_plane_cpu};

fn room(name: &str) -> RoomScene {
    let (room, phot) = common::example_room(name);
    RoomScene::new(&room, &phot)
}

fn close(a: IlluminanceFigures, b: IlluminanceFigures, tolerance: f64) -> Result<(), String> {
    for (name, x, y) in [
        ("Emin", a.e_min_lx, b.e_min_lx),
        ("Eavg", a.e_avg_lx, b.e_avg_lx),
        ("Emax", a.e_max_lx, b.e_max_lx),
        ("U0", a.u0, b.u0),
    ] {
        if (x - y).abs() > tolerance * y.abs() {
            return Err(format!("{name}: {x} vs {y}"));
        }
    }
    Ok(())
}

#[test]
fn cubature_figures_match_the_monte_carlo_reference_within_one_percent() {
    for name in ["office.toml", "corridor.toml"] {
        let scene = room(name);
        let cubature = work_plane_cpu(&scene, Shading::Cubature).figures();
        let reference = work_plane_reference(&scene, 1024).figures();
        let point = work_plane_cpu(&scene, Shading::PointLight).figures();
        eprintln!(
            "{name}: cubature {cubature:?}\n  reference {reference:?}\n  point lights {point:?}"
        );
        close(cubature, reference, 0.01).unwrap();
    }
}

#[test]
fn gpu_figures_match_the_cpu_within_one_percent() {
    let Some(ctx) = lucerna_gpu::open_for_tests() else {
        return;
    };
    let renderer = GpuRoomRenderer::new(ctx).unwrap();
    for name in ["office.toml", "corridor.toml"] {
        let scene = room(name);
        let uploaded = renderer.upload(&scene).unwrap();
        for shading in [Shading::Cubature, Shading::PointLight] {
            let gpu = renderer
                .work_plane(&scene, &uploaded, shading)
                .unwrap()
                .figures();
            let cpu = work_plane_cpu(&scene, shading).figures();
            close(gpu, cpu, 0.01).unwrap();
        }
    }
}

#[test]
fn the_grid_csv_reads_back_one_row_per_point_x_fastest() {
    let grid = lucerna_room::WorkPlaneGrid {
        xs: vec![0.25, 0.75, 1.25],
        ys: vec![0.5, 1.5],
        height_m: 0.8,
        lux: vec![100.0, 200.0, 300.0, 400.0, 500.0, 612.3456],
    };
    let bytes = grid.csv().unwrap();
    let mut reader = csv::Reader::from_reader(bytes.as_slice());
    assert_eq!(
        reader.headers().unwrap(),
        vec!["x_m", "y_m", "illuminance_lx"]
    );
    let rows: Vec<(f64, f64, f64)> = reader.deserialize().map(|r| r.unwrap()).collect();
    assert_eq!(rows.len(), 6);
    assert_eq!(rows[1], (0.75, 0.5, 200.0));
    assert_eq!(rows[5], (1.25, 1.5, 612.346), "three decimals");
}
