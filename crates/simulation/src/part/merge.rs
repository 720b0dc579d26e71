//! Parts of one run checked and summed exactly into its map.

use std::path::PathBuf;

use lucerna_photometry::{CubeMapLayout, IntensityMap};

use super::{PartManifest, PartSpec, PhotonRange, ReadPartError, read_manifest, read_part_counts};

/// Why parts cannot be merged into one run.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum MergePartsError {
    #[error(transparent)]
    Read(#[from] ReadPartError),
    #[error("{path} and {other} are not parts of one run: {what} differs ({a} and {b})")]
    Mismatch {
        path: PathBuf,
        other: PathBuf,
        what: &'static str,
        a: String,
        b: String,
    },
    #[error("{path} and {other} are both part {part}: each part is merged once")]
    Duplicate {
        path: PathBuf,
        other: PathBuf,
        part: PartSpec,
    },
    #[error("{path} overlaps {other}: {a} and {b}")]
    Overlap {
        path: PathBuf,
        other: PathBuf,
        a: PhotonRange,
        b: PhotonRange,
    },
    #[error("photons are missing: {}", describe_missing(.0))]
    Missing(Vec<Gap>),
    #[error("no part was given")]
    NoParts,
}

/// A range of photons no part holds, and the part that should have.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Gap {
    pub range: PhotonRange,
    /// The part whose range it lies in.
    pub part: PartSpec,
    /// The file of that part if it was given (an unfinished checkpoint).
    pub partial: Option<PathBuf>,
}

fn describe_missing(gaps: &[Gap]) -> String {
    let shown: Vec<String> = gaps
        .iter()
        .take(12)
        .map(|g| match &g.partial {
            Some(p) => format!(
                "{} of part {} ({} stopped there: resume it)",
                g.range,
                g.part,
                p.display()
            ),
            None => format!("{} (part {}, not given)", g.range, g.part),
        })
        .collect();
    let more = gaps.len().saturating_sub(shown.len());
    if more > 0 {
        format!("{}; and {more} more", shown.join("; "))
    } else {
        shown.join("; ")
    }
}

/// Checks that `parts` (manifest path, manifest) are parts of one run,
/// each once, covering every photon of it.
pub fn check_parts(parts: &[(PathBuf, PartManifest)]) -> Result<(), MergePartsError> {
    let Some((first_path, first)) = parts.first() else {
        return Err(MergePartsError::NoParts);
    };
    for (path, m) in &parts[1..] {
        let mismatch = |what: &'static str, a: String, b: String| MergePartsError::Mismatch {
            path: first_path.clone(),
            other: path.clone(),
            what,
            a,
            b,
        };
        if m.scene.sha256 != first.scene.sha256 {
            let why = first
                .scene
                .first_difference(&m.scene)
                .unwrap_or_else(|| "the scene".to_owned());
            return Err(mismatch(
                "the scene",
                format!(
                    "{}…",
                    &first.scene.sha256[..12.min(first.scene.sha256.len())]
                ),
                format!(
                    "{}…: {why}",
                    &m.scene.sha256[..12.min(m.scene.sha256.len())]
                ),
            ));
        }
        let (a, b) = (&first.trace, &m.trace);
        let fields: [(&'static str, String, String); 6] = [
            ("the seed", a.seed.to_string(), b.seed.to_string()),
            (
                "the resolution",
                a.resolution.to_string(),
                b.resolution.to_string(),
            ),
            (
                "the bounce limit",
                a.max_bounces.to_string(),
                b.max_bounces.to_string(),
            ),
            (
                "the run's photons",
                a.photons_total.to_string(),
                b.photons_total.to_string(),
            ),
            (
                "the number of parts",
                a.parts.to_string(),
                b.parts.to_string(),
            ),
            (
                "the emitter flux",
                a.emitter_flux_lm.to_string(),
                b.emitter_flux_lm.to_string(),
            ),
        ];
        for (what, x, y) in fields {
            if x != y {
                return Err(mismatch(what, x, y));
            }
        }
        let differences = first.job.output_differences(&m.job);
        if !differences.is_empty() {
            let describe = |pick: fn(&(String, String, String)) -> &String| {
                differences
                    .iter()
                    .map(|d| format!("{} {}", d.0, pick(d)))
                    .collect::<Vec<_>>()
                    .join(", ")
            };
            return Err(mismatch(
                "the output settings",
                describe(|d| &d.1),
                describe(|d| &d.2),
            ));
        }
    }
    // Each part once.
    let mut by_part: Vec<&(PathBuf, PartManifest)> = parts.iter().collect();
    by_part.sort_by_key(|(_, m)| m.part);
    for pair in by_part.windows(2) {
        let ((p, a), (q, b)) = (pair[0], pair[1]);
        if a.part == b.part {
            return Err(MergePartsError::Duplicate {
                path: p.clone(),
                other: q.clone(),
                part: a.spec(),
            });
        }
    }
    // The ranges, from the manifests' own numbers (not re-derived): a
    // hand-edited range is caught here too.
    let mut ranges: Vec<(PhotonRange, &PathBuf, &PartManifest)> =
        parts.iter().map(|(p, m)| (m.traced(), p, m)).collect();
    ranges.sort_by_key(|(r, _, _)| (r.first, r.end));
    for pair in ranges.windows(2) {
        let ((a, p, _), (b, q, _)) = (&pair[0], &pair[1]);
        if b.first < a.end {
            return Err(MergePartsError::Overlap {
                path: (*p).clone(),
                other: (*q).clone(),
                a: *a,
                b: *b,
            });
        }
    }
    let total = first.trace.photons_total;
    let spec_of = |photon: u64| {
        let count = first.trace.parts;
        // The part whose range holds `photon` (ranges are floor(T·k/N)).
        let mut k = ((u128::from(photon) * u128::from(count)) / u128::from(total.max(1))) as u32;
        k = k.min(count - 1);
        while k + 1 < count
            && (PartSpec {
                index: k + 2,
                count,
            })
            .range(total)
            .first
                <= photon
        {
            k += 1;
        }
        while k > 0
            && (PartSpec {
                index: k + 1,
                count,
            })
            .range(total)
            .first
                > photon
        {
            k -= 1;
        }
        PartSpec {
            index: k + 1,
            count,
        }
    };
    let mut gaps = Vec::new();
    let mut at = 0u64;
    let gap_to = |from: u64, to: u64, gaps: &mut Vec<Gap>| {
        // One gap per part it spans, so each names its part.
        let mut from = from;
        while from < to {
            let part = spec_of(from);
            let end = part.range(total).end.min(to);
            let partial = parts
                .iter()
                .find(|(_, m)| m.part == part.index)
                .map(|(p, _)| p.clone());
            gaps.push(Gap {
                range: PhotonRange { first: from, end },
                part,
                partial,
            });
            from = end;
        }
    };
    for (r, _, _) in &ranges {
        if r.first > at {
            gap_to(at, r.first, &mut gaps);
        }
        at = at.max(r.end);
    }
    if at < total {
        gap_to(at, total, &mut gaps);
    }
    if !gaps.is_empty() {
        return Err(MergePartsError::Missing(gaps));
    }
    Ok(())
}

/// A run put back together from its parts.
#[derive(Debug, Clone)]
pub struct MergedParts {
    /// The first part's manifest (they agree on everything but the part).
    pub manifest: PartManifest,
    pub map: IntensityMap,
    /// Backends that traced the parts, each once.
    pub backends: Vec<String>,
    /// Tracing wall time over all parts (s).
    pub wall_seconds: f64,
}

/// Reads the manifests at `paths`, checks they are the whole of one run,
/// then adds their counts exactly (u64; one part's counts in memory at a
/// time besides the sum).
pub fn merge_parts(paths: &[PathBuf]) -> Result<MergedParts, MergePartsError> {
    let parts = paths
        .iter()
        .map(|p| Ok((p.clone(), read_manifest(p)?)))
        .collect::<Result<Vec<_>, ReadPartError>>()?;
    check_parts(&parts)?;
    let (_, first) = &parts[0];
    let layout = CubeMapLayout::new(first.trace.resolution);
    let mut map = IntensityMap::new(layout, first.trace.emitter_flux_lm);
    let mut backends: Vec<String> = Vec::new();
    let mut wall_seconds = 0.0;
    for (path, manifest) in &parts {
        let part = read_part_counts(path, manifest)?;
        map.merge(&part).map_err(|e| ReadPartError::Corrupt {
            path: path.clone(),
            why: e.to_string(),
        })?;
        // CPU parts are bit-identical whatever their thread count; GPU
        // parts per adapter.
        let backend = if manifest.backend_kind == "cpu" {
            "CPU tracer".to_owned()
        } else {
            manifest.backend.clone()
        };
        if !backends.contains(&backend) {
            backends.push(backend);
        }
        wall_seconds += manifest.wall_seconds;
    }
    Ok(MergedParts {
        manifest: first.clone(),
        map,
        backends,
        wall_seconds,
    })
}
