//! The isocandela map: intensity over C (across) and γ (down, 0° at the
//! top) in the cube-map view's false colour, with the lines of equal
//! intensity of `lucerna_pictures::isocandela` (shared with the
//! datasheet's chart).

use std::sync::Arc;

use egui::{Color32, ColorImage, TextureHandle, TextureOptions, Ui};
use egui_plot::{Line, Plot, PlotImage, PlotPoint, Text};
use lucerna_photometry::CandelaTable;
use lucerna_pictures::isocandela::{
    C_STEP_DEG, COLUMNS, Isoline, LEVELS, ROWS, isolines, lit_gamma_range, sampled,
};

use super::IntensityUnit;
use crate::colour::intensity_colour;

/// The map's texture and lines, rebuilt when the table changes.
#[derive(Default)]
pub struct IsocandelaCache {
    shown: Option<Arc<CandelaTable>>,
    texture: Option<TextureHandle>,
    lines: Vec<Isoline>,
    range: (f64, f64),
}

impl std::fmt::Debug for IsocandelaCache {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("IsocandelaCache").finish_non_exhaustive()
    }
}

pub fn isocandela_ui(
    ui: &mut Ui,
    table: &Arc<CandelaTable>,
    factor: f64,
    unit: IntensityUnit,
    cache: &mut IsocandelaCache,
) {
    if !cache.shown.as_ref().is_some_and(|t| Arc::ptr_eq(t, table)) || cache.texture.is_none() {
        cache.range = lit_gamma_range(table);
        let values = sampled(table, cache.range);
        let peak = values.iter().copied().fold(0.0, f64::max);
        let mut image = ColorImage::filled([COLUMNS, ROWS], Color32::BLACK);
        for (pixel, v) in image.pixels.iter_mut().zip(&values) {
            *pixel = intensity_colour(*v, peak);
        }
        match &mut cache.texture {
            Some(t) => t.set(image, TextureOptions::LINEAR),
            None => {
                cache.texture = Some(ui.ctx().load_texture(
                    "isocandela",
                    image,
                    TextureOptions::LINEAR,
                ));
            }
        }
        cache.lines = isolines(table, cache.range);
        cache.shown = Some(table.clone());
    }
    let Some(texture) = &cache.texture else {
        return;
    };
    let peak = factor * table.peak().0;
    let (g0, g1) = cache.range;
    ui.label(format!(
        "Lines at {} % of the peak ({peak:.0} {}); colour: log scale as on the cube map; γ {g0:.0}°–{g1:.0}°, where the light is",
        LEVELS.map(|l| format!("{:.0}", 100.0 * l)).join(", "),
        unit.label()
    ));
    let unit_label = unit.label().to_owned();
    let table_for_hover = table.clone();
    Plot::new("isocandela map")
        .x_axis_label("C (°)")
        .y_axis_label("γ (°)")
        .y_axis_formatter(|mark, _| format!("{:.0}", (-mark.value).max(0.0)))
        .include_x(0.0)
        .include_x(360.0)
        .include_y(-g0)
        .include_y(-g1)
        .label_formatter(move |hover| {
            let p = match hover {
                egui_plot::HoverPosition::NearDataPoint { position, .. }
                | egui_plot::HoverPosition::Elsewhere { position } => *position,
            };
            let (c, gamma) = (p.x.rem_euclid(360.0), (-p.y).clamp(0.0, 180.0));
            Some(format!(
                "C {c:.1}°, γ {gamma:.1}°: {:.0} {unit_label}",
                factor * table_for_hover.intensity(c, gamma)
            ))
        })
        .show(ui, |plot| {
            // Rows are samples at their centres: the image spans half a
            // row beyond the first and last.
            let row_deg = (g1 - g0) / (ROWS - 1) as f64;
            plot.image(PlotImage::new(
                "",
                texture.id(),
                PlotPoint::new(180.0, -(0.5 * (g0 + g1))),
                egui::vec2(
                    (COLUMNS as f64 * C_STEP_DEG) as f32,
                    ((g1 - g0) + row_deg) as f32,
                ),
            ));
            for line in &cache.lines {
                for polyline in &line.polylines {
                    let points: Vec<[f64; 2]> = polyline.iter().map(|p| [p[0], -p[1]]).collect();
                    // Labelled mid-way, away from the map's edges.
                    if let Some(middle) = points.get(points.len() / 2).copied() {
                        plot.line(Line::new("", points).color(Color32::WHITE).width(1.0));
                        plot.text(
                            Text::new(
                                "",
                                PlotPoint::new(middle[0], middle[1]),
                                format!("{:.0} %", 100.0 * line.level),
                            )
                            .color(Color32::WHITE),
                        );
                    }
                }
            }
        });
}
