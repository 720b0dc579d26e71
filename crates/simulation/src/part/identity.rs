//! What a part belongs to: the scene byte for byte, and the photons of
//! which run.

use std::path::{Path, PathBuf};

use lucerna_scene::Scene;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

/// A file of the scene that cannot be read to be hashed.
#[derive(Debug, thiserror::Error)]
#[error("cannot read {path}")]
pub struct SceneFileError {
    pub path: PathBuf,
    #[source]
    pub source: std::io::Error,
}

/// Why a part's scene is not the one it was traced from.
#[derive(Debug, thiserror::Error)]
pub enum SceneCheckError {
    #[error(transparent)]
    Read(#[from] SceneFileError),
    #[error("the scene changed since {path} was written: {why}")]
    Changed { path: PathBuf, why: String },
}

/// One file a scene reads, and its SHA-256.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct FileDigest {
    /// As the scene names it (relative to the scene file), or the scene
    /// file's own name.
    pub path: String,
    pub sha256: String,
}

/// What a scene is, byte for byte: its file and every file it references.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct SceneIdentity {
    /// The scene file as the bake was given it (absolute), where a merge
    /// or a resume loads it from.
    pub path: PathBuf,
    /// SHA-256 over the files' digests below, in order: the scene hash.
    pub sha256: String,
    pub files: Vec<FileDigest>,
}

impl SceneIdentity {
    /// Hashes `scene_path` and the files `scene` (loaded from it)
    /// references.
    pub fn of(scene_path: &Path, scene: &Scene) -> Result<SceneIdentity, SceneFileError> {
        let dir = scene_path.parent().unwrap_or(Path::new("."));
        let digest = |path: &Path| -> Result<String, SceneFileError> {
            let bytes = std::fs::read(path).map_err(|source| SceneFileError {
                path: path.to_path_buf(),
                source,
            })?;
            Ok(hex(&Sha256::digest(&bytes)))
        };
        let mut files = vec![FileDigest {
            path: scene_path
                .file_name()
                .map_or(String::new(), |n| n.to_string_lossy().into_owned()),
            sha256: digest(scene_path)?,
        }];
        for referenced in scene.referenced_files() {
            files.push(FileDigest {
                path: referenced.to_owned(),
                sha256: digest(&dir.join(referenced))?,
            });
        }
        let mut all = Sha256::new();
        for f in &files {
            all.update(f.path.as_bytes());
            all.update([0]);
            all.update(f.sha256.as_bytes());
            all.update([0]);
        }
        let path = std::path::absolute(scene_path).unwrap_or_else(|_| scene_path.to_path_buf());
        Ok(SceneIdentity {
            path,
            sha256: hex(&all.finalize()),
            files,
        })
    }

    /// The first file whose bytes differ from `other`'s, for a message.
    pub fn first_difference(&self, other: &SceneIdentity) -> Option<String> {
        for f in &self.files {
            match other.files.iter().find(|g| g.path == f.path) {
                None => return Some(format!("{} is no longer referenced", f.path)),
                Some(g) if g.sha256 != f.sha256 => {
                    return Some(format!(
                        "{} changed (SHA-256 {}… now {}…)",
                        f.path,
                        &f.sha256[..12.min(f.sha256.len())],
                        &g.sha256[..12.min(g.sha256.len())]
                    ));
                }
                _ => {}
            }
        }
        other
            .files
            .iter()
            .find(|g| !self.files.iter().any(|f| f.path == g.path))
            .map(|g| format!("{} is newly referenced", g.path))
    }

    /// Checks that the scene at `scene_path` (loaded as `scene`) is still
    /// the one identified as `self` in `manifest_path`.
    pub fn check_unchanged(
        &self,
        manifest_path: &Path,
        scene_path: &Path,
        scene: &Scene,
    ) -> Result<(), SceneCheckError> {
        let now = SceneIdentity::of(scene_path, scene)?;
        if now.sha256 != self.sha256 {
            return Err(SceneCheckError::Changed {
                path: manifest_path.to_path_buf(),
                why: self
                    .first_difference(&now)
                    .unwrap_or_else(|| "its files differ".to_owned()),
            });
        }
        Ok(())
    }
}

fn hex(bytes: &[u8]) -> String {
    bytes.iter().map(|b| format!("{b:02x}")).collect()
}

/// What makes the counts of two parts belong to one run: the same photons
/// of the same stream into the same map.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TraceIdentity {
    pub resolution: u32,
    pub seed: u32,
    pub max_bounces: u32,
    /// Photons of the whole run (all parts).
    pub photons_total: u64,
    /// Parts the run is split into.
    pub parts: u32,
    pub emitter_flux_lm: f64,
}
