//! The luminaire simulation as one job, shared by `lucerna bake`, `render`,
//! the benches and the editor: a [`Luminaire`] loaded and prepared once, a
//! synchronous progressive [`Run`] (trace, pool over the luminaire's
//! symmetry, filter, tabulate, figures) and the [`Simulation`] that drives
//! a run on its own worker thread, restarts it on every edit and publishes
//! immutable [`Snapshot`]s that any thread reads without waiting.
//!
//! Nothing here prints or panics on user input: every failure is a
//! [`SimulationError`] value a UI can show.

mod error;
pub mod export;
mod job;
mod live_filter;
mod luminaire;
pub mod part;
mod run;
mod settings;
mod snapshot;
mod worker;

pub use error::SimulationError;
pub use export::{
    DEFAULT_TM25_RAYS, ExportFormats, ExportOptions, ExportRequest, ExportRequestError,
    ExportStage, ExportedFiles, Labels, photometry, write_bake_files,
};
pub use job::{BakeJob, BakeJobError, BakeOutput, DEFAULT_BAKE_PHOTONS};
pub use live_filter::LiveFilter;
pub use lucerna_gpu::BackendRequest;
pub use luminaire::Luminaire;
pub use part::{PartManifest, PartSpec, PhotonRange};
pub use run::{Run, bake, prepare_snapshots, snapshot_of_map};
pub use settings::{FilterChoice, SettingsError, SimulationSettings, StoppingRule, TableGrid};
pub use snapshot::{FilterSummary, Noise, RunState, Snapshot, StopReason};
pub use worker::{Pace, Published, Simulation};
