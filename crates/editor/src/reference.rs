//! A reference distribution to compare the design with: a measured
//! prototype, a competitor's file, or the result pinned before an edit
//! ("A/B").

use std::path::{Path, PathBuf};
use std::sync::Arc;

use lucerna_photometry::CandelaTable;
use lucerna_scene::file::{MAX_PROFILE_FILE_BYTES, ReadFileError, read_limited};
use lucerna_simulation::Snapshot;

/// A distribution drawn beside the current one.
#[derive(Debug, Clone)]
pub struct Reference {
    /// What the views call it: the file name, or "pinned at …".
    pub name: String,
    pub table: Arc<CandelaTable>,
    /// The flux cd/klm is relative to: the file's lamps, or the pinned
    /// run's emitters (lm).
    pub lamp_flux_lm: f64,
    /// Drawn scaled to the shown table's flux (a design toward its shape:
    /// what the design matches), not in its own candela.
    pub at_shown_flux: bool,
}

#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ReferenceError {
    #[error("cannot read the reference {}", path.display())]
    Read {
        path: PathBuf,
        #[source]
        source: ReadFileError,
    },
    #[error("{} is not a usable IES or EULUMDAT file", path.display())]
    Parse {
        path: PathBuf,
        #[source]
        source: lucerna_photometry::ParsePhotometryError,
    },
}

impl Reference {
    /// Reads an IES or LDT file (its format told by its content).
    pub fn load(path: &Path) -> Result<Reference, ReferenceError> {
        let bytes =
            read_limited(path, MAX_PROFILE_FILE_BYTES).map_err(|source| ReferenceError::Read {
                path: path.to_path_buf(),
                source,
            })?;
        let photometry = lucerna_photometry::read_photometry(&bytes).map_err(|source| {
            ReferenceError::Parse {
                path: path.to_path_buf(),
                source,
            }
        })?;
        let lamp_flux_lm = photometry
            .lamp_flux_lm()
            .unwrap_or_else(|| photometry.table.flux_lm());
        let name = path.file_name().map_or_else(
            || path.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        );
        Ok(Reference {
            name,
            table: Arc::new(photometry.table),
            lamp_flux_lm,
            at_shown_flux: false,
        })
    }

    /// The factor its candela are drawn with beside `shown` (a table in
    /// candela drawn with `shown_factor`, for a lamp flux of
    /// `lamp_flux_lm`): the unit's, or scaled to the shown table's flux.
    pub fn factor(
        &self,
        unit: crate::intensity_unit::IntensityUnit,
        shown: &CandelaTable,
        shown_factor: f64,
    ) -> f64 {
        let own = self.table.flux_lm();
        if self.at_shown_flux && own > 0.0 {
            shown_factor * shown.flux_lm() / own
        } else {
            unit.factor(self.lamp_flux_lm)
        }
    }

    /// The snapshot's exported table, kept as the "A" of an A/B
    /// comparison.
    pub fn pinned(snapshot: &Snapshot) -> Reference {
        Reference {
            name: format!(
                "pinned result ({:.3e} photons, {:.0} lm)",
                snapshot.photons as f64, snapshot.figures.flux_lm
            ),
            table: snapshot.table.clone(),
            lamp_flux_lm: snapshot.map.emitter_flux_lm,
            at_shown_flux: false,
        }
    }
}
