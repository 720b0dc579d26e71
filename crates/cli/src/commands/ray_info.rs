//! `lucerna info FILE.tm25ray`: a TM-25 ray file's header, its rays'
//! count, flux and extent, and the far-field figures of the rays binned
//! into a table.

use std::fmt::{self, Write as _};
use std::path::Path;

use anyhow::Result;
use lucerna_photometry::Figures;
use lucerna_photometry::tm25::Description;
use serde::Serialize;

#[derive(Debug, Serialize)]
pub struct RayFileReport {
    file: String,
    format: &'static str,
    creation_method: String,
    date_time: String,
    description: Vec<(&'static str, String)>,
    rays: u64,
    columns: usize,
    spectrum: String,
    /// The header's totals; `None` where the file says unknown (NaN).
    declared_luminous_flux_lm: Option<f32>,
    declared_radiant_flux_w: Option<f32>,
    /// The rays' luminous flux, summed (README's rule for radiant files).
    rays_luminous_flux_lm: f64,
    /// Where the header and the rays disagree, and which one a bake uses.
    warnings: Vec<String>,
    extent_min_mm: [f32; 3],
    extent_max_mm: [f32; 3],
    /// The far field of the rays binned on a cube map, tabulated on C
    /// every 5° and the bake's automatic γ grid (γ = 0 along −z of the
    /// file's frame).
    far_field: Figures,
    /// How faithfully the far field's table holds the rays' binned map:
    /// its γ grid and what the ray count limits.
    far_field_table: String,
}

/// Below this share of the flux going down, the note that the source
/// emits along +z (an isotropic source splits 50/50 and gets none).
const UPWARD_NOTE_BELOW: f64 = 0.1;

pub fn report(path: &Path) -> Result<RayFileReport> {
    let set = super::input::read_rays(path)?;
    let h = &set.header;
    let (lo, hi) = set.extent_mm().unwrap_or_default();
    let name = path
        .file_name()
        .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
    let (photometry, fidelity) = set.far_field_photometry_and_fidelity(&name);
    let description = Description::FIELD_NAMES
        .into_iter()
        .zip(h.description.fields())
        .filter(|(_, v)| !v.trim().is_empty())
        .map(|(k, v)| (k, v.to_owned()))
        .collect();
    Ok(RayFileReport {
        file: path.display().to_string(),
        format: "IES TM-25 ray file",
        creation_method: format!("{:?}", h.creation_method).to_lowercase(),
        date_time: h.date_time.clone(),
        description,
        rays: h.ray_count,
        columns: h.columns().count,
        spectrum: match h.spectrum {
            lucerna_photometry::tm25::SpectrumType::SingleWavelength => format!(
                "single wavelength {} nm",
                h.wavelength_nm.unwrap_or(f32::NAN)
            ),
            s => format!("{s:?}").to_lowercase(),
        },
        declared_luminous_flux_lm: h.luminous_flux_lm,
        declared_radiant_flux_w: h.radiant_flux_w,
        rays_luminous_flux_lm: set.total_luminous_flux_lm(),
        warnings: set.flux_warnings().into_iter().chain(h.notes()).collect(),
        extent_min_mm: lo,
        extent_max_mm: hi,
        far_field: photometry.figures(),
        far_field_table: format!("{} rays; {}", set.len(), fidelity.summary(),),
    })
}

impl fmt::Display for RayFileReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut s = String::new();
        let _ = writeln!(s, "file           {}", self.file);
        let _ = writeln!(
            s,
            "format         {} ({})",
            self.format, self.creation_method
        );
        if !self.date_time.is_empty() {
            let _ = writeln!(s, "created        {}", self.date_time);
        }
        for (k, v) in &self.description {
            let _ = writeln!(s, "{k:<23}{v}");
        }
        let _ = writeln!(
            s,
            "rays           {} ({} values each)",
            self.rays, self.columns
        );
        let _ = writeln!(s, "spectrum       {}", self.spectrum);
        let declared =
            |v: Option<f32>, unit: &str| v.map_or("unknown".to_owned(), |v| format!("{v} {unit}"));
        let _ = writeln!(
            s,
            "flux           {:.2} lm in the rays; the header says {} and {}",
            self.rays_luminous_flux_lm,
            declared(self.declared_luminous_flux_lm, "lm"),
            declared(self.declared_radiant_flux_w, "W")
        );
        let [a, b, c] = self.extent_min_mm;
        let [x, y, z] = self.extent_max_mm;
        let _ = writeln!(
            s,
            "source extent  x {a:.3}..{x:.3}  y {b:.3}..{y:.3}  z {c:.3}..{z:.3} mm"
        );
        let fig = &self.far_field;
        let _ = writeln!(
            s,
            "far field      {:.1} lm, peak {:.1} cd at C{}° γ{}° (γ = 0 along −z)",
            fig.flux_lm, fig.peak_cd, fig.peak_c_deg, fig.peak_gamma_deg
        );
        let _ = writeln!(
            s,
            "direction      {:.1} % of the flux below the horizontal (γ < 90°), {:.1} % above{}",
            100.0 * fig.downward_fraction,
            100.0 * (1.0 - fig.downward_fraction),
            if fig.downward_fraction < UPWARD_NOTE_BELOW {
                ": the source emits along +z in its own frame, as LED files do; aim it with the emitter's transform"
            } else {
                ""
            }
        );
        super::info::beam_and_field_lines(&mut s, fig);
        let _ = writeln!(s, "table          {}", self.far_field_table);
        for w in &self.warnings {
            let _ = writeln!(s, "warning        {w}");
        }
        f.write_str(&s)
    }
}
