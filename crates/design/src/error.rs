//! Why a design could not start or could not be written.

/// Why a design could not start or could not be written.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DesignError {
    #[error("cannot load the scene {path}")]
    Scene {
        path: String,
        #[source]
        source: lucerna_scene::LoadSceneError,
    },
    #[error("the scene {path} cannot be traced")]
    Prepare {
        path: String,
        #[source]
        source: Box<lucerna_simulation::SimulationError>,
    },
    #[error("target {path}: {why}")]
    Target { path: String, why: String },
    #[error("--vary {what}: {why}")]
    Vary { what: String, why: String },
    #[error("--points {points}: {why}")]
    Points { points: usize, why: String },
    #[error("--free-ends: {0}")]
    FreeEnds(String),
    #[error("the time for a design must be positive")]
    Time,
    #[error("the start scene itself cannot be traced: {0}")]
    Start(String),
    #[error("the design's files cannot be made: {0}")]
    Output(String),
    #[error("cannot write {path}")]
    Write {
        path: String,
        #[source]
        source: std::io::Error,
    },
}
