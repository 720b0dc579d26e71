//! The partial maps in a folder: a merge's inputs, a resume's checkpoint.

use std::path::{Path, PathBuf};

use super::{PartManifest, PartSpec, ReadPartError, read_manifest};

/// Why a folder's parts cannot be found.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FindPartsError {
    #[error("cannot list {path}")]
    List {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error(transparent)]
    Read(#[from] ReadPartError),
    #[error("{dir} holds no checkpoint{which} (no *.part-K-of-N.json)")]
    NoCheckpoint { dir: PathBuf, which: String },
    #[error("{dir} holds checkpoints of several parts ({parts}): say which with --part K/N")]
    SeveralCheckpoints { dir: PathBuf, parts: String },
}

/// The manifests in `dir` (files named `*.part-K-of-N.json`), sorted.
pub fn manifests_in(dir: &Path) -> Result<Vec<PathBuf>, FindPartsError> {
    let entries = std::fs::read_dir(dir).map_err(|source| FindPartsError::List {
        path: dir.to_path_buf(),
        source,
    })?;
    let mut found: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.ends_with(".json") && n.contains(".part-"))
        })
        .collect();
    found.sort();
    Ok(found)
}

/// The checkpoint in `dir` to resume: that of `part` if given, else the
/// only one there.
pub fn find_checkpoint(
    dir: &Path,
    part: Option<PartSpec>,
) -> Result<(PathBuf, PartManifest), FindPartsError> {
    let mut found = Vec::new();
    for path in manifests_in(dir)? {
        let manifest = read_manifest(&path)?;
        if part.is_none_or(|p| p == manifest.spec()) {
            found.push((path, manifest));
        }
    }
    match found.len() {
        0 => Err(FindPartsError::NoCheckpoint {
            dir: dir.to_path_buf(),
            which: part.map_or(String::new(), |p| format!(" of part {p}")),
        }),
        1 => Ok(found.remove(0)),
        _ => Err(FindPartsError::SeveralCheckpoints {
            dir: dir.to_path_buf(),
            parts: found
                .iter()
                .map(|(_, m)| m.spec().to_string())
                .collect::<Vec<_>>()
                .join(", "),
        }),
    }
}
