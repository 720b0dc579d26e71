//! I(γ) for the chosen C-planes, linear or logarithmic: where a polar
//! diagram hides the stray light a thousand times below the beam.

use egui::Ui;
use egui_plot::{Line, LineStyle, Plot};
use lucerna_photometry::CandelaTable;

use super::PlotTables;
use super::polar::{C0_COLOUR, C90_COLOUR, EXTRA_COLOUR};

/// Which planes are drawn and how.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CartesianOptions {
    pub c0: bool,
    pub c90: bool,
    pub c180: bool,
    pub c270: bool,
    pub log: bool,
}

impl Default for CartesianOptions {
    fn default() -> Self {
        CartesianOptions {
            c0: true,
            c90: true,
            c180: false,
            c270: false,
            log: false,
        }
    }
}

/// Decades below the peak a log plot reaches.
const LOG_DECADES: f64 = 5.0;

/// The plane's I(γ) points, every 0.5°, scaled; on a log plot as
/// log10(I), floored `LOG_DECADES` below `peak`.
pub fn gamma_points(
    table: &CandelaTable,
    c_deg: f64,
    factor: f64,
    log_below: Option<f64>,
) -> Vec<[f64; 2]> {
    (0..=360)
        .map(|k| {
            let gamma = f64::from(k) * 0.5;
            let i = factor * table.intensity(c_deg, gamma);
            let y = match log_below {
                Some(peak) => i.max(peak * 10f64.powf(-LOG_DECADES)).max(1e-300).log10(),
                None => i,
            };
            [gamma, y]
        })
        .collect()
}

pub fn cartesian_ui(ui: &mut Ui, t: &PlotTables<'_>, options: &mut CartesianOptions) {
    ui.horizontal_wrapped(|ui| {
        ui.checkbox(&mut options.c0, "C0");
        ui.checkbox(&mut options.c90, "C90");
        ui.checkbox(&mut options.c180, "C180");
        ui.checkbox(&mut options.c270, "C270");
        ui.checkbox(&mut options.log, "Log intensity");
    });
    let unit = t.unit.label();
    let peak = (t.current_factor * t.current.peak().0).max(1e-9);
    let log = options.log.then_some(peak);
    let mut planes: Vec<(f64, egui::Color32)> = Vec::new();
    for (on, c, colour) in [
        (options.c0, 0.0, C0_COLOUR),
        (options.c90, 90.0, C90_COLOUR),
        (options.c180, 180.0, C0_COLOUR.gamma_multiply(0.6)),
        (options.c270, 270.0, C90_COLOUR.gamma_multiply(0.6)),
    ] {
        if on {
            planes.push((c, colour));
        }
    }
    if let Some(c) = t.extra_plane {
        planes.push((c, EXTRA_COLOUR));
    }
    let mut plot = Plot::new("cartesian diagram")
        .legend(egui_plot::Legend::default())
        .x_axis_label("γ (°)")
        .y_axis_label(if options.log {
            format!("{unit} (log)")
        } else {
            unit.to_owned()
        })
        .include_x(0.0)
        .include_x(180.0)
        .include_y(if options.log {
            peak.log10() - LOG_DECADES
        } else {
            0.0
        });
    if options.log {
        plot = plot.y_axis_formatter(|mark, _| format!("{:.3}", 10f64.powf(mark.value)));
    }
    plot.show(ui, |plot| {
        for &(c, colour) in &planes {
            plot.line(
                Line::new(
                    format!("C{c:.0}"),
                    gamma_points(t.current, c, t.current_factor, log),
                )
                .color(colour)
                .width(2.0),
            );
            if let Some((r, rf)) = t.reference {
                plot.line(
                    Line::new(
                        format!("reference C{c:.0}"),
                        gamma_points(&r.table, c, rf, log),
                    )
                    .color(colour.gamma_multiply(0.8))
                    .style(LineStyle::dashed_loose())
                    .width(1.5),
                );
            }
        }
    });
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_points_are_floored_below_the_peak() {
        let table = CandelaTable::from_fn(90.0, 90.0, |_, g| if g < 90.0 { 1000.0 } else { 0.0 });
        let linear = gamma_points(&table, 0.0, 1.0, None);
        assert_eq!(linear[0], [0.0, 1000.0]);
        let log = gamma_points(&table, 0.0, 1.0, Some(1000.0));
        assert!((log[0][1] - 3.0).abs() < 1e-12);
        // Darkness sits at the floor, not at −∞.
        assert!((log[360][1] - (3.0 - LOG_DECADES)).abs() < 1e-12);
    }
}
