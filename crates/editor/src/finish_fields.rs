//! A part's finish in the scene panel, in the numbers a toolmaker uses:
//! the dimples' pitch, depth and punch radius; each wave's amplitude,
//! wavelength and direction; a measured finish's slope spread. Under it,
//! what the finish does to the light: its flat land and rms slope.

use egui::{DragValue, Ui};
use lucerna_scene::finish::{DimplePattern, Finish, Ripple, WaveShape};

use crate::widgets::{degrees, labelled, number};

/// Finish kinds as the combo box lists them.
const KINDS: [&str; 5] = ["none", "dimples", "ripples", "facets", "slopes"];

/// A length in mm fine enough for a finish (micrometres), with a tick
/// beside it where a design may vary it.
fn fine_mm(ui: &mut Ui, label: &str, metres: &mut f64) -> egui::Response {
    let mut mm = *metres * 1000.0;
    let response = labelled(ui, label, |ui| {
        ui.add(
            DragValue::new(&mut mm)
                .clamp_existing_to_range(false)
                .speed(0.001)
                .range(0.0..=100.0)
                .suffix(" mm")
                .max_decimals(4),
        )
    });
    if response.changed() {
        *metres = mm / 1000.0;
    }
    response
}

/// The finish editor; `tick(ui, field, label)` draws a field's Design
/// tick (`field` as `--vary` names it after `PART.finish.`).
pub fn finish_ui(
    ui: &mut Ui,
    finish: &mut Option<Finish>,
    tick: &mut dyn FnMut(&mut Ui, &str, &str),
) {
    let kind = match finish {
        None => "none",
        Some(Finish::Dimples { .. }) => "dimples",
        Some(Finish::Ripples { .. }) => "ripples",
        Some(Finish::Slopes { .. }) => "slopes",
        Some(Finish::HeightMap { .. }) => "height map",
        Some(Finish::Facets { .. }) => "facets",
    };
    let mut chosen = kind;
    labelled(ui, "Finish", |ui| {
        egui::ComboBox::from_id_salt("part finish")
            .selected_text(chosen)
            .show_ui(ui, |ui| {
                for k in KINDS {
                    ui.selectable_value(&mut chosen, k, k);
                }
            })
            .response
    });
    if chosen != kind {
        *finish = default_of_kind(chosen);
    }
    let Some(f) = finish else { return };
    match f {
        Finish::Dimples {
            pitch,
            depth,
            radius,
            pattern,
        } => {
            for (field, label, value) in [
                ("pitch", "Dimple pitch", pitch),
                ("depth", "Dimple depth", depth),
                ("radius", "Punch radius", radius),
            ] {
                ui.horizontal(|ui| {
                    fine_mm(ui, label, value);
                    tick(ui, field, label);
                });
            }
            labelled(ui, "Pattern", |ui| {
                egui::ComboBox::from_id_salt("dimple pattern")
                    .selected_text(match pattern {
                        DimplePattern::Hexagonal => "hexagonal",
                        DimplePattern::Square => "square",
                    })
                    .show_ui(ui, |ui| {
                        ui.selectable_value(pattern, DimplePattern::Hexagonal, "hexagonal");
                        ui.selectable_value(pattern, DimplePattern::Square, "square");
                    })
                    .response
            });
        }
        Finish::Ripples { waves } => {
            let mut remove = None;
            for (i, w) in waves.iter_mut().enumerate() {
                ui.push_id(("wave", i), |ui| {
                    ui.label(format!("Wave {}", i + 1));
                    ui.horizontal(|ui| {
                        fine_mm(ui, "Amplitude", &mut w.amplitude);
                        tick(ui, &format!("waves[{i}].amplitude"), "Amplitude");
                    });
                    ui.horizontal(|ui| {
                        fine_mm(ui, "Wavelength", &mut w.wavelength);
                        tick(ui, &format!("waves[{i}].wavelength"), "Wavelength");
                    });
                    degrees(ui, "Direction (0° along the profile)", &mut w.direction_deg);
                    labelled(ui, "Shape", |ui| {
                        egui::ComboBox::from_id_salt("wave shape")
                            .selected_text(match w.shape {
                                WaveShape::Sine => "sine",
                                WaveShape::Trochoid => "trochoid",
                            })
                            .show_ui(ui, |ui| {
                                ui.selectable_value(&mut w.shape, WaveShape::Sine, "sine");
                                ui.selectable_value(&mut w.shape, WaveShape::Trochoid, "trochoid");
                            })
                            .response
                    });
                    if ui.button("Remove wave").clicked() {
                        remove = Some(i);
                    }
                });
            }
            if let Some(i) = remove
                && waves.len() > 1
            {
                waves.remove(i);
            }
            if ui.button("Add wave").clicked() {
                let last = waves.last().cloned().unwrap_or_else(default_wave);
                waves.push(Ripple {
                    direction_deg: last.direction_deg + 90.0,
                    ..last
                });
            }
        }
        Finish::Slopes {
            sigma_u,
            sigma_v,
            orientation_deg,
        } => {
            ui.horizontal(|ui| {
                number(ui, "Slope σ along", sigma_u, 0.0..=1.0, 0.001, "");
                tick(ui, "sigma_u", "Slope σ along");
            });
            ui.horizontal(|ui| {
                number(ui, "Slope σ across", sigma_v, 0.0..=1.0, 0.001, "");
                tick(ui, "sigma_v", "Slope σ across");
            });
            degrees(ui, "Orientation", orientation_deg);
        }
        Finish::Facets {
            size_along,
            size_around,
        } => {
            ui.horizontal(|ui| {
                fine_mm(ui, "Facet length along", size_along);
                tick(ui, "size_along", "Facet length along");
            });
            ui.horizontal(|ui| {
                fine_mm(ui, "Facet width around", size_around);
                tick(ui, "size_around", "Facet width around");
            });
            ui.weak("Flat facets touching the surface: their spread comes from its curvature");
        }
        Finish::HeightMap {
            path,
            pixel_size,
            height_step,
            ..
        } => {
            // The map is read with the scene file; its scales are edited.
            labelled(ui, "Height map", |ui| ui.label(path.as_str()));
            ui.horizontal(|ui| {
                fine_mm(ui, "Pixel size", pixel_size);
                tick(ui, "pixel_size", "Pixel size");
            });
            ui.horizontal(|ui| {
                let mut um = *height_step * 1e6;
                let r = labelled(ui, "Height per grey level", |ui| {
                    ui.add(
                        DragValue::new(&mut um)
                            .speed(0.001)
                            .range(0.0..=1000.0)
                            .suffix(" µm")
                            .max_decimals(5),
                    )
                });
                if r.changed() {
                    *height_step = um * 1e-6;
                }
                tick(ui, "height_step", "Height per grey level");
            });
        }
    }
    summary_ui(ui, f);
}

/// What the finish does to the light, from its statistics (cached by the
/// finish's numbers: a dimple pattern's integral takes milliseconds).
fn summary_ui(ui: &mut Ui, f: &Finish) {
    if !f.problems().is_empty() {
        return;
    }
    let id = egui::Id::unique(("finish summary", format!("{f:?}")));
    let summary = ui.ctx().memory_mut(|m| {
        *m.data.get_temp_mut_or_insert_with(id, || {
            let s = f.statistics();
            let c = s.covariance;
            (s.flat_share, (c[0] + c[2]).sqrt())
        })
    });
    let (flat, rms) = summary;
    // The pattern's own figures (a revolved part's rings of whole counts
    // overlap a little: the traced part has a few per cent more land).
    ui.weak(format!(
        "Pattern: flat land {:.1} % (a mirror's peak); rms slope {:.3}, turning the rest of the light by {:.1}° rms",
        flat * 100.0,
        rms,
        2.0 * rms.atan().to_degrees()
    ));
}

fn default_wave() -> Ripple {
    Ripple {
        amplitude: 0.01e-3,
        wavelength: 1e-3,
        direction_deg: 0.0,
        shape: WaveShape::Sine,
    }
}

/// A new finish of `kind` with a toolmaker's everyday numbers.
fn default_of_kind(kind: &str) -> Option<Finish> {
    match kind {
        // Nearly touching 0.15 mm dimples of a 3.4 mm punch on 2 mm.
        "dimples" => Some(Finish::Dimples {
            pitch: 2e-3,
            depth: 0.15e-3,
            radius: 3.4e-3,
            pattern: DimplePattern::Hexagonal,
        }),
        "ripples" => Some(Finish::Ripples {
            waves: vec![default_wave()],
        }),
        "facets" => Some(Finish::Facets {
            size_along: 3e-3,
            size_around: 3e-3,
        }),
        "slopes" => Some(Finish::Slopes {
            sigma_u: 0.05,
            sigma_v: 0.05,
            orientation_deg: 0.0,
        }),
        _ => None,
    }
}
