//! File ▸ Export geometry…: the luminaire's parts as STEP (exact
//! surfaces), STL and OBJ, through the library `lucerna export-geometry`
//! uses, so the same choices write the same bytes.

use std::path::{Path, PathBuf};
use std::sync::mpsc;

use egui::Ui;
use lucerna_cad::{GeometryFormat, GeometryRequest, write_geometry};

use crate::command::{Command, DialogKind};
use crate::state::EditorState;
use crate::widgets::labelled;

/// The dialog's choices and its running export.
#[derive(Debug, Default)]
pub struct GeometryDialog {
    pub open: bool,
    initialised: bool,
    /// STEP, STL, OBJ in [`GeometryFormat::ALL`]'s order.
    formats: [bool; 3],
    /// Every enabled part and emitter: its name, the label shown and
    /// whether it is exported.
    bodies: Vec<(String, String, bool)>,
    pub folder: String,
    pub base_name: String,
    job: Option<mpsc::Receiver<Result<Vec<PathBuf>, String>>>,
    result: Option<Result<Vec<PathBuf>, String>>,
}

impl GeometryDialog {
    /// The defaults on opening: every format, every enabled part and
    /// emitter, the scene's folder and name.
    fn initialise(&mut self, state: &EditorState) {
        self.initialised = true;
        self.formats = [true; 3];
        self.bodies = state
            .scene()
            .map(|scene| {
                let parts = scene
                    .parts
                    .iter()
                    .filter(|p| p.enabled)
                    .map(|p| (p.name.clone(), p.name.clone(), true));
                let emitters = scene
                    .emitters
                    .iter()
                    .filter(|e| e.enabled)
                    .map(|e| (e.name.clone(), format!("{} (emitter)", e.name), true));
                parts.chain(emitters).collect()
            })
            .unwrap_or_default();
        self.folder = std::path::absolute(state.scene_dir())
            .unwrap_or_else(|_| state.scene_dir().to_path_buf())
            .display()
            .to_string();
        self.base_name = state.path().and_then(Path::file_stem).map_or_else(
            || "luminaire".to_owned(),
            |s| s.to_string_lossy().into_owned(),
        );
        self.result = None;
    }

    /// What the ticks ask for; `None` parts when every body is ticked
    /// (the command line's default).
    pub fn request(&self) -> GeometryRequest {
        let formats = GeometryFormat::ALL
            .into_iter()
            .zip(self.formats)
            .filter_map(|(f, on)| on.then_some(f))
            .collect();
        let parts = if self.bodies.iter().all(|(_, _, on)| *on) {
            None
        } else {
            Some(
                self.bodies
                    .iter()
                    .filter(|(_, _, on)| *on)
                    .map(|(name, _, _)| name.clone())
                    .collect(),
            )
        };
        GeometryRequest {
            formats,
            parts,
            finish: Default::default(),
        }
    }

    /// Opens the dialog on its defaults.
    pub(crate) fn open_fresh(&mut self) {
        self.open = true;
        self.initialised = false;
    }
}

pub fn geometry_dialog_ui(
    ctx: &egui::Context,
    state: &mut EditorState,
    dialog: &mut GeometryDialog,
) {
    if !dialog.open {
        return;
    }
    if !dialog.initialised {
        dialog.initialise(state);
    }
    let mut open = dialog.open;
    egui::Window::new("Export geometry")
        .open(&mut open)
        .resizable(true)
        .default_width(420.0)
        .show(ctx, |ui| dialog_ui(ui, state, dialog));
    dialog.open = open;
}

fn dialog_ui(ui: &mut Ui, state: &mut EditorState, dialog: &mut GeometryDialog) {
    ui.label(
        "Millimetres, luminaire coordinates: light leaves towards −z, C0 along +x. \
         Sheets are written as surfaces.",
    );
    ui.separator();
    ui.strong("Files");
    let [step, stl, obj] = &mut dialog.formats;
    ui.checkbox(step, "STEP (exact surfaces)")
        .on_hover_text("AP214: each part its own named body; revolved and extruded profiles, disks and planes exact, faceted parts as their facets");
    ui.checkbox(stl, "STL (traced triangles)")
        .on_hover_text("Binary STL of the triangles the tracer intersects");
    ui.checkbox(obj, "OBJ (traced triangles)")
        .on_hover_text("One object per part, with the shading normals");
    ui.separator();
    ui.strong("Parts and emitters");
    for (_, label, on) in &mut dialog.bodies {
        ui.checkbox(on, label.as_str());
    }
    ui.separator();
    if let Some(chosen) = state.chosen_export_folder.take() {
        dialog.folder = chosen.display().to_string();
    }
    ui.horizontal(|ui| {
        labelled(ui, "Output folder", |ui| {
            ui.add(egui::TextEdit::singleline(&mut dialog.folder).desired_width(260.0))
        });
        if ui
            .add_enabled(
                !state.files.dialogs.is_open(),
                egui::Button::new("Choose folder…"),
            )
            .on_hover_text("Choose the folder in a dialog")
            .clicked()
        {
            state.push(Command::FileDialog(DialogKind::ExportFolder));
        }
    });
    labelled(ui, "Base name", |ui| {
        ui.add(egui::TextEdit::singleline(&mut dialog.base_name).desired_width(260.0))
    });
    if let Some(job) = &dialog.job {
        match job.try_recv() {
            Ok(result) => {
                dialog.result = Some(result);
                dialog.job = None;
            }
            Err(mpsc::TryRecvError::Empty) => {}
            Err(mpsc::TryRecvError::Disconnected) => {
                dialog.result = Some(Err("the export stopped unexpectedly".to_owned()));
                dialog.job = None;
            }
        }
    }
    let exportable = dialog.job.is_none() && state.scene().is_some();
    if ui
        .add_enabled(exportable, egui::Button::new("Export"))
        .on_hover_text("Write the chosen files, all or none")
        .clicked()
    {
        dialog.result = None;
        if let Some(scene) = state.scene().cloned() {
            let (tx, rx) = mpsc::channel();
            let scene_dir = state.scene_dir().to_path_buf();
            let folder = PathBuf::from(dialog.folder.trim());
            // A relative folder is the scene's, as the scene's own paths.
            let folder = if folder.is_relative() {
                scene_dir.join(folder)
            } else {
                folder
            };
            let base_name = dialog.base_name.trim().to_owned();
            let request = dialog.request();
            let ctx = ui.ctx().clone();
            std::thread::spawn(move || {
                let result = write_geometry(&scene, &scene_dir, &folder, &base_name, &request)
                    .map_err(|e| error_chain(&e));
                let _ = tx.send(result);
                ctx.request_repaint();
            });
            dialog.job = Some(rx);
        }
    }
    if dialog.job.is_some() {
        ui.horizontal(|ui| {
            ui.spinner();
            ui.label("Exporting geometry…");
        });
    }
    crate::widgets::export_result_ui(ui, dialog.result.as_ref());
}

/// An error with its causes, as the command line prints it.
fn error_chain(e: &dyn std::error::Error) -> String {
    let mut text = e.to_string();
    let mut source = e.source();
    while let Some(s) = source {
        text.push_str(": ");
        text.push_str(&s.to_string());
        source = s.source();
    }
    text
}
