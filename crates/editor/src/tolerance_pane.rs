//! The Tolerance pane: what manufacturing does to the selected part or
//! emitter (its placement's σ, a profile's form error, a mirror's slope
//! error), every tolerance set, the Design pane's spec, Run and Stop, and
//! the yield and each figure's histogram filling in as the samples
//! arrive; a click on a bar opens the worst sample in it.

use egui::{Color32, DragValue, RichText, Ui};
use egui_plot::{Bar, BarChart, Plot, VLine};
use lucerna_scene::{Material, Scene};
use lucerna_tolerance::report::shown;
use lucerna_tolerance::statistics::Fraction;

use crate::command::Command;
use crate::selection::Selection;
use crate::state::EditorState;
use crate::tolerance_state::{FormErrorForm, PLACEMENTS, SlopeErrorForm, ToleranceSetup};
use crate::widgets::labelled;

const PASS: Color32 = Color32::from_rgb(70, 120, 200);
const FAIL: Color32 = Color32::from_rgb(210, 60, 50);

pub fn tolerance_pane_ui(ui: &mut Ui, state: &mut EditorState) {
    let Some(scene) = state.scene().cloned() else {
        ui.label("Open a scene to analyse its tolerances.");
        return;
    };
    state.tolerance.setup.keep_only_what(&scene);
    let mut commands = Vec::new();
    egui::ScrollArea::vertical()
        .auto_shrink([false, false])
        .show(ui, |ui| {
            ui.label(
                "Will the luminaire that is built meet the spec? Each sample is the luminaire built with what manufacturing does to it, traced with the nominal's photons.",
            );
            let running = state.tolerance.is_running();
            ui.add_enabled_ui(!running, |ui| {
                ui.add_space(4.0);
                ui.label(
                    "A part's or an emitter's tolerances are set in the scene panel, under its parameters: select it.",
                );
                ui.add_space(4.0);
                ui.strong("Every tolerance");
                all_ui(ui, &mut state.tolerance.setup);
                ui.add_space(4.0);
                ui.strong("Spec (the Design pane's)");
                let spec = state.design.setup.spec.to_toml();
                if spec.is_empty() {
                    ui.label("No term: set one in the Design pane's Spec.");
                } else {
                    ui.label(RichText::new(spec.trim_end()).monospace());
                }
                ui.add_space(4.0);
                labelled(ui, "Samples", |ui| {
                    ui.add(
                        DragValue::new(&mut state.tolerance.setup.samples)
                            .range(1..=100_000)
                            .speed(5),
                    )
                });
                labelled(ui, "Photons per sample", |ui| {
                    ui.add(
                        DragValue::new(&mut state.tolerance.setup.photons)
                            .range(1_000..=100_000_000)
                            .speed(10_000),
                    )
                });
            });
            ui.horizontal(|ui| {
                if ui
                    .add_enabled(!running, egui::Button::new("Run tolerance analysis"))
                    .clicked()
                {
                    commands.push(Command::StartTolerance);
                }
                let stopping = state.tolerance.run.as_ref().is_some_and(|r| r.stopping);
                if ui
                    .add_enabled(running && !stopping, egui::Button::new("Stop analysis"))
                    .clicked()
                {
                    commands.push(Command::StopTolerance);
                }
            });
            if let Some(e) = &state.tolerance.error {
                ui.colored_label(ui.visuals().error_fg_color, e);
            }
            progress_ui(ui, state);
            histograms_ui(ui, state, &mut commands);
        });
    for c in commands {
        state.push(c);
    }
}

/// The tolerances of the selected part or emitter (shown by the scene
/// panel under its parameters).
pub(crate) fn selected_ui(
    ui: &mut Ui,
    scene: &Scene,
    selection: Option<&Selection>,
    setup: &mut ToleranceSetup,
) {
    let (name, part) = match selection {
        Some(Selection::Part(i)) if *i < scene.parts.len() => (&scene.parts[*i].name, Some(*i)),
        Some(Selection::Emitter(i)) if *i < scene.emitters.len() => {
            (&scene.emitters[*i].name, None)
        }
        _ => return,
    };
    ui.strong(format!("Tolerances of '{name}' (normal σ)"));
    egui::Grid::new("tolerance placements")
        .num_columns(3)
        .show(ui, |ui| {
            for (field, unit) in PLACEMENTS {
                let at = format!("{name}.{field}");
                let current = setup.placement(&at);
                let mut on = current.is_some();
                if ui.checkbox(&mut on, field).changed() {
                    setup.set_placement(&at, on.then_some(if unit == "mm" { 0.1 } else { 0.5 }));
                }
                let mut sigma = current.unwrap_or(if unit == "mm" { 0.1 } else { 0.5 });
                let response = ui.add_enabled(
                    on,
                    DragValue::new(&mut sigma)
                        .range(1e-6..=100.0)
                        .speed(0.01)
                        .max_decimals(4)
                        .suffix(format!(" {unit}")),
                );
                let enabled = response.enabled();
                response.widget_info(|| egui::WidgetInfo {
                    label: Some(format!("σ {field}")),
                    ..egui::WidgetInfo::drag_value(enabled, sigma)
                });
                if on && response.changed() {
                    setup.set_placement(&at, Some(sigma));
                }
                ui.end_row();
            }
        });
    let Some(part) = part else { return };
    let p = &scene.parts[part];
    if lucerna_tolerance::tolerances::has_profile(&p.shape) {
        let k = setup.form_errors.iter().position(|f| f.part == p.name);
        let mut on = k.is_some();
        ui.horizontal(|ui| {
            if ui.checkbox(&mut on, "Form error").changed() {
                if on {
                    setup.form_errors.push(FormErrorForm {
                        part: p.name.clone(),
                        sigma_mm: 0.05,
                        correlation_mm: 10.0,
                    });
                } else if let Some(k) = k {
                    setup.form_errors.remove(k);
                }
            }
            if let Some(f) = setup.form_errors.iter_mut().find(|f| f.part == p.name) {
                ui.label("σ");
                ui.add(
                    DragValue::new(&mut f.sigma_mm)
                        .range(1e-5..=10.0)
                        .speed(0.005)
                        .max_decimals(4)
                        .suffix(" mm"),
                );
                ui.label("along")
                    .on_hover_text("correlation length along the profile");
                ui.add(
                    DragValue::new(&mut f.correlation_mm)
                        .range(0.01..=1000.0)
                        .speed(0.5)
                        .suffix(" mm"),
                );
            }
        });
    }
    let shiny = matches!(
        scene.materials.get(&p.material),
        Some(Material::Mirror { .. } | Material::RoughConductor { .. })
    );
    if shiny {
        let k = setup.slope_errors.iter().position(|s| s.part == p.name);
        let mut on = k.is_some();
        ui.horizontal(|ui| {
            if ui.checkbox(&mut on, "Slope error").changed() {
                if on {
                    setup.slope_errors.push(SlopeErrorForm {
                        part: p.name.clone(),
                        sigma_mrad: 1.0,
                    });
                } else if let Some(k) = k {
                    setup.slope_errors.remove(k);
                }
            }
            if let Some(s) = setup.slope_errors.iter_mut().find(|s| s.part == p.name) {
                ui.label("σ");
                ui.add(
                    DragValue::new(&mut s.sigma_mrad)
                        .range(0.01..=200.0)
                        .speed(0.05)
                        .suffix(" mrad"),
                );
            }
        });
    }
}

/// Every tolerance set, each with a remove button.
fn all_ui(ui: &mut Ui, setup: &mut ToleranceSetup) {
    if setup.placements.is_empty() && setup.form_errors.is_empty() && setup.slope_errors.is_empty()
    {
        ui.label("None yet.");
        return;
    }
    let mut remove_placement = None;
    for (i, p) in setup.placements.iter().enumerate() {
        ui.horizontal(|ui| {
            let unit = if p.at.contains(".translate_") {
                "mm"
            } else {
                "°"
            };
            ui.label(format!("{}: σ {} {unit}", p.at, p.sigma));
            if ui.small_button("Remove").clicked() {
                remove_placement = Some(i);
            }
        });
    }
    if let Some(i) = remove_placement {
        setup.placements.remove(i);
    }
    let mut remove_form = None;
    for (i, f) in setup.form_errors.iter().enumerate() {
        ui.horizontal(|ui| {
            ui.label(format!(
                "{} form error: σ {} mm over {} mm",
                f.part, f.sigma_mm, f.correlation_mm
            ));
            if ui.small_button("Remove").clicked() {
                remove_form = Some(i);
            }
        });
    }
    if let Some(i) = remove_form {
        setup.form_errors.remove(i);
    }
    let mut remove_slope = None;
    for (i, s) in setup.slope_errors.iter().enumerate() {
        ui.horizontal(|ui| {
            ui.label(format!("{} slope error: σ {} mrad", s.part, s.sigma_mrad));
            if ui.small_button("Remove").clicked() {
                remove_slope = Some(i);
            }
        });
    }
    if let Some(i) = remove_slope {
        setup.slope_errors.remove(i);
    }
}

/// The yield so far and each term's.
fn progress_ui(ui: &mut Ui, state: &EditorState) {
    let t = &state.tolerance;
    let records = t.records();
    if let Some(run) = &t.run {
        if run.reference.is_none() {
            ui.label("Tracing the nominal and its photon noise…");
            ui.ctx().request_repaint();
            return;
        }
        ui.label(format!(
            "{} of {} samples in {:.0} s",
            records.len(),
            t.setup.samples,
            run.began.elapsed().as_secs_f64()
        ));
    }
    if records.is_empty() {
        return;
    }
    let passed = records.iter().filter(|r| r.passes()).count();
    let y = Fraction::wilson(passed, records.len());
    ui.label(
        RichText::new(format!(
            "Yield {:.1} % (95 %: {:.1}–{:.1} %) of {} built luminaires",
            100.0 * y.value,
            100.0 * y.low,
            100.0 * y.high,
            records.len()
        ))
        .strong(),
    );
    let refused = records.iter().filter(|r| r.refused.is_some()).count();
    if refused > 0 {
        ui.label(format!("{refused} could not be built (counted as failed)"));
    }
    if let Some(first) = records.iter().find_map(|r| r.measured.as_ref()) {
        for (j, term) in first.terms.iter().enumerate() {
            let met = records
                .iter()
                .filter(|r| r.measured.as_ref().is_some_and(|m| m.terms[j].met))
                .count();
            ui.label(format!(
                "  {} ({}): {:.1} %",
                term.term,
                term.wanted,
                100.0 * met as f64 / records.len() as f64
            ));
        }
    }
    if let Some(o) = &t.outcome
        && let Some(w) = &o.report.worst
    {
        ui.label(format!("Worst sample {}: {}", w.index, w.missed.join("; ")));
    }
}

/// Each figure's histogram; a click on a bar opens its worst sample.
fn histograms_ui(ui: &mut Ui, state: &EditorState, commands: &mut Vec<Command>) {
    let t = &state.tolerance;
    let (Some(setup), Some(reference)) = (t.analysis(), t.reference()) else {
        return;
    };
    let records = t.records();
    if records.is_empty() {
        return;
    }
    ui.add_space(4.0);
    ui.label("Click a bar to open its worst sample as the scene (one undo step back).");
    for (f, figure) in setup.figures.iter().enumerate() {
        if !shown(*figure) {
            continue;
        }
        let values: Vec<(u32, f64, f64)> = records
            .iter()
            .filter_map(|r| {
                r.measured
                    .as_ref()
                    .map(|m| (r.index, m.values[f], m.shortfall))
            })
            .filter(|(_, v, _)| v.is_finite())
            .collect();
        if values.is_empty() {
            continue;
        }
        let limits = lucerna_tolerance::picture::limits(setup, *figure);
        let nominal = reference.nominal.values[f];
        let bins = histogram(&values, nominal, limits);
        ui.label(figure.label());
        let response = Plot::new(("tolerance histogram", f))
            .height(110.0)
            .allow_drag(false)
            .allow_zoom(false)
            .allow_scroll(false)
            .show_y(false)
            .show(ui, |plot| {
                let bars: Vec<Bar> = bins
                    .bars
                    .iter()
                    .map(|b| {
                        Bar::new(b.centre, b.samples.len() as f64)
                            .width(bins.width * 0.95)
                            .fill(if b.outside { FAIL } else { PASS })
                    })
                    .collect();
                plot.bar_chart(BarChart::new(figure.label(), bars));
                for x in [limits.0, limits.1].into_iter().flatten() {
                    plot.vline(VLine::new("spec limit", x).color(FAIL).width(2.0));
                }
                if nominal.is_finite() {
                    plot.vline(VLine::new("nominal", nominal).color(Color32::GRAY));
                }
            });
        if response.response.clicked()
            && let Some(pos) = response.response.interact_pointer_pos()
        {
            let x = response.transform.value_from_position(pos).x;
            if let Some(bar) = bins
                .bars
                .iter()
                .find(|b| (x - b.centre).abs() <= 0.5 * bins.width)
                && let Some(worst) = bar.worst
            {
                commands.push(Command::OpenToleranceSample(worst));
            }
        }
    }
}

struct HistogramBar {
    centre: f64,
    samples: Vec<u32>,
    /// The sample in it with the largest shortfall.
    worst: Option<u32>,
    outside: bool,
}

struct Histogram {
    bars: Vec<HistogramBar>,
    width: f64,
}

/// The samples' values in the report picture's bins
/// ([`lucerna_tolerance::picture::Binning`]), each bar with its worst
/// sample.
fn histogram(
    values: &[(u32, f64, f64)],
    nominal: f64,
    (lower, upper): (Option<f64>, Option<f64>),
) -> Histogram {
    let plain: Vec<f64> = values.iter().map(|v| v.1).collect();
    let binning = lucerna_tolerance::picture::Binning::over(&plain, &[Some(nominal), lower, upper]);
    let mut bars: Vec<HistogramBar> = (0..binning.bins)
        .map(|k| {
            let centre = binning.centre(k);
            HistogramBar {
                centre,
                samples: Vec::new(),
                worst: None,
                outside: lower.is_some_and(|l| centre < l) || upper.is_some_and(|u| centre > u),
            }
        })
        .collect();
    let mut worst_shortfall = vec![f64::NEG_INFINITY; binning.bins];
    for &(index, v, shortfall) in values {
        let k = binning.index(v);
        bars[k].samples.push(index);
        if shortfall > worst_shortfall[k] {
            worst_shortfall[k] = shortfall;
            bars[k].worst = Some(index);
        }
    }
    Histogram {
        bars,
        width: binning.width,
    }
}
