//! The simulation panel: progress, figures, noise and warnings of the
//! newest snapshot, and the run's controls.

use egui::Ui;
use lucerna_simulation::{FilterChoice, Snapshot};

use crate::state::{Command, EditorState};

/// Cube-map resolutions offered (texels per face edge).
const RESOLUTIONS: [u32; 5] = [32, 64, 128, 256, 512];

pub fn simulation_panel_ui(ui: &mut Ui, state: &mut EditorState) {
    ui.heading("Simulation");
    let mut commands = Vec::new();
    controls_ui(ui, state, &mut commands);
    ui.separator();
    if let Some(error) = &state.sim_error {
        ui.colored_label(ui.visuals().error_fg_color, error);
    }
    match &state.snapshot {
        Some(s) => figures_ui(ui, s),
        None if state.scene.is_some() => {
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
        if state.paused {
            if ui.button("Resume").clicked() {
                commands.push(Command::Resume);
            }
        } else if ui.button("Pause").clicked() {
            commands.push(Command::Pause);
        }
    });
    let mut settings = state.settings;
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
    let mut automatic = settings.filter != FilterChoice::Raw;
    if ui.checkbox(&mut automatic, "Filter (automatic)").changed() {
        settings.filter = if automatic {
            FilterChoice::Automatic
        } else {
            FilterChoice::Raw
        };
    }
    ui.checkbox(&mut settings.pool_symmetry, "Symmetry pooling");
    if settings != state.settings {
        commands.push(Command::SetSettings(settings));
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
                ui.label(value);
                ui.end_row();
            };
            row("State", format!("{:?}", s.state));
            row("Iteration", s.iteration.to_string());
            row("Photons", format!("{:.3e}", s.photons as f64));
            row("Photons/s", format!("{:.3e}", s.photons_per_second));
            row("Backend", s.backend.clone());
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
                row("Filter", filter.rule.clone());
            }
        });
    for w in &s.warnings {
        ui.colored_label(ui.visuals().warn_fg_color, w);
    }
}
