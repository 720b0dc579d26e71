//! The JSON manifest of a partial map: what run it belongs to, which
//! photons it holds, and the bake it is part of; written beside its counts
//! so that a process killed at any instant leaves a usable pair.

use std::path::{Path, PathBuf};

use lucerna_photometry::IntensityMap;
use lucerna_scene::io::write_atomically;
use serde::{Deserialize, Serialize};

use super::counts::{CountsFile, decode_counts, encode_counts};
use super::{
    MANIFEST_FORMAT, PARTIAL_MAP_VERSION, PartSpec, PhotonRange, ReadPartError, SceneIdentity,
    TraceIdentity,
};
use crate::BakeJob;

/// A part's files cannot be written.
#[derive(Debug, thiserror::Error)]
#[error("cannot write {path}")]
pub struct WritePartError {
    pub path: PathBuf,
    #[source]
    pub source: std::io::Error,
}

/// The JSON manifest of a partial map.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PartManifest {
    /// Always "lucerna partial map".
    pub format: String,
    pub version: u32,
    /// The Lucerna that wrote it.
    pub tool_version: String,
    pub scene: SceneIdentity,
    pub trace: TraceIdentity,
    /// The bake this is part of, as it was given: a resume traces on with
    /// its settings and a merge writes its files, the one-machine bake's.
    pub job: BakeJob,
    /// Which part of `trace.parts` (from 1).
    pub part: u32,
    /// The photon numbers this part is to trace.
    pub range: PhotonRange,
    /// Photons of the range traced so far, from its first: all of them
    /// once `complete`.
    pub photons_traced: u64,
    pub complete: bool,
    /// The backend that traced it (counts are bit-identical on one
    /// backend; CPU and GPU differ in the last digits of their floats).
    pub backend: String,
    /// `cpu` or `gpu`: what a resume traces on, so that one part's
    /// photons all come from one backend.
    pub backend_kind: String,
    /// Whether the bake writes its photometric files itself once complete
    /// (a whole bake with checkpoints) rather than leaving the partial
    /// map to `lucerna merge` (a part).
    pub write_outputs: bool,
    /// Wall time of tracing so far, over every resume (s).
    pub wall_seconds: f64,
    pub photons_per_second: f64,
    pub counts: CountsFile,
}

impl PartManifest {
    pub fn spec(&self) -> PartSpec {
        PartSpec {
            index: self.part,
            count: self.trace.parts,
        }
    }

    /// The photons this file holds: the range's first `photons_traced`.
    pub fn traced(&self) -> PhotonRange {
        PhotonRange {
            first: self.range.first,
            end: self.range.first + self.photons_traced,
        }
    }
}

/// The manifest's file name of part `spec` of a bake whose files are
/// `stem` (its counts files are named after it).
pub fn manifest_file_name(stem: &str, spec: PartSpec) -> String {
    format!("{stem}.part-{}-of-{}.json", spec.index, spec.count)
}

/// Writes a partial map: its counts, then its manifest at
/// `manifest_path`, each atomically. The counts go to the one of two slot
/// files (`….a.counts`, `….b.counts`) the manifest on disk does not name,
/// and the other is removed only once the new manifest is in place: a
/// process killed at any instant leaves a manifest whose counts are
/// intact.
pub fn write_part(
    manifest_path: &Path,
    manifest: &mut PartManifest,
    map: &IntensityMap,
) -> Result<(), WritePartError> {
    let dir = manifest_path.parent().unwrap_or(Path::new("."));
    let base = manifest_path
        .file_name()
        .and_then(|n| n.to_str())
        .and_then(|n| n.strip_suffix(".json"))
        .unwrap_or("part");
    let slots = [format!("{base}.a.counts"), format!("{base}.b.counts")];
    let previous = std::mem::take(&mut manifest.counts.file);
    let slot = if previous == slots[0] {
        &slots[1]
    } else {
        &slots[0]
    };
    let bytes = encode_counts(map);
    manifest.counts = CountsFile {
        file: slot.clone(),
        bytes: bytes.len() as u64,
        crc32: crc32fast::hash(&bytes[..bytes.len() - 4]),
    };
    manifest.photons_traced = map.photons_emitted;
    manifest.complete = map.photons_emitted == manifest.range.len();
    let counts_path = dir.join(slot);
    write_atomically(&counts_path, &bytes).map_err(|source| WritePartError {
        path: counts_path,
        source,
    })?;
    let mut text = serde_json::to_string_pretty(manifest).expect("a manifest serialises");
    text.push('\n');
    write_atomically(manifest_path, text.as_bytes()).map_err(|source| WritePartError {
        path: manifest_path.to_path_buf(),
        source,
    })?;
    if !previous.is_empty() && previous != *slot {
        // The renames must be on disk before the older slot goes, or a
        // power cut could leave a manifest naming a removed file.
        #[cfg(unix)]
        let _ = std::fs::File::open(dir).and_then(|d| d.sync_all());
        // Stale now; a failure to remove it loses nothing.
        let _ = std::fs::remove_file(dir.join(&previous));
    }
    Ok(())
}

/// Reads and checks a manifest (not yet its counts).
pub fn read_manifest(path: &Path) -> Result<PartManifest, ReadPartError> {
    let text =
        lucerna_scene::io::read_limited_text(path, 1 << 20).map_err(|e| ReadPartError::Io {
            path: path.to_path_buf(),
            source: std::io::Error::other(e.to_string()),
        })?;
    let value: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| ReadPartError::NotAPart {
            path: path.to_path_buf(),
            why: format!("not JSON ({e})"),
        })?;
    if value.get("format").and_then(|f| f.as_str()) != Some(MANIFEST_FORMAT) {
        return Err(ReadPartError::NotAPart {
            path: path.to_path_buf(),
            why: format!("its \"format\" is not \"{MANIFEST_FORMAT}\""),
        });
    }
    // The version first: a newer file may not parse as this one.
    match value.get("version").and_then(|v| v.as_u64()) {
        Some(v) if v > u64::from(PARTIAL_MAP_VERSION) => {
            return Err(ReadPartError::NewerVersion {
                path: path.to_path_buf(),
                version: u32::try_from(v).unwrap_or(u32::MAX),
            });
        }
        Some(v) if v < u64::from(PARTIAL_MAP_VERSION) => {
            return Err(ReadPartError::OlderVersion {
                path: path.to_path_buf(),
                version: u32::try_from(v).unwrap_or(0),
            });
        }
        Some(_) => {}
        None => {
            return Err(ReadPartError::NotAPart {
                path: path.to_path_buf(),
                why: "it has no \"version\"".to_owned(),
            });
        }
    }
    let manifest: PartManifest =
        serde_json::from_value(value).map_err(|e| ReadPartError::Corrupt {
            path: path.to_path_buf(),
            why: e.to_string(),
        })?;
    let spec =
        PartSpec::new(manifest.part, manifest.trace.parts).map_err(|e| ReadPartError::Corrupt {
            path: path.to_path_buf(),
            why: e.to_string(),
        })?;
    if spec.range(manifest.trace.photons_total) != manifest.range
        || manifest.photons_traced > manifest.range.len()
        || manifest.complete != (manifest.photons_traced == manifest.range.len())
    {
        return Err(ReadPartError::Corrupt {
            path: path.to_path_buf(),
            why: format!(
                "its range {} and {} photons traced are not those of part {spec} of {} photons",
                manifest.range, manifest.photons_traced, manifest.trace.photons_total
            ),
        });
    }
    let is_digest = |d: &str| d.len() == 64 && d.bytes().all(|b| b.is_ascii_hexdigit());
    if !is_digest(&manifest.scene.sha256)
        || !manifest.scene.files.iter().all(|f| is_digest(&f.sha256))
    {
        return Err(ReadPartError::Corrupt {
            path: path.to_path_buf(),
            why: "a scene digest is not 64 hexadecimal digits".to_owned(),
        });
    }
    let t = &manifest.trace;
    if !(1..=4096).contains(&t.resolution)
        || t.photons_total > 1 << 62
        || !(t.emitter_flux_lm.is_finite() && t.emitter_flux_lm > 0.0)
    {
        return Err(ReadPartError::Corrupt {
            path: path.to_path_buf(),
            why: format!(
                "its trace ({} texels per face edge, {} photons, {} lm) is not one Lucerna traces",
                t.resolution, t.photons_total, t.emitter_flux_lm
            ),
        });
    }
    let counts = Path::new(&manifest.counts.file);
    if counts.file_name() != Some(counts.as_os_str()) {
        return Err(ReadPartError::Corrupt {
            path: path.to_path_buf(),
            why: format!("counts file '{}' is not a plain name", manifest.counts.file),
        });
    }
    Ok(manifest)
}

/// Reads the counts a manifest at `manifest_path` names and checks they
/// are the ones it describes.
pub fn read_part_counts(
    manifest_path: &Path,
    manifest: &PartManifest,
) -> Result<IntensityMap, ReadPartError> {
    let dir = manifest_path.parent().unwrap_or(Path::new("."));
    let path = dir.join(&manifest.counts.file);
    let bytes = std::fs::read(&path).map_err(|source| ReadPartError::Io {
        path: path.clone(),
        source,
    })?;
    if (bytes.len() as u64) < manifest.counts.bytes {
        return Err(ReadPartError::Truncated {
            path,
            expected: manifest.counts.bytes,
            got: bytes.len() as u64,
        });
    }
    let map = decode_counts(&bytes, &path)?;
    let checks = [
        (
            "is not the counts file its manifest names (size or CRC-32 differ)",
            bytes.len() as u64 == manifest.counts.bytes
                && crc32fast::hash(&bytes[..bytes.len() - 4]) == manifest.counts.crc32,
        ),
        (
            "holds another number of photons than its manifest",
            map.photons_emitted == manifest.photons_traced,
        ),
        (
            "is of another resolution or emitter flux than its manifest",
            map.layout.resolution == manifest.trace.resolution
                && map.emitter_flux_lm == manifest.trace.emitter_flux_lm,
        ),
    ];
    for (why, ok) in checks {
        if !ok {
            return Err(ReadPartError::Corrupt {
                path,
                why: why.to_owned(),
            });
        }
    }
    Ok(map)
}

/// A manifest to be written for part `spec` of a run (its counts file's
/// file, size and CRC filled in by [`write_part`]).
pub fn new_manifest(
    scene: SceneIdentity,
    trace: TraceIdentity,
    job: BakeJob,
    spec: PartSpec,
    backend_kind: &str,
    write_outputs: bool,
) -> PartManifest {
    PartManifest {
        format: MANIFEST_FORMAT.to_owned(),
        version: PARTIAL_MAP_VERSION,
        tool_version: env!("CARGO_PKG_VERSION").to_owned(),
        scene,
        trace,
        job,
        part: spec.index,
        range: spec.range(trace.photons_total),
        photons_traced: 0,
        complete: false,
        backend: String::new(),
        backend_kind: backend_kind.to_owned(),
        write_outputs,
        wall_seconds: 0.0,
        photons_per_second: 0.0,
        counts: CountsFile {
            file: String::new(),
            bytes: 0,
            crc32: 0,
        },
    }
}
