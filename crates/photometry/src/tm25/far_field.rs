//! A ray set's far field: each ray's luminous flux binned by direction on
//! a cube map (exact texel solid angles), tabulated on a C-γ grid in the
//! file's own frame (γ = 0 along −z, C0 along +x, as Lucerna's
//! photometry; an LED file emitting along +z shows as up-light).

use crate::photometry::{Dimensions, Format, LampSet, Metadata, Photometry};
use crate::resample::table_from_cube_map;
use crate::table::CPlaneSymmetry;
use crate::{CandelaTable, CubeMapLayout};

use super::RaySet;

/// Texels per cube face edge of the binning for `rays` rays: about 100
/// rays per texel were they spread over the sphere, so the figures are
/// not the noise of a few rays, between 8 (11° texels) and 128 (0.7°).
pub fn far_field_resolution(rays: usize) -> u32 {
    ((rays as f64 / 600.0).sqrt().round() as u32).clamp(8, 128)
}

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

    /// The far field as a candela table on C every 5°, γ every 1°.
    pub fn far_field_table(&self) -> CandelaTable {
        let layout = CubeMapLayout::new(far_field_resolution(self.len()));
        let c: Vec<f64> = (0..72).map(|k| 5.0 * f64::from(k)).collect();
        let gamma: Vec<f64> = (0..=180).map(f64::from).collect();
        table_from_cube_map(layout, &self.far_field_candela(layout), &c, &gamma)
    }

    /// The far field as a photometric file's content: absolute
    /// photometry of the rays' luminous flux, labelled from the
    /// description block, the source's extent as its luminous area.
    pub fn far_field_photometry(&self, file_name: &str) -> Photometry {
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
        let n = far_field_resolution(self.len());
        Photometry {
            format: Format::Ies(2019),
            symmetry: CPlaneSymmetry::None,
            table: self.far_field_table(),
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
        }
    }
}
