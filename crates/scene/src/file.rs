//! Scene files: TOML load (with file:line errors) and atomic save; the
//! bounded reading every input file of the project goes through.

use std::io::{Read, Write};
use std::path::{Path, PathBuf};

use crate::model::Scene;
use crate::validate::{FieldPath, PathSegment, validation};

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

/// One problem in a scene file, located by line where the key exists.
#[derive(Debug, Clone, PartialEq)]
pub struct Located {
    pub line: Option<usize>,
    pub field: String,
    pub message: String,
}

impl std::fmt::Display for Located {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.line {
            Some(line) => write!(f, "line {line}: {}: {}", self.field, self.message),
            None => write!(f, "{}: {}", self.field, self.message),
        }
    }
}

#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum LoadSceneError {
    /// Missing, unreadable, larger than [`MAX_SCENE_FILE_BYTES`] or not text.
    #[error(transparent)]
    Read(#[from] ReadFileError),
    /// Not TOML, a wrong type, an unknown or missing field.
    #[error("{path}:{line}:{column}: {message}")]
    Syntax {
        path: PathBuf,
        line: usize,
        column: usize,
        message: String,
    },
    /// Well-formed, but values out of range or references that don't
    /// resolve: the first [`crate::validate::MAX_LISTED_PROBLEMS`] in file
    /// order, and how many more there are.
    #[error("{path}: invalid scene:\n{}", list(problems, *unlisted))]
    Invalid {
        path: PathBuf,
        problems: Vec<Located>,
        unlisted: usize,
    },
}

fn list(problems: &[Located], unlisted: usize) -> String {
    let mut lines: Vec<String> = problems.iter().map(|p| format!("  {p}")).collect();
    if unlisted > 0 {
        lines.push(format!("  … and {unlisted} more problems"));
    }
    lines.join("\n")
}

#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SaveSceneError {
    #[error("cannot serialise the scene")]
    Serialise(#[from] toml::ser::Error),
    #[error("cannot write scene file {path}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

/// 1-based line and column of byte offset `at` in `text`.
fn line_column(text: &str, at: usize) -> (usize, usize) {
    let at = at.min(text.len());
    let before = &text.as_bytes()[..at];
    let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
    let column = at
        - before
            .iter()
            .rposition(|&b| b == b'\n')
            .map_or(0, |i| i + 1)
        + 1;
    (line, column)
}

/// Finds the lines of values by their field paths in one parse of the
/// text, so that reporting N problems costs one parse, not N.
struct Locator<'t> {
    root: Option<toml::Spanned<toml::de::DeTable<'t>>>,
    /// Byte offset at which each line starts.
    line_starts: Vec<usize>,
}

impl<'t> Locator<'t> {
    fn new(text: &'t str) -> Self {
        Locator {
            root: toml::de::DeTable::parse(text).ok(),
            line_starts: std::iter::once(0)
                .chain(text.match_indices('\n').map(|(i, _)| i + 1))
                .collect(),
        }
    }

    /// 1-based line of byte offset `at`.
    fn line_of(&self, at: usize) -> usize {
        self.line_starts.partition_point(|&start| start <= at)
    }

    /// The line of the value at `path` (or of its nearest existing parent).
    fn line(&self, path: &FieldPath) -> Option<usize> {
        use toml::de::DeValue;
        let mut span = None;
        let mut table = Some(self.root.as_ref()?.get_ref());
        let mut array: Option<&toml::de::DeArray> = None;
        for segment in &path.0 {
            let value = match segment {
                PathSegment::Key(k) => table?.get_key_value(k.as_str()).map(|(key, v)| {
                    // A table's own span can be its header; the key's line
                    // is where a reader looks.
                    span = Some(key.span());
                    v
                }),
                PathSegment::Index(i) => array?.get(*i).inspect(|v| span = Some(v.span())),
            };
            let Some(value) = value else { break };
            table = None;
            array = None;
            match value.get_ref() {
                DeValue::Table(t) => table = Some(t),
                DeValue::Array(a) => array = Some(a),
                _ => {}
            }
        }
        span.map(|s| self.line_of(s.start))
    }
}

/// Tagged enums (materials, shapes) are buffered by serde, so an unknown
/// field inside one is reported at the table (or its header); find the
/// offending key between there and the next table header instead.
fn refine_unknown_field(text: &str, span: std::ops::Range<usize>, message: &str) -> usize {
    let Some(name) = message
        .strip_prefix("unknown field `")
        .and_then(|rest| rest.split('`').next())
    else {
        return span.start;
    };
    let end = text
        .get(span.end..)
        .and_then(|rest| rest.find("\n[").map(|i| span.end + i))
        .unwrap_or(text.len())
        .max(span.end)
        .min(text.len());
    let Some(inside) = text.get(span.start..end) else {
        return span.start;
    };
    let is_key_at = |i: usize| {
        let before_ok = i == 0
            || inside[..i]
                .chars()
                .next_back()
                .is_some_and(|c| c.is_whitespace() || c == '{' || c == ',');
        let after = inside[i + name.len()..].trim_start();
        before_ok && after.starts_with('=')
    };
    inside
        .match_indices(name)
        .map(|(i, _)| i)
        .find(|&i| is_key_at(i))
        .map_or(span.start, |i| span.start + i)
}

/// Parses and validates scene text; `path` only names the source in errors.
pub fn parse_scene(text: &str, path: &Path) -> Result<Scene, LoadSceneError> {
    let scene: Scene = toml::from_str(text).map_err(|e| {
        let (line, column) = e
            .span()
            .map(|s| line_column(text, refine_unknown_field(text, s, e.message())))
            .unwrap_or((1, 1));
        LoadSceneError::Syntax {
            path: path.to_owned(),
            line,
            column,
            message: e.message().trim().to_owned(),
        }
    })?;
    let found = validation(&scene);
    if !found.problems.is_empty() {
        let locator = Locator::new(text);
        return Err(LoadSceneError::Invalid {
            path: path.to_owned(),
            problems: found
                .problems
                .into_iter()
                .map(|p| Located {
                    line: locator.line(&p.field),
                    field: p.field.to_string(),
                    message: p.message,
                })
                .collect(),
            unlisted: found.unlisted,
        });
    }
    Ok(scene)
}

/// Reads (at most [`MAX_SCENE_FILE_BYTES`]), parses and validates a scene
/// file.
pub fn load_scene(path: &Path) -> Result<Scene, LoadSceneError> {
    let text = read_limited_text(path, MAX_SCENE_FILE_BYTES)?;
    parse_scene(&text, path)
}

/// The scene as TOML text, in the form [`parse_scene`] reads back losslessly.
pub fn scene_to_toml(scene: &Scene) -> Result<String, toml::ser::Error> {
    toml::to_string_pretty(scene)
}

/// Writes bytes to `path` through a temporary file in the same directory
/// and a rename, so no reader ever sees a half-written file.
pub fn write_atomically(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
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
    tmp.persist(path).map_err(|e| e.error)?;
    Ok(())
}

/// Writes several files all or none: every file is staged beside its
/// place first, and only once all are staged are they renamed into place
/// (an export of five files never leaves two). On failure the staged
/// files are removed and the path that failed is returned with the error.
pub fn write_all_atomically(files: &[(PathBuf, Vec<u8>)]) -> Result<(), (PathBuf, std::io::Error)> {
    let mut staged = Vec::with_capacity(files.len());
    for (path, bytes) in files {
        let dir = match path.parent() {
            Some(d) if !d.as_os_str().is_empty() => d,
            _ => Path::new("."),
        };
        let mut builder = tempfile::Builder::new();
        #[cfg(unix)]
        {
            use std::os::unix::fs::PermissionsExt;
            builder.permissions(std::fs::Permissions::from_mode(0o644));
        }
        let stage = || -> std::io::Result<tempfile::NamedTempFile> {
            let mut tmp = builder.tempfile_in(dir)?;
            tmp.write_all(bytes)?;
            tmp.as_file().sync_all()?;
            Ok(tmp)
        };
        // A staged file dropped on an early return deletes itself.
        staged.push(stage().map_err(|e| (path.clone(), e))?);
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

/// Saves a scene atomically.
pub fn save_scene(scene: &Scene, path: &Path) -> Result<(), SaveSceneError> {
    let text = scene_to_toml(scene)?;
    write_atomically(path, text.as_bytes()).map_err(|source| SaveSceneError::Io {
        path: path.to_owned(),
        source,
    })
}
