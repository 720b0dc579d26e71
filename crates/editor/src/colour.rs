//! The visual rules of `lucerna_pictures::scale` in egui's colours: the
//! editor's cube-map view, isocandela map, 3D cube and room use the same
//! palette and scales as the exported pictures, so the same colour means
//! the same candela or lux in a PNG and in the window.

use egui::{Color32, Ui};
pub use lucerna_pictures::scale::{DECADES, LUX_PARTS, LinearScale};
use lucerna_pictures::scale::{log_colour, ticks_125};

/// egui's colour of an sRGB triple.
pub fn colour32([r, g, b]: [u8; 3]) -> Color32 {
    Color32::from_rgb(r, g, b)
}

/// The false colour of `v` on the logarithmic scale over [`DECADES`]
/// below `peak`, as an exported cube map draws it.
pub fn intensity_colour(v: f64, peak: f64) -> Color32 {
    colour32(log_colour(v, peak))
}

/// Swatches at the 1-2-5 ticks of the scale below `peak`, labelled in cd
/// (the exported cube map's legend).
pub fn legend_ui(ui: &mut Ui, peak: f64) {
    let ticks = ticks_125(peak / 10f64.powf(DECADES), peak);
    swatches_ui(ui, ticks.into_iter().rev(), "cd", |v| {
        intensity_colour(v, peak)
    });
}

/// A row of colour swatches, each labelled with its value and `unit`.
fn swatches_ui(
    ui: &mut Ui,
    values: impl Iterator<Item = f64>,
    unit: &str,
    colour: impl Fn(f64) -> Color32,
) {
    ui.horizontal_wrapped(|ui| {
        for v in values {
            let (rect, _) = ui.allocate_exact_size(egui::vec2(14.0, 14.0), egui::Sense::hover());
            ui.painter().rect_filled(rect, 2.0, colour(v));
            ui.label(format!("{} {unit}", lucerna_pictures::canvas::label(v)));
        }
    });
}

/// The false colour of `lux` on a linear illuminance scale, white for a
/// luminaire (negative), as `lucerna render --false-colour` draws it.
pub fn lux_colour(scale: &LinearScale, lux: f64) -> Color32 {
    colour32(scale.colour(lux))
}

/// Swatches at the scale's ticks, each labelled in lux.
pub fn lux_legend_ui(ui: &mut Ui, scale: &LinearScale) {
    swatches_ui(ui, scale.ticks().into_iter(), "lx", |v| {
        lux_colour(scale, v)
    });
}
