//! The Design pane: a target (a file or a spec), what may vary (ticked in
//! the scene panel and the profile pane), Start and Stop, the merit over
//! time with its noise, and the outcome with its one undo step.

use egui::{DragValue, RichText, Ui};
use egui_plot::{Line, Plot, PlotPoints, Points, Polygon};
use lucerna_design::{Maximise, Phase, Reachability, Stopped};
use lucerna_scene::Shape;

use crate::command::{Command, DialogKind};
use crate::design_state::{DesignState, MeritPoint, SpecForm, TargetKind};
use crate::reference::Reference;
use crate::state::EditorState;
use crate::views::ViewsState;
use crate::widgets::labelled;

pub fn design_pane_ui(ui: &mut Ui, state: &mut EditorState, views: &mut ViewsState) {
    if state.scene().is_none() {
        ui.label("Open a scene to design it.");
        return;
    }
    let mut commands = Vec::new();
    egui::ScrollArea::vertical()
        .auto_shrink([false, false])
        .show(ui, |ui| {
            // The spec's rows may be wider than a narrow pane; what follows
            // them still wraps at the pane's own width.
            let width = ui.available_width();
            ui.label(
                "Shape the luminaire toward the light you want: the photon tracer judges each candidate.",
            );
            let running = state.design.is_running();
            ui.add_enabled_ui(!running, |ui| {
                ui.add_space(4.0);
                ui.strong("Target");
                target_ui(ui, state, &mut commands);
                ui.scope(|ui| {
                    ui.set_max_width(width);
                    ui.add_space(4.0);
                    ui.strong("Variables");
                    variables_ui(ui, state, &mut commands);
                    ui.add_space(4.0);
                    ui.strong("Run");
                    budget_ui(ui, &mut state.design);
                });
            });
            ui.scope(|ui| {
            ui.set_max_width(width);
            ui.horizontal(|ui| {
                if ui
                    .add_enabled(!running, egui::Button::new("Start design"))
                    .clicked()
                {
                    // The target file drawn over the polar and cartesian
                    // views while the design runs.
                    if state.design.setup.target_kind == TargetKind::File
                        && let Some(path) = &state.design.setup.target_file
                        && let Ok(mut r) = Reference::load(path)
                    {
                        r.name = format!("design target {}", r.name);
                        r.at_shown_flux = !state.design.setup.absolute;
                        views.reference = Some(r);
                        views.reference_error = None;
                    }
                    commands.push(Command::StartDesign);
                }
                let stopping = state.design.run.as_ref().is_some_and(|r| r.stopping);
                if ui
                    .add_enabled(running && !stopping, egui::Button::new("Stop design"))
                    .on_hover_text("Ends the design with the best it found so far")
                    .clicked()
                {
                    commands.push(Command::StopDesign);
                }
            });
            if let Some(error) = &state.design.error {
                ui.colored_label(ui.visuals().error_fg_color, error);
            }
            ui.add_space(4.0);
            progress_ui(ui, state, &mut commands);
            });
        });
    for c in commands {
        state.push(c);
    }
}

fn target_ui(ui: &mut Ui, state: &mut EditorState, commands: &mut Vec<Command>) {
    let setup = &mut state.design.setup;
    ui.horizontal(|ui| {
        ui.selectable_value(&mut setup.target_kind, TargetKind::File, "Target file");
        ui.selectable_value(&mut setup.target_kind, TargetKind::Spec, "Spec");
    });
    match setup.target_kind {
        TargetKind::File => {
            ui.horizontal(|ui| {
                let name = setup
                    .target_file
                    .as_ref()
                    .map_or("none chosen".to_owned(), |p| {
                        p.file_name().map_or(p.display().to_string(), |n| {
                            n.to_string_lossy().into_owned()
                        })
                    });
                ui.label(format!("File: {name}"));
                if ui
                    .button("Choose target file…")
                    .on_hover_text("An IES or EULUMDAT file: the distribution to match")
                    .clicked()
                {
                    commands.push(Command::FileDialog(DialogKind::DesignTarget));
                }
            });
            ui.checkbox(&mut setup.absolute, "Match absolute candela")
                .on_hover_text("Off: match the shape, both scaled to the same flux");
        }
        TargetKind::Spec => spec_ui(ui, &mut setup.spec),
    }
}

/// A spec's number, named for accessibility (its row's label is the
/// term's tick).
fn value(ui: &mut Ui, v: &mut f64, range: std::ops::RangeInclusive<f64>, suffix: &str, name: &str) {
    ui.add(
        DragValue::new(v)
            .range(range)
            .speed(0.1)
            .suffix(suffix)
            .max_decimals(2),
    )
    .accessible_name(name);
}

fn angle(ui: &mut Ui, v: &mut f64, range: std::ops::RangeInclusive<f64>, name: &str) {
    value(ui, v, range, "°", name);
}

fn spec_ui(ui: &mut Ui, spec: &mut SpecForm) {
    egui::Grid::new("design spec")
        .num_columns(2)
        .striped(true)
        .show(ui, |ui| {
            ui.checkbox(&mut spec.beam, "Beam angle");
            ui.horizontal(|ui| {
                angle(ui, &mut spec.beam_angle_deg, 0.1..=359.0, "Beam angle (°)");
                ui.label("±");
                angle(
                    ui,
                    &mut spec.beam_tolerance_deg,
                    0.01..=90.0,
                    "Beam tolerance (°)",
                );
            });
            ui.end_row();
            ui.checkbox(&mut spec.field, "Field angle at most");
            angle(
                ui,
                &mut spec.field_angle_max_deg,
                0.1..=359.0,
                "Field angle at most (°)",
            );
            ui.end_row();
            ui.checkbox(&mut spec.cutoff, "Cut-off above γ");
            ui.horizontal(|ui| {
                angle(ui, &mut spec.cutoff_gamma_deg, 0.1..=180.0, "Cut-off γ (°)");
                ui.label("at most");
                value(
                    ui,
                    &mut spec.cutoff_max_percent,
                    0.01..=99.0,
                    " % of the peak",
                    "Cut-off at most (% of the peak)",
                );
            });
            ui.end_row();
            ui.checkbox(&mut spec.lor, "LOR at least");
            value(
                ui,
                &mut spec.lor_min_percent,
                0.1..=100.0,
                " %",
                "LOR at least (%)",
            );
            ui.end_row();
            ui.checkbox(&mut spec.ugr, "UGR at most");
            ui.horizontal(|ui| {
                value(ui, &mut spec.ugr_max, 1.0..=40.0, "", "UGR at most");
                ui.weak("4H × 8H room, 70/50/20 (CIE 190)");
            });
            ui.end_row();
            ui.label("Maximise");
            ui.horizontal(|ui| {
                egui::ComboBox::from_id_salt("design maximise")
                    .selected_text(match spec.maximise {
                        None => "nothing",
                        Some(Maximise::Lor) => "the LOR",
                        Some(Maximise::ConeFlux) => "the flux in a cone",
                    })
                    .show_ui(ui, |ui| {
                        ui.selectable_value(&mut spec.maximise, None, "nothing");
                        ui.selectable_value(&mut spec.maximise, Some(Maximise::Lor), "the LOR");
                        ui.selectable_value(
                            &mut spec.maximise,
                            Some(Maximise::ConeFlux),
                            "the flux in a cone",
                        );
                    });
                if spec.maximise == Some(Maximise::ConeFlux) {
                    ui.label("of half-angle");
                    angle(
                        ui,
                        &mut spec.cone_half_angle_deg,
                        0.1..=180.0,
                        "Cone half-angle (°)",
                    );
                }
            });
            ui.end_row();
        });
    if let Err(why) = spec.spec() {
        ui.colored_label(ui.visuals().error_fg_color, why);
    }
}

fn variables_ui(ui: &mut Ui, state: &mut EditorState, commands: &mut Vec<Command>) {
    let design = &state.design;
    if design.setup.vary.is_empty() {
        ui.label(
            "Nothing ticked yet: tick a parameter in the scene panel (select the part), or a point in the Profile pane.",
        );
    }
    for vary in &design.setup.vary {
        let bounds = design.bounds(vary).unwrap_or_default();
        let text = bounds
            .iter()
            .map(|v| {
                let coordinate = v.name.rsplit_once('.').map_or("", |(_, c)| c);
                let shown = if vary.ends_with(']') {
                    format!("{coordinate} ")
                } else {
                    String::new()
                };
                let (k, unit) = shown_unit(&v.name);
                // A finish's depth (0.037 … 0.150 mm) needs more places
                // than a focal length.
                let places = if (v.upper * k).abs() < 10.0 { 3 } else { 1 };
                format!(
                    "{shown}{} ({:.places$} … {:.places$}{unit})",
                    value_text(&v.name, v.start),
                    v.lower * k,
                    v.upper * k
                )
            })
            .collect::<Vec<_>>()
            .join(", ");
        let mut on = true;
        if ui
            .checkbox(&mut on, format!("{vary}: {text}"))
            .on_hover_text("Untick: it stays as it is")
            .changed()
        {
            commands.push(Command::TickDesignVariable {
                vary: vary.clone(),
                on: false,
            });
        }
    }
    // A profile's interior points at once (the Profile pane ticks them one
    // by one).
    let profiles: Vec<(String, usize)> = state.scene().map_or(Vec::new(), |s| {
        s.parts
            .iter()
            .filter_map(|p| match &p.shape {
                Shape::Revolved(r) => Some((p.name.clone(), r.profile.len())),
                Shape::Extruded(e) => Some((p.name.clone(), e.profile.len())),
                _ => None,
            })
            .collect()
    });
    for (name, n) in profiles {
        if n > 2
            && ui
                .button(format!("Vary the interior points of {name}"))
                .clicked()
        {
            for k in 1..n - 1 {
                commands.push(Command::TickDesignVariable {
                    vary: format!("{name}.profile[{k}]"),
                    on: true,
                });
            }
        }
    }
    if !design.setup.vary.is_empty() && ui.button("Untick all").clicked() {
        for vary in &design.setup.vary {
            commands.push(Command::TickDesignVariable {
                vary: vary.clone(),
                on: false,
            });
        }
    }
}

fn budget_ui(ui: &mut Ui, design: &mut DesignState) {
    let setup = &mut design.setup;
    labelled(ui, "Time", |ui| {
        ui.add(
            DragValue::new(&mut setup.time_s)
                .range(1.0..=86_400.0)
                .speed(1.0)
                .suffix(" s"),
        )
    });
    ui.horizontal(|ui| {
        let mut limited = setup.evaluations.is_some();
        ui.checkbox(&mut limited, "Stop after")
            .on_hover_text("A budget that does not depend on the machine: the same seed gives the same design anywhere");
        let mut n = setup.evaluations.unwrap_or(200);
        ui.add_enabled(limited, DragValue::new(&mut n).range(1..=1_000_000))
            .accessible_name("Candidates at most");
        ui.label("candidates");
        setup.evaluations = limited.then_some(n);
    });
    labelled(ui, "Seed", |ui| ui.add(DragValue::new(&mut setup.seed)));
}

fn progress_ui(ui: &mut Ui, state: &mut EditorState, commands: &mut Vec<Command>) {
    let command_line = state.design.setup.command_line(state.path());
    ui.weak("The same design on the command line:");
    ui.add(egui::Label::new(RichText::new(command_line).monospace().small()).selectable(true));
    if state.design.setup.target_kind == TargetKind::Spec {
        ui.collapsing("SPEC.toml", |ui| {
            ui.add(
                egui::Label::new(RichText::new(state.design.setup.spec.to_toml()).monospace())
                    .selectable(true),
            );
        });
    }
    if let Some(run) = &state.design.run {
        let elapsed = run.began.elapsed().as_secs_f64();
        let doing = if run.stopping { "Stopping" } else { "Running" };
        match &run.latest {
            Some(p) => {
                let what = match (p.phase, p.photons) {
                    (Phase::Start, _) => "tracing the start".to_owned(),
                    (Phase::Direct, 0) => {
                        "direct design: the energy-balance mappings polished in the meridian model"
                            .to_owned()
                    }
                    (Phase::Direct, _) => "direct design: the best mappings traced".to_owned(),
                    (Phase::Correction, _) => {
                        "correcting for the extended source (traced, aimed again)".to_owned()
                    }
                    (Phase::Refinement, photons) => format!(
                        "refining with the tracer in the loop ({} photons a candidate)",
                        photons
                    ),
                    (Phase::Fallback, 0) => {
                        "fallback: the meridian model's global search".to_owned()
                    }
                    (Phase::Fallback, _) => "fallback: its best traced".to_owned(),
                    (Phase::Survey, _) => {
                        "surveying the variables' range (evenly across their bounds)".to_owned()
                    }
                };
                ui.label(format!(
                    "{doing}, {elapsed:.1} s of {:.0} s toward {}: {what}; {} candidates; best {:.4}{}",
                    state.design.setup.time_s,
                    run.target_name,
                    p.evaluations,
                    p.best_merit,
                    if p.photons == 0 { " (model)" } else { "" }
                ));
                for (v, x) in p
                    .frame
                    .variables
                    .iter()
                    .zip(&p.best_values)
                    .take(SHOWN_VALUES)
                {
                    ui.weak(format!("{} = {}", v.name, value_text(&v.name, *x)));
                }
                if p.frame.variables.len() > SHOWN_VALUES {
                    ui.weak(format!(
                        "… and {} more (the Profile pane shows them all)",
                        p.frame.variables.len() - SHOWN_VALUES
                    ));
                }
            }
            None => {
                ui.label(format!(
                    "{doing}, {elapsed:.1} s: what the geometry can reach…"
                ));
            }
        }
        merit_plot_ui(ui, &run.history);
        if let Some(r) = &run.reach {
            reach_ui(ui, r, None);
        }
        return;
    }
    let Some(outcome) = &state.design.outcome else {
        return;
    };
    let why = match outcome.stopped {
        Stopped::Converged => "converged (the last stage agrees within its noise)",
        Stopped::Time => "its time is up",
        Stopped::Evaluations => "it traced the candidates it was given",
        Stopped::Interrupted => "stopped: the best so far",
    };
    ui.label(format!(
        "Design ended, {why}: {} candidates in {:.1} s; merit {:.4} at the start, now {:.4} ± {:.4}.",
        outcome.evaluations, outcome.seconds, outcome.start_merit, outcome.merit, outcome.noise
    ));
    egui::Grid::new("design outcome")
        .num_columns(3)
        .striped(true)
        .show(ui, |ui| {
            ui.strong("Variable");
            ui.strong("Start");
            ui.strong("Designed");
            ui.end_row();
            for (name, start, designed) in &outcome.variables {
                ui.label(name);
                ui.label(value_text(name, *start));
                ui.label(value_text(name, *designed));
                ui.end_row();
            }
        });
    if matches!(outcome.target, lucerna_design::Target::Distribution { .. }) {
        ui.label(format!(
            "Remaining difference to the target (relative L2 on the sphere, {} photons): {:.4} ± {:.4}",
            outcome.photons, outcome.merit, outcome.noise
        ));
    }
    if let Some(n) = outcome.points {
        ui.label(format!("The designed profile has {n} control points."));
    }
    let current = state.scene() == Some(&outcome.scene);
    if ui
        .add_enabled(
            current && state.can_undo(),
            egui::Button::new("Undo design"),
        )
        .on_hover_text("Back to the scene before the design: one undo step for the whole run")
        .clicked()
    {
        commands.push(Command::Undo);
    }
    merit_plot_ui(ui, &outcome.history);
    if let Some(r) = &outcome.reach {
        reach_ui(ui, r, Some(outcome.merit));
    }
    if let Some(s) = &outcome.survey {
        survey_ui(ui, s);
    }
}

/// How far each term went across the surveyed range, and what no traced
/// candidate met.
fn survey_ui(ui: &mut Ui, s: &lucerna_design::Survey) {
    ui.add_space(4.0);
    ui.strong("Across the range");
    ui.label(format!(
        "{} candidates traced across {}: merit {:.4} … {:.4}.",
        s.traced,
        // The pane's units (mm, °), not the file's metres.
        s.across_with(value_text),
        s.merit_range[0],
        s.merit_range[1]
    ));
    for t in &s.terms {
        ui.label(format!(
            "{}: {:.3} … {:.3}, wanted {}, met by {} of {}",
            t.term, t.lowest, t.highest, t.wanted, t.met_by, s.traced
        ));
    }
    for f in s.findings() {
        ui.colored_label(ui.visuals().warn_fg_color, capitalised(&f));
    }
}

/// A sentence's first letter in capitals.
fn capitalised(s: &str) -> String {
    let mut c = s.chars();
    c.next()
        .map(|f| f.to_uppercase().chain(c).collect())
        .unwrap_or_default()
}

/// Values listed while a design runs, at most (a profile of 33 points
/// has 62).
const SHOWN_VALUES: usize = 8;

/// What the geometry can reach, and, with the design's result, what
/// would help.
fn reach_ui(ui: &mut Ui, r: &Reachability, result: Option<f64>) {
    ui.add_space(4.0);
    ui.strong("What this geometry can reach");
    ui.label(format!(
        "The LED's direct light leaves through a {:.1}° cone: at least {:.1} % of any design's light is there; the target has {:.1} % there.",
        r.direct_cone_deg,
        100.0 * r.design_cone_share_min,
        100.0 * r.target_cone_share
    ));
    ui.label(format!(
        "No mirror between these ends that stays out of that cone can come closer than {:.4}; one reaching into it shades the direct light and could come down to {:.4}.",
        r.bound, r.with_cap
    ));
    let aim = result.unwrap_or(0.02).min(0.02);
    for a in r.advice(aim) {
        ui.weak(format!("What would help: {a}"));
    }
}

/// A merit with two significant digits (the log plot's marks).
fn significant(v: f64) -> String {
    if !(v > 0.0) {
        return "0".to_owned();
    }
    let decimals = (1.0 - v.log10().floor()).max(0.0) as usize;
    format!("{v:.decimals$}")
}

/// A length in mm, an angle in degrees.
fn value_text(name: &str, value: f64) -> String {
    let (k, unit) = shown_unit(name);
    format!("{:.3}{unit}", value * k)
}

/// How a variable is shown: degrees, a finish's slopes as they are
/// (rms slope, no unit), lengths in mm.
fn shown_unit(name: &str) -> (f64, &'static str) {
    if name.ends_with("_deg") {
        (1.0, "°")
    } else if name.ends_with(".sigma_u") || name.ends_with(".sigma_v") {
        (1.0, "")
    } else {
        (1000.0, " mm")
    }
}

/// Every traced candidate's merit against time, the best of each stage
/// with its photon noise as a band.
fn merit_plot_ui(ui: &mut Ui, history: &[MeritPoint]) {
    if history.is_empty() {
        return;
    }
    let colour = ui.visuals().widgets.inactive.fg_stroke.color;
    let accent = ui.visuals().selection.bg_fill;
    // Logarithmic: a design takes its merit down by decades.
    let log = |m: f64| m.max(1e-6).log10();
    // Fixed: within the pane's scroll area the height left is unbounded.
    let height = 200.0;
    Plot::new("design merit")
        .height(height)
        .legend(egui_plot::Legend::default())
        .x_axis_label("s")
        .y_axis_label("merit (log)")
        .y_axis_formatter(|mark, _| significant(10f64.powf(mark.value)))
        .label_formatter(|hover| {
            let p = match hover {
                egui_plot::HoverPosition::NearDataPoint { position, .. } => position,
                egui_plot::HoverPosition::Elsewhere { position } => position,
            };
            Some(format!("{:.1} s: merit {:.4}", p.x, 10f64.powf(p.y)))
        })
        .allow_scroll(false)
        .show(ui, |plot| {
            let traced: Vec<[f64; 2]> = history
                .iter()
                .filter(|p| p.photons > 0)
                .map(|p| [p.elapsed_s, log(p.merit)])
                .collect();
            let modelled: Vec<[f64; 2]> = history
                .iter()
                .filter(|p| p.photons == 0)
                .map(|p| [p.elapsed_s, log(p.merit)])
                .collect();
            if !modelled.is_empty() {
                plot.points(
                    Points::new("meridian model", PlotPoints::from(modelled))
                        .radius(1.5)
                        .filled(false)
                        .color(colour.gamma_multiply(0.6)),
                );
            }
            plot.points(
                Points::new("traced candidates", PlotPoints::from(traced))
                    .radius(1.5)
                    .color(colour),
            );
            // The best of each run of traced candidates at one phase and
            // photon count, with its photon noise as a band.
            let traced: Vec<&MeritPoint> = history.iter().filter(|p| p.photons > 0).collect();
            let mut stage_start = 0;
            for k in 1..=traced.len() {
                let same = |a: &MeritPoint, b: &MeritPoint| {
                    a.phase == b.phase && a.photons == b.photons && a.stage == b.stage
                };
                if k < traced.len() && same(traced[k], traced[stage_start]) {
                    continue;
                }
                let stage = &traced[stage_start..k];
                let best: Vec<[f64; 2]> =
                    stage.iter().map(|p| [p.elapsed_s, log(p.best)]).collect();
                let band: Vec<[f64; 2]> = stage
                    .iter()
                    .map(|p| [p.elapsed_s, log(p.best + p.noise)])
                    .chain(
                        stage
                            .iter()
                            .rev()
                            .map(|p| [p.elapsed_s, log((p.best - p.noise).max(0.2 * p.best))]),
                    )
                    .collect();
                let name = format!(
                    "best, {} ({} photons)",
                    stage[0].phase.name(),
                    stage[0].photons
                );
                if stage.len() > 1 && stage.iter().any(|p| p.noise > 0.0) {
                    plot.polygon(
                        Polygon::new(format!("{name} noise"), PlotPoints::from(band))
                            .fill_color(accent.gamma_multiply(0.3))
                            .stroke(egui::Stroke::NONE),
                    );
                }
                plot.line(
                    Line::new(name, PlotPoints::from(best))
                        .color(accent)
                        .width(2.0),
                );
                stage_start = k;
            }
        });
}
