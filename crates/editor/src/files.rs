//! File handling apart from drawing: a new scene, the unsaved-changes
//! question shared by New, Open and Quit, recent files, autosave and
//! recovery, OBJ import, dropped files, file dialogs and the theme.
//! `state.rs` calls in here at a few points (commands, frame start and
//! end, open and save); the rest of the editor does not know about it.

use std::path::{Component, Path, PathBuf};
use std::time::{Duration, Instant};

use lucerna_scene::obj::{LoadObjError, load_obj};
use lucerna_scene::shapes::{Mesh, Paraboloid};
use lucerna_scene::{
    Emission, Emitter, EmitterShape, FORMAT_VERSION, Material, Part, Scene, Shape, TessellateError,
    Transform, tessellate,
};

use crate::command::DialogKind;
use crate::config::{EditorConfig, EditorPaths, ThemeChoice};
use crate::dialogs::Dialogs;
use crate::error_text::error_chain;
use crate::modelling::unique_name;
use crate::recovery::{RecoveryOffer, read_recovery, remove_recovery, write_recovery};
use crate::state::{Command, EditorState, Selection};

/// How often unsaved changes are written to the recovery file.
pub const DEFAULT_AUTOSAVE_INTERVAL: Duration = Duration::from_secs(20);

/// What waits for the user to drop unsaved changes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum PendingAction {
    New,
    Open(PathBuf),
    Quit,
}

/// The file-handling part of [`EditorState`].
#[derive(Debug)]
pub(crate) struct FileState {
    /// The scene file being edited (`None`: a new scene not yet saved).
    pub path: Option<PathBuf>,
    /// The scene as last loaded or saved, for the unsaved-changes marker.
    pub saved: Option<Scene>,
    /// The last file error (load, save, import, dialog), shown until the
    /// next success.
    pub file_error: Option<String>,
    pub paths: EditorPaths,
    pub config: EditorConfig,
    pub pending: Option<PendingAction>,
    /// Unsaved changes of an earlier session, offered until answered;
    /// nothing is autosaved meanwhile, so the offer is never overwritten.
    pub recovery: Option<RecoveryOffer>,
    pub autosave_interval: Duration,
    last_autosave: Option<Instant>,
    /// What the recovery file holds now (`None`: no recovery file).
    autosaved: Option<Scene>,
    /// A structural edit asks for a write at once.
    pub autosave_now: bool,
    pub dialogs: Dialogs,
    /// A message that is not an error (an import's units, a settings file
    /// that could not be read).
    pub notice: Option<String>,
    theme_applied: bool,
    /// Quitting was confirmed: a close request is let through.
    pub quitting: bool,
}

impl FileState {
    pub fn new(paths: EditorPaths) -> Self {
        let native_dialogs = paths.native_dialogs;
        let mut notice = None;
        let config = EditorConfig::load(&paths).unwrap_or_else(|e| {
            notice = Some(format!("{}; using the defaults", error_chain(&e)));
            EditorConfig::default()
        });
        let recovery = match paths.config_dir.as_deref().map(read_recovery) {
            Some(Ok(offer)) => offer,
            Some(Err(e)) => {
                notice = Some(error_chain(&e));
                None
            }
            None => None,
        };
        FileState {
            path: None,
            saved: None,
            file_error: None,
            paths,
            config,
            pending: None,
            recovery,
            autosave_interval: DEFAULT_AUTOSAVE_INTERVAL,
            last_autosave: None,
            autosaved: None,
            autosave_now: false,
            dialogs: Dialogs::new(native_dialogs),
            notice,
            theme_applied: false,
            quitting: false,
        }
    }

    fn save_config(&mut self) {
        if let Err(e) = self.config.save(&self.paths) {
            self.notice = Some(error_chain(&e));
        }
    }
}

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

/// Why an OBJ file could not be imported.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ImportMeshError {
    #[error("cannot import {path}")]
    Load {
        path: PathBuf,
        #[source]
        source: Box<LoadObjError>,
    },
    #[error("cannot import {path}")]
    Unusable {
        path: PathBuf,
        #[source]
        source: Box<TessellateError>,
    },
    #[error("cannot import {path}: scene files store paths as UTF-8")]
    NotUtf8 { path: PathBuf },
}

/// Extent (m) above which an OBJ file is taken to be in millimetres: CAD
/// exports usually are, and no luminaire part is this large.
const MILLIMETRE_GUESS_M: f32 = 5.0;

/// A mesh part for the OBJ file at `obj` (relative paths from the working
/// directory), checked by tessellating it alone. The file's path is
/// stored relative to the scene's folder where the scene has one.
pub fn mesh_part(
    scene: &Scene,
    scene_path: Option<&Path>,
    obj: &Path,
) -> Result<(Part, Option<String>), ImportMeshError> {
    let absolute = std::path::absolute(obj).unwrap_or_else(|_| obj.to_path_buf());
    let groups = load_obj(&absolute).map_err(|source| ImportMeshError::Load {
        path: obj.to_owned(),
        source: Box::new(source),
    })?;
    let (mut lo, mut hi) = ([f32::MAX; 3], [f32::MIN; 3]);
    for p in groups.iter().flat_map(|g| &g.mesh.positions) {
        for (k, x) in [p.x, p.y, p.z].into_iter().enumerate() {
            lo[k] = lo[k].min(x);
            hi[k] = hi[k].max(x);
        }
    }
    let extent = (0..3).map(|k| hi[k] - lo[k]).fold(0.0_f32, f32::max);
    let (scale, notice) = if extent > MILLIMETRE_GUESS_M {
        (
            0.001,
            Some(format!(
                "{} is {extent:.0} units across: read as millimetres (scale 0.001)",
                obj.display()
            )),
        )
    } else {
        (1.0, None)
    };
    let scene_dir = scene_path.map(folder_of);
    let stored_text =
        stored_path(scene_path, absolute).ok_or_else(|| ImportMeshError::NotUtf8 {
            path: obj.to_owned(),
        })?;
    let stem = obj
        .file_stem()
        .map_or_else(|| "mesh".to_owned(), |s| s.to_string_lossy().into_owned());
    let mut alone = scene.clone();
    if alone.materials.is_empty() {
        alone.materials.insert(
            "white_paint".to_owned(),
            Material::Lambertian { albedo: 0.8 },
        );
    }
    let material = alone.materials.keys().next().cloned().unwrap_or_default();
    let part = Part {
        name: unique_name(&stem, |n| scene.parts.iter().any(|p| p.name == n)),
        shape: Shape::Mesh(Mesh {
            path: stored_text,
            group_materials: Default::default(),
        }),
        material,
        enabled: true,
        transform: Transform {
            scale: [scale; 3],
            ..Transform::default()
        },
    };
    alone.parts = vec![part.clone()];
    alone.emitters.clear();
    alone.opening = None;
    let dir = scene_dir.map_or_else(|| PathBuf::from("."), Path::to_path_buf);
    tessellate(&alone, &dir).map_err(|source| ImportMeshError::Unusable {
        path: obj.to_owned(),
        source: Box::new(source),
    })?;
    Ok((part, notice))
}

/// Why a ray file cannot be added as an emitter.
#[derive(Debug, thiserror::Error)]
pub enum RayFileEmitterError {
    #[error("cannot add {path} as an emitter")]
    Read {
        path: PathBuf,
        #[source]
        source: Box<lucerna_photometry::tm25::ReadRayFileError>,
    },
    #[error("the path {path} is not UTF-8, which a scene file cannot hold")]
    NotUtf8 { path: PathBuf },
}

/// An emitter for the TM-25 ray file at `file` (relative paths from the
/// working directory), read and checked first: named after the file,
/// at the origin, with the file's own luminous flux (declared, else its
/// rays' sum). The path is stored relative to the scene's folder where
/// the scene has one.
pub fn ray_file_emitter(
    scene: &Scene,
    scene_path: Option<&Path>,
    file: &Path,
) -> Result<Emitter, RayFileEmitterError> {
    let absolute = std::path::absolute(file).unwrap_or_else(|_| file.to_path_buf());
    let rays = lucerna_photometry::tm25::read_ray_file(&absolute).map_err(|source| {
        RayFileEmitterError::Read {
            path: file.to_owned(),
            source: Box::new(source),
        }
    })?;
    let flux_lm = rays
        .header
        .luminous_flux_lm
        .map_or_else(|| rays.total_luminous_flux_lm(), f64::from);
    let path = stored_path(scene_path, absolute).ok_or_else(|| RayFileEmitterError::NotUtf8 {
        path: file.to_owned(),
    })?;
    let stem = file.file_stem().map_or_else(
        || "ray file".to_owned(),
        |s| s.to_string_lossy().into_owned(),
    );
    Ok(Emitter {
        name: unique_name(&stem, |n| scene.emitters.iter().any(|e| e.name == n)),
        shape: EmitterShape::RayFile { path },
        flux_lm,
        emission: Emission::Lambertian,
        material: None,
        enabled: true,
        transform: Transform::default(),
    })
}

/// How a scene at `scene_path` refers to the file at `absolute`: relative
/// to the scene's folder where it has one; None where the path is not
/// UTF-8 (a scene file cannot hold it).
fn stored_path(scene_path: Option<&Path>, absolute: PathBuf) -> Option<String> {
    let stored = scene_path
        .map(folder_of)
        .and_then(|dir| relative_path(dir, &absolute))
        .unwrap_or(absolute);
    stored.to_str().map(str::to_owned)
}

/// The folder a file is in: "." for a bare file name, whose parent is "".
fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// `file` relative to `dir` (both made canonical), through `..` where
/// needed; `None` when they share no more than the root, where an
/// absolute path says more.
fn relative_path(dir: &Path, file: &Path) -> Option<PathBuf> {
    let dir = std::fs::canonicalize(dir).ok()?;
    let file = std::fs::canonicalize(file).ok()?;
    let d: Vec<Component<'_>> = dir.components().collect();
    let f: Vec<Component<'_>> = file.components().collect();
    let common = d.iter().zip(&f).take_while(|(a, b)| a == b).count();
    if common <= 1 {
        return None;
    }
    let mut relative = PathBuf::new();
    for _ in common..d.len() {
        relative.push("..");
    }
    for c in &f[common..] {
        relative.push(c);
    }
    Some(relative)
}

/// The scene with its relative file paths (OBJ meshes, emitter profiles)
/// rewritten to name the same files from `new_path`'s folder; `None` when
/// nothing changes. Missing files are left as written. The undo history
/// keeps the old paths: undoing across a "Save as" to another folder gives
/// paths the simulation reports as missing, and redo brings them back.
pub(crate) fn rebased_for(scene: &Scene, scene_dir: &Path, new_path: &Path) -> Option<Scene> {
    let to_dir = folder_of(new_path);
    let scene_dir = if scene_dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        scene_dir
    };
    let same_dir = match (
        std::fs::canonicalize(scene_dir),
        std::fs::canonicalize(to_dir),
    ) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    };
    if same_dir {
        return None;
    }
    let mut out = scene.clone();
    let mut changed = false;
    let mut rebase = |path: &mut String| {
        let old = Path::new(path.as_str());
        if old.is_absolute() {
            return;
        }
        let target = scene_dir.join(old);
        if !target.exists() {
            return;
        }
        let new = relative_path(to_dir, &target)
            .unwrap_or_else(|| std::fs::canonicalize(&target).unwrap_or(target));
        if let Some(text) = new.to_str()
            && text != path
        {
            *path = text.to_owned();
            changed = true;
        }
    };
    for part in &mut out.parts {
        if let Shape::Mesh(mesh) = &mut part.shape {
            rebase(&mut mesh.path);
        }
    }
    for emitter in &mut out.emitters {
        if let Emission::Profile(file) = &mut emitter.emission {
            rebase(file);
        }
    }
    changed.then_some(out)
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
        tessellate(&starter_scene(), dir.path()).unwrap();
    }

    #[test]
    fn relative_paths_go_up_where_needed() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a/luminaires");
        let m = dir.path().join("a/meshes");
        std::fs::create_dir_all(&a).unwrap();
        std::fs::create_dir_all(&m).unwrap();
        std::fs::write(m.join("x.obj"), "").unwrap();
        assert_eq!(
            relative_path(&a, &m.join("x.obj")),
            Some(PathBuf::from("../meshes/x.obj"))
        );
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
