//! Why a tolerance analysis could not start or could not be written.

/// Why a tolerance analysis could not start or could not be written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ToleranceError {
    #[error("cannot load the scene {path}")]
    Scene {
        path: String,
        #[source]
        source: lucerna_scene::LoadSceneError,
    },
    /// A problem in the tolerances file: line 0 is the file as a whole.
    #[error("{path}{}: {}{why}", if *line > 0 { format!(":{line}") } else { String::new() }, if field.is_empty() { String::new() } else { format!("{field}: ") })]
    File {
        path: String,
        line: usize,
        field: String,
        why: String,
    },
    #[error("spec {path}: {why}")]
    Spec { path: String, why: String },
    #[error("the nominal scene cannot be traced: {0}")]
    Nominal(String),
    #[error("{0}")]
    Settings(String),
    #[error("the part files cannot be merged: {0}")]
    Merge(String),
    #[error("the analysis's files cannot be made: {0}")]
    Output(String),
    #[error("cannot write {path}")]
    Write {
        path: String,
        #[source]
        source: std::io::Error,
    },
}
