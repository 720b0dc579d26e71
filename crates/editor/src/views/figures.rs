//! Every figure of the current result with its noise estimate (1σ),
//! copyable as text for a report.

use egui::Ui;
use lucerna_photometry::figures::ZONES_DEG;
use lucerna_simulation::Snapshot;

/// The zone of `ZONES_DEG` spanning `zone` (degrees).
fn zone_index(zone: (f64, f64)) -> usize {
    ZONES_DEG.iter().position(|z| *z == zone).unwrap_or(0)
}

/// One row: figure, value, noise.
fn rows(s: &Snapshot) -> Vec<(String, String, String)> {
    let f = &s.figures;
    let n = &s.noise;
    let percent = |r: f64| {
        if r.is_finite() {
            format!("± {:.2} %", 100.0 * r)
        } else {
            "—".to_owned()
        }
    };
    let degrees = |a: Option<f64>, noise: Option<f64>| {
        (
            a.map_or_else(|| "—".to_owned(), |a| format!("{a:.1}°")),
            noise.map_or_else(|| "—".to_owned(), |e| format!("± {e:.2}°")),
        )
    };
    let mut rows = vec![
        (
            "Flux".to_owned(),
            format!("{:.1} lm", f.flux_lm),
            percent(n.flux_relative),
        ),
        (
            "LOR".to_owned(),
            f.light_output_ratio
                .map_or_else(|| "—".to_owned(), |l| format!("{:.1} %", 100.0 * l)),
            percent(n.flux_relative),
        ),
        (
            "Downward flux".to_owned(),
            format!(
                "{:.1} lm ({:.1} %)",
                f.downward_flux_lm,
                100.0 * f.downward_fraction
            ),
            percent(n.zonal_relative[zone_index((0.0, 90.0))]),
        ),
        (
            "Upward flux".to_owned(),
            format!("{:.1} lm", f.upward_flux_lm),
            percent(n.zonal_relative[zone_index((90.0, 180.0))]),
        ),
        (
            "Peak".to_owned(),
            format!("{:.0} cd", f.peak_cd),
            percent(n.peak_relative),
        ),
        (
            "Peak direction".to_owned(),
            format!("C {:.1}°, γ {:.1}°", f.peak_c_deg, f.peak_gamma_deg),
            String::new(),
        ),
    ];
    for (k, plane) in ["C0-C180", "C90-C270"].iter().enumerate() {
        let (v, e) = degrees(f.beam_angle_deg[k], n.beam_angle_deg[k]);
        rows.push((format!("Beam angle {plane}"), v, e));
        let (v, e) = degrees(f.field_angle_deg[k], n.field_angle_deg[k]);
        rows.push((format!("Field angle {plane}"), v, e));
    }
    for (k, (g0, g1)) in ZONES_DEG.iter().enumerate() {
        let share = if f.flux_lm > 0.0 {
            100.0 * f.zonal_flux_lm[k] / f.flux_lm
        } else {
            0.0
        };
        rows.push((
            format!("Zone {g0:.0}-{g1:.0}°"),
            format!("{:.1} lm ({share:.1} %)", f.zonal_flux_lm[k]),
            percent(n.zonal_relative[k]),
        ));
    }
    rows.push((
        "Photons".to_owned(),
        format!("{:.3e}", s.photons as f64),
        String::new(),
    ));
    rows
}

/// The figures as tab-separated text, one per line (for a spreadsheet or
/// a report).
pub fn figures_text(s: &Snapshot) -> String {
    let mut text = String::from("Figure\tValue\tNoise (1σ)\n");
    for (name, value, noise) in rows(s) {
        text.push_str(&format!("{name}\t{value}\t{noise}\n"));
    }
    text
}

pub fn figures_ui(ui: &mut Ui, s: &Snapshot) {
    if ui
        .button("Copy as text")
        .on_hover_text("Tab-separated: pastes into a spreadsheet")
        .clicked()
    {
        ui.ctx().copy_text(figures_text(s));
    }
    egui::ScrollArea::vertical().show(ui, |ui| {
        egui::Grid::new("all figures")
            .num_columns(3)
            .striped(true)
            .show(ui, |ui| {
                ui.strong("Figure");
                ui.strong("Value");
                ui.strong("Noise (1σ)");
                ui.end_row();
                for (name, value, noise) in rows(s) {
                    ui.label(name);
                    ui.label(value);
                    ui.label(noise);
                    ui.end_row();
                }
            });
        ui.label(
            "Noise: the photons' Monte Carlo error of each figure (binomial for fluxes, \
             Poisson for intensities, through the slope for angles).",
        );
    });
}
