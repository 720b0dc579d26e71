//! The polar diagram as datasheets draw it: γ = 0 straight down, the
//! plane C to the right and C + 180° to the left.

use egui::{Color32, Ui};
use egui_plot::{Line, Plot, PlotPoint, PlotPoints, Text};
use lucerna_photometry::CandelaTable;

/// Points of the vertical plane through `c_deg` and `c_deg + 180°` in the
/// polar diagram's frame: γ = 0 straight down, plane C to the right.
fn plane_points(table: &CandelaTable, c_deg: f64) -> Vec<[f64; 2]> {
    let mut points = Vec::with_capacity(721);
    for k in (0..=360).rev() {
        let gamma = f64::from(k) * 0.5;
        let i = table.intensity(c_deg + 180.0, gamma);
        points.push([-i * gamma.to_radians().sin(), -i * gamma.to_radians().cos()]);
    }
    for k in 1..=360 {
        let gamma = f64::from(k) * 0.5;
        let i = table.intensity(c_deg, gamma);
        points.push([i * gamma.to_radians().sin(), -i * gamma.to_radians().cos()]);
    }
    points
}

pub fn polar_ui(ui: &mut Ui, table: &CandelaTable) {
    let (peak, _, _) = table.peak();
    let reach = if peak > 0.0 { peak * 1.1 } else { 1.0 };
    Plot::new("polar diagram")
        .data_aspect(1.0)
        .legend(egui_plot::Legend::default())
        .x_axis_label("cd")
        .show(ui, |plot| {
            // γ spokes every 30°, labelled at the rim.
            for k in 0..=6 {
                let gamma = f64::from(k) * 30.0;
                let (s, c) = gamma.to_radians().sin_cos();
                for side in [-1.0, 1.0] {
                    let rim = [side * reach * s, -reach * c];
                    plot.line(
                        Line::new("", PlotPoints::from(vec![[0.0, 0.0], rim]))
                            .color(Color32::from_gray(90))
                            .width(0.5),
                    );
                }
                // Unnamed items stay out of the legend.
                plot.text(Text::new(
                    "",
                    PlotPoint::new(reach * 1.05 * s, -reach * 1.05 * c),
                    format!("γ {gamma:.0}°"),
                ));
            }
            plot.line(Line::new("C0-C180", plane_points(table, 0.0)).width(2.0));
            plot.line(Line::new("C90-C270", plane_points(table, 90.0)).width(2.0));
        });
}
