//! Tables from cube maps as exports make them: the γ grid fixed or
//! automatic (`crate::gamma_grid`), the table's figures beside its map's
//! (`crate::fidelity`), through the shared cell binnings of
//! `crate::resample`.

use std::sync::Arc;

use crate::cubemap::CubeMapLayout;
use crate::fidelity::{AngleNoise, BeamFigures, FidelityTargets, TableFidelity};
pub use crate::gamma_grid::MAX_AUTOMATIC_GAMMAS;
use crate::noise::PhotonNoise;
use crate::resample::{CellBinning, CellFlux, MAX_STORED_RESOLUTION, gamma_cell_edges};
use crate::table::CandelaTable;

/// The γ grid of an exported table.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GammaGrid {
    /// Equal steps (degrees) from 0° to 180°, checked against the targets.
    Step(f64, FidelityTargets),
    /// Listed angles, fine where the distribution bends and coarse where
    /// it does not, at most [`MAX_AUTOMATIC_GAMMAS`] of them: the coarsest
    /// such grid that holds the map's figures within the targets
    /// ([`crate::gamma_grid`]).
    Automatic(FidelityTargets),
}

/// Whether a table's C-planes share their photons.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CPooling {
    /// Each cell from its own texels: any luminaire.
    #[default]
    Separate,
    /// Every C-plane the mean of its γ band's whole ring, for a luminaire
    /// whose light is the same in every C-plane (the scene's
    /// `rotationally_symmetric`): all of a ring's photons behind each
    /// value, and no square-texel pattern in the isocandela lines.
    Rotational,
}

/// A table and how faithfully it carries its map.
#[derive(Debug, Clone, PartialEq)]
pub struct ResampledTable {
    pub table: CandelaTable,
    pub fidelity: TableFidelity,
}

/// Tables from cube maps through the shared [`CellBinning`] of the layout
/// and grid: the first table of a layout in a process pays for the
/// binning (about 80 ms at 6 × 256²), later ones only for a sparse sum.
#[derive(Debug, Default)]
pub struct TableResampler {
    binning: Option<Arc<CellBinning>>,
}

impl TableResampler {
    pub fn new() -> Self {
        Self::default()
    }

    /// The table of `candela_per_texel` on `c_planes_deg` and `gammas`,
    /// with its figures beside the map's. `noise` (the photons behind the
    /// map, where known) keeps the automatic grid from resolving photon
    /// noise and lets the peak be held within its map texel's noise.
    pub fn table(
        &mut self,
        layout: CubeMapLayout,
        candela_per_texel: &[f64],
        c_planes_deg: &[f64],
        gammas: GammaGrid,
        noise: Option<PhotonNoise>,
        pooling: CPooling,
    ) -> ResampledTable {
        let (edges, targets) = match gammas {
            GammaGrid::Step(step, targets) => (
                gamma_cell_edges(&crate::table::uniform_gammas(step, 180.0)),
                targets,
            ),
            GammaGrid::Automatic(targets) => (crate::gamma_grid::band_edges_deg(), targets),
        };
        let map = BeamFigures::of_map(layout, candela_per_texel);
        let peak_noise = noise.map_or(0.0, |n| n.peak_texel(layout, candela_per_texel));
        let angle_noise = AngleNoise::of_map(layout, candela_per_texel, noise);
        let stale = self.binning.as_ref().is_none_or(|b| {
            b.layout() != layout || b.c_planes_deg() != c_planes_deg || b.band_edges_deg() != edges
        });
        if stale && layout.resolution <= MAX_STORED_RESOLUTION {
            self.binning = CellBinning::shared(layout, c_planes_deg, &edges).ok();
        }
        let cells = match &self.binning {
            Some(b) if layout.resolution <= MAX_STORED_RESOLUTION => b.integrate(candela_per_texel),
            _ => CellFlux::streamed(layout, candela_per_texel, c_planes_deg, &edges),
        };
        let cells = match pooling {
            CPooling::Separate => cells,
            CPooling::Rotational => cells.pooled_over_c(),
        };
        let (table, fidelity) = match gammas {
            GammaGrid::Step(step, _) => {
                let table = cells.table(&crate::table::uniform_gammas(step, 180.0));
                let fidelity =
                    TableFidelity::new(false, map, &table, targets, peak_noise, angle_noise);
                (table, fidelity)
            }
            GammaGrid::Automatic(_) => {
                let noise_of_map = (peak_noise, angle_noise);
                crate::gamma_grid::automatic(&cells, layout, map, targets, noise, noise_of_map)
            }
        };
        ResampledTable { table, fidelity }
    }
}
