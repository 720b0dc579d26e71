//! `lucerna convert`: IES ↔ EULUMDAT, LM-63-2002 ↔ 2019.

use std::path::Path;

use anyhow::{Context, Result, bail};
use lucerna_photometry::{IesVersion, to_latin1, write_ies, write_ldt};

use super::input;

/// Output format, from the flag or else the output file's extension.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum OutFormat {
    Ies2002,
    #[value(alias = "ies")]
    Ies2019,
    Ldt,
}

impl OutFormat {
    pub fn extension(self) -> &'static str {
        match self {
            OutFormat::Ies2002 | OutFormat::Ies2019 => "ies",
            OutFormat::Ldt => "ldt",
        }
    }
}

pub fn out_format(path: &Path, flag: Option<OutFormat>) -> Result<OutFormat> {
    if let Some(f) = flag {
        return Ok(f);
    }
    match path
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase)
        .as_deref()
    {
        Some("ies") => Ok(OutFormat::Ies2019),
        Some("ldt") => Ok(OutFormat::Ldt),
        _ => bail!(
            "cannot tell the output format of {}: use a .ies or .ldt extension or --to",
            path.display()
        ),
    }
}

/// Converts and writes atomically; returns a one-line summary.
/// `resample_c_deg` puts the table on equal C-plane steps first (some
/// readers misread EULUMDAT files with unequal steps).
pub fn convert(
    input: &Path,
    output: &Path,
    to: Option<OutFormat>,
    resample_c_deg: Option<f64>,
) -> Result<String> {
    let mut p = input::read_photometry(input)?;
    let format = out_format(output, to)?;
    for w in p.consistency_warnings() {
        eprintln!("warning: {}: {w}", input.display());
    }
    if p.meta.lamps.len() > 1 && matches!(format, OutFormat::Ies2002 | OutFormat::Ies2019) {
        eprintln!(
            "note: {} lists {} lamp sets (alternatives); the IES describes set 1 and names the others in its [{}] keyword",
            input.display(),
            p.meta.lamps.len(),
            lucerna_photometry::ies::LAMP_SET_KEYWORD
        );
    }
    if let Some(step) = resample_c_deg {
        if !((0.1..=90.0).contains(&step) && ((360.0 / step) - (360.0 / step).round()).abs() < 1e-9)
        {
            bail!("--resample-c must divide 360° evenly and be at least 0.1°, got {step}");
        }
        let gammas = p.table.gammas_deg.clone();
        p.table = p
            .table
            .resampled(lucerna_photometry::table::uniform_c_planes(step), gammas);
    } else if format == OutFormat::Ldt && p.table.uniform_c_step().is_none() {
        eprintln!(
            "warning: {} has unequal C-plane steps; some readers misread such EULUMDAT files: --resample-c 5 (or 15) writes an equidistant grid",
            input.display()
        );
    }
    let bytes = match format {
        OutFormat::Ies2002 => write_ies(&p, IesVersion::Lm63_2002).map(String::into_bytes),
        OutFormat::Ies2019 => write_ies(&p, IesVersion::Lm63_2019).map(String::into_bytes),
        OutFormat::Ldt => write_ldt(&p).map(|t| to_latin1(&t)),
    }
    .with_context(|| {
        format!(
            "{} cannot be written as {format:?}; nothing was written",
            input.display()
        )
    })?;
    // What the file says, read back before it is written: the figures
    // printed are the written file's, and a file that would not read back
    // with the same flux is not written.
    let written = lucerna_photometry::read_photometry(&bytes).with_context(|| {
        format!(
            "the {format:?} written from {} would not read back; nothing was written",
            input.display()
        )
    })?;
    let (before, after) = (p.figures(), written.figures());
    if (after.flux_lm - before.flux_lm).abs() > 1e-3 * before.flux_lm.abs().max(1e-12) {
        bail!(
            "the {format:?} file would hold {:.1} lm where {} holds {:.1} lm; nothing was written",
            after.flux_lm,
            input.display(),
            before.flux_lm
        );
    }
    lucerna_scene::write_atomically(output, &bytes)
        .with_context(|| format!("cannot write {}", output.display()))?;
    Ok(format!(
        "{} ({}) -> {} ({:?}): {:.1} lm, peak {:.1} cd, symmetry {} (as written)",
        input.display(),
        p.format,
        output.display(),
        format,
        after.flux_lm,
        after.peak_cd,
        written.symmetry.describe()
    ))
}
