//! `lucerna info`: what a photometric file contains, with the figures a
//! datasheet shows.

use std::fmt::{self, Write as _};
use std::path::Path;

use anyhow::Result;
use lucerna_photometry::Figures;
use serde::Serialize;

#[derive(Debug, Serialize)]
pub struct InfoReport {
    file: String,
    format: String,
    symmetry: String,
    c_planes: usize,
    c_range_deg: [f64; 2],
    c_step_deg: Option<f64>,
    gammas: usize,
    gamma_range_deg: [f64; 2],
    gamma_step_deg: Option<f64>,
    photometry: &'static str,
    lamp_flux_lm: Option<f64>,
    figures: Figures,
    manufacturer: String,
    luminaire: String,
    catalog_number: String,
    test_report: String,
    issue_date: String,
    luminous_area: lucerna_photometry::Dimensions,
    /// The lamp set the table and figures describe (the file's first).
    lamps: Vec<lucerna_photometry::LampSet>,
    /// Alternative lamp sets (EULUMDAT's later sets) with the luminaire
    /// flux and efficacy each gives.
    variants: Vec<lucerna_photometry::LampVariant>,
    declared_lor_percent: Option<f64>,
    power_w: Option<f64>,
    tilt_included: bool,
    warnings: Vec<String>,
}

pub fn report(path: &Path) -> Result<InfoReport> {
    let p = super::input::read_photometry(path)?;
    let t = &p.table;
    let c = &t.c_planes_deg;
    let g = &t.gammas_deg;
    Ok(InfoReport {
        file: path.display().to_string(),
        format: p.format.to_string(),
        symmetry: p.symmetry.describe().to_owned(),
        c_planes: c.len(),
        c_range_deg: [c[0], c[c.len() - 1]],
        c_step_deg: t.uniform_c_step().filter(|s| *s > 0.0),
        gammas: g.len(),
        gamma_range_deg: [g[0], g[g.len() - 1]],
        gamma_step_deg: t.uniform_gamma_step(),
        photometry: if p.meta.absolute {
            "absolute"
        } else {
            "relative"
        },
        lamp_flux_lm: p.lamp_flux_lm(),
        figures: p.figures(),
        manufacturer: p.meta.manufacturer.clone(),
        luminaire: p.meta.luminaire.clone(),
        catalog_number: p.meta.catalog_number.clone(),
        test_report: p.meta.test_report.clone(),
        issue_date: p.meta.issue_date.clone(),
        luminous_area: p.meta.luminous_area,
        lamps: p.lamp_set().into_iter().cloned().collect(),
        variants: p.variants(),
        declared_lor_percent: p.meta.declared_lor_percent,
        power_w: p.power_w(),
        tilt_included: p.meta.tilt.is_some(),
        warnings: p
            .meta
            .warnings
            .iter()
            .cloned()
            .chain(p.consistency_warnings())
            .collect(),
    })
}

fn angle(a: Option<f64>) -> String {
    a.map_or("—".to_owned(), |v| format!("{v:.1}°"))
}

/// The beam and field angle lines of `info`, for a photometric file and a
/// ray file's far field alike.
pub(crate) fn beam_and_field_lines(s: &mut String, fig: &Figures) {
    let _ = writeln!(
        s,
        "beam (50 %)    C0-C180 {}   C90-C270 {}",
        angle(fig.beam_angle_deg[0]),
        angle(fig.beam_angle_deg[1])
    );
    let _ = writeln!(
        s,
        "field (10 %)   C0-C180 {}   C90-C270 {}",
        angle(fig.field_angle_deg[0]),
        angle(fig.field_angle_deg[1])
    );
}

impl fmt::Display for InfoReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let fig = &self.figures;
        let mut s = String::new();
        let _ = writeln!(s, "file           {}", self.file);
        let _ = writeln!(s, "format         {}", self.format);
        for (k, v) in [
            ("manufacturer", &self.manufacturer),
            ("luminaire", &self.luminaire),
            ("catalogue no.", &self.catalog_number),
            ("test report", &self.test_report),
            ("issue date", &self.issue_date),
        ] {
            if !v.is_empty() {
                let _ = writeln!(s, "{k:<15}{v}");
            }
        }
        let _ = writeln!(s, "symmetry       {}", self.symmetry);
        let step = |x: Option<f64>| x.map_or("non-uniform".to_owned(), |v| format!("step {v}°"));
        let _ = writeln!(
            s,
            "C-planes       {} from C{}° to C{}° ({})",
            self.c_planes,
            self.c_range_deg[0],
            self.c_range_deg[1],
            if self.c_planes == 1 {
                "one plane".to_owned()
            } else {
                step(self.c_step_deg)
            }
        );
        let _ = writeln!(
            s,
            "γ angles       {} from {}° to {}° ({})",
            self.gammas,
            self.gamma_range_deg[0],
            self.gamma_range_deg[1],
            step(self.gamma_step_deg)
        );
        let _ = writeln!(s, "photometry     {}", self.photometry);
        if let Some(l) = self.lamp_flux_lm {
            let _ = writeln!(s, "lamp flux      {l:.1} lm");
        }
        let _ = writeln!(
            s,
            "flux           {:.1} lm (integrated from the table)",
            fig.flux_lm
        );
        let _ = writeln!(
            s,
            "                down {:.1} lm ({:.1} %), up {:.1} lm",
            fig.downward_flux_lm,
            fig.downward_fraction * 100.0,
            fig.upward_flux_lm
        );
        if let Some(lor) = fig.light_output_ratio {
            let declared = self
                .declared_lor_percent
                .map_or(String::new(), |d| format!(" (the file declares {d:.1} %)"));
            let _ = writeln!(s, "LOR            {:.1} %{declared}", lor * 100.0);
        }
        if let Some(w) = self.power_w {
            let efficacy = if w > 0.0 {
                format!(", {:.1} lm/W", fig.flux_lm / w)
            } else {
                String::new()
            };
            let _ = writeln!(s, "power          {w:.1} W{efficacy}");
        }
        let _ = writeln!(
            s,
            "peak           {:.1} cd at C{}° γ{}°",
            fig.peak_cd, fig.peak_c_deg, fig.peak_gamma_deg
        );
        beam_and_field_lines(&mut s, fig);
        let a = &self.luminous_area;
        if a.circular {
            let _ = writeln!(
                s,
                "luminous area  circular, ⌀ {:.1} mm, height {:.1} mm",
                a.length_m * 1e3,
                a.height_m * 1e3
            );
        } else {
            let _ = writeln!(
                s,
                "luminous area  {:.1} × {:.1} mm (length C0-C180 × width C90-C270), height {:.1} mm",
                a.length_m * 1e3,
                a.width_m * 1e3,
                a.height_m * 1e3
            );
        }
        for l in &self.lamps {
            let _ = writeln!(
                s,
                "lamps          {} × {} {:.1} lm {} W{}",
                l.count,
                if l.kind.is_empty() { "lamp" } else { &l.kind },
                l.flux_lm,
                l.watts,
                if self.variants.is_empty() {
                    ""
                } else {
                    " (set 1: the figures above)"
                }
            );
        }
        for v in &self.variants {
            let l = &v.lamps;
            let _ = writeln!(
                s,
                "variant        set {}: {} × {} {:.1} lm {} W -> luminaire {:.1} lm{}",
                v.set,
                l.count,
                if l.kind.is_empty() { "lamp" } else { &l.kind },
                l.flux_lm,
                l.watts,
                v.luminaire_flux_lm,
                v.efficacy_lm_per_w
                    .map_or(String::new(), |e| format!(", {e:.1} lm/W"))
            );
        }
        if self.tilt_included {
            let _ = writeln!(
                s,
                "tilt           TILT=INCLUDE data present (table at nominal tilt)"
            );
        }
        for w in &self.warnings {
            let _ = writeln!(s, "warning        {w}");
        }
        f.write_str(&s)
    }
}
