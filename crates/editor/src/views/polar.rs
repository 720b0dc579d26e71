//! The polar diagram as datasheets draw it: γ = 0 straight down, the
//! planes C0 and C90 to the right and C180, C270 to the left, rings in
//! the chosen unit, γ labelled at the rim, the reference dashed.

use egui::{Color32, Ui};
use egui_plot::{Line, LineStyle, Plot, PlotPoint, PlotPoints, Text};
use lucerna_photometry::CandelaTable;
use lucerna_simulation::Snapshot;

use super::PlotTables;

pub const C0_COLOUR: Color32 = Color32::from_rgb(220, 70, 60);
pub const C90_COLOUR: Color32 = Color32::from_rgb(70, 130, 230);
pub const EXTRA_COLOUR: Color32 = Color32::from_rgb(80, 190, 90);

/// Points of the vertical plane through `c_deg` and `c_deg + 180°` in the
/// polar diagram's frame, scaled by `factor`: γ = 0 straight down, plane
/// C to the right.
pub fn plane_points(table: &CandelaTable, c_deg: f64, factor: f64) -> Vec<[f64; 2]> {
    let mut points = Vec::with_capacity(721);
    for k in (0..=360).rev() {
        let gamma = f64::from(k) * 0.5;
        let i = factor * table.intensity(c_deg + 180.0, gamma);
        points.push([-i * gamma.to_radians().sin(), -i * gamma.to_radians().cos()]);
    }
    for k in 1..=360 {
        let gamma = f64::from(k) * 0.5;
        let i = factor * table.intensity(c_deg, gamma);
        points.push([i * gamma.to_radians().sin(), -i * gamma.to_radians().cos()]);
    }
    points
}

/// A round ring spacing (1, 2 or 5 × 10ⁿ), at least a quarter of `reach`,
/// as the exported polar diagram spaces its rings.
pub fn ring_step(reach: f64) -> f64 {
    lucerna_pictures::scale::round_step(reach / 4.0)
}

fn angle(a: Option<f64>) -> String {
    a.map_or_else(|| "—".to_owned(), |a| format!("{a:.1}°"))
}

pub fn polar_ui(ui: &mut Ui, t: &PlotTables<'_>, snapshot: &Snapshot) {
    let peak = t.current_factor * t.current.peak().0;
    let reference_peak = t.reference.map_or(0.0, |(r, f)| f * r.table.peak().0);
    let reach = 1.1 * peak.max(reference_peak).max(1e-9);
    let step = ring_step(reach);
    let unit = t.unit.label();
    // The figures of the table drawn: the snapshot's for the exported one.
    let figures = if std::ptr::eq(t.current, &*snapshot.table) {
        snapshot.figures.clone()
    } else {
        lucerna_photometry::figures(t.current, Some(snapshot.map.emitter_flux_lm))
    };
    let height = (ui.available_height() - 64.0).max(120.0);
    Plot::new("polar diagram")
        .data_aspect(1.0)
        .height(height)
        .legend(egui_plot::Legend::default())
        .show_grid(false)
        .show_axes(false)
        .show(ui, |plot| {
            let grey = Color32::from_gray(95);
            // Rings of equal intensity, labelled on the vertical axis.
            let mut r = step;
            while r <= reach * 1.0001 {
                let ring: Vec<[f64; 2]> = (0..=180)
                    .map(|k| {
                        let a = f64::from(k) * 2.0f64.to_radians();
                        [r * a.sin(), r * a.cos()]
                    })
                    .collect();
                plot.line(Line::new("", ring).color(grey).width(0.5));
                plot.text(
                    Text::new("", PlotPoint::new(0.0, -r), format!("{r:.0}"))
                        .color(Color32::from_gray(150))
                        .anchor(egui::Align2::LEFT_TOP),
                );
                r += step;
            }
            // γ spokes every 30°, labelled at the rim.
            for k in 0..=6 {
                let gamma = f64::from(k) * 30.0;
                let (s, c) = gamma.to_radians().sin_cos();
                for side in [-1.0, 1.0] {
                    let rim = [side * reach * s, -reach * c];
                    plot.line(
                        Line::new("", PlotPoints::from(vec![[0.0, 0.0], rim]))
                            .color(grey)
                            .width(0.5),
                    );
                    if side > 0.0 || (k != 0 && k != 6) {
                        plot.text(Text::new(
                            "",
                            PlotPoint::new(side * reach * 1.07 * s, -reach * 1.07 * c),
                            format!("γ {gamma:.0}°"),
                        ));
                    }
                }
            }
            // Which half is which plane: users of other tools are
            // confused by unlabelled polar diagrams.
            plot.text(
                Text::new(
                    "",
                    PlotPoint::new(1.1 * reach, -1.1 * reach),
                    "right: C0, C90",
                )
                .anchor(egui::Align2::RIGHT_BOTTOM),
            );
            plot.text(
                Text::new(
                    "",
                    PlotPoint::new(-1.1 * reach, -1.1 * reach),
                    "left: C180, C270",
                )
                .anchor(egui::Align2::LEFT_BOTTOM),
            );
            plot.text(
                Text::new("", PlotPoint::new(-1.1 * reach, 1.1 * reach), unit)
                    .anchor(egui::Align2::LEFT_TOP),
            );
            let f = t.current_factor;
            plot.line(
                Line::new("C0-C180", plane_points(t.current, 0.0, f))
                    .color(C0_COLOUR)
                    .width(2.0),
            );
            plot.line(
                Line::new("C90-C270", plane_points(t.current, 90.0, f))
                    .color(C90_COLOUR)
                    .width(2.0),
            );
            if let Some(c) = t.extra_plane {
                plot.line(
                    Line::new(
                        format!("C{c:.1}-C{:.1}", c + 180.0),
                        plane_points(t.current, c, f),
                    )
                    .color(EXTRA_COLOUR)
                    .width(2.0),
                );
            }
            if let Some((r, rf)) = t.reference {
                for (c, colour) in [(0.0, C0_COLOUR), (90.0, C90_COLOUR)] {
                    plot.line(
                        Line::new(
                            format!("reference C{c:.0}-C{:.0}", c + 180.0),
                            plane_points(&r.table, c, rf),
                        )
                        .color(colour.gamma_multiply(0.8))
                        .style(LineStyle::dashed_loose())
                        .width(1.5),
                    );
                }
            }
        });
    ui.label(format!(
        "Beam angle C0-C180 {}, C90-C270 {} · field angle C0-C180 {}, C90-C270 {}",
        angle(figures.beam_angle_deg[0]),
        angle(figures.beam_angle_deg[1]),
        angle(figures.field_angle_deg[0]),
        angle(figures.field_angle_deg[1]),
    ));
    ui.label(format!(
        "Peak {:.0} {unit} at C {:.1}°, γ {:.1}°",
        t.current_factor * figures.peak_cd,
        figures.peak_c_deg,
        figures.peak_gamma_deg
    ));
    if let Some((r, rf)) = t.reference {
        ui.label(format!(
            "Reference peak {:.0} {unit}{}",
            rf * r.table.peak().0,
            if r.at_shown_flux {
                " (its shape at this flux, as the design matches it)"
            } else {
                ""
            }
        ));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rings_are_round_numbers_about_a_quarter_of_the_reach() {
        assert_eq!(ring_step(1100.0), 500.0);
        assert_eq!(ring_step(400.0), 100.0);
        assert_eq!(ring_step(121_000.0), 50_000.0);
        assert_eq!(ring_step(0.0), 1.0);
    }

    #[test]
    fn a_plane_is_drawn_down_the_nadir_and_out_to_each_side() {
        // 100 cd everywhere: a circle of radius 100 in both halves.
        let table = CandelaTable::from_fn(90.0, 90.0, |_, _| 100.0);
        let points = plane_points(&table, 0.0, 2.0);
        for p in &points {
            assert!((p[0].hypot(p[1]) - 200.0).abs() < 1e-9);
        }
        // γ = 0 straight down; the C180 half on the left.
        assert!(points[360][1] < -199.0);
        assert!(points[180][0] < 0.0 && points[540][0] > 0.0);
    }
}
