//! The simulation panel: progress, figures, noise and warnings of the
//! newest snapshot, and the run's controls.

use egui::Ui;
use lucerna_simulation::{BackendRequest, FilterChoice, Snapshot};

use crate::state::{Command, EditorState};

/// Cube-map resolutions offered (texels per face edge).
const RESOLUTIONS: [u32; 5] = [32, 64, 128, 256, 512];
/// The photon threshold a manual filter starts from: the paper's fixed
/// rule, which the automatic filter also weighs.
const DEFAULT_THRESHOLD_PHOTONS: f64 = 100.0;
/// The peak noise a new stopping rule aims at (%): a figure that no
/// longer moves in a datasheet's precision.
const DEFAULT_PEAK_NOISE_PERCENT: f64 = 1.0;

pub fn simulation_panel_ui(ui: &mut Ui, state: &mut EditorState) {
    ui.heading("Simulation");
    let mut commands = Vec::new();
    controls_ui(ui, state, &mut commands);
    ui.separator();
    if let Some(error) = &state.run.sim_error {
        ui.colored_label(ui.visuals().error_fg_color, error);
    }
    match &state.run.snapshot {
        Some(s) => figures_ui(ui, s),
        None if state.doc.scene.is_some() => {
            ui.label("Preparing the luminaire…");
        }
        None => {}
    }
    for c in commands {
        state.push(c);
    }
}

fn controls_ui(ui: &mut Ui, state: &EditorState, commands: &mut Vec<Command>) {
    ui.horizontal(|ui| {
        if state.run.paused {
            if ui.button("Resume").clicked() {
                commands.push(Command::Resume);
            }
        } else if ui.button("Pause").clicked() {
            commands.push(Command::Pause);
        }
    });
    let mut settings = state.run.settings;
    crate::widgets::labelled(ui, "Backend", |ui| {
        egui::ComboBox::from_id_salt("backend")
            .selected_text(backend_name(settings.backend))
            .show_ui(ui, |ui| {
                for b in [
                    BackendRequest::Auto,
                    BackendRequest::Cpu,
                    BackendRequest::Gpu,
                ] {
                    ui.selectable_value(&mut settings.backend, b, backend_name(b));
                }
            })
            .response
    });
    crate::widgets::labelled(ui, "Resolution", |ui| {
        egui::ComboBox::from_id_salt("resolution")
            .selected_text(format!("{} per face", settings.resolution))
            .show_ui(ui, |ui| {
                for r in RESOLUTIONS {
                    ui.selectable_value(&mut settings.resolution, r, format!("{r} per face"));
                }
            })
            .response
    });
    if state.is_coarse_preview()
        && let Some(s) = &state.run.snapshot
    {
        ui.label(format!(
            "Coarse preview while dragging ({} per face)",
            s.map.layout.resolution
        ));
    }
    filter_ui(ui, &mut settings.filter);
    ui.checkbox(&mut settings.pool_symmetry, "Symmetry pooling");
    let mut stop_at_noise = settings.stop.peak_relative_error.is_some();
    ui.horizontal(|ui| {
        ui.checkbox(&mut stop_at_noise, "Stop at peak noise");
        if let Some(error) = &mut settings.stop.peak_relative_error {
            let mut percent = *error * 100.0;
            let response = ui
                .add(
                    egui::DragValue::new(&mut percent)
                        .speed(0.05)
                        .range(0.05..=50.0)
                        .max_decimals(2)
                        .suffix(" %"),
                )
                .accessible_name("Target peak noise");
            if response.changed() {
                *error = percent / 100.0;
            }
        }
    });
    if stop_at_noise != settings.stop.peak_relative_error.is_some() {
        settings.stop.peak_relative_error =
            stop_at_noise.then_some(DEFAULT_PEAK_NOISE_PERCENT / 100.0);
    }
    crate::widgets::labelled(ui, "Max bounces", |ui| {
        ui.add(
            egui::DragValue::new(&mut settings.max_bounces)
                .speed(0.2)
                .range(1..=100_000),
        )
    });
    if settings != state.run.settings {
        commands.push(Command::SetSettings(settings));
    }
}

fn backend_name(backend: BackendRequest) -> &'static str {
    match backend {
        BackendRequest::Auto => "Automatic",
        BackendRequest::Cpu => "CPU",
        BackendRequest::Gpu => "GPU",
    }
}

/// Off, automatic, or a manual photon threshold with its field.
fn filter_ui(ui: &mut Ui, filter: &mut FilterChoice) {
    #[derive(Clone, Copy, PartialEq)]
    enum Mode {
        Off,
        Automatic,
        Manual,
    }
    let current = match filter {
        FilterChoice::Raw => Mode::Off,
        FilterChoice::Automatic => Mode::Automatic,
        FilterChoice::Threshold(_) => Mode::Manual,
    };
    let name = |m: Mode| match m {
        Mode::Off => "Off (raw counts)",
        Mode::Automatic => "Automatic",
        Mode::Manual => "Manual threshold",
    };
    let mut mode = current;
    crate::widgets::labelled(ui, "Filter", |ui| {
        egui::ComboBox::from_id_salt("filter")
            .selected_text(name(mode))
            .show_ui(ui, |ui| {
                for m in [Mode::Off, Mode::Automatic, Mode::Manual] {
                    ui.selectable_value(&mut mode, m, name(m));
                }
            })
            .response
    });
    if mode != current {
        *filter = match mode {
            Mode::Off => FilterChoice::Raw,
            Mode::Automatic => FilterChoice::Automatic,
            Mode::Manual => FilterChoice::Threshold(DEFAULT_THRESHOLD_PHOTONS),
        };
    }
    if let FilterChoice::Threshold(photons) = filter {
        crate::widgets::number(ui, "Photon threshold", photons, 1.0..=1e9, 1.0, " photons");
    }
}

fn angle(a: Option<f64>) -> String {
    a.map_or_else(|| "—".to_owned(), |a| format!("{a:.1}°"))
}

fn figures_ui(ui: &mut Ui, s: &Snapshot) {
    let f = &s.figures;
    egui::Grid::new("figures")
        .num_columns(2)
        .striped(true)
        .show(ui, |ui| {
            let mut row = |name: &str, value: String| {
                ui.label(name);
                // Values (adapter names) can run long: cut to the panel,
                // in full on hover.
                ui.add(egui::Label::new(value.clone()).truncate())
                    .on_hover_text(value);
                ui.end_row();
            };
            row("State", format!("{:?}", s.state));
            row("Iteration", s.iteration.to_string());
            row("Photons", format!("{:.3e}", s.photons as f64));
            row("Photons/s", format!("{:.3e}", s.photons_per_second));
            row("Backend", format!("{} ({})", s.backend, s.backend_reason));
            row(
                "Noise (peak)",
                format!("{:.2} %", 100.0 * s.noise.peak_relative),
            );
            row(
                "Noise (flux)",
                format!("{:.3} %", 100.0 * s.noise.flux_relative),
            );
            row("Flux", format!("{:.1} lm", f.flux_lm));
            row(
                "LOR",
                f.light_output_ratio
                    .map_or_else(|| "—".to_owned(), |l| format!("{:.1} %", 100.0 * l)),
            );
            row("Peak", format!("{:.0} cd", f.peak_cd));
            row(
                "Peak direction",
                format!("C {:.1}°, γ {:.1}°", f.peak_c_deg, f.peak_gamma_deg),
            );
            row("Beam C0-C180", angle(f.beam_angle_deg[0]));
            row("Beam C90-C270", angle(f.beam_angle_deg[1]));
            row("Field C0-C180", angle(f.field_angle_deg[0]));
            row("Field C90-C270", angle(f.field_angle_deg[1]));
            if let Some(filter) = &s.filter {
                row("Filter rule", filter.rule.clone());
            }
        });
    for w in &s.warnings {
        ui.colored_label(ui.visuals().warn_fg_color, w);
    }
}
