//! What the editor remembers between runs: the recent files and the theme,
//! in one small TOML file in the user's config directory. The directory is
//! injected ([`EditorPaths`]) so that tests use a temporary one and never
//! touch the real home.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

/// How many scenes the "Recent" menu lists.
pub const MAX_RECENT: usize = 10;

/// Where the editor keeps its own files (settings, recent files, the
/// recovery file of unsaved changes).
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct EditorPaths {
    /// `None`: remember nothing and write nothing (the default for tests
    /// that are not about it).
    pub config_dir: Option<PathBuf>,
    /// Native file dialogs where the desktop has them; otherwise (and in
    /// tests, which never open one) a path prompt in the window.
    pub native_dialogs: bool,
}

impl EditorPaths {
    /// The user's: `$XDG_CONFIG_HOME/lucerna`, else `~/.config/lucerna`
    /// (the platform's config directory elsewhere).
    pub fn user() -> Self {
        EditorPaths {
            config_dir: dirs::config_dir().map(|d| d.join("lucerna")),
            native_dialogs: true,
        }
    }

    /// Everything in `dir` (tests: a temporary directory).
    pub fn in_dir(dir: impl Into<PathBuf>) -> Self {
        EditorPaths {
            config_dir: Some(dir.into()),
            native_dialogs: false,
        }
    }

    pub(crate) fn config_file(&self) -> Option<PathBuf> {
        self.config_dir.as_ref().map(|d| d.join("editor.toml"))
    }
}

/// The editor's colour theme.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ThemeChoice {
    /// Whatever the desktop asks for (egui's default).
    #[default]
    System,
    Dark,
    Light,
}

impl From<ThemeChoice> for egui::ThemePreference {
    fn from(t: ThemeChoice) -> Self {
        match t {
            ThemeChoice::System => egui::ThemePreference::System,
            ThemeChoice::Dark => egui::ThemePreference::Dark,
            ThemeChoice::Light => egui::ThemePreference::Light,
        }
    }
}

/// The contents of `editor.toml`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub(crate) struct EditorConfig {
    #[serde(default)]
    pub theme: ThemeChoice,
    /// The UI zoom (egui's zoom factor, on top of the screen's own scale)
    /// last chosen with Ctrl+Plus / Ctrl+Minus; absent is 1.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub zoom: Option<f32>,
    /// Most recent first; paths as UTF-8 text (others are not remembered).
    #[serde(default)]
    pub recent: Vec<String>,
}

/// Why the editor's own settings could not be read or written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ConfigError {
    #[error("cannot read {path}")]
    Read {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{path} is not a valid editor settings file")]
    Parse {
        path: PathBuf,
        #[source]
        source: toml::de::Error,
    },
    #[error("cannot write {path}")]
    Write {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

impl EditorConfig {
    /// The remembered settings; a missing file is the defaults.
    pub fn load(paths: &EditorPaths) -> Result<Self, ConfigError> {
        let Some(path) = paths.config_file() else {
            return Ok(EditorConfig::default());
        };
        match std::fs::read_to_string(&path) {
            Ok(text) => toml::from_str(&text).map_err(|source| ConfigError::Parse { path, source }),
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => Ok(EditorConfig::default()),
            Err(source) => Err(ConfigError::Read { path, source }),
        }
    }

    /// Writes the settings atomically, creating the directory.
    pub fn save(&self, paths: &EditorPaths) -> Result<(), ConfigError> {
        let Some(path) = paths.config_file() else {
            return Ok(());
        };
        let write = |source| ConfigError::Write {
            path: path.clone(),
            source,
        };
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir).map_err(write)?;
        }
        // Serialising plain strings and an enum cannot fail.
        let text = toml::to_string_pretty(self).unwrap_or_default();
        lucerna_scene::write_atomically(&path, text.as_bytes()).map_err(write)
    }

    /// Puts `path` first in the recent list (once), keeping [`MAX_RECENT`].
    pub fn remember(&mut self, path: &Path) {
        // One entry per file however it was named (relative, `..`).
        let path = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
        let Some(text) = path.to_str() else { return };
        self.recent.retain(|p| p != text);
        self.recent.insert(0, text.to_owned());
        self.recent.truncate(MAX_RECENT);
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)] // reason: tests may panic

    use super::*;

    #[test]
    fn recent_files_are_unique_newest_first_and_capped() {
        let dir = tempfile::tempdir().unwrap();
        let mut config = EditorConfig::default();
        for i in 0..12 {
            let p = dir.path().join(format!("{i}.toml"));
            std::fs::write(&p, "").unwrap();
            config.remember(&p);
        }
        config.remember(&dir.path().join("./5.toml"));
        assert_eq!(config.recent.len(), MAX_RECENT);
        assert!(config.recent[0].ends_with("5.toml"), "{:?}", config.recent);
        assert_eq!(
            config
                .recent
                .iter()
                .filter(|p| p.ends_with("5.toml"))
                .count(),
            1
        );
        let paths = EditorPaths::in_dir(dir.path().join("config"));
        config.save(&paths).unwrap();
        assert_eq!(EditorConfig::load(&paths).unwrap(), config);
    }
}
