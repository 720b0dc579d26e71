//! The editor's file commands apart from drawing: a new scene, the
//! unsaved-changes question shared by New, Open and Quit, recent files,
//! autosave and recovery, imports, dropped files, file dialogs and the
//! theme, acting on [`crate::file_state::FileState`]. `state.rs` calls in
//! here at a few points (commands, frame start and end, open and save).

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use lucerna_scene::shapes::Paraboloid;
use lucerna_scene::{
    Emission, Emitter, EmitterShape, FORMAT_VERSION, Material, Part, Scene, Shape, Transform,
};

use crate::command::DialogKind;
use crate::config::{EditorPaths, ThemeChoice};
use crate::error_text::error_chain;
use crate::file_state::PendingAction;
use crate::imports::{mesh_part, ray_file_emitter};
use crate::recovery::{RecoveryOffer, remove_recovery, write_recovery};
use crate::state::{Command, EditorState, Selection};

/// The scene "New" starts from: an LED of 1000 lm at the focus of a small
/// mirror paraboloid, facing it, and a white paint for added parts; it
/// validates and simulates at once.
pub fn starter_scene() -> Scene {
    let mut scene = Scene {
        format_version: FORMAT_VERSION,
        name: "New luminaire".to_owned(),
        description: String::new(),
        manufacturer: String::new(),
        export: Default::default(),
        materials: Default::default(),
        emitters: vec![Emitter {
            name: "LED".to_owned(),
            shape: EmitterShape::Disk { radius: 0.002 },
            flux_lm: 1000.0,
            emission: Emission::Lambertian,
            material: None,
            enabled: true,
            // Facing up into the reflector.
            transform: Transform {
                rotate_deg: [180.0, 0.0, 0.0],
                ..Transform::default()
            },
        }],
        parts: vec![Part {
            name: "reflector".to_owned(),
            shape: Shape::Paraboloid(Paraboloid {
                focal_length: 0.025,
                aperture_diameter: 0.1,
                neck_diameter: 0.0,
                segments_around: 96,
                segments_along: 32,
                faceted: false,
            }),
            material: "mirror".to_owned(),
            enabled: true,
            transform: Transform::default(),
            finish: None,
        }],
        opening: None,
    };
    scene
        .materials
        .insert("mirror".to_owned(), Material::Mirror { reflectance: 0.9 });
    scene.materials.insert(
        "white_paint".to_owned(),
        Material::Lambertian { albedo: 0.8 },
    );
    scene
}

/// What a file dropped on the window asks for, by its extension.
pub fn dropped_file_command(path: &Path) -> Result<Command, String> {
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    match ext.as_deref() {
        Some("obj") => Ok(Command::ImportMesh(path.to_owned())),
        Some("tm25ray") => Ok(Command::AddRayFileEmitter(path.to_owned())),
        Some("toml") => Ok(Command::Open(path.to_owned())),
        _ => Err(format!(
            "cannot use the dropped file {}: drop a scene (.toml), an OBJ mesh (.obj) or a TM-25 ray file (.tm25ray)",
            path.display()
        )),
    }
}

impl EditorState {
    /// The unsaved-changes question waiting for an answer.
    pub fn pending(&self) -> Option<&PendingAction> {
        self.files.pending.as_ref()
    }

    /// The file waiting to be opened until unsaved changes are dropped.
    pub fn pending_open(&self) -> Option<&Path> {
        match &self.files.pending {
            Some(PendingAction::Open(path)) => Some(path),
            _ => None,
        }
    }

    /// Unsaved changes of an earlier session, until recovered or discarded.
    pub fn recovery_offer(&self) -> Option<&RecoveryOffer> {
        self.files.recovery.as_ref()
    }

    /// The recent scenes, newest first, each with whether it still exists.
    pub fn recent_files(&self) -> Vec<(PathBuf, bool)> {
        self.files
            .config
            .recent
            .iter()
            .map(|p| (PathBuf::from(p), Path::new(p).is_file()))
            .collect()
    }

    /// How often unsaved changes go to the recovery file (tests: zero).
    pub fn set_autosave_interval(&mut self, interval: Duration) {
        self.files.autosave_interval = interval;
    }

    pub fn theme_choice(&self) -> ThemeChoice {
        self.files.config.theme
    }

    /// A message that is not an error, shown under the top bar.
    pub fn notice(&self) -> Option<&str> {
        self.files.notice.as_deref()
    }

    /// Quitting was asked for and confirmed.
    pub fn quit_requested(&self) -> bool {
        self.files.quitting
    }

    /// Where the editor keeps its own files.
    pub fn paths(&self) -> &EditorPaths {
        &self.files.paths
    }

    /// Start of a frame: the theme, dropped files, a finished dialog and
    /// the window's close button.
    pub(crate) fn files_begin_frame(&mut self, ctx: &egui::Context) {
        if !self.files.theme_applied {
            ctx.set_theme(self.files.config.theme);
            if let Some(zoom) = self.files.config.zoom
                && zoom.is_finite()
            {
                ctx.set_zoom_factor(zoom.clamp(0.2, 5.0));
            }
            self.files.theme_applied = true;
        } else {
            // egui applies Ctrl+Plus / Ctrl+Minus at the end of a frame:
            // remembered here, the frame after.
            let zoom = ctx.zoom_factor();
            if self.files.config.zoom.unwrap_or(1.0) != zoom {
                self.files.config.zoom = Some(zoom);
                self.files.save_config();
            }
        }
        let dropped: Vec<PathBuf> = ctx.input(|i| {
            i.raw
                .dropped_files
                .iter()
                .map(|f| f.path().to_path_buf())
                .collect()
        });
        for path in dropped {
            match dropped_file_command(&path) {
                Ok(command) => self.push(command),
                Err(message) => self.files.file_error = Some(message),
            }
        }
        match self.files.dialogs.poll() {
            Some(Ok(command)) => self.push(command),
            Some(Err(message)) => self.files.file_error = Some(message),
            None => {}
        }
        if ctx.input(|i| i.viewport().close_requested()) && !self.files.quitting {
            if self.is_dirty() {
                ctx.send_viewport_cmd(egui::ViewportCommand::CancelClose);
                self.files.pending = Some(PendingAction::Quit);
            } else {
                self.quit_now(ctx);
            }
        }
    }

    /// The file commands of [`EditorState`]'s `apply`.
    pub(crate) fn apply_file_command(&mut self, command: Command) {
        match command {
            Command::New if self.is_dirty() => self.files.pending = Some(PendingAction::New),
            Command::New | Command::NewDiscarding => {
                self.files.pending = None;
                if self.files.recovery.is_none() {
                    self.forget_recovery();
                }
                // Clean until edited: nothing to lose yet.
                let scene = starter_scene();
                self.replace_document(scene.clone(), None, Some(scene));
            }
            Command::Quit if self.is_dirty() => self.files.pending = Some(PendingAction::Quit),
            Command::Quit | Command::QuitDiscarding => {
                self.files.pending = None;
                if let Some(ctx) = self.ctx.clone() {
                    self.quit_now(&ctx);
                } else {
                    self.files.quitting = true;
                }
            }
            Command::Recover => {
                if let Some(offer) = self.files.recovery.take() {
                    let saved = offer
                        .original
                        .as_deref()
                        .and_then(|p| lucerna_scene::load_scene(p).ok());
                    self.replace_document(offer.scene.clone(), offer.original.clone(), saved);
                    // The recovery file stays until the changes are saved
                    // or discarded: it now belongs to this document.
                    self.files.autosaved = Some(offer.scene);
                    self.files.last_autosave = Some(Instant::now());
                }
            }
            Command::DiscardRecovery => {
                if self.files.recovery.take().is_some() {
                    self.forget_recovery();
                }
            }
            Command::ImportMesh(obj) => self.import_mesh(&obj),
            Command::AddRayFileEmitter(file) => self.add_ray_file_emitter(&file),
            Command::FileDialog(kind) => {
                let start_dir = self.scene_dir_for_dialogs();
                let file_name = match kind {
                    DialogKind::SaveAs => self
                        .files
                        .path
                        .as_deref()
                        .and_then(Path::file_name)
                        .map(|n| n.to_string_lossy().into_owned())
                        .or_else(|| Some("luminaire.toml".to_owned())),
                    _ => None,
                };
                if let Err(message) =
                    self.files
                        .dialogs
                        .start(kind, &start_dir, file_name, self.ctx.clone())
                {
                    self.files.file_error = Some(message);
                }
            }
            Command::SetTheme(theme) => {
                self.files.config.theme = theme;
                if let Some(ctx) = &self.ctx {
                    ctx.set_theme(theme);
                }
                self.files.save_config();
            }
            Command::ClearRecent => {
                self.files.config.recent.clear();
                self.files.save_config();
            }
            other => debug_assert!(false, "not a file command: {other:?}"),
        }
    }

    fn scene_dir_for_dialogs(&self) -> PathBuf {
        let dir = self.files.path.as_deref().and_then(Path::parent);
        match dir {
            Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
            _ => std::env::current_dir().unwrap_or_else(|_| PathBuf::from(".")),
        }
    }

    fn quit_now(&mut self, ctx: &egui::Context) {
        // A clean exit, or changes the user chose to drop; an offer not
        // yet answered stays for the next start.
        if self.files.recovery.is_none() {
            self.forget_recovery();
        }
        self.files.quitting = true;
        ctx.send_viewport_cmd(egui::ViewportCommand::Close);
    }

    /// Adds the OBJ file as a mesh part, one undo step; a file that does
    /// not load changes nothing.
    fn import_mesh(&mut self, obj: &Path) {
        let Some(scene) = &self.doc.scene else {
            self.files.file_error =
                Some("open a scene or start a new one before importing".to_owned());
            return;
        };
        match mesh_part(scene, self.files.path.as_deref(), obj) {
            Ok((part, notice)) => {
                self.files.notice = notice;
                self.files.file_error = None;
                self.structural(move |scene, selection| {
                    if !scene.materials.contains_key(&part.material) {
                        scene
                            .materials
                            .insert(part.material.clone(), Material::Lambertian { albedo: 0.8 });
                    }
                    scene.parts.push(part);
                    *selection = Some(Selection::Part(scene.parts.len() - 1));
                });
            }
            Err(e) => self.files.file_error = Some(error_chain(&e)),
        }
    }

    fn add_ray_file_emitter(&mut self, file: &Path) {
        let Some(scene) = &self.doc.scene else {
            self.files.file_error =
                Some("open a scene or start a new one before adding an emitter".to_owned());
            return;
        };
        match ray_file_emitter(scene, self.files.path.as_deref(), file) {
            Ok(emitter) => {
                self.files.file_error = None;
                self.structural(move |scene, selection| {
                    scene.emitters.push(emitter);
                    *selection = Some(Selection::Emitter(scene.emitters.len() - 1));
                });
            }
            Err(e) => self.files.file_error = Some(error_chain(&e)),
        }
    }

    /// After a successful open: remembered as recent.
    pub(crate) fn files_opened(&mut self, path: &Path) {
        self.files.config.remember(path);
        self.files.save_config();
        // A new document: what the recovery file held is not its changes.
        if self.files.recovery.is_none() {
            self.forget_recovery();
        }
    }

    /// After a successful save: recent, and nothing left to recover.
    pub(crate) fn files_saved(&mut self, path: &Path) {
        self.files.config.remember(path);
        self.files.save_config();
        if self.files.recovery.is_none() {
            self.forget_recovery();
        }
    }

    fn forget_recovery(&mut self) {
        if let Some(dir) = &self.files.paths.config_dir {
            remove_recovery(dir);
        }
        self.files.autosaved = None;
        self.files.last_autosave = None;
    }

    /// End of a frame: unsaved changes go to the recovery file every
    /// `autosave_interval`, and at once after a structural edit.
    pub(crate) fn autosave(&mut self, ctx: &egui::Context) {
        let now_wanted = std::mem::take(&mut self.files.autosave_now);
        let Some(dir) = self.files.paths.config_dir.clone() else {
            return;
        };
        if self.files.recovery.is_some() || self.files.quitting {
            return;
        }
        if !self.is_dirty() {
            // Undone back to the saved file: nothing to recover.
            if self.files.autosaved.is_some() {
                self.forget_recovery();
            }
            return;
        }
        let Some(scene) = &self.doc.scene else { return };
        if self.files.autosaved.as_ref() == Some(scene) {
            return;
        }
        let due = self.files.last_autosave.map_or(Duration::ZERO, |t| {
            self.files.autosave_interval.saturating_sub(t.elapsed())
        });
        if !now_wanted && !due.is_zero() {
            // Come back when it is due, even if nothing else repaints.
            ctx.request_repaint_after(due);
            return;
        }
        match write_recovery(&dir, scene, self.files.path.as_deref()) {
            Ok(()) => {
                self.files.autosaved = Some(scene.clone());
                self.files.last_autosave = Some(Instant::now());
            }
            Err(e) => {
                self.files.notice = Some(format!("autosave failed: {}", error_chain(&e)));
                // Not again every frame.
                self.files.last_autosave = Some(Instant::now());
            }
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)] // reason: tests may panic

    use super::*;

    #[test]
    fn the_starter_scene_validates() {
        assert_eq!(lucerna_scene::validate(&starter_scene()), vec![]);
        let dir = tempfile::tempdir().unwrap();
        lucerna_scene::tessellate(&starter_scene(), dir.path()).unwrap();
    }

    #[test]
    fn dropped_files_are_told_apart_by_extension() {
        assert!(matches!(
            dropped_file_command(Path::new("/x/a.OBJ")),
            Ok(Command::ImportMesh(_))
        ));
        assert!(matches!(
            dropped_file_command(Path::new("/x/a.toml")),
            Ok(Command::Open(_))
        ));
        assert!(dropped_file_command(Path::new("/x/a.png")).is_err());
    }
}
