//! What can go wrong in a simulation, as values a UI can show.

use lucerna_gpu::GpuError;
use lucerna_scene::{LoadSceneError, TessellateError};
use lucerna_tracer::PrepareError;

use crate::settings::SettingsError;

/// Why a simulation could not start, go on or export.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SimulationError {
    #[error(transparent)]
    Settings(#[from] SettingsError),
    #[error(transparent)]
    LoadScene(#[from] LoadSceneError),
    #[error("the scene cannot be tessellated")]
    Tessellate(#[from] TessellateError),
    #[error("the scene cannot be prepared for tracing")]
    Prepare(#[from] PrepareError),
    #[error("the GPU tracer failed")]
    Gpu(#[from] GpuError),
    #[error("cannot write {path}")]
    Write {
        path: std::path::PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("the photometric file cannot be written")]
    WritePhotometry(#[from] lucerna_photometry::WritePhotometryError),
    #[error(transparent)]
    Request(#[from] crate::export::ExportRequestError),
    #[error("cannot draw {what}: {message}")]
    Picture { what: &'static str, message: String },
    #[error("the traced map cannot be continued")]
    Continue(#[from] lucerna_tracer::session::ContinueError),
    #[error("the simulation's worker thread has stopped")]
    WorkerGone,
}
