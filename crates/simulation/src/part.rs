//! Split bakes. Photon k of a run is photon k mod 2³⁰ of random-number
//! block k / 2³⁰ of its seed, so a range of photon numbers is a well-defined
//! piece of a run that any machine can trace. A part's (or a checkpoint's)
//! counts are stored as a *partial map*: a small binary counts file (exact
//! u64 counts, versioned, CRC-checked) and a JSON manifest that says what
//! run it belongs to. Merging sums the counts exactly, so the merged map is
//! the one-machine map bit for bit.
//!
//! Every check here names the file it is about, and nothing is written by
//! a check that fails.

use std::fmt;
use std::path::{Path, PathBuf};

use lucerna_photometry::{CubeMapLayout, IntensityMap};
use lucerna_scene::Scene;
use lucerna_scene::file::write_atomically;
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

/// The partial-map format version this build writes and reads (manifest
/// and counts file share it).
pub const PARTIAL_MAP_VERSION: u32 = 1;

/// What a manifest's `format` field says.
const MANIFEST_FORMAT: &str = "lucerna partial map";

/// The first 16 bytes of a counts file.
const COUNTS_MAGIC: &[u8; 16] = b"LUCERNA-COUNTS\0\0";

/// Bytes before the counts: magic, version, resolution, emitted, absorbed,
/// cut off, emitter flux, texel count.
const COUNTS_HEADER_BYTES: usize = 16 + 4 + 4 + 8 * 5;

/// Part `index` of `count` (both from 1: `--part 3/8`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct PartSpec {
    pub index: u32,
    pub count: u32,
}

/// The most parts a run is split into (a job array of 100 000 tasks is
/// already beyond what schedulers allow by default).
pub const MAX_PARTS: u32 = 1_000_000;

impl PartSpec {
    /// The whole run as one part.
    pub const WHOLE: PartSpec = PartSpec { index: 1, count: 1 };

    pub fn new(index: u32, count: u32) -> Result<PartSpec, PartError> {
        if count == 0 || count > MAX_PARTS {
            return Err(PartError::Spec(format!(
                "{index}/{count}: the number of parts must be between 1 and {MAX_PARTS}"
            )));
        }
        if index == 0 || index > count {
            return Err(PartError::Spec(format!(
                "{index}/{count}: parts are numbered 1 to {count}"
            )));
        }
        Ok(PartSpec { index, count })
    }

    /// The photons of this part among `total`: parts differ in size by at
    /// most one photon and together cover `0..total` once.
    pub fn range(&self, total: u64) -> PhotonRange {
        let at = |k: u32| (u128::from(total) * u128::from(k) / u128::from(self.count)) as u64;
        PhotonRange {
            first: at(self.index - 1),
            end: at(self.index),
        }
    }

    /// The part a scheduler's task is: a Slurm job array
    /// (`SLURM_ARRAY_TASK_ID` with `SLURM_ARRAY_TASK_COUNT`, or with
    /// `SLURM_ARRAY_TASK_MIN`/`MAX`, task ids counted from the minimum) or
    /// a Kubernetes Indexed Job (`JOB_COMPLETION_INDEX`, from 0, with
    /// `parts` given). `env` reads a variable.
    pub fn from_scheduler(
        env: &dyn Fn(&str) -> Option<String>,
        parts: Option<u32>,
    ) -> Result<PartSpec, PartError> {
        let number = |name: &str| -> Result<Option<u32>, PartError> {
            match env(name) {
                None => Ok(None),
                Some(v) => v
                    .trim()
                    .parse::<u32>()
                    .map(Some)
                    .map_err(|_| PartError::Spec(format!("{name}='{v}' is not a task number"))),
            }
        };
        if let Some(id) = number("SLURM_ARRAY_TASK_ID")? {
            let min = number("SLURM_ARRAY_TASK_MIN")?;
            let max = number("SLURM_ARRAY_TASK_MAX")?;
            let count = number("SLURM_ARRAY_TASK_COUNT")?;
            let (first, count) = match (min, max, count) {
                (Some(min), Some(max), _) if max >= min => (min, max - min + 1),
                (min, _, Some(count)) => (min.unwrap_or(0), count),
                _ => {
                    return Err(PartError::Spec(
                        "SLURM_ARRAY_TASK_ID is set but neither SLURM_ARRAY_TASK_COUNT nor \
                         SLURM_ARRAY_TASK_MIN/MAX: is this a job array?"
                            .to_owned(),
                    ));
                }
            };
            if let (Some(min), Some(max), Some(listed)) =
                (min, max, number("SLURM_ARRAY_TASK_COUNT")?)
                && max >= min
                && listed != max - min + 1
            {
                return Err(PartError::Spec(format!(
                    "the job array has {listed} tasks numbered {min} to {max}: number them \
                     contiguously (--array={min}-{}) so that each task is one part",
                    min + listed - 1
                )));
            }
            if let Some(parts) = parts
                && parts != count
            {
                return Err(PartError::Spec(format!(
                    "--parts {parts} disagrees with the job array's {count} tasks"
                )));
            }
            let index = id.checked_sub(first).ok_or_else(|| {
                PartError::Spec(format!(
                    "SLURM_ARRAY_TASK_ID={id} is below the array's first task {first}"
                ))
            })?;
            return PartSpec::new(index + 1, count)
                .map_err(|e| PartError::Spec(format!("the Slurm array task is not a part: {e}")));
        }
        if let Some(index) = number("JOB_COMPLETION_INDEX")? {
            let Some(count) = parts else {
                return Err(PartError::Spec(
                    "JOB_COMPLETION_INDEX is set: give the Job's completions as --parts N"
                        .to_owned(),
                ));
            };
            return PartSpec::new(index.saturating_add(1), count)
                .map_err(|e| PartError::Spec(format!("JOB_COMPLETION_INDEX={index}: {e}")));
        }
        Err(PartError::Spec(
            "--part auto needs a scheduler's task: none of SLURM_ARRAY_TASK_ID or \
             JOB_COMPLETION_INDEX is set"
                .to_owned(),
        ))
    }
}

impl fmt::Display for PartSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl std::str::FromStr for PartSpec {
    type Err = PartError;

    /// `K/N`, e.g. `3/8`.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let bad = || PartError::Spec(format!("'{s}' is not a part K/N such as 3/8"));
        let (k, n) = s.split_once('/').ok_or_else(bad)?;
        let k: u32 = k.trim().parse().map_err(|_| bad())?;
        let n: u32 = n.trim().parse().map_err(|_| bad())?;
        PartSpec::new(k, n)
    }
}

/// Photon numbers `first..end` of a run's stream.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
pub struct PhotonRange {
    pub first: u64,
    pub end: u64,
}

impl PhotonRange {
    pub fn len(&self) -> u64 {
        self.end - self.first
    }

    pub fn is_empty(&self) -> bool {
        self.end <= self.first
    }
}

impl fmt::Display for PhotonRange {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "photons {}..{}", self.first, self.end)
    }
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
    pub fn of(scene_path: &Path, scene: &Scene) -> Result<SceneIdentity, PartError> {
        let dir = scene_path.parent().unwrap_or(Path::new("."));
        let digest = |path: &Path| -> Result<String, PartError> {
            let bytes = std::fs::read(path).map_err(|source| PartError::Io {
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

/// The counts file beside a manifest.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct CountsFile {
    /// File name, in the manifest's folder.
    pub file: String,
    pub bytes: u64,
    pub crc32: u32,
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
    /// The output flags of the bake, as `lucerna bake` takes them (filter,
    /// pooling, table grid, formats, labels): a merge writes with these,
    /// so its files are the one-machine bake's.
    pub export_args: Vec<String>,
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

/// Why a part cannot be used: every variant names its file.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum PartError {
    /// A part number that is not one (`0/4`, `5/4`, a scheduler's
    /// variables that do not make one).
    #[error("{0}")]
    Spec(String),
    #[error("cannot read {path}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("cannot write {path}")]
    Write {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{path} is not a Lucerna partial map: {why}")]
    NotAPart { path: PathBuf, why: String },
    #[error(
        "{path} is of partial-map format version {version}, written by a newer Lucerna; this \
         build reads version {PARTIAL_MAP_VERSION} and older"
    )]
    NewerVersion { path: PathBuf, version: u32 },
    #[error("{path} is truncated: {got} bytes of the {expected} its manifest states")]
    Truncated {
        path: PathBuf,
        expected: u64,
        got: u64,
    },
    #[error("{path} is corrupt: {why}")]
    Corrupt { path: PathBuf, why: String },
    #[error("{path} and {other} are not parts of one run: {what} differs ({a} and {b})")]
    Mismatch {
        path: PathBuf,
        other: PathBuf,
        what: &'static str,
        a: String,
        b: String,
    },
    #[error("{path} and {other} are both part {part}: each part is merged once")]
    Duplicate {
        path: PathBuf,
        other: PathBuf,
        part: PartSpec,
    },
    #[error("{path} overlaps {other}: {a} and {b}")]
    Overlap {
        path: PathBuf,
        other: PathBuf,
        a: PhotonRange,
        b: PhotonRange,
    },
    #[error("photons are missing: {}", describe_missing(.0))]
    Missing(Vec<Gap>),
    #[error("no part was given")]
    NoParts,
    #[error("{dir} holds no checkpoint{which} (no *.part-K-of-N.json)")]
    NoCheckpoint { dir: PathBuf, which: String },
    #[error("{dir} holds checkpoints of several parts ({parts}): say which with --part K/N")]
    SeveralCheckpoints { dir: PathBuf, parts: String },
    #[error("the scene changed since {path} was written: {why}")]
    SceneChanged { path: PathBuf, why: String },
}

/// A range of photons no part holds, and the part that should have.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Gap {
    pub range: PhotonRange,
    /// The part whose range it lies in.
    pub part: PartSpec,
    /// The file of that part if it was given (an unfinished checkpoint).
    pub partial: Option<PathBuf>,
}

fn describe_missing(gaps: &[Gap]) -> String {
    let shown: Vec<String> = gaps
        .iter()
        .take(12)
        .map(|g| match &g.partial {
            Some(p) => format!(
                "{} of part {} ({} stopped there: resume it)",
                g.range,
                g.part,
                p.display()
            ),
            None => format!("{} (part {}, not given)", g.range, g.part),
        })
        .collect();
    let more = gaps.len().saturating_sub(shown.len());
    if more > 0 {
        format!("{}; and {more} more", shown.join("; "))
    } else {
        shown.join("; ")
    }
}

/// Encodes `map` as a counts file: header, the texels' counts as LEB128
/// varints (a count of 100 takes one byte, not eight), CRC-32 of it all.
pub fn encode_counts(map: &IntensityMap) -> Vec<u8> {
    let mut out = Vec::with_capacity(COUNTS_HEADER_BYTES + map.counts.len() + 4);
    out.extend_from_slice(COUNTS_MAGIC);
    out.extend_from_slice(&PARTIAL_MAP_VERSION.to_le_bytes());
    out.extend_from_slice(&map.layout.resolution.to_le_bytes());
    for v in [
        map.photons_emitted,
        map.photons_absorbed,
        map.photons_cut_off,
        map.emitter_flux_lm.to_bits(),
        map.counts.len() as u64,
    ] {
        out.extend_from_slice(&v.to_le_bytes());
    }
    for &c in &map.counts {
        let mut c = c;
        loop {
            let byte = (c & 0x7f) as u8;
            c >>= 7;
            if c == 0 {
                out.push(byte);
                break;
            }
            out.push(byte | 0x80);
        }
    }
    let crc = crc32fast::hash(&out);
    out.extend_from_slice(&crc.to_le_bytes());
    out
}

/// Decodes a counts file (`path` names it in errors).
pub fn decode_counts(bytes: &[u8], path: &Path) -> Result<IntensityMap, PartError> {
    let corrupt = |why: String| PartError::Corrupt {
        path: path.to_path_buf(),
        why,
    };
    if bytes.len() < 20 || &bytes[..16] != COUNTS_MAGIC {
        return Err(PartError::NotAPart {
            path: path.to_path_buf(),
            why: "it does not start as a counts file".to_owned(),
        });
    }
    let u32_at = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().expect("4 bytes"));
    let version = u32_at(16);
    if version > PARTIAL_MAP_VERSION {
        return Err(PartError::NewerVersion {
            path: path.to_path_buf(),
            version,
        });
    }
    if bytes.len() < COUNTS_HEADER_BYTES + 4 {
        return Err(corrupt(format!(
            "{} bytes is shorter than a counts file's header",
            bytes.len()
        )));
    }
    let (body, crc) = bytes.split_at(bytes.len() - 4);
    let stored = u32::from_le_bytes(crc.try_into().expect("4 bytes"));
    if crc32fast::hash(body) != stored {
        return Err(corrupt("its CRC-32 does not match its bytes".to_owned()));
    }
    let u64_at = |at: usize| u64::from_le_bytes(body[at..at + 8].try_into().expect("8 bytes"));
    let resolution = u32_at(20);
    let (emitted, absorbed, cut_off) = (u64_at(24), u64_at(32), u64_at(40));
    let flux = f64::from_bits(u64_at(48));
    let texels = u64_at(56);
    if !(1..=4096).contains(&resolution) {
        return Err(corrupt(format!("resolution {resolution}")));
    }
    let layout = CubeMapLayout::new(resolution);
    if texels != layout.texel_count() as u64 {
        return Err(corrupt(format!(
            "{texels} texels for a map of {resolution} per face edge"
        )));
    }
    if !(flux.is_finite() && flux > 0.0) {
        return Err(corrupt(format!("emitter flux {flux} lm")));
    }
    let mut counts = Vec::with_capacity(layout.texel_count());
    let mut rest = &body[COUNTS_HEADER_BYTES..];
    for _ in 0..texels {
        let mut value: u64 = 0;
        let mut shift = 0;
        loop {
            let Some((&byte, tail)) = rest.split_first() else {
                return Err(corrupt(format!("it ends after {} texels", counts.len())));
            };
            rest = tail;
            if shift == 63 && byte > 1 || shift > 63 {
                return Err(corrupt(format!("texel {} overflows 64 bits", counts.len())));
            }
            value |= u64::from(byte & 0x7f) << shift;
            shift += 7;
            if byte & 0x80 == 0 {
                break;
            }
        }
        counts.push(value);
    }
    if !rest.is_empty() {
        return Err(corrupt(format!(
            "{} bytes follow the last texel",
            rest.len()
        )));
    }
    let map = IntensityMap {
        layout,
        counts,
        photons_emitted: emitted,
        photons_absorbed: absorbed,
        photons_cut_off: cut_off,
        emitter_flux_lm: flux,
    };
    // Summed in u128: a corrupt file must not overflow the check itself.
    let escaped: u128 = map.counts.iter().map(|&c| u128::from(c)).sum();
    if escaped + u128::from(absorbed) + u128::from(cut_off) != u128::from(emitted) {
        return Err(corrupt(format!(
            "its photons do not add up: {escaped} escaped + {absorbed} absorbed + {cut_off} cut \
             off ≠ {emitted} emitted"
        )));
    }
    Ok(map)
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
) -> Result<(), PartError> {
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
    write_atomically(&counts_path, &bytes).map_err(|source| PartError::Write {
        path: counts_path,
        source,
    })?;
    let mut text = serde_json::to_string_pretty(manifest).expect("a manifest serialises");
    text.push('\n');
    write_atomically(manifest_path, text.as_bytes()).map_err(|source| PartError::Write {
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
pub fn read_manifest(path: &Path) -> Result<PartManifest, PartError> {
    let text =
        lucerna_scene::file::read_limited_text(path, 1 << 20).map_err(|e| PartError::Io {
            path: path.to_path_buf(),
            source: std::io::Error::other(e.to_string()),
        })?;
    let value: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| PartError::NotAPart {
            path: path.to_path_buf(),
            why: format!("not JSON ({e})"),
        })?;
    if value.get("format").and_then(|f| f.as_str()) != Some(MANIFEST_FORMAT) {
        return Err(PartError::NotAPart {
            path: path.to_path_buf(),
            why: format!("its \"format\" is not \"{MANIFEST_FORMAT}\""),
        });
    }
    // The version first: a newer file may not parse as this one.
    match value.get("version").and_then(|v| v.as_u64()) {
        Some(v) if v > u64::from(PARTIAL_MAP_VERSION) => {
            return Err(PartError::NewerVersion {
                path: path.to_path_buf(),
                version: u32::try_from(v).unwrap_or(u32::MAX),
            });
        }
        Some(_) => {}
        None => {
            return Err(PartError::NotAPart {
                path: path.to_path_buf(),
                why: "it has no \"version\"".to_owned(),
            });
        }
    }
    let manifest: PartManifest = serde_json::from_value(value).map_err(|e| PartError::Corrupt {
        path: path.to_path_buf(),
        why: e.to_string(),
    })?;
    let spec =
        PartSpec::new(manifest.part, manifest.trace.parts).map_err(|e| PartError::Corrupt {
            path: path.to_path_buf(),
            why: e.to_string(),
        })?;
    if spec.range(manifest.trace.photons_total) != manifest.range
        || manifest.photons_traced > manifest.range.len()
        || manifest.complete != (manifest.photons_traced == manifest.range.len())
    {
        return Err(PartError::Corrupt {
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
        return Err(PartError::Corrupt {
            path: path.to_path_buf(),
            why: "a scene digest is not 64 hexadecimal digits".to_owned(),
        });
    }
    let t = &manifest.trace;
    if !(1..=4096).contains(&t.resolution)
        || t.photons_total > 1 << 62
        || !(t.emitter_flux_lm.is_finite() && t.emitter_flux_lm > 0.0)
    {
        return Err(PartError::Corrupt {
            path: path.to_path_buf(),
            why: format!(
                "its trace ({} texels per face edge, {} photons, {} lm) is not one Lucerna traces",
                t.resolution, t.photons_total, t.emitter_flux_lm
            ),
        });
    }
    let counts = Path::new(&manifest.counts.file);
    if counts.file_name() != Some(counts.as_os_str()) {
        return Err(PartError::Corrupt {
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
) -> Result<IntensityMap, PartError> {
    let dir = manifest_path.parent().unwrap_or(Path::new("."));
    let path = dir.join(&manifest.counts.file);
    let bytes = std::fs::read(&path).map_err(|source| PartError::Io {
        path: path.clone(),
        source,
    })?;
    if (bytes.len() as u64) < manifest.counts.bytes {
        return Err(PartError::Truncated {
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
            return Err(PartError::Corrupt {
                path,
                why: why.to_owned(),
            });
        }
    }
    Ok(map)
}

/// Checks that `parts` (manifest path, manifest) are parts of one run,
/// each once, covering every photon of it.
pub fn check_parts(parts: &[(PathBuf, PartManifest)]) -> Result<(), PartError> {
    let Some((first_path, first)) = parts.first() else {
        return Err(PartError::NoParts);
    };
    for (path, m) in &parts[1..] {
        let mismatch = |what: &'static str, a: String, b: String| PartError::Mismatch {
            path: first_path.clone(),
            other: path.clone(),
            what,
            a,
            b,
        };
        if m.scene.sha256 != first.scene.sha256 {
            let why = first
                .scene
                .first_difference(&m.scene)
                .unwrap_or_else(|| "the scene".to_owned());
            return Err(mismatch(
                "the scene",
                format!(
                    "{}…",
                    &first.scene.sha256[..12.min(first.scene.sha256.len())]
                ),
                format!(
                    "{}…: {why}",
                    &m.scene.sha256[..12.min(m.scene.sha256.len())]
                ),
            ));
        }
        let (a, b) = (&first.trace, &m.trace);
        let fields: [(&'static str, String, String); 6] = [
            ("the seed", a.seed.to_string(), b.seed.to_string()),
            (
                "the resolution",
                a.resolution.to_string(),
                b.resolution.to_string(),
            ),
            (
                "the bounce limit",
                a.max_bounces.to_string(),
                b.max_bounces.to_string(),
            ),
            (
                "the run's photons",
                a.photons_total.to_string(),
                b.photons_total.to_string(),
            ),
            (
                "the number of parts",
                a.parts.to_string(),
                b.parts.to_string(),
            ),
            (
                "the emitter flux",
                a.emitter_flux_lm.to_string(),
                b.emitter_flux_lm.to_string(),
            ),
        ];
        for (what, x, y) in fields {
            if x != y {
                return Err(mismatch(what, x, y));
            }
        }
        if m.export_args != first.export_args {
            return Err(mismatch(
                "the output settings",
                first.export_args.join(" "),
                m.export_args.join(" "),
            ));
        }
    }
    // Each part once.
    let mut by_part: Vec<&(PathBuf, PartManifest)> = parts.iter().collect();
    by_part.sort_by_key(|(_, m)| m.part);
    for pair in by_part.windows(2) {
        let ((p, a), (q, b)) = (pair[0], pair[1]);
        if a.part == b.part {
            return Err(PartError::Duplicate {
                path: p.clone(),
                other: q.clone(),
                part: a.spec(),
            });
        }
    }
    // The ranges, from the manifests' own numbers (not re-derived): a
    // hand-edited range is caught here too.
    let mut ranges: Vec<(PhotonRange, &PathBuf, &PartManifest)> =
        parts.iter().map(|(p, m)| (m.traced(), p, m)).collect();
    ranges.sort_by_key(|(r, _, _)| (r.first, r.end));
    for pair in ranges.windows(2) {
        let ((a, p, _), (b, q, _)) = (&pair[0], &pair[1]);
        if b.first < a.end {
            return Err(PartError::Overlap {
                path: (*p).clone(),
                other: (*q).clone(),
                a: *a,
                b: *b,
            });
        }
    }
    let total = first.trace.photons_total;
    let spec_of = |photon: u64| {
        let count = first.trace.parts;
        // The part whose range holds `photon` (ranges are floor(T·k/N)).
        let mut k = ((u128::from(photon) * u128::from(count)) / u128::from(total.max(1))) as u32;
        k = k.min(count - 1);
        while k + 1 < count
            && (PartSpec {
                index: k + 2,
                count,
            })
            .range(total)
            .first
                <= photon
        {
            k += 1;
        }
        while k > 0
            && (PartSpec {
                index: k + 1,
                count,
            })
            .range(total)
            .first
                > photon
        {
            k -= 1;
        }
        PartSpec {
            index: k + 1,
            count,
        }
    };
    let mut gaps = Vec::new();
    let mut at = 0u64;
    let gap_to = |from: u64, to: u64, gaps: &mut Vec<Gap>| {
        // One gap per part it spans, so each names its part.
        let mut from = from;
        while from < to {
            let part = spec_of(from);
            let end = part.range(total).end.min(to);
            let partial = parts
                .iter()
                .find(|(_, m)| m.part == part.index)
                .map(|(p, _)| p.clone());
            gaps.push(Gap {
                range: PhotonRange { first: from, end },
                part,
                partial,
            });
            from = end;
        }
    };
    for (r, _, _) in &ranges {
        if r.first > at {
            gap_to(at, r.first, &mut gaps);
        }
        at = at.max(r.end);
    }
    if at < total {
        gap_to(at, total, &mut gaps);
    }
    if !gaps.is_empty() {
        return Err(PartError::Missing(gaps));
    }
    Ok(())
}

/// A run put back together from its parts.
#[derive(Debug, Clone)]
pub struct MergedParts {
    /// The first part's manifest (they agree on everything but the part).
    pub manifest: PartManifest,
    pub map: IntensityMap,
    /// Backends that traced the parts, each once.
    pub backends: Vec<String>,
    /// Tracing wall time over all parts (s).
    pub wall_seconds: f64,
}

/// Reads the manifests at `paths`, checks they are the whole of one run,
/// then adds their counts exactly (u64; one part's counts in memory at a
/// time besides the sum).
pub fn merge_parts(paths: &[PathBuf]) -> Result<MergedParts, PartError> {
    let parts = paths
        .iter()
        .map(|p| Ok((p.clone(), read_manifest(p)?)))
        .collect::<Result<Vec<_>, PartError>>()?;
    check_parts(&parts)?;
    let (_, first) = &parts[0];
    let layout = CubeMapLayout::new(first.trace.resolution);
    let mut map = IntensityMap::new(layout, first.trace.emitter_flux_lm);
    let mut backends: Vec<String> = Vec::new();
    let mut wall_seconds = 0.0;
    for (path, manifest) in &parts {
        let part = read_part_counts(path, manifest)?;
        map.merge(&part).map_err(|e| PartError::Corrupt {
            path: path.clone(),
            why: e.to_string(),
        })?;
        // CPU parts are bit-identical whatever their thread count; GPU
        // parts per adapter.
        let backend = if manifest.backend_kind == "cpu" {
            "CPU tracer".to_owned()
        } else {
            manifest.backend.clone()
        };
        if !backends.contains(&backend) {
            backends.push(backend);
        }
        wall_seconds += manifest.wall_seconds;
    }
    Ok(MergedParts {
        manifest: first.clone(),
        map,
        backends,
        wall_seconds,
    })
}

/// The manifests in `dir` (files named `*.part-K-of-N.json`), sorted.
pub fn manifests_in(dir: &Path) -> Result<Vec<PathBuf>, PartError> {
    let entries = std::fs::read_dir(dir).map_err(|source| PartError::Io {
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
) -> Result<(PathBuf, PartManifest), PartError> {
    let mut found = Vec::new();
    for path in manifests_in(dir)? {
        let manifest = read_manifest(&path)?;
        if part.is_none_or(|p| p == manifest.spec()) {
            found.push((path, manifest));
        }
    }
    match found.len() {
        0 => Err(PartError::NoCheckpoint {
            dir: dir.to_path_buf(),
            which: part.map_or(String::new(), |p| format!(" of part {p}")),
        }),
        1 => Ok(found.remove(0)),
        _ => Err(PartError::SeveralCheckpoints {
            dir: dir.to_path_buf(),
            parts: found
                .iter()
                .map(|(_, m)| m.spec().to_string())
                .collect::<Vec<_>>()
                .join(", "),
        }),
    }
}

/// A manifest to be written for part `spec` of a run (its counts file's
/// file, size and CRC filled in by [`write_part`]).
pub fn new_manifest(
    scene: SceneIdentity,
    trace: TraceIdentity,
    export_args: Vec<String>,
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
        export_args,
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
