//! Scene files: TOML load (with file:line errors) and atomic save.

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::model::Scene;
use crate::validate::{FieldPath, PathSegment, validate};

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
    #[error("cannot read scene file {path}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// Not TOML, a wrong type, an unknown or missing field.
    #[error("{path}:{line}:{column}: {message}")]
    Syntax {
        path: PathBuf,
        line: usize,
        column: usize,
        message: String,
    },
    /// Well-formed, but values out of range or references that don't resolve.
    #[error("{path}: invalid scene:\n{}", list(problems))]
    Invalid {
        path: PathBuf,
        problems: Vec<Located>,
    },
}

fn list(problems: &[Located]) -> String {
    problems
        .iter()
        .map(|p| format!("  {p}"))
        .collect::<Vec<_>>()
        .join("\n")
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

/// Finds the line of the value at `path` (or of its nearest existing parent).
fn locate(text: &str, path: &FieldPath) -> Option<usize> {
    use toml::de::{DeTable, DeValue};
    let root = DeTable::parse(text).ok()?;
    let mut span = None;
    let mut table: Option<&DeTable> = Some(root.get_ref());
    let mut array: Option<&toml::de::DeArray> = None;
    for segment in &path.0 {
        let value = match segment {
            PathSegment::Key(k) => table?
                .iter()
                .find(|(key, _)| key.get_ref().as_ref() == k.as_str())
                .map(|(key, v)| {
                    // A table's own span can be its header; the key's line is
                    // where a reader looks.
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
    span.map(|s| line_column(text, s.start).0)
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
    let problems = validate(&scene);
    if !problems.is_empty() {
        return Err(LoadSceneError::Invalid {
            path: path.to_owned(),
            problems: problems
                .into_iter()
                .map(|p| Located {
                    line: locate(text, &p.field),
                    field: p.field.to_string(),
                    message: p.message,
                })
                .collect(),
        });
    }
    Ok(scene)
}

/// Reads, parses and validates a scene file.
pub fn load_scene(path: &Path) -> Result<Scene, LoadSceneError> {
    let text = std::fs::read_to_string(path).map_err(|source| LoadSceneError::Io {
        path: path.to_owned(),
        source,
    })?;
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

/// Saves a scene atomically.
pub fn save_scene(scene: &Scene, path: &Path) -> Result<(), SaveSceneError> {
    let text = scene_to_toml(scene)?;
    write_atomically(path, text.as_bytes()).map_err(|source| SaveSceneError::Io {
        path: path.to_owned(),
        source,
    })
}
