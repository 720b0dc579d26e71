//! Illuminance on the work-plane grid and the figures lighting designers
//! check against EN 12464-1: Emin, Eavg, Emax and the uniformity
//! U0 = Emin / Eavg.

use glam::DVec3;
use rayon::prelude::*;
use serde::Serialize;

pub use crate::model::{grid_coordinates, grid_count};
use crate::render::{Shading, light_illuminance};
use crate::scene::RoomScene;

/// Illuminance (lx) at the grid points, row by row (y), x fastest.
#[derive(Debug, Clone, PartialEq)]
pub struct WorkPlaneGrid {
    pub xs: Vec<f64>,
    pub ys: Vec<f64>,
    pub height_m: f64,
    pub lux: Vec<f64>,
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct IlluminanceFigures {
    pub e_min_lx: f64,
    pub e_avg_lx: f64,
    pub e_max_lx: f64,
    /// Emin / Eavg.
    pub u0: f64,
    pub points: usize,
}

/// The work-plane points (facing up) of a room.
pub fn grid_points(scene: &RoomScene) -> (Vec<f64>, Vec<f64>) {
    let w = scene.work_plane;
    (
        grid_coordinates(scene.size.x, w.border_m, w.spacing_m),
        grid_coordinates(scene.size.y, w.border_m, w.spacing_m),
    )
}

/// The work-plane grid with `lux(k, point)` at every point k (row by row,
/// x fastest), evaluated in parallel.
fn grid_of(scene: &RoomScene, lux: impl Fn(usize, DVec3) -> f64 + Sync) -> WorkPlaneGrid {
    let (xs, ys) = grid_points(scene);
    let h = scene.work_plane.height_m;
    let nx = xs.len();
    let lux = (0..xs.len() * ys.len())
        .into_par_iter()
        .map(|k| lux(k, DVec3::new(xs[k % nx], ys[k / nx], h)))
        .collect();
    WorkPlaneGrid {
        xs,
        ys,
        height_m: h,
        lux,
    }
}

/// Illuminance on the work plane by the CPU shading.
pub fn work_plane_cpu(scene: &RoomScene, shading: Shading) -> WorkPlaneGrid {
    grid_of(scene, |_, p| {
        scene
            .lights
            .iter()
            .map(|l| light_illuminance(l, p, DVec3::Z, shading).lux)
            .sum()
    })
}

/// The work plane by Monte Carlo integration of eq. 1 over every opening
/// (MIS of area and profile sampling, `samples` per technique, light and
/// point): the reference for the figures.
pub fn work_plane_reference(scene: &RoomScene, samples: usize) -> WorkPlaneGrid {
    use crate::reference::{ProfileDirectionSampler, mis_illuminance, monte_carlo_illuminance};
    let samplers: Vec<Option<ProfileDirectionSampler>> = scene
        .lights
        .iter()
        .map(|l| ProfileDirectionSampler::new(&l.profile))
        .collect();
    grid_of(scene, |k, p| {
        scene
            .lights
            .iter()
            .zip(&samplers)
            .enumerate()
            .map(|(i, (l, sampler))| {
                let seed = (k * 7919 + i) as u64;
                match sampler {
                    Some(s) => mis_illuminance(l, s, p, DVec3::Z, samples, seed),
                    None => monte_carlo_illuminance(l, p, DVec3::Z, samples, seed),
                }
            })
            .sum()
    })
}

impl WorkPlaneGrid {
    pub fn figures(&self) -> IlluminanceFigures {
        let n = self.lux.len().max(1);
        let e_min = self.lux.iter().copied().fold(f64::INFINITY, f64::min);
        let e_max = self.lux.iter().copied().fold(0.0, f64::max);
        let e_avg = self.lux.iter().sum::<f64>() / n as f64;
        IlluminanceFigures {
            e_min_lx: if e_min.is_finite() { e_min } else { 0.0 },
            e_avg_lx: e_avg,
            e_max_lx: e_max,
            u0: if e_avg > 0.0 { e_min / e_avg } else { 0.0 },
            points: self.lux.len(),
        }
    }

    /// `x_m,y_m,illuminance_lx` rows (mm and mlx resolution) after a
    /// header, for spreadsheets; written by the csv crate so the format
    /// stays standard if a column ever holds text.
    pub fn csv(&self) -> Result<Vec<u8>, WriteGridCsvError> {
        let mut out = csv::Writer::from_writer(Vec::new());
        out.write_record(["x_m", "y_m", "illuminance_lx"])?;
        for (j, y) in self.ys.iter().enumerate() {
            for (i, x) in self.xs.iter().enumerate() {
                let lux = self.lux[j * self.xs.len() + i];
                out.write_record([format!("{x:.3}"), format!("{y:.3}"), format!("{lux:.3}")])?;
            }
        }
        out.into_inner()
            .map_err(|e| csv::Error::from(e.into_error()).into())
    }
}

/// Writing the work-plane grid as CSV failed (into memory, so only on a
/// bug or exhausted memory).
#[derive(Debug, thiserror::Error)]
#[error("cannot write the work-plane grid as CSV")]
pub struct WriteGridCsvError(#[from] csv::Error);
