//! A survey of one or two variables' whole range before the local
//! search: candidates traced evenly across the bounds, so that the
//! refinement starts in the best basin traced (a local search cannot
//! cross a plateau or a jump, as the half-peak beam makes where a
//! mirror's spike and a spread plateau trade places), and the user
//! hears how far each term goes over the range: a term every candidate
//! misses on the same side is most likely out of these variables' reach
//! (one missed on both sides lies between two traced points).
//!
//! Unlike [`crate::Reachability`] it is not a bound: between two traced
//! points a term could change fast. So it says what was traced, not
//! what is impossible.

use lucerna_photometry::format_number;
use serde::Serialize;

use crate::history::Phase;
use crate::merit::TermStatus;
use crate::variables::Place;

use super::{Context, PHASE_PHOTONS};

/// Variables a survey covers at most: a grid over more would take the
/// design's budget.
pub const MAX_SURVEYED: usize = 2;

/// Points along each variable at most: 9 along one, 5 × 5 over two.
const MOST_POINTS: [usize; MAX_SURVEYED] = [9, 5];

/// The share of the design's candidates (or time) a survey may take: the
/// rest is the refinement's.
const BUDGET_SHARE: f64 = 1.0 / 3.0;

/// One surveyed variable.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SurveyAxis {
    pub name: String,
    pub lower: f64,
    pub upper: f64,
    /// Evenly spaced points traced from `lower` to `upper`, both included.
    pub points: usize,
}

/// A spec term over the surveyed candidates.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TermRange {
    pub term: String,
    pub wanted: String,
    /// The least and the greatest value traced, in the term's units.
    pub lowest: f64,
    pub highest: f64,
    /// How many of the traced candidates meet it, and how many miss it
    /// below and above what is wanted.
    pub met_by: usize,
    pub too_low: usize,
    pub too_high: usize,
}

impl TermRange {
    /// Every traced candidate misses on the same side: what is wanted
    /// lies beyond the range traced, not between two of its points.
    pub fn beyond(&self) -> bool {
        self.met_by == 0 && (self.too_low == 0 || self.too_high == 0)
    }
}

/// What the survey traced.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Survey {
    pub axes: Vec<SurveyAxis>,
    /// Candidates traced (those refused are not counted).
    pub traced: usize,
    /// Each spec term's range (empty for a distribution).
    pub terms: Vec<TermRange>,
    /// The least and the greatest merit traced (a distribution's: the
    /// relative L2 difference).
    pub merit_range: [f64; 2],
    /// The best traced candidate: its values and merit.
    pub best_values: Vec<f64>,
    pub best_merit: f64,
}

impl Survey {
    /// The variables and their ranges, in words, their values in the
    /// file's units (four significant digits).
    pub fn across(&self) -> String {
        self.across_with(|_, x| format_number(x, 4))
    }

    /// The same with each value as `shown(name, value)` writes it (the
    /// editor's mm and degrees).
    pub fn across_with(&self, shown: impl Fn(&str, f64) -> String) -> String {
        self.axes
            .iter()
            .map(|a| {
                format!(
                    "{} {} … {}",
                    a.name,
                    shown(&a.name, a.lower),
                    shown(&a.name, a.upper)
                )
            })
            .collect::<Vec<_>>()
            .join(" × ")
    }

    /// What the user should hear: each term every traced candidate
    /// misses on the same side, with how far it went.
    pub fn findings(&self) -> Vec<String> {
        let these = if self.axes.len() == 1 {
            "this variable"
        } else {
            "these variables"
        };
        let mut out = self
            .terms
            .iter()
            .filter(|t| t.beyond())
            .map(|t| {
                format!(
                    "none of the {} candidates traced across {} meets the {} ({}): it goes from {:.3} to {:.3} there, so {these} most likely cannot reach it",
                    self.traced,
                    self.across(),
                    t.term,
                    t.wanted,
                    t.lowest,
                    t.highest
                )
            })
            .collect::<Vec<_>>();
        if !out.is_empty() {
            out.extend(self.at_bounds());
        }
        out
    }

    /// Where the best traced candidate lies on a variable's bound: the
    /// range, more than the geometry, may be what stops the design.
    fn at_bounds(&self) -> Vec<String> {
        self.axes
            .iter()
            .zip(&self.best_values)
            .filter_map(|(a, &x)| {
                let which = if x >= a.upper {
                    "upper"
                } else if x <= a.lower {
                    "lower"
                } else {
                    return None;
                };
                Some(format!(
                    "the best traced has {} at its {which} bound ({}): the bounds lie within a factor of four of the start value (or where the scene stops being valid), so a start nearer the light wanted moves them",
                    a.name,
                    format_number(x, 4)
                ))
            })
            .collect()
    }
}

/// Traces a grid across the bounds of a design of one or two variables
/// (a part's shape, placement or finish numbers, not a profile's
/// points); None where it does not apply or the budget leaves no room
/// for three points a variable.
pub fn survey(ctx: &mut Context) -> Option<Survey> {
    let dims = ctx.variables.len();
    if dims == 0
        || dims > MAX_SURVEYED
        || ctx
            .variables
            .iter()
            .any(|v| matches!(v.place, Place::ProfilePoint { .. }) || v.upper <= v.lower)
    {
        return None;
    }
    let n = points(ctx, dims)?;
    let axes: Vec<SurveyAxis> = ctx
        .variables
        .iter()
        .map(|v| SurveyAxis {
            name: v.name.clone(),
            lower: v.lower,
            upper: v.upper,
            points: n,
        })
        .collect();
    let mut ranges: Vec<TermRange> = Vec::new();
    let mut merits = [f64::INFINITY, f64::NEG_INFINITY];
    let mut best: Option<(Vec<f64>, f64)> = None;
    let mut traced = 0;
    for k in 0..n.pow(dims as u32) {
        if ctx.spent().is_some() {
            break;
        }
        let values: Vec<f64> = ctx
            .variables
            .iter()
            .enumerate()
            .map(|(d, v)| {
                let i = (k / n.pow(d as u32)) % n;
                v.at(i as f64 / (n - 1) as f64)
            })
            .collect();
        let Some(judged) = ctx.judge(Phase::Survey, &values, PHASE_PHOTONS) else {
            continue;
        };
        traced += 1;
        merits = [merits[0].min(judged.merit), merits[1].max(judged.merit)];
        if best.as_ref().is_none_or(|b| judged.merit < b.1) {
            best = Some((values, judged.merit));
        }
        let t = &judged.traced;
        let terms = ctx.aim.terms(
            &t.table,
            t.map.light_output_ratio(),
            ctx.lamp_flux_lm,
            &t.opening,
        );
        absorb(&mut ranges, &terms);
    }
    let (best_values, best_merit) = best?;
    Some(Survey {
        axes,
        traced,
        terms: ranges,
        merit_range: merits,
        best_values,
        best_merit,
    })
}

/// Points along each variable: as many as [`MOST_POINTS`] allows within
/// [`BUDGET_SHARE`] of the candidates (with `--evaluations`, so that the
/// same budget gives the same design on any machine) or else of the
/// time left; at least 3.
fn points(ctx: &Context, dims: usize) -> Option<usize> {
    let share_of = |total: f64| (total * BUDGET_SHARE).powf(1.0 / dims as f64).floor();
    let candidates = match ctx.budget().evaluations {
        Some(e) => e as f64,
        None => {
            // The start's trace (its scene's preparation included)
            // prices one candidate.
            let one = ctx.history.elapsed().as_secs_f64().max(1e-3);
            let left = ctx
                .deadline()
                .saturating_duration_since(std::time::Instant::now())
                .as_secs_f64();
            left / one
        }
    };
    let n = share_of(candidates).min(MOST_POINTS[dims - 1] as f64);
    (n >= 3.0).then_some(n as usize)
}

/// Widens each term's range by a candidate's terms.
fn absorb(ranges: &mut Vec<TermRange>, terms: &[TermStatus]) {
    for t in terms.iter().filter(|t| !t.term.ends_with("(aim)")) {
        let met = t.missed_by <= 0.0;
        let [m, low, high] = [met, !met && t.too_low, !met && !t.too_low].map(usize::from);
        match ranges.iter_mut().find(|r| r.term == t.term) {
            Some(r) => {
                r.lowest = r.lowest.min(t.value);
                r.highest = r.highest.max(t.value);
                r.met_by += m;
                r.too_low += low;
                r.too_high += high;
            }
            None => ranges.push(TermRange {
                term: t.term.clone(),
                wanted: t.wanted.clone(),
                lowest: t.value,
                highest: t.value,
                met_by: m,
                too_low: low,
                too_high: high,
            }),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn beam(value: f64) -> TermStatus {
        // 12° ± 0.5°.
        let off = (value - 12.0f64).abs();
        TermStatus {
            term: "beam angle".to_owned(),
            value,
            wanted: "12° ± 0.5°".to_owned(),
            missed_by: (off - 0.5).max(0.0),
            too_low: off > 0.5 && value < 12.0,
        }
    }

    fn survey_of(values: &[f64]) -> Survey {
        let mut terms = Vec::new();
        for &v in values {
            absorb(&mut terms, &[beam(v)]);
        }
        Survey {
            axes: vec![SurveyAxis {
                name: "reflector.finish.depth".to_owned(),
                lower: 0.0000375,
                upper: 0.00015,
                points: values.len(),
            }],
            traced: values.len(),
            terms,
            merit_range: [0.0, 1.0],
            best_values: vec![0.00015],
            best_merit: 0.0,
        }
    }

    #[test]
    fn a_term_missed_on_one_side_everywhere_is_beyond_the_range() {
        let s = survey_of(&[3.1, 3.2, 3.0]);
        let t = &s.terms[0];
        assert_eq!((t.lowest, t.highest), (3.0, 3.2));
        assert_eq!((t.met_by, t.too_low, t.too_high), (0, 3, 0));
        assert!(t.beyond());
        let f = s.findings();
        assert!(f[0].contains("none of the 3 candidates"), "{f:?}");
        assert!(f[0].contains("0.0000375 … 0.00015"), "{f:?}");
        assert!(f[1].contains("at its upper bound (0.00015)"), "{f:?}");
    }

    #[test]
    fn a_term_missed_on_both_sides_lies_between_two_points() {
        let s = survey_of(&[3.0, 20.0]);
        assert!(!s.terms[0].beyond());
        assert!(s.findings().is_empty());
        let met = survey_of(&[3.0, 12.2]);
        assert_eq!(met.terms[0].met_by, 1);
        assert!(met.findings().is_empty());
    }
}
