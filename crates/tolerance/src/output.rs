//! The analysis's files, written all or none: `samples.csv` (one row per
//! built luminaire), `figures.csv` (each figure's spread beside its
//! photon noise), `yield.csv`, `sensitivities.csv`, `histograms.png`,
//! `sensitivities.png`, `tolerance.json` and `worst.toml` (the worst
//! sample as a scene to open). A part of a split run writes
//! `tolerance.part-K-of-N.json` instead: its samples, merged later.

use std::path::{Path, PathBuf};

use lucerna_scene::{Emission, EmitterShape, Scene, Shape};
use serde::{Deserialize, Serialize};
use sha2::{Digest, Sha256};

use crate::analysis::{SampleRecord, Settings, Setup};
use crate::error::ToleranceError;
use crate::report::Report;

/// The CSV of the samples: the same bytes from one run and from merged
/// parts.
pub fn samples_csv(setup: &Setup, records: &[SampleRecord]) -> Result<String, ToleranceError> {
    let t = &setup.model.tolerances;
    let mut header: Vec<String> = vec!["sample".to_owned(), "status".to_owned()];
    header.extend(t.scalars.iter().map(|s| format!("{} ({})", s.name, s.unit)));
    header.extend(
        t.form_errors
            .iter()
            .map(|f| format!("{} form error rms (m)", f.part_name)),
    );
    header.extend(setup.figures.iter().map(|f| f.key().to_owned()));
    let term_names: Vec<String> = records
        .iter()
        .find_map(|r| r.measured.as_ref())
        .map(|m| {
            m.terms
                .iter()
                .map(|t| format!("meets {}", t.term))
                .collect()
        })
        .unwrap_or_default();
    header.extend(term_names.iter().cloned());
    header.push("shortfall".to_owned());
    header.push("why refused".to_owned());
    let mut w = csv::Writer::from_writer(Vec::new());
    let bad = |e: csv::Error| ToleranceError::Output(format!("samples.csv: {e}"));
    w.write_record(&header).map_err(bad)?;
    for r in records {
        let draw = setup.model.draw(r.index);
        let mut row: Vec<String> = vec![
            r.index.to_string(),
            match (&r.measured, &r.refused) {
                (Some(m), _) if m.terms.iter().all(|t| t.met) => "pass".to_owned(),
                (Some(_), _) => "fail".to_owned(),
                (None, _) => "refused".to_owned(),
            },
        ];
        row.extend(draw.deviations.iter().map(|d| number(*d)));
        for d in setup.model.form_deviations(&draw) {
            let rms = (d.iter().map(|x| x * x).sum::<f64>() / d.len().max(1) as f64).sqrt();
            row.push(number(rms));
        }
        match &r.measured {
            Some(m) => {
                row.extend(m.values.iter().map(|v| number(*v)));
                row.extend(m.terms.iter().map(|t| u8::from(t.met).to_string()));
                row.push(number(m.shortfall));
            }
            None => {
                row.extend(setup.figures.iter().map(|_| String::new()));
                row.extend(term_names.iter().map(|_| "0".to_owned()));
                row.push(String::new());
            }
        }
        row.push(r.refused.clone().unwrap_or_default());
        w.write_record(&row).map_err(bad)?;
    }
    let bytes = w
        .into_inner()
        .map_err(|e| ToleranceError::Output(e.to_string()))?;
    String::from_utf8(bytes).map_err(|e| ToleranceError::Output(e.to_string()))
}

/// A number as the CSVs write it: the shortest text that reads back to
/// the same bits; empty for NaN.
fn number(v: f64) -> String {
    if v.is_nan() {
        String::new()
    } else {
        format!("{v}")
    }
}

fn figures_csv(report: &Report) -> String {
    let mut s = String::from(
        "figure,nominal,as_built_nominal,mean,sd,photon_noise_sd,manufacturing_sd,q05,q50,q95,min,max,samples,unbounded\n",
    );
    for f in &report.figures {
        let p = &f.spread;
        s.push_str(&format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
            f.figure,
            number(f.nominal),
            number(f.as_built),
            number(p.mean),
            number(p.sd),
            number(f.photon_noise_sd),
            number(f.manufacturing_sd),
            number(p.q05),
            number(p.q50),
            number(p.q95),
            number(p.min),
            number(p.max),
            p.count,
            p.unbounded
        ));
    }
    s
}

fn yield_csv(report: &Report) -> Result<String, ToleranceError> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let bad = |e: csv::Error| ToleranceError::Output(format!("yield.csv: {e}"));
    w.write_record([
        "term",
        "wanted",
        "nominal",
        "nominal_meets",
        "passed",
        "samples",
        "yield",
        "ci95_low",
        "ci95_high",
    ])
    .map_err(bad)?;
    let y = &report.overall;
    w.write_record([
        "every term".to_owned(),
        String::new(),
        String::new(),
        String::new(),
        y.passed.to_string(),
        y.samples.to_string(),
        number(y.value),
        number(y.low),
        number(y.high),
    ])
    .map_err(bad)?;
    for t in &report.terms {
        let f = &t.fraction;
        w.write_record([
            t.term.clone(),
            t.wanted.clone(),
            number(t.nominal),
            u8::from(t.nominal_met).to_string(),
            f.passed.to_string(),
            f.samples.to_string(),
            number(f.value),
            number(f.low),
            number(f.high),
        ])
        .map_err(bad)?;
    }
    let bytes = w
        .into_inner()
        .map_err(|e| ToleranceError::Output(e.to_string()))?;
    String::from_utf8(bytes).map_err(|e| ToleranceError::Output(e.to_string()))
}

fn sensitivities_csv(report: &Report) -> Result<String, ToleranceError> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let bad = |e: csv::Error| ToleranceError::Output(format!("sensitivities.csv: {e}"));
    w.write_record(["figure", "tolerance", "share", "noise"])
        .map_err(bad)?;
    for s in &report.sensitivities {
        w.write_record([
            s.figure.to_owned(),
            s.tolerance.clone(),
            number(s.share.share),
            number(s.share.noise),
        ])
        .map_err(bad)?;
    }
    let bytes = w
        .into_inner()
        .map_err(|e| ToleranceError::Output(e.to_string()))?;
    String::from_utf8(bytes).map_err(|e| ToleranceError::Output(e.to_string()))
}

/// The worst sample's scene as a file written into `out_dir`: its file
/// references (meshes, profiles, ray files) made absolute, so it opens
/// from there.
pub fn worst_scene_text(setup: &Setup, index: u32) -> Result<String, ToleranceError> {
    let mut scene = setup
        .model
        .scene(&setup.model.draw(index))
        .map_err(ToleranceError::Output)?;
    absolute_references(&mut scene, &setup.scene_dir);
    scene.name = format!("{} (tolerance sample {index})", scene.name);
    lucerna_scene::scene_to_toml(&scene)
        .map_err(|e| ToleranceError::Output(format!("worst.toml: {e}")))
}

/// Every relative file reference of `scene` made absolute from `dir`.
fn absolute_references(scene: &mut Scene, dir: &Path) {
    let fix = |p: &mut String| {
        if Path::new(p.as_str()).is_relative() {
            let joined = dir.join(p.as_str());
            let full = std::fs::canonicalize(&joined).unwrap_or(joined);
            if let Some(s) = full.to_str() {
                *p = s.to_owned();
            }
        }
    };
    for part in &mut scene.parts {
        if let Shape::Mesh(m) = &mut part.shape {
            fix(&mut m.path);
        }
    }
    for e in &mut scene.emitters {
        if let Emission::Profile(p) = &mut e.emission {
            fix(p);
        }
        if let EmitterShape::RayFile { path, .. } = &mut e.shape {
            fix(path);
        }
    }
}

/// The files of a finished analysis.
pub fn files(
    setup: &Setup,
    report: &Report,
    records: &[SampleRecord],
    out_dir: &Path,
) -> Result<Vec<(PathBuf, Vec<u8>)>, ToleranceError> {
    let png = |r: Result<Vec<u8>, image::ImageError>, name: &str| {
        r.map_err(|e| ToleranceError::Output(format!("{name}: {e}")))
    };
    let mut files = vec![
        (
            out_dir.join("samples.csv"),
            samples_csv(setup, records)?.into_bytes(),
        ),
        (
            out_dir.join("figures.csv"),
            figures_csv(report).into_bytes(),
        ),
        (out_dir.join("yield.csv"), yield_csv(report)?.into_bytes()),
        (
            out_dir.join("sensitivities.csv"),
            sensitivities_csv(report)?.into_bytes(),
        ),
        (
            out_dir.join("histograms.png"),
            png(
                crate::picture::histograms_png(setup, report, records),
                "histograms.png",
            )?,
        ),
        (
            out_dir.join("sensitivities.png"),
            png(
                crate::picture::sensitivities_png(setup, report),
                "sensitivities.png",
            )?,
        ),
        (
            out_dir.join("tolerance.json"),
            serde_json::to_vec_pretty(report)
                .map_err(|e| ToleranceError::Output(format!("tolerance.json: {e}")))?,
        ),
    ];
    if let Some(w) = &report.worst {
        files.push((
            out_dir.join("worst.toml"),
            worst_scene_text(setup, w.index)?.into_bytes(),
        ));
    }
    Ok(files)
}

/// Writes the analysis's `files` into `out_dir` all or none; a
/// `worst.toml` of an earlier run there is removed when this one has
/// none (every sample refused), so what is there is this run's.
pub fn write_analysis(files: &[(PathBuf, Vec<u8>)], out_dir: &Path) -> Result<(), ToleranceError> {
    write(files)?;
    let worst = out_dir.join("worst.toml");
    if !files.iter().any(|(p, _)| *p == worst) && worst.exists() {
        std::fs::remove_file(&worst).map_err(|source| ToleranceError::Write {
            path: worst.display().to_string(),
            source,
        })?;
    }
    Ok(())
}

/// Writes `files` all or none (as the design writes its own).
pub fn write(files: &[(PathBuf, Vec<u8>)]) -> Result<(), ToleranceError> {
    lucerna_design::output::write(files).map_err(|e| match e {
        lucerna_design::DesignError::Write { path, source } => {
            ToleranceError::Write { path, source }
        }
        other => ToleranceError::Output(other.to_string()),
    })
}

/// What every part of one run shares: the inputs' hash and the
/// settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    pub format: u32,
    /// SHA-256 over the scene, spec and tolerances files' bytes.
    pub inputs_sha256: String,
    pub samples: u32,
    pub parts: u32,
    pub settings: Settings,
    /// A target distribution's largest relative L2 (None for a spec).
    pub max_relative_l2: Option<f64>,
}

/// One part's samples.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PartFile {
    pub manifest: Manifest,
    pub part: u32,
    pub records: Vec<SampleRecord>,
}

/// The most parts a run is split into (as a split bake's).
pub const MAX_PARTS: u32 = 1_000_000;

/// Refuses records that do not fit the analysis: each traced one must
/// have a value per figure and a result per term of the nominal's.
pub fn check_records(
    setup: &Setup,
    terms: usize,
    records: &[SampleRecord],
) -> Result<(), ToleranceError> {
    for r in records {
        if let Some(m) = &r.measured
            && (m.values.len() != setup.figures.len() || m.terms.len() != terms)
        {
            return Err(ToleranceError::Merge(format!(
                "sample {} has {} figures and {} terms, the analysis {} and {}",
                r.index,
                m.values.len(),
                m.terms.len(),
                setup.figures.len(),
                terms
            )));
        }
    }
    Ok(())
}

/// The part file's name.
pub fn part_file_name(part: u32, parts: u32) -> String {
    format!("tolerance.part-{part}-of-{parts}.json")
}

/// The hash of the inputs' bytes.
pub fn inputs_sha256(paths: &[&Path]) -> Result<String, ToleranceError> {
    let mut h = Sha256::new();
    for p in paths {
        let bytes = std::fs::read(p)
            .map_err(|e| ToleranceError::Output(format!("cannot read {}: {e}", p.display())))?;
        h.update((bytes.len() as u64).to_le_bytes());
        h.update(&bytes);
    }
    Ok(h.finalize().iter().map(|b| format!("{b:02x}")).collect())
}

/// Reads the part files in `dir` of the run `expected` describes (its
/// number of parts read from the files), and returns every sample in
/// order; refuses a part of another run, a part twice, or a missing part
/// or sample, naming it.
pub fn merge_parts(dir: &Path, expected: &Manifest) -> Result<Vec<SampleRecord>, ToleranceError> {
    let entries = std::fs::read_dir(dir)
        .map_err(|e| ToleranceError::Merge(format!("cannot read {}: {e}", dir.display())))?;
    let mut paths: Vec<PathBuf> = entries
        .flatten()
        .filter(|e| {
            let name = e.file_name().to_string_lossy().into_owned();
            name.starts_with("tolerance.part-") && name.ends_with(".json")
        })
        .map(|e| e.path())
        .collect();
    paths.sort();
    let mut parts: Vec<PartFile> = Vec::new();
    for path in &paths {
        let bytes = std::fs::read(path)
            .map_err(|e| ToleranceError::Merge(format!("cannot read {}: {e}", path.display())))?;
        let part: PartFile = serde_json::from_slice(&bytes).map_err(|e| {
            ToleranceError::Merge(format!("{} is not a part file: {e}", path.display()))
        })?;
        let want = Manifest {
            parts: part.manifest.parts,
            ..expected.clone()
        };
        if part.manifest != want {
            return Err(ToleranceError::Merge(format!(
                "{} is a part of another run (its scene, spec, tolerances, --samples or settings differ)",
                path.display()
            )));
        }
        if let Some(first) = parts.first()
            && first.manifest.parts != part.manifest.parts
        {
            return Err(ToleranceError::Merge(format!(
                "{} is one of {} parts, {} one of {}",
                path.display(),
                part.manifest.parts,
                paths[0].display(),
                first.manifest.parts
            )));
        }
        parts.push(part);
    }
    let count = parts.first().map(|p| p.manifest.parts);
    if let Some(n) = count
        && !(1..=MAX_PARTS).contains(&n)
    {
        return Err(ToleranceError::Merge(format!(
            "the part files say the run has {n} parts (1 to {MAX_PARTS})"
        )));
    }
    let Some(count) = count else {
        return Err(ToleranceError::Merge(format!(
            "{} holds no part file (tolerance.part-K-of-N.json)",
            dir.display()
        )));
    };
    let mut found: Vec<Option<PartFile>> = vec![None; count as usize];
    for part in parts {
        let k = part.part;
        if !(1..=count).contains(&k) {
            return Err(ToleranceError::Merge(format!(
                "a file names part {k} of {count}"
            )));
        }
        if found[(k - 1) as usize].is_some() {
            return Err(ToleranceError::Merge(format!("part {k} is there twice")));
        }
        found[(k - 1) as usize] = Some(part);
    }
    let manifest = Manifest {
        parts: count,
        ..expected.clone()
    };
    let missing: Vec<String> = found
        .iter()
        .enumerate()
        .filter(|(_, p)| p.is_none())
        .map(|(k, _)| (k + 1).to_string())
        .collect();
    if !missing.is_empty() {
        return Err(ToleranceError::Merge(format!(
            "parts {} of {} are missing in {}",
            missing.join(", "),
            manifest.parts,
            dir.display()
        )));
    }
    let mut records: Vec<SampleRecord> = found
        .into_iter()
        .flatten()
        .flat_map(|p| p.records)
        .collect();
    records.sort_by_key(|r| r.index);
    for (i, r) in records.iter().enumerate() {
        if r.index as usize != i {
            return Err(ToleranceError::Merge(format!(
                "sample {i} is missing or there twice (a part stopped early?)"
            )));
        }
    }
    if records.len() != manifest.samples as usize {
        return Err(ToleranceError::Merge(format!(
            "{} of {} samples are there (a part stopped early?)",
            records.len(),
            manifest.samples
        )));
    }
    Ok(records)
}
