//! A bake as one typed value: what is traced and what is written. The
//! command line converts to it once; a split bake's manifest stores it, so
//! a resume or a merge writes with exactly the settings the bake was given
//! (no argv text parsed back); `lucerna report` starts from its defaults.

use std::path::{Path, PathBuf};

use lucerna_datasheet::DatasheetOptions;
use lucerna_photometry::CPlaneSymmetry;
use serde::{Deserialize, Serialize};

use crate::{ExportFormats, ExportOptions, ExportRequest, SettingsError, SimulationSettings};
use crate::{Snapshot, StoppingRule};

/// Photons a bake traces when no limit is given.
pub const DEFAULT_BAKE_PHOTONS: u64 = 10_000_000;

/// One bake: the scene, how it is traced, and the files written.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BakeJob {
    /// The scene file (its relative paths resolve from its folder).
    pub scene: PathBuf,
    /// Resolution, seed, bounces, backend, stopping rule, filter, pooling
    /// and the table's grid.
    pub settings: SimulationSettings,
    pub output: BakeOutput,
    /// A ray-file emitter's rays used as they are, again and again, rather
    /// than each photon's direction turned by the file's kernel
    /// (`--ray-reuse loop`; `lucerna_tracer::ray_kernel`).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub loop_rays: bool,
}

/// The files a bake writes and how they are labelled.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct BakeOutput {
    pub out_dir: PathBuf,
    /// The files' base name: `STEM.ies`, `STEM_polar.png`, …
    pub stem: String,
    pub formats: ExportFormats,
    /// C-plane symmetry imposed on the table; `None` declares what the
    /// photons were pooled over.
    pub symmetrise: Option<CPlaneSymmetry>,
    /// ISO date the files state; `None`: the day they are written.
    pub date: Option<String>,
    /// The datasheet's UGR spacings and outdoor rating (its source name is
    /// the scene file's).
    pub datasheet: DatasheetOptions,
}

/// A job that cannot run, named by what the user set.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum BakeJobError {
    #[error(transparent)]
    Settings(#[from] SettingsError),
    #[error("'{0}' is not a plain file name (no folders)")]
    Stem(String),
    #[error("no file to write")]
    NoFormats,
}

impl BakeJob {
    /// `lucerna bake SCENE --out OUT_DIR` with every default: the one
    /// home of the bake's defaults.
    pub fn new(scene: &Path, out_dir: &Path) -> BakeJob {
        let stem = scene
            .file_stem()
            .map_or("luminaire".to_owned(), |s| s.to_string_lossy().into_owned());
        BakeJob {
            scene: scene.to_path_buf(),
            settings: SimulationSettings {
                stop: StoppingRule {
                    photons: Some(DEFAULT_BAKE_PHOTONS),
                    ..StoppingRule::default()
                },
                ..SimulationSettings::default()
            },
            output: BakeOutput {
                out_dir: out_dir.to_path_buf(),
                stem,
                formats: ExportFormats::default(),
                symmetrise: None,
                date: None,
                datasheet: DatasheetOptions::default(),
            },
            loop_rays: false,
        }
    }

    /// How the job's ray-file emitters reuse their rays.
    pub fn ray_reuse(&self) -> lucerna_tracer::RayReuse {
        if self.loop_rays {
            lucerna_tracer::RayReuse::Loop
        } else {
            lucerna_tracer::RayReuse::Interpolate
        }
    }

    /// Checks every setting before anything is traced.
    pub fn validate(&self) -> Result<(), BakeJobError> {
        self.settings.validate()?;
        let stem = &self.output.stem;
        if stem.trim().is_empty() || Path::new(stem).file_name() != Some(stem.as_ref()) {
            return Err(BakeJobError::Stem(stem.clone()));
        }
        if self.output.formats.is_empty() {
            return Err(BakeJobError::NoFormats);
        }
        Ok(())
    }

    /// The scene file's name, as the files and the datasheet state it.
    pub fn scene_file_name(&self) -> String {
        self.scene
            .file_name()
            .map_or(String::new(), |s| s.to_string_lossy().into_owned())
    }

    /// The export of `snapshot` (a finished run of this job) this job
    /// writes; `today` is the date stated when the job fixes none.
    pub fn export_request(&self, snapshot: &Snapshot, today: &str) -> ExportRequest {
        let scene_file = self.scene_file_name();
        let options = ExportOptions {
            symmetrise: self.output.symmetrise,
            date: self.output.date.clone().unwrap_or_else(|| today.to_owned()),
            seed: self.settings.seed,
            scene_file: scene_file.clone(),
            // The scene's name, manufacturer and [export] keywords.
            labels: None,
        };
        let mut request =
            ExportRequest::new(snapshot, options, &self.output.out_dir, &self.output.stem);
        request.formats = self.output.formats;
        request.filter = self.settings.filter;
        request.grid = self.settings.table;
        request.datasheet = DatasheetOptions {
            source_name: scene_file,
            ..self.output.datasheet.clone()
        };
        request
    }

    /// The settings that shape the files but not the photons, by name,
    /// where `self` and `other` differ: two parts of one bake must agree
    /// on all of them. The places (scene path, output folder), the backend
    /// and the stopping rule are left out: parts of one bake run on
    /// different machines, and the photons are checked apart.
    pub fn output_differences(&self, other: &BakeJob) -> Vec<(String, String, String)> {
        let a = serde_json::to_value(self.output_settings()).unwrap_or_default();
        let b = serde_json::to_value(other.output_settings()).unwrap_or_default();
        let mut out = Vec::new();
        if let (Some(a), Some(b)) = (a.as_object(), b.as_object()) {
            for (key, va) in a {
                let vb = b.get(key).cloned().unwrap_or_default();
                if *va != vb {
                    out.push((key.clone(), va.to_string(), vb.to_string()));
                }
            }
        }
        out
    }

    fn output_settings(&self) -> OutputSettings {
        OutputSettings {
            filter: self.settings.filter,
            pool_symmetry: self.settings.pool_symmetry,
            table: self.settings.table,
            stem: self.output.stem.clone(),
            formats: self.output.formats,
            symmetrise: self.output.symmetrise,
            date: self.output.date.clone(),
            ugr_spacings: self.output.datasheet.ugr_spacings.clone(),
            outdoor: self.output.datasheet.outdoor,
        }
    }
}

/// [`BakeJob::output_differences`]'s fields, flat.
#[derive(Serialize)]
struct OutputSettings {
    filter: crate::FilterChoice,
    pool_symmetry: bool,
    #[serde(flatten)]
    table: crate::TableGrid,
    stem: String,
    #[serde(flatten)]
    formats: ExportFormats,
    symmetrise: Option<CPlaneSymmetry>,
    date: Option<String>,
    ugr_spacings: Vec<f64>,
    outdoor: lucerna_datasheet::Outdoor,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_job_round_trips_through_json_and_names_its_differences() {
        let mut job = BakeJob::new(Path::new("a/spot.toml"), Path::new("out"));
        job.settings.filter = crate::FilterChoice::Threshold(250.0);
        job.output.formats.tm25_rays = Some(5000);
        job.output.date = Some("2026-01-31".to_owned());
        let text = serde_json::to_string(&job).unwrap();
        let back: BakeJob = serde_json::from_str(&text).unwrap();
        assert_eq!(back, job);
        assert_eq!(job.output.stem, "spot");
        assert_eq!(job.settings.stop.photons, Some(DEFAULT_BAKE_PHOTONS));

        // Places and backend are not output settings; the filter is.
        let mut elsewhere = job.clone();
        elsewhere.output.out_dir = PathBuf::from("/elsewhere");
        elsewhere.settings.backend = lucerna_gpu::BackendRequest::Gpu;
        assert!(job.output_differences(&elsewhere).is_empty());
        elsewhere.settings.filter = crate::FilterChoice::Automatic;
        let d = job.output_differences(&elsewhere);
        assert_eq!(d.len(), 1, "{d:?}");
        assert_eq!(d[0].0, "filter");
    }

    #[test]
    fn a_job_refuses_a_stem_with_folders_and_bad_settings() {
        let mut job = BakeJob::new(Path::new("spot.toml"), Path::new("out"));
        assert_eq!(job.validate(), Ok(()));
        job.output.stem = "../x".to_owned();
        assert!(matches!(job.validate(), Err(BakeJobError::Stem(_))));
        job.output.stem = "x".to_owned();
        job.settings.resolution = 3;
        assert!(matches!(job.validate(), Err(BakeJobError::Settings(_))));
    }
}
