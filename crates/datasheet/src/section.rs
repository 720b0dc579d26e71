//! A datasheet section that is either there or left out for a stated
//! reason: a file without a luminous opening has no luminance table, an
//! upward-only luminaire no UGR, and the sheet says why instead of
//! inventing figures.

use serde::Serialize;

/// A section's content, or why it is left out. In JSON the content
/// itself, or `{"omitted": "reason"}`.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Section<T> {
    Shown(T),
    Omitted { omitted: String },
}

impl<T> Section<T> {
    pub fn omitted(reason: impl Into<String>) -> Self {
        Section::Omitted {
            omitted: reason.into(),
        }
    }

    pub fn shown(&self) -> Option<&T> {
        match self {
            Section::Shown(t) => Some(t),
            Section::Omitted { .. } => None,
        }
    }
}

impl<T, E: std::fmt::Display> From<Result<T, E>> for Section<T> {
    fn from(r: Result<T, E>) -> Self {
        match r {
            Ok(t) => Section::Shown(t),
            Err(e) => Section::omitted(e.to_string()),
        }
    }
}
