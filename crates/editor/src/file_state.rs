//! The file side of the editor's state: the scene file and its saved
//! copy, the unsaved-changes question, autosave and recovery, the config
//! and the dialogs. `files.rs` holds the commands that act on it.

use std::path::PathBuf;
use std::time::{Duration, Instant};

use lucerna_scene::Scene;

use crate::config::{EditorConfig, EditorPaths};
use crate::dialogs::Dialogs;
use crate::error_text::error_chain;
use crate::recovery::{RecoveryOffer, read_recovery};

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
    pub(crate) last_autosave: Option<Instant>,
    /// What the recovery file holds now (`None`: no recovery file).
    pub(crate) autosaved: Option<Scene>,
    /// A structural edit asks for a write at once.
    pub autosave_now: bool,
    pub dialogs: Dialogs,
    /// A message that is not an error (an import's units, a settings file
    /// that could not be read).
    pub notice: Option<String>,
    pub(crate) theme_applied: bool,
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

    pub(crate) fn save_config(&mut self) {
        if let Err(e) = self.config.save(&self.paths) {
            self.notice = Some(error_chain(&e));
        }
    }
}
