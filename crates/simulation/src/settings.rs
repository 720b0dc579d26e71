//! What a simulation is asked to do, checked before anything runs.

use std::time::Duration;

use lucerna_filter::Threshold;
use lucerna_gpu::BackendRequest;
use serde::{Deserialize, Serialize};

/// How the exported map is filtered.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FilterChoice {
    /// The raw counts (pooled over the symmetry, if asked).
    #[default]
    Raw,
    /// The pull-push filter with its rule chosen by cross-validation on
    /// the photons.
    Automatic,
    /// The pull-push filter with a fixed photon threshold (the paper's).
    Threshold(f64),
}

impl FilterChoice {
    /// The filter's threshold, or `None` for the raw map.
    pub fn threshold(self) -> Option<Threshold> {
        match self {
            FilterChoice::Raw => None,
            FilterChoice::Automatic => Some(Threshold::Automatic),
            FilterChoice::Threshold(t) => Some(Threshold::Fixed(t)),
        }
    }
}

impl std::str::FromStr for FilterChoice {
    type Err = String;

    /// `none`, `auto` or a photon threshold.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "none" | "raw" => Ok(FilterChoice::Raw),
            "auto" => Ok(FilterChoice::Automatic),
            _ => match s.parse::<f64>() {
                Ok(t) if t.is_finite() && (1.0..=1e9).contains(&t) => {
                    Ok(FilterChoice::Threshold(t))
                }
                _ => Err(format!("'{s}' is not none, auto or a photon threshold ≥ 1")),
            },
        }
    }
}

/// When tracing stops by itself; the first limit reached wins, and with
/// none it runs until stopped.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct StoppingRule {
    pub photons: Option<u64>,
    pub time: Option<Duration>,
    /// Relative standard error of the peak intensity (e.g. 0.01).
    pub peak_relative_error: Option<f64>,
}

/// The C-γ grid of the exported table.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct TableGrid {
    /// C-plane spacing (degrees).
    pub c_step_deg: f64,
    /// γ spacing (degrees); `None`: 2.5° refined until the table holds the
    /// traced flux within 0.5 %.
    pub gamma_step_deg: Option<f64>,
}

impl Default for TableGrid {
    fn default() -> Self {
        TableGrid {
            c_step_deg: 5.0,
            gamma_step_deg: None,
        }
    }
}

/// Everything a run needs besides the luminaire.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SimulationSettings {
    /// Texels per cube-face edge of the intensity map.
    pub resolution: u32,
    pub seed: u32,
    /// Surface interactions after which a photon is cut off.
    pub max_bounces: u32,
    pub backend: BackendRequest,
    pub filter: FilterChoice,
    /// Pool the photons over the luminaire's symmetry about its axis
    /// (found from its geometry).
    pub pool_symmetry: bool,
    pub stop: StoppingRule,
    pub table: TableGrid,
}

impl Default for SimulationSettings {
    fn default() -> Self {
        SimulationSettings {
            resolution: 256,
            seed: 1,
            max_bounces: 64,
            backend: BackendRequest::Auto,
            filter: FilterChoice::Raw,
            pool_symmetry: true,
            stop: StoppingRule::default(),
            table: TableGrid::default(),
        }
    }
}

/// A setting out of its range, named as the user set it.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SettingsError {
    #[error("the resolution must be between 8 and 2048 texels per face edge, got {0}")]
    Resolution(u32),
    #[error("the photon limit must be at least 1")]
    Photons,
    #[error("the target relative error must be between 0 and 1, got {0}")]
    RelativeError(f64),
    #[error("the time limit must be positive and finite")]
    Time,
    #[error("the bounce limit must be between 1 and 100000, got {0}")]
    MaxBounces(u32),
    #[error(
        "the {what} step must divide 180° evenly and be at least {min}° (e.g. 1, 2.5, 5, 10), got {value}"
    )]
    Step {
        what: &'static str,
        value: f64,
        min: f64,
    },
    #[error("the filter threshold must be between 1 and 1e9 photons, got {0}")]
    FilterThreshold(f64),
}

impl SimulationSettings {
    /// Checks every range, so a run never starts on nonsense.
    pub fn validate(&self) -> Result<(), SettingsError> {
        if !(8..=2048).contains(&self.resolution) {
            return Err(SettingsError::Resolution(self.resolution));
        }
        if self.stop.photons == Some(0) {
            return Err(SettingsError::Photons);
        }
        if let Some(e) = self.stop.peak_relative_error
            && !(e > 0.0 && e < 1.0)
        {
            return Err(SettingsError::RelativeError(e));
        }
        if let Some(t) = self.stop.time
            && t.is_zero()
        {
            return Err(SettingsError::Time);
        }
        if !(1..=100_000).contains(&self.max_bounces) {
            return Err(SettingsError::MaxBounces(self.max_bounces));
        }
        // EULUMDAT holds at most 3600 C-planes and 3600 γ angles (IES
        // 10 000): 0.1° C steps give 3600 planes, 0.0625° γ steps 2881
        // angles.
        for (what, value, min) in [
            ("C-plane", Some(self.table.c_step_deg), 0.1),
            ("γ", self.table.gamma_step_deg, 0.0625),
        ] {
            let Some(v) = value else { continue };
            if !(v >= min && v <= 90.0 && ((180.0 / v) - (180.0 / v).round()).abs() < 1e-9) {
                return Err(SettingsError::Step {
                    what,
                    value: v,
                    min,
                });
            }
        }
        if let FilterChoice::Threshold(t) = self.filter
            && !(t.is_finite() && (1.0..=1e9).contains(&t))
        {
            return Err(SettingsError::FilterThreshold(t));
        }
        Ok(())
    }
}
