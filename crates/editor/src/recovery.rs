//! The recovery file: unsaved changes written to the config directory now
//! and then, so a crash or a killed session loses little. Two files, each
//! written atomically: `recovery.toml`, the scene as a scene file (it loads
//! with `lucerna validate` too), and `recovery-index.toml`, which scene
//! file it belongs to and when it was written. The index is written last,
//! so a scene without its index is recovered as a new, unnamed scene.

use std::path::{Path, PathBuf};
use std::time::{Duration, SystemTime, UNIX_EPOCH};

use lucerna_scene::{Scene, scene_to_toml, write_atomically};
use serde::{Deserialize, Serialize};

const SCENE_FILE: &str = "recovery.toml";
const INDEX_FILE: &str = "recovery-index.toml";

#[derive(Debug, Serialize, Deserialize)]
struct Index {
    /// The scene file the changes belong to; absent for a scene never saved.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    scene_path: Option<String>,
    /// When the changes were written, seconds since the Unix epoch.
    written_unix_s: u64,
}

/// Unsaved changes found on start.
#[derive(Debug, Clone, PartialEq)]
pub struct RecoveryOffer {
    pub scene: Scene,
    /// The file they are changes to; relative paths in the scene resolve
    /// from its folder.
    pub original: Option<PathBuf>,
    pub written: SystemTime,
}

impl RecoveryOffer {
    /// "HH:MM" in local time, or the date too when not from today.
    pub fn written_local(&self) -> String {
        let written: chrono::DateTime<chrono::Local> = self.written.into();
        if written.date_naive() == chrono::Local::now().date_naive() {
            written.format("%H:%M").to_string()
        } else {
            written.format("%Y-%m-%d %H:%M").to_string()
        }
    }
}

/// Why the recovery file could not be written or read.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RecoveryError {
    #[error("cannot write the recovery file {path}")]
    Write {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("cannot serialise the scene for the recovery file")]
    Serialise(#[from] toml::ser::Error),
    #[error("cannot read the recovery file {path}")]
    Read {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("the recovery file {path} is not a scene")]
    Parse {
        path: PathBuf,
        #[source]
        source: toml::de::Error,
    },
}

/// Writes `scene` (changes to `original`) as the recovery file in `dir`.
pub fn write_recovery(
    dir: &Path,
    scene: &Scene,
    original: Option<&Path>,
) -> Result<(), RecoveryError> {
    let scene_file = dir.join(SCENE_FILE);
    let index_file = dir.join(INDEX_FILE);
    std::fs::create_dir_all(dir).map_err(|source| RecoveryError::Write {
        path: dir.to_owned(),
        source,
    })?;
    let text = scene_to_toml(scene)?;
    write_atomically(&scene_file, text.as_bytes()).map_err(|source| RecoveryError::Write {
        path: scene_file,
        source,
    })?;
    let index = Index {
        // An absolute path: the editor may be started from another folder.
        scene_path: original
            .map(|p| std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf()))
            .and_then(|p| p.to_str().map(str::to_owned)),
        written_unix_s: SystemTime::now()
            .duration_since(UNIX_EPOCH)
            .map_or(0, |d| d.as_secs()),
    };
    let text = toml::to_string(&index)?;
    write_atomically(&index_file, text.as_bytes()).map_err(|source| RecoveryError::Write {
        path: index_file,
        source,
    })
}

/// The recovery file in `dir`, if there is one. The scene is not
/// validated: unsaved changes may be half-way through an edit.
pub fn read_recovery(dir: &Path) -> Result<Option<RecoveryOffer>, RecoveryError> {
    let scene_file = dir.join(SCENE_FILE);
    let text = match std::fs::read_to_string(&scene_file) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
        Err(source) => {
            return Err(RecoveryError::Read {
                path: scene_file,
                source,
            });
        }
    };
    let scene: Scene = toml::from_str(&text).map_err(|source| RecoveryError::Parse {
        path: scene_file.clone(),
        source,
    })?;
    // A missing or broken index loses only the name, not the changes.
    let index = std::fs::read_to_string(dir.join(INDEX_FILE))
        .ok()
        .and_then(|t| toml::from_str::<Index>(&t).ok());
    let written = match &index {
        Some(index) => UNIX_EPOCH + Duration::from_secs(index.written_unix_s),
        None => std::fs::metadata(&scene_file)
            .and_then(|m| m.modified())
            .unwrap_or_else(|_| SystemTime::now()),
    };
    Ok(Some(RecoveryOffer {
        scene,
        original: index.and_then(|i| i.scene_path).map(PathBuf::from),
        written,
    }))
}

/// Removes the recovery file (after a clean save, a discard or a clean
/// exit); a missing one is fine.
pub fn remove_recovery(dir: &Path) {
    for name in [INDEX_FILE, SCENE_FILE] {
        // Nothing to do about a file that cannot be removed: it is offered
        // again on the next start, which is the safe side.
        let _ = std::fs::remove_file(dir.join(name));
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)] // reason: tests may panic

    use super::*;

    #[test]
    fn a_recovery_file_round_trips_with_its_original_path_and_is_removed() {
        let dir = tempfile::tempdir().unwrap();
        assert_eq!(read_recovery(dir.path()).unwrap(), None);
        let scene = crate::files::starter_scene();
        let original = dir.path().join("lamp.toml");
        write_recovery(dir.path(), &scene, Some(&original)).unwrap();
        let offer = read_recovery(dir.path()).unwrap().unwrap();
        assert_eq!(offer.scene, scene);
        assert_eq!(offer.original.as_deref(), Some(original.as_path()));
        // The scene half is an ordinary scene file.
        assert_eq!(
            lucerna_scene::load_scene(&dir.path().join(SCENE_FILE)).unwrap(),
            scene
        );
        remove_recovery(dir.path());
        assert_eq!(read_recovery(dir.path()).unwrap(), None);
    }
}
