//! A ray set's far field: each ray's luminous flux binned by direction on
//! a cube map (exact texel solid angles), tabulated on a C-γ grid in the
//! file's own frame (γ = 0 along −z, C0 along +x, as Lucerna's
//! photometry; an LED file emitting along +z shows as up-light).

use crate::fidelity::FidelityTargets;
use crate::noise::PhotonNoise;
use crate::photometry::{Dimensions, Format, LampSet, Metadata, Photometry};
use crate::table::CPlaneSymmetry;
use crate::tabulate::{CPooling, GammaGrid, ResampledTable, TableResampler};
use crate::{CandelaTable, CubeMapLayout};

use super::RaySet;

/// Texels per cube face edge of the binning for `rays` rays spread over
/// the sphere: about 100 rays per texel, between 8 (11° texels) and 128
/// (0.7°). A set whose rays gather in a beam gets finer texels
/// ([`RaySet::far_field_layout`]).
pub fn far_field_resolution(rays: usize) -> u32 {
    ((rays as f64 / 600.0).sqrt().round() as u32).clamp(8, 128)
}

/// The rays a texel should hold where the light is, and the finest
/// texels a far field is binned on.
const RAYS_PER_TEXEL: f64 = 100.0;
const MAX_FAR_FIELD_RESOLUTION: u32 = 512;
/// The coarsest γ step a far field's table gets where the automatic grid
/// would step coarser everywhere (a wide source), degrees.
const COARSEST_STEP_DEG: f64 = 1.0;
/// The far field's C-plane steps (degrees), tried coarsest first: a beam
/// leaving sideways spans few C-planes, and a table on 5° planes reads a
/// 10° cone at γ 90° 2.5 % high. 1° keeps within what EULUMDAT holds
/// (360 planes).
const C_STEPS_DEG: [f64; 3] = [5.0, 2.5, 1.0];
/// How far the table's flux may be from the rays' before a finer C step
/// is tried (a share): a beam leaving sideways across few planes, not the
/// few tenths of a per cent a wide LED's table keeps (finer planes would
/// cost a 100 k-ray file 0.6 GB and seconds for them).
const FLUX_HELD: f64 = 0.01;

impl RaySet {
    /// Candela per texel of `layout`: the rays' luminous flux in each
    /// texel over its solid angle.
    pub fn far_field_candela(&self, layout: CubeMapLayout) -> Vec<f64> {
        let mut flux = vec![0.0f64; layout.texel_count()];
        for i in 0..self.len() {
            let d = self.direction(i).map(f64::from);
            flux[layout.texel_of_direction(d)] += f64::from(self.luminous_flux_lm[i]);
        }
        flux.iter()
            .enumerate()
            .map(|(t, f)| f / layout.texel_solid_angle(t))
            .collect()
    }

    /// The cube map the far field is binned on: the finest whose texels
    /// hold, where the light is, about [`RAYS_PER_TEXEL`] rays (the mean
    /// over the flux of the rays in each ray's texel): a beam of a few
    /// degrees gets texels of a fraction of a degree, where binning by the
    /// ray count alone would give 7° texels to a 100 k-ray file and read
    /// its 10° cone 11 % low.
    pub fn far_field_layout(&self) -> CubeMapLayout {
        let total = self.total_luminous_flux_lm();
        let coarse = far_field_resolution(self.len());
        if !(total > 0.0) {
            return CubeMapLayout::new(coarse);
        }
        let mut resolution = coarse;
        let mut r = coarse;
        while r <= MAX_FAR_FIELD_RESOLUTION {
            let layout = CubeMapLayout::new(r);
            let mut rays = vec![0u32; layout.texel_count()];
            let texels: Vec<usize> = (0..self.len())
                .map(|i| layout.texel_of_direction(self.direction(i).map(f64::from)))
                .collect();
            for &t in &texels {
                rays[t] += 1;
            }
            let held: f64 = texels
                .iter()
                .zip(&self.luminous_flux_lm)
                .map(|(&t, &f)| f64::from(rays[t]) * f64::from(f))
                .sum::<f64>()
                / total;
            if held < RAYS_PER_TEXEL {
                break;
            }
            resolution = r;
            r *= 2;
        }
        CubeMapLayout::new(resolution)
    }

    /// The far field as a candela table on C every 5° (finer where that
    /// loses flux: [`C_STEPS_DEG`]), its γ angles chosen as a bake's are: the coarsest listed grid that holds the
    /// map's flux, cone fluxes, beam and field angles and peak within
    /// [`FidelityTargets`], the rays counted as the photons behind the map
    /// (so the targets give way where the rays' own noise is larger); with
    /// how faithfully it holds them.
    pub fn far_field(&self) -> (CubeMapLayout, ResampledTable) {
        // Binned where each texel holds about [`RAYS_PER_TEXEL`] rays:
        // finer texels would hold a sharp-edged beam's flux a little
        // better (a 45° cone of 5 000 rays leaving sideways reads 1 % high
        // on 11° texels, 0.05 % on 2.8°) but make its peak and angles the
        // noise of single rays, and cost memory.
        let layout = self.far_field_layout();
        (layout, self.far_field_on(layout))
    }

    /// [`RaySet::far_field`] binned on `layout`.
    pub fn far_field_on(&self, layout: CubeMapLayout) -> ResampledTable {
        let candela = self.far_field_candela(layout);
        let total = self.total_luminous_flux_lm();
        let noise = (total > 0.0 && !self.is_empty()).then(|| PhotonNoise {
            // Rays of unequal flux: a texel's noise is that of its rays,
            // counted as the mean ray's flux each.
            lm_per_photon: total / self.len() as f64,
            pooled_images: 1.0,
        });
        let mut resampler = TableResampler::new();
        let mut table = |c_step: f64| {
            let c: Vec<f64> = (0..(360.0 / c_step).round() as usize)
                .map(|k| c_step * k as f64)
                .collect();
            let automatic = resampler.table(
                layout,
                &candela,
                &c,
                GammaGrid::Automatic(FidelityTargets::default()),
                noise,
                CPooling::Separate,
            );
            // Where the rays' noise lets the automatic grid step coarser than
            // 1° everywhere, 1° steps still: a wide LED's beam angle read on 5° steps is
            // 4° off its rays' (it is cheap to keep, and what the eye and
            // other readers compare).
            let finest = automatic
                .table
                .gammas_deg
                .windows(2)
                .map(|w| w[1] - w[0])
                .fold(f64::INFINITY, f64::min);
            if finest > COARSEST_STEP_DEG + 1e-9 {
                resampler.table(
                    layout,
                    &candela,
                    &c,
                    GammaGrid::Step(COARSEST_STEP_DEG, FidelityTargets::default()),
                    noise,
                    CPooling::Separate,
                )
            } else {
                automatic
            }
        };
        let mut found = table(C_STEPS_DEG[0]);
        for &step in &C_STEPS_DEG[1..] {
            let flux = crate::figures(&found.table, None).flux_lm;
            if !(total > 0.0) || (flux / total - 1.0).abs() <= FLUX_HELD {
                break;
            }
            found = table(step);
        }
        found
    }

    /// [`RaySet::far_field`]'s table.
    pub fn far_field_table(&self) -> CandelaTable {
        self.far_field().1.table
    }

    /// The far field as a photometric file's content: absolute
    /// photometry of the rays' luminous flux, labelled from the
    /// description block, the source's extent as its luminous area.
    pub fn far_field_photometry(&self, file_name: &str) -> Photometry {
        self.far_field_photometry_and_fidelity(file_name).0
    }

    /// [`RaySet::far_field_photometry`], with how faithfully its table
    /// holds the rays' binned map (what `info` states as the ray count's
    /// limits).
    pub fn far_field_photometry_and_fidelity(
        &self,
        file_name: &str,
    ) -> (Photometry, crate::fidelity::TableFidelity) {
        let d = &self.header.description;
        let or = |s: &str, default: &str| {
            if s.trim().is_empty() || s.trim() == "unknown" {
                default.to_owned()
            } else {
                s.to_owned()
            }
        };
        let (lo, hi) = self.extent_mm().unwrap_or(([0.0; 3], [0.0; 3]));
        let flux = self.total_luminous_flux_lm();
        let (layout, ResampledTable { table, fidelity }) = self.far_field();
        let n = layout.resolution;
        let photometry = Photometry {
            format: Format::Tm25RayFile,
            symmetry: CPlaneSymmetry::None,
            table,
            meta: Metadata {
                manufacturer: or(&d.manufacturer, ""),
                luminaire: or(&d.name, file_name),
                catalog_number: or(&d.name, file_name),
                test_report: format!("far field of the ray file {file_name}"),
                test_lab: or(&d.ray_file_creator, "TM-25 ray file"),
                file_generation_info: format!(
                    "{} rays binned on a {n} x {n} cube map by Lucerna {}",
                    self.len(),
                    env!("CARGO_PKG_VERSION")
                ),
                lamps: vec![LampSet {
                    count: 1,
                    kind: or(&d.name, "ray file source"),
                    flux_lm: flux,
                    colour_temperature: String::new(),
                    colour_rendering: String::new(),
                    watts: 0.0,
                }],
                absolute: true,
                ballast_factor: 1.0,
                luminous_area: Dimensions {
                    length_m: f64::from(hi[0] - lo[0]) * 1e-3,
                    width_m: f64::from(hi[1] - lo[1]) * 1e-3,
                    height_m: f64::from(hi[2] - lo[2]) * 1e-3,
                    circular: false,
                },
                ..Metadata::default()
            },
        };
        (photometry, fidelity)
    }
}
