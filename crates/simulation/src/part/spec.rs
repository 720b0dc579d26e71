//! Which part of a run a job traces: `K/N`, from the command line or a
//! scheduler's task, and the photon numbers it covers.

use std::fmt;

use serde::{Deserialize, Serialize};

/// A part number that is not one (`0/4`, `5/4`, a scheduler's variables
/// that do not make one).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{0}")]
pub struct PartSpecError(pub String);

/// Part `index` of `count` (both from 1: `--part 3/8`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct PartSpec {
    pub index: u32,
    pub count: u32,
}

/// The most parts a run is split into (a job array of 100 000 tasks is
/// already beyond what schedulers allow by default).
pub const MAX_PARTS: u32 = 1_000_000;

impl PartSpec {
    /// The whole run as one part.
    pub const WHOLE: PartSpec = PartSpec { index: 1, count: 1 };

    pub fn new(index: u32, count: u32) -> Result<PartSpec, PartSpecError> {
        if count == 0 || count > MAX_PARTS {
            return Err(PartSpecError(format!(
                "{index}/{count}: the number of parts must be between 1 and {MAX_PARTS}"
            )));
        }
        if index == 0 || index > count {
            return Err(PartSpecError(format!(
                "{index}/{count}: parts are numbered 1 to {count}"
            )));
        }
        Ok(PartSpec { index, count })
    }

    /// The photons of this part among `total`: parts differ in size by at
    /// most one photon and together cover `0..total` once.
    pub fn range(&self, total: u64) -> PhotonRange {
        let at = |k: u32| (u128::from(total) * u128::from(k) / u128::from(self.count)) as u64;
        PhotonRange {
            first: at(self.index - 1),
            end: at(self.index),
        }
    }

    /// The part a scheduler's task is: a Slurm job array
    /// (`SLURM_ARRAY_TASK_ID` with `SLURM_ARRAY_TASK_COUNT`, or with
    /// `SLURM_ARRAY_TASK_MIN`/`MAX`, task ids counted from the minimum) or
    /// a Kubernetes Indexed Job (`JOB_COMPLETION_INDEX`, from 0, with
    /// `parts` given). `env` reads a variable.
    pub fn from_scheduler(
        env: &dyn Fn(&str) -> Option<String>,
        parts: Option<u32>,
    ) -> Result<PartSpec, PartSpecError> {
        let number = |name: &str| -> Result<Option<u32>, PartSpecError> {
            match env(name) {
                None => Ok(None),
                Some(v) => v
                    .trim()
                    .parse::<u32>()
                    .map(Some)
                    .map_err(|_| PartSpecError(format!("{name}='{v}' is not a task number"))),
            }
        };
        if let Some(id) = number("SLURM_ARRAY_TASK_ID")? {
            let min = number("SLURM_ARRAY_TASK_MIN")?;
            let max = number("SLURM_ARRAY_TASK_MAX")?;
            let count = number("SLURM_ARRAY_TASK_COUNT")?;
            let (first, count) = match (min, max, count) {
                (Some(min), Some(max), _) if max >= min => (min, max - min + 1),
                (min, _, Some(count)) => (min.unwrap_or(0), count),
                _ => {
                    return Err(PartSpecError(
                        "SLURM_ARRAY_TASK_ID is set but neither SLURM_ARRAY_TASK_COUNT nor \
                         SLURM_ARRAY_TASK_MIN/MAX: is this a job array?"
                            .to_owned(),
                    ));
                }
            };
            if let (Some(min), Some(max), Some(listed)) =
                (min, max, number("SLURM_ARRAY_TASK_COUNT")?)
                && max >= min
                && listed != max - min + 1
            {
                return Err(PartSpecError(format!(
                    "the job array has {listed} tasks numbered {min} to {max}: number them \
                     contiguously (--array={min}-{}) so that each task is one part",
                    min + listed - 1
                )));
            }
            if let Some(parts) = parts
                && parts != count
            {
                return Err(PartSpecError(format!(
                    "--parts {parts} disagrees with the job array's {count} tasks"
                )));
            }
            let index = id.checked_sub(first).ok_or_else(|| {
                PartSpecError(format!(
                    "SLURM_ARRAY_TASK_ID={id} is below the array's first task {first}"
                ))
            })?;
            return PartSpec::new(index + 1, count)
                .map_err(|e| PartSpecError(format!("the Slurm array task is not a part: {e}")));
        }
        if let Some(index) = number("JOB_COMPLETION_INDEX")? {
            let Some(count) = parts else {
                return Err(PartSpecError(
                    "JOB_COMPLETION_INDEX is set: give the Job's completions as --parts N"
                        .to_owned(),
                ));
            };
            return PartSpec::new(index.saturating_add(1), count)
                .map_err(|e| PartSpecError(format!("JOB_COMPLETION_INDEX={index}: {e}")));
        }
        Err(PartSpecError(
            "--part auto needs a scheduler's task: none of SLURM_ARRAY_TASK_ID or \
             JOB_COMPLETION_INDEX is set"
                .to_owned(),
        ))
    }
}

impl fmt::Display for PartSpec {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

impl std::str::FromStr for PartSpec {
    type Err = PartSpecError;

    /// `K/N`, e.g. `3/8`.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let bad = || PartSpecError(format!("'{s}' is not a part K/N such as 3/8"));
        let (k, n) = s.split_once('/').ok_or_else(bad)?;
        let k: u32 = k.trim().parse().map_err(|_| bad())?;
        let n: u32 = n.trim().parse().map_err(|_| bad())?;
        PartSpec::new(k, n)
    }
}

/// Photon numbers `first..end` of a run's stream.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Serialize, Deserialize)]
pub struct PhotonRange {
    pub first: u64,
    pub end: u64,
}

impl PhotonRange {
    pub fn len(&self) -> u64 {
        self.end - self.first
    }

    pub fn is_empty(&self) -> bool {
        self.end <= self.first
    }
}

impl fmt::Display for PhotonRange {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "photons {}..{}", self.first, self.end)
    }
}
