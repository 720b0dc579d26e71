//! The analysis's results from its samples: the yield and each term's,
//! each figure's spread beside its photon noise, the sensitivities, the
//! worst sample.

use serde::Serialize;

use crate::analysis::{Reference, SampleRecord, Settings, Setup, Stopped};
use crate::figures::Figure;
use crate::statistics::{Fraction, Share, Spread, binned_share, regression_share};

/// A spec term's yield.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TermYield {
    pub term: String,
    pub wanted: String,
    /// The nominal's value and whether it meets the term.
    #[serde(with = "crate::numbers::one")]
    pub nominal: f64,
    pub nominal_met: bool,
    #[serde(rename = "yield")]
    pub fraction: Fraction,
}

/// A figure's distribution over the samples.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FigureSummary {
    pub figure: &'static str,
    pub label: &'static str,
    #[serde(with = "crate::numbers::one")]
    pub nominal: f64,
    /// The nominal with its slope errors (NaN without any).
    #[serde(with = "crate::numbers::one")]
    pub as_built: f64,
    pub spread: Spread,
    /// The figure's standard deviation over independent photon streams
    /// of the nominal.
    #[serde(with = "crate::numbers::one")]
    pub photon_noise_sd: f64,
    /// The spread manufacturing makes: with common random numbers the
    /// samples' σ itself (their photon noise is mostly one shift for
    /// all); with independent streams √(σ² − photon noise²).
    #[serde(with = "crate::numbers::one")]
    pub manufacturing_sd: f64,
}

/// Which tolerance drives a figure, and how much.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Sensitivity {
    pub figure: &'static str,
    pub tolerance: String,
    pub share: Share,
}

/// A tolerance as the report lists it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ToleranceLine {
    pub name: String,
    pub distribution: String,
}

/// The worst sample found.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Worst {
    pub index: u32,
    #[serde(with = "crate::numbers::one")]
    pub shortfall: f64,
    pub missed: Vec<String>,
}

/// Everything the analysis found.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Report {
    pub settings: Settings,
    pub stopped: Stopped,
    pub seconds: f64,
    pub samples: usize,
    pub refused: usize,
    /// The first refusals (sample, why).
    pub refusals: Vec<(u32, String)>,
    pub tolerances: Vec<ToleranceLine>,
    #[serde(rename = "yield")]
    pub overall: Fraction,
    pub terms: Vec<TermYield>,
    pub figures: Vec<FigureSummary>,
    pub sensitivities: Vec<Sensitivity>,
    pub worst: Option<Worst>,
    /// What makes the numbers less sure than they look.
    pub warnings: Vec<String>,
}

/// The figures whose spread, sensitivities and histograms mean
/// something (a C-plane angle wraps, and is noise where the light is on
/// the axis: it is in samples.csv only).
pub fn shown(figure: Figure) -> bool {
    !matches!(figure, Figure::PeakC | Figure::CentroidC)
}

/// Points along a form error's profile its sensitivity is fitted on.
const FORM_FEATURES: usize = 6;

impl Report {
    pub fn new(
        setup: &Setup,
        reference: &Reference,
        records: &[SampleRecord],
        stopped: Stopped,
        seconds: f64,
    ) -> Report {
        let n = records.len();
        let traced: Vec<&SampleRecord> = records.iter().filter(|r| r.measured.is_some()).collect();
        let passed = records.iter().filter(|r| r.passes()).count();
        let refused = n - traced.len();
        let terms: Vec<TermYield> = reference
            .nominal
            .terms
            .iter()
            .enumerate()
            .map(|(j, t)| {
                let base = reference.as_built.as_ref().map_or(t, |m| &m.terms[j]);
                let met = traced
                    .iter()
                    .filter(|r| r.measured.as_ref().is_some_and(|m| m.terms[j].met))
                    .count();
                TermYield {
                    term: t.term.clone(),
                    wanted: t.wanted.clone(),
                    nominal: base.value,
                    nominal_met: base.met,
                    fraction: Fraction::wilson(met, n),
                }
            })
            .collect();
        let column = |f: usize| -> Vec<f64> {
            traced
                .iter()
                .filter_map(|r| r.measured.as_ref().map(|m| m.values[f]))
                .collect()
        };
        let figures: Vec<FigureSummary> = setup
            .figures
            .iter()
            .enumerate()
            .filter(|(_, fig)| shown(**fig))
            .map(|(f, fig)| {
                let spread = Spread::of(&column(f));
                let noise = reference.noise_sd[f];
                FigureSummary {
                    figure: fig.key(),
                    label: fig.label(),
                    nominal: reference.nominal.values[f],
                    as_built: reference
                        .as_built
                        .as_ref()
                        .map_or(f64::NAN, |m| m.values[f]),
                    spread,
                    photon_noise_sd: noise,
                    manufacturing_sd: match setup.settings.streams {
                        crate::analysis::Streams::Common => spread.sd,
                        crate::analysis::Streams::Independent => {
                            (spread.sd * spread.sd - noise * noise).max(0.0).sqrt()
                        }
                    },
                }
            })
            .collect();
        let sensitivities = sensitivities(setup, &traced);
        let worst = traced
            .iter()
            .filter_map(|r| r.measured.as_ref().map(|m| (r.index, m)))
            .filter(|(_, m)| m.shortfall.is_finite())
            .max_by(|a, b| a.1.shortfall.total_cmp(&b.1.shortfall).then(b.0.cmp(&a.0)))
            .map(|(index, m)| Worst {
                index,
                shortfall: m.shortfall,
                missed: m
                    .terms
                    .iter()
                    .filter(|t| !t.met)
                    .map(|t| format!("{} {:.4} (wanted {})", t.term, t.value, t.wanted))
                    .collect(),
            });
        let tolerances = tolerance_lines(setup);
        let warnings = noise_warnings(&terms, &figures);
        Report {
            settings: setup.settings,
            stopped,
            seconds,
            samples: n,
            refused,
            refusals: records
                .iter()
                .filter_map(|r| r.refused.as_ref().map(|w| (r.index, w.clone())))
                .take(10)
                .collect(),
            tolerances,
            overall: Fraction::wilson(passed, n),
            terms,
            figures,
            sensitivities,
            worst,
            warnings,
        }
    }
}

/// A term judged on a figure whose photon noise is above a third of its
/// spread over the samples: the samples near its limit are judged by the
/// photons as much as by the geometry.
fn noise_warnings(terms: &[TermYield], figures: &[FigureSummary]) -> Vec<String> {
    let mut out = Vec::new();
    for t in terms {
        let Some(figure) = Figure::of_term(&t.term) else {
            continue;
        };
        let Some(f) = figures.iter().find(|f| f.figure == figure.key()) else {
            continue;
        };
        if f.photon_noise_sd > f.spread.sd / 3.0 && f.spread.sd > 0.0 {
            out.push(format!(
                "the {}'s photon noise (σ {:.4}) is above a third of its spread over the samples (σ {:.4}): more --photons would judge the samples near its limit by their geometry",
                t.term, f.photon_noise_sd, f.spread.sd
            ));
        }
    }
    out
}

/// The tolerances in words, with their units.
pub fn tolerance_lines(setup: &Setup) -> Vec<ToleranceLine> {
    let t = &setup.model.tolerances;
    let mut out: Vec<ToleranceLine> = t
        .scalars
        .iter()
        .map(|s| ToleranceLine {
            name: s.name.clone(),
            distribution: format!("{} ({})", s.distribution.describe(), s.unit),
        })
        .collect();
    for f in &t.form_errors {
        out.push(ToleranceLine {
            name: format!("{} form error", f.part_name),
            distribution: format!(
                "σ {} m along the normal, correlation length {} m",
                f.sigma_m, f.correlation_length_m
            ),
        });
    }
    for s in &t.slope_errors {
        out.push(ToleranceLine {
            name: format!("{} slope error", s.part_name),
            distribution: format!("σ {} rad per axis, on every sample", s.sigma_rad),
        });
    }
    out
}

/// Each shown figure's first-order share of its variance per tolerance:
/// a scalar's by its Sobol coordinate, a form error's by a fit on its
/// deviations at a few points along the profile.
fn sensitivities(setup: &Setup, traced: &[&SampleRecord]) -> Vec<Sensitivity> {
    let draws: Vec<_> = traced.iter().map(|r| setup.model.draw(r.index)).collect();
    let deviations: Vec<Vec<Vec<f64>>> = draws
        .iter()
        .map(|d| setup.model.form_deviations(d))
        .collect();
    let mut out = Vec::new();
    for (f, fig) in setup.figures.iter().enumerate() {
        if !shown(*fig) {
            continue;
        }
        let pairs: Vec<(usize, f64)> = traced
            .iter()
            .enumerate()
            .filter_map(|(i, r)| r.measured.as_ref().map(|m| (i, m.values[f])))
            .filter(|(_, v)| v.is_finite())
            .collect();
        let y: Vec<f64> = pairs.iter().map(|p| p.1).collect();
        for (k, s) in setup.model.tolerances.scalars.iter().enumerate() {
            let u: Vec<f64> = pairs.iter().map(|(i, _)| draws[*i].uniforms[k]).collect();
            if let Some(share) = binned_share(&u, &y) {
                out.push(Sensitivity {
                    figure: fig.key(),
                    tolerance: s.name.clone(),
                    share,
                });
            }
        }
        for (k, form) in setup.model.forms.iter().enumerate() {
            let dim = form.dimension();
            let m = FORM_FEATURES.min(dim);
            let at: Vec<usize> = (0..m).map(|j| (j * (dim - 1)) / (m - 1).max(1)).collect();
            let rows: Vec<Vec<f64>> = pairs
                .iter()
                .map(|(i, _)| {
                    let d = &deviations[*i][k];
                    let mut row: Vec<f64> = at.iter().map(|&j| d[j]).collect();
                    // A deformation's size and its slopes' (what widens
                    // a beam whichever way the surface bends).
                    row.push(rms(d));
                    row.push(rms(&form.slopes(d)));
                    row
                })
                .collect();
            if let Some(share) = regression_share(&rows, &y) {
                out.push(Sensitivity {
                    figure: fig.key(),
                    tolerance: format!(
                        "{} form error",
                        setup.model.tolerances.form_errors[k].part_name
                    ),
                    share,
                });
            }
        }
    }
    out
}

fn rms(v: &[f64]) -> f64 {
    (v.iter().map(|x| x * x).sum::<f64>() / v.len().max(1) as f64).sqrt()
}
