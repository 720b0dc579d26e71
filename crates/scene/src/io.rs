//! The bounded reading every input file of the project goes through, and
//! the atomic writing of every output: a reader never sees half a file.

use std::io::{Read, Write};
use std::path::{Path, PathBuf};

/// One mebibyte, the unit the file-size limits are stated in.
pub const MIB: u64 = 1 << 20;
/// Largest scene file read: hand-written luminaires are a few kB, and a
/// file that is not a scene (`/dev/zero`) must not be read until memory
/// runs out.
pub const MAX_SCENE_FILE_BYTES: u64 = 16 * MIB;
/// Largest emission profile (IES or EULUMDAT) a scene's emitters may name:
/// measured files are far below 1 MiB even at 1° × 1°.
pub const MAX_PROFILE_FILE_BYTES: u64 = 16 * MIB;

/// A file could not be read whole within its size limit.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReadFileError {
    #[error("cannot read {path}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("file {path} is larger than {} MiB", limit_bytes.div_ceil(MIB))]
    TooLarge { path: PathBuf, limit_bytes: u64 },
    #[error("file {path} is not UTF-8 text (line {line})")]
    NotText { path: PathBuf, line: usize },
}

/// Reads the whole file at `path`, refusing one larger than `max_bytes`
/// without reading further than that: devices and pipes (`/dev/zero`)
/// have no length to check beforehand, so the read itself is bounded.
pub fn read_limited(path: &Path, max_bytes: u64) -> Result<Vec<u8>, ReadFileError> {
    let io = |source| ReadFileError::Io {
        path: path.to_owned(),
        source,
    };
    let too_large = || ReadFileError::TooLarge {
        path: path.to_owned(),
        limit_bytes: max_bytes,
    };
    let file = std::fs::File::open(path).map_err(io)?;
    // A regular file's length refuses it before any byte is read (a
    // sparse file of many GiB costs nothing); 0 for devices and pipes.
    let stated_bytes = file.metadata().map_err(io)?.len();
    if stated_bytes > max_bytes {
        return Err(too_large());
    }
    let mut bytes = Vec::with_capacity(stated_bytes as usize + 1);
    file.take(max_bytes.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(io)?;
    if bytes.len() as u64 > max_bytes {
        return Err(too_large());
    }
    Ok(bytes)
}

/// [`read_limited`] for text files: the bytes must be UTF-8.
pub fn read_limited_text(path: &Path, max_bytes: u64) -> Result<String, ReadFileError> {
    String::from_utf8(read_limited(path, max_bytes)?).map_err(|e| {
        let valid = &e.as_bytes()[..e.utf8_error().valid_up_to()];
        ReadFileError::NotText {
            path: path.to_owned(),
            line: valid.iter().filter(|&&b| b == b'\n').count() + 1,
        }
    })
}

/// Writes bytes to `path` through a temporary file in the same directory
/// and a rename, so no reader ever sees a half-written file.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    stage(path, bytes)?.persist(path).map_err(|e| e.error)?;
    Ok(())
}

/// `bytes` written and synced to a temporary file beside `path`, to be
/// renamed into place (dropped, it deletes itself).
fn stage(path: &Path, bytes: &[u8]) -> std::io::Result<tempfile::NamedTempFile> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut builder = tempfile::Builder::new();
    // Temporary files are private (0600); the result is an ordinary
    // document other tools and users read.
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        builder.permissions(std::fs::Permissions::from_mode(0o644));
    }
    let mut tmp = builder.tempfile_in(dir)?;
    tmp.write_all(bytes)?;
    tmp.as_file().sync_all()?;
    Ok(tmp)
}

/// Writes several files all or none: every file is staged beside its
/// place first, and only once all are staged are they renamed into place
/// (an export of five files never leaves two). On failure the staged
/// files are removed and the path that failed is returned with the error.
pub fn write_all_atomically(files: &[(PathBuf, Vec<u8>)]) -> Result<(), (PathBuf, std::io::Error)> {
    let mut staged = Vec::with_capacity(files.len());
    for (path, bytes) in files {
        // A staged file dropped on an early return deletes itself.
        staged.push(stage(path, bytes).map_err(|e| (path.clone(), e))?);
    }
    // What would refuse a rename is found before any file is renamed.
    for (path, _) in files {
        if path.is_dir() {
            let e = std::io::Error::new(std::io::ErrorKind::IsADirectory, "is a folder");
            return Err((path.clone(), e));
        }
    }
    let mut renamed = Vec::new();
    for (tmp, (path, _)) in staged.into_iter().zip(files) {
        let existed = path.exists();
        if let Err(e) = tmp.persist(path) {
            // Files this call created are taken back; ones it replaced
            // cannot be.
            for created in renamed {
                let _ = std::fs::remove_file(created);
            }
            return Err((path.clone(), e.error));
        }
        if !existed {
            renamed.push(path);
        }
    }
    Ok(())
}
