//! Scene files: TOML load (with file:line errors) and atomic save.

use std::path::{Path, PathBuf};

use crate::check::{FieldPath, PathSegment};
pub use crate::io::{
    MAX_PROFILE_FILE_BYTES, MAX_SCENE_FILE_BYTES, MIB, ReadFileError, read_limited,
    read_limited_text, write_all_atomically, write_atomically,
};
use crate::model::Scene;
use crate::validate::validation;

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
    let mut scene: Scene = toml::from_str(text).map_err(|e| {
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
    let unread = ray_files_own_flux(&mut scene, path);
    let maps = read_height_maps(&mut scene, path);
    let mut found = validation(&scene);
    for p in &mut found.problems {
        if let Some((_, why)) = unread.iter().find(|(at, _)| *at == p.field) {
            p.message = format!("not given, and the ray file cannot give its own: {why}");
        }
        if let Some((_, why)) = maps.iter().find(|(at, _)| *at == p.field) {
            p.message = format!("the height map cannot be read: {why}");
        }
    }
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

/// The largest height-map file read (a 16-bit 4096² scan is 32 MiB raw).
const MAX_HEIGHT_MAP_FILE_BYTES: u64 = 256 << 20;

/// Each height-map finish read from beside `path` into the finish;
/// those that cannot be, by field (`part[i].finish.path`), with why.
fn read_height_maps(scene: &mut Scene, path: &Path) -> Vec<(FieldPath, String)> {
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut unread = Vec::new();
    for (i, p) in scene.parts.iter_mut().enumerate() {
        if let Some(crate::finish::Finish::HeightMap {
            path: file,
            heights,
            ..
        }) = &mut p.finish
        {
            let at = dir.join(&*file);
            let grid = read_limited(&at, MAX_HEIGHT_MAP_FILE_BYTES)
                .map_err(|e| e.to_string())
                .and_then(|bytes| {
                    crate::finish::HeightGrid::from_png(&bytes, &at.display().to_string())
                });
            match grid {
                Ok(grid) => *heights = Some(std::sync::Arc::new(grid)),
                Err(why) => unread.push((
                    FieldPath::default()
                        .key("part")
                        .index(i)
                        .key("finish")
                        .key("path"),
                    why,
                )),
            }
        }
    }
    unread
}

/// Each ray-file emitter that states no `flux_lm` gets its file's own
/// (the header's, else the rays' sum), the file found beside `path`;
/// those whose file cannot give it, by field, with why.
fn ray_files_own_flux(scene: &mut Scene, path: &Path) -> Vec<(FieldPath, String)> {
    let dir = path.parent().unwrap_or(Path::new("."));
    let mut unread = Vec::new();
    for (i, e) in scene.emitters.iter_mut().enumerate() {
        if let (true, crate::model::EmitterShape::RayFile { path: file }) =
            (e.flux_lm.is_nan(), &e.shape)
        {
            match lucerna_photometry::tm25::ray_file_luminous_flux(&dir.join(file)) {
                Ok(flux) => e.flux_lm = flux,
                Err(why) => unread.push((
                    FieldPath::default().key("emitter").index(i).key("flux_lm"),
                    why.to_string(),
                )),
            }
        }
    }
    unread
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

/// Saves a scene atomically.
pub fn save_scene(scene: &Scene, path: &Path) -> Result<(), SaveSceneError> {
    let text = scene_to_toml(scene)?;
    write_atomically(path, text.as_bytes()).map_err(|source| SaveSceneError::Io {
        path: path.to_owned(),
        source,
    })
}
