//! Labelled input widgets: every field carries its label as its accessible
//! name, so screen readers and the kittest tests find it by that name.

use egui::{DragValue, Response, Ui};

/// A length stored in metres, edited in millimetres.
pub fn length_mm(ui: &mut Ui, label: &str, metres: &mut f64, max_mm: f64) -> Response {
    let mut mm = *metres * 1000.0;
    let response = labelled(ui, label, |ui| {
        ui.add(
            DragValue::new(&mut mm)
                .clamp_existing_to_range(false)
                .speed(0.1)
                .range(0.0..=max_mm)
                .suffix(" mm")
                .max_decimals(3),
        )
    });
    // Written back only on a change, so the stored metres never drift by
    // the round trip through millimetres.
    if response.changed() {
        *metres = mm / 1000.0;
    }
    response
}

/// A signed length stored in metres, edited in millimetres.
pub fn offset_mm(ui: &mut Ui, label: &str, metres: &mut f64) -> Response {
    let mut mm = *metres * 1000.0;
    let response = labelled(ui, label, |ui| {
        ui.add(
            DragValue::new(&mut mm)
                .clamp_existing_to_range(false)
                .speed(0.1)
                .range(-10_000.0..=10_000.0)
                .suffix(" mm")
                .max_decimals(3),
        )
    });
    if response.changed() {
        *metres = mm / 1000.0;
    }
    response
}

/// An angle in degrees.
pub fn degrees(ui: &mut Ui, label: &str, deg: &mut f64) -> Response {
    labelled(ui, label, |ui| {
        ui.add(
            DragValue::new(deg)
                .clamp_existing_to_range(false)
                .speed(0.5)
                .range(-360.0..=360.0)
                .suffix("°"),
        )
    })
}

/// A plain number with a unit suffix and a range.
pub fn number(
    ui: &mut Ui,
    label: &str,
    value: &mut f64,
    range: std::ops::RangeInclusive<f64>,
    speed: f64,
    suffix: &str,
) -> Response {
    labelled(ui, label, |ui| {
        ui.add(
            DragValue::new(value)
                .clamp_existing_to_range(false)
                .speed(speed)
                .range(range)
                .suffix(suffix),
        )
    })
}

/// A count of segments (tessellation resolution).
pub fn segments(ui: &mut Ui, label: &str, value: &mut u32, min: u32) -> Response {
    labelled(ui, label, |ui| {
        ui.add(
            DragValue::new(value)
                .clamp_existing_to_range(false)
                .speed(0.2)
                .range(min..=2048),
        )
    })
}

/// A checkbox (its text is its accessible name already).
pub fn flag(ui: &mut Ui, label: &str, value: &mut bool) -> Response {
    ui.checkbox(value, label)
}

/// A single-line text field.
pub fn text(ui: &mut Ui, label: &str, value: &mut String) -> Response {
    labelled(ui, label, |ui| ui.text_edit_singleline(value))
}

/// `label` then the widget on one row, the widget labelled by it.
pub fn labelled(ui: &mut Ui, label: &str, widget: impl FnOnce(&mut Ui) -> Response) -> Response {
    ui.horizontal(|ui| {
        let label = ui.label(label);
        widget(ui).labelled_by(label.id)
    })
    .inner
}

/// What an export wrote, or why it wrote nothing: the export dialogs'
/// last line.
pub fn export_result_ui(
    ui: &mut egui::Ui,
    result: Option<&Result<Vec<std::path::PathBuf>, String>>,
) {
    match result {
        Some(Ok(files)) => {
            ui.label(format!("Wrote {} files:", files.len()));
            for f in files {
                ui.label(f.display().to_string());
            }
        }
        Some(Err(e)) => {
            ui.colored_label(
                ui.visuals().error_fg_color,
                format!("Export failed, nothing written: {e}"),
            );
        }
        None => {}
    }
}
