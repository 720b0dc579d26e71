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

mod counts;
mod find;
mod identity;
mod manifest;
mod merge;
mod spec;

use std::path::PathBuf;

pub use counts::{CountsFile, decode_counts, encode_counts};
pub use find::{FindPartsError, find_checkpoint, manifests_in};
pub use identity::{FileDigest, SceneCheckError, SceneFileError, SceneIdentity, TraceIdentity};
pub use manifest::{
    PartManifest, WritePartError, manifest_file_name, new_manifest, read_manifest,
    read_part_counts, write_part,
};
pub use merge::{Gap, MergePartsError, MergedParts, check_parts, merge_parts};
pub use spec::{MAX_PARTS, PartSpec, PartSpecError, PhotonRange};

/// The partial-map format version this build writes and reads (manifest
/// and counts file share it). Version 2 stores the bake as a typed
/// [`crate::BakeJob`] where version 1 stored command-line flags.
pub const PARTIAL_MAP_VERSION: u32 = 2;

/// What a manifest's `format` field says.
const MANIFEST_FORMAT: &str = "lucerna partial map";

/// A part's manifest or counts cannot be used: every variant names its
/// file.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReadPartError {
    #[error("cannot read {path}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("{path} is not a Lucerna partial map: {why}")]
    NotAPart { path: PathBuf, why: String },
    #[error(
        "{path} is of partial-map format version {version}, written by a newer Lucerna; this \
         build reads version {PARTIAL_MAP_VERSION}"
    )]
    NewerVersion { path: PathBuf, version: u32 },
    #[error(
        "{path} is of partial-map format version {version}, written by an older Lucerna; this \
         build reads version {PARTIAL_MAP_VERSION}: trace that part again"
    )]
    OlderVersion { path: PathBuf, version: u32 },
    #[error("{path} is truncated: {got} bytes of the {expected} its manifest states")]
    Truncated {
        path: PathBuf,
        expected: u64,
        got: u64,
    },
    #[error("{path} is corrupt: {why}")]
    Corrupt { path: PathBuf, why: String },
}
