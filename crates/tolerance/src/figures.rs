//! What is measured of each built luminaire: its figures (beam, field,
//! peak and its direction, the flux centroid's direction, cut-off, LOR,
//! UGR, the difference from a target distribution) and which spec terms
//! it meets.

use lucerna_design::merit::Aim;
use lucerna_design::traced::evaluate::Traced;
use lucerna_design::{Spec, Target};
use lucerna_photometry::{IntensityMap, figures};
use serde::{Deserialize, Serialize};

/// One figure a sample is measured by.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Figure {
    /// The full beam angle (50 %): of the two main planes, the one a
    /// spec's beam term judges (farther from its aim), else the wider.
    Beam,
    /// The full field angle (10 %), the wider of the two main planes.
    Field,
    PeakCandela,
    PeakGamma,
    PeakC,
    /// The direction of the downward flux's vector (the flux-weighted
    /// mean direction of the light below the horizon, the beam's
    /// centroid): γ from the nadir and its C-plane. A lateral LED offset
    /// tilts it; the peak's γ of a flat-topped beam sits where the noise
    /// puts it.
    CentroidGamma,
    CentroidC,
    /// The spec's cut-off: the most intensity above its γ, % of the peak.
    Cutoff,
    Lor,
    Ugr,
    /// Relative L2 difference from a target distribution.
    RelativeL2,
}

impl Figure {
    /// The CSV column and JSON name.
    pub fn key(self) -> &'static str {
        match self {
            Figure::Beam => "beam_deg",
            Figure::Field => "field_deg",
            Figure::PeakCandela => "peak_cd",
            Figure::PeakGamma => "peak_gamma_deg",
            Figure::PeakC => "peak_c_deg",
            Figure::CentroidGamma => "centroid_gamma_deg",
            Figure::CentroidC => "centroid_c_deg",
            Figure::Cutoff => "cutoff_percent_of_peak",
            Figure::Lor => "lor_percent",
            Figure::Ugr => "ugr",
            Figure::RelativeL2 => "relative_l2",
        }
    }

    /// How a picture's axis names it.
    pub fn label(self) -> &'static str {
        match self {
            Figure::Beam => "beam angle (°)",
            Figure::Field => "field angle (°)",
            Figure::PeakCandela => "peak (cd)",
            Figure::PeakGamma => "peak γ (°)",
            Figure::PeakC => "peak C (°)",
            Figure::CentroidGamma => "flux centroid γ (°)",
            Figure::CentroidC => "flux centroid C (°)",
            Figure::Cutoff => "above cut-off (% of peak)",
            Figure::Lor => "LOR (%)",
            Figure::Ugr => "UGR",
            Figure::RelativeL2 => "relative L2",
        }
    }

    /// The figure whose value a spec term states.
    pub fn of_term(term: &str) -> Option<Figure> {
        if term == "beam angle" {
            Some(Figure::Beam)
        } else if term == "field angle" {
            Some(Figure::Field)
        } else if term.starts_with("cut-off") {
            Some(Figure::Cutoff)
        } else if term == "LOR" {
            Some(Figure::Lor)
        } else if term.starts_with("UGR") {
            Some(Figure::Ugr)
        } else if term.starts_with("relative L2") {
            Some(Figure::RelativeL2)
        } else {
            None
        }
    }
}

/// What a sample is judged against: a spec's terms, or a distribution
/// with the largest relative L2 difference allowed.
#[derive(Debug, Clone)]
pub struct Judge {
    pub aim: Aim,
    /// A distribution's largest relative L2 (None for a spec).
    pub max_relative_l2: Option<f64>,
}

/// One spec term as a sample holds it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TermResult {
    pub term: String,
    pub wanted: String,
    #[serde(with = "crate::numbers::one")]
    pub value: f64,
    pub met: bool,
}

/// A traced sample's figures and terms.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Measured {
    /// Values in the order of [`Judge::figures`] (NaN where the figure
    /// has no value, infinite where it is unbounded).
    #[serde(with = "crate::numbers::list")]
    pub values: Vec<f64>,
    pub terms: Vec<TermResult>,
    /// The design's merit of the sample (how badly it misses; 0 meets
    /// every term): the worst sample has the largest.
    #[serde(with = "crate::numbers::one")]
    pub shortfall: f64,
}

impl Judge {
    pub fn new(target: Target, max_relative_l2: Option<f64>) -> Result<Judge, String> {
        match (&target, max_relative_l2) {
            (Target::Distribution { .. }, None) => {
                return Err(
                    "a target distribution needs the largest relative L2 difference allowed (--max-relative-l2)"
                        .to_owned(),
                );
            }
            (Target::Distribution { .. }, Some(m)) if !(m.is_finite() && m > 0.0) => {
                return Err(format!(
                    "--max-relative-l2 must be a positive number, got {m}"
                ));
            }
            (Target::Spec(_), Some(_)) => {
                return Err("--max-relative-l2 is for a target distribution, not a spec".to_owned());
            }
            _ => {}
        }
        Ok(Judge {
            aim: Aim::new(target),
            max_relative_l2,
        })
    }

    fn spec(&self) -> Option<&Spec> {
        match self.aim.target() {
            Target::Spec(s) => Some(s),
            Target::Distribution { .. } => None,
        }
    }

    /// The figures measured: always beam, field, peak and its direction,
    /// the flux centroid's direction and LOR; the cut-off and UGR where
    /// the spec has them; the relative L2 for a distribution.
    pub fn figures(&self) -> Vec<Figure> {
        let mut out = vec![
            Figure::Beam,
            Figure::Field,
            Figure::PeakCandela,
            Figure::PeakGamma,
            Figure::PeakC,
            Figure::CentroidGamma,
            Figure::CentroidC,
        ];
        if self.spec().is_some_and(|s| s.cutoff_gamma_deg.is_some()) {
            out.push(Figure::Cutoff);
        }
        out.push(Figure::Lor);
        if self.spec().is_some_and(|s| s.ugr_max.is_some()) {
            out.push(Figure::Ugr);
        }
        if self.max_relative_l2.is_some() {
            out.push(Figure::RelativeL2);
        }
        out
    }

    /// The terms judged, as a sample's [`Measured::terms`] lists them.
    pub fn measure(&self, traced: &Traced) -> Measured {
        let table = &traced.table;
        let lamp_flux_lm = traced.map.emitter_flux_lm;
        let lor = traced.map.light_output_ratio();
        let f = figures(table, Some(lamp_flux_lm));
        let mut terms: Vec<TermResult> = Vec::new();
        let mut cutoff = f64::NAN;
        let mut ugr = f64::NAN;
        let mut l2 = f64::NAN;
        match (self.aim.target(), self.max_relative_l2) {
            (Target::Distribution { absolute, .. }, Some(max)) => {
                l2 = self.aim.relative_l2(table, *absolute);
                terms.push(TermResult {
                    term: "relative L2".to_owned(),
                    wanted: format!("at most {max}"),
                    value: l2,
                    met: l2 <= max,
                });
            }
            _ => {
                for t in self.aim.terms(table, lor, lamp_flux_lm, &traced.opening) {
                    if t.term.ends_with("(aim)") {
                        continue;
                    }
                    match Figure::of_term(&t.term) {
                        Some(Figure::Cutoff) => cutoff = t.value,
                        Some(Figure::Ugr) => ugr = t.value,
                        _ => {}
                    }
                    terms.push(TermResult {
                        met: t.missed_by <= 0.0,
                        term: t.term,
                        wanted: t.wanted,
                        value: t.value,
                    });
                }
            }
        }
        let shortfall = if self.max_relative_l2.is_some() {
            l2
        } else {
            self.aim
                .shortfall(table, lor, lamp_flux_lm, &traced.opening)
        };
        // The beam as its term judges it (the plane farther from the
        // aim), so a sample drawn inside the limits meets the term.
        let beam_term = terms
            .iter()
            .find(|t| Figure::of_term(&t.term) == Some(Figure::Beam))
            .map(|t| t.value);
        let widest = |a: [Option<f64>; 2]| {
            let v = a.map(|x| x.unwrap_or(if f.peak_cd > 0.0 { 360.0 } else { 0.0 }));
            v[0].max(v[1])
        };
        let (centroid_gamma, centroid_c) = flux_centroid(&traced.map);
        let values = self
            .figures()
            .iter()
            .map(|fig| match fig {
                Figure::Beam => beam_term.unwrap_or_else(|| widest(f.beam_angle_deg)),
                Figure::Field => widest(f.field_angle_deg),
                Figure::PeakCandela => f.peak_cd,
                Figure::PeakGamma => f.peak_gamma_deg,
                Figure::PeakC => f.peak_c_deg,
                Figure::CentroidGamma => centroid_gamma,
                Figure::CentroidC => centroid_c,
                Figure::Cutoff => cutoff,
                Figure::Lor => 100.0 * lor,
                Figure::Ugr => ugr,
                Figure::RelativeL2 => l2,
            })
            .collect();
        Measured {
            values,
            terms,
            shortfall,
        }
    }
}

/// The direction of a map's downward flux vector Σ Φ·d (γ from the
/// nadir, its C-plane; degrees): each texel's photons at its centre
/// direction. Up-light is left out: a beam's centroid is where the
/// downward light goes, and light that flips between the reflector and
/// the sky when a part moves would turn the whole vector.
pub fn flux_centroid(map: &IntensityMap) -> (f64, f64) {
    let v = flux_vector(map);
    let gamma = v[0].hypot(v[1]).atan2(-v[2]).to_degrees();
    let c = v[1].atan2(v[0]).to_degrees().rem_euclid(360.0);
    (gamma, c)
}

/// Σ counts·d over the texels below the horizon (photons × unit
/// direction).
pub fn flux_vector(map: &IntensityMap) -> [f64; 3] {
    let mut v = [0.0; 3];
    for (t, &n) in map.counts.iter().enumerate() {
        if n == 0 {
            continue;
        }
        let d = map.layout.texel_centre_direction(t);
        if d[2] >= 0.0 {
            continue;
        }
        for k in 0..3 {
            v[k] += n as f64 * d[k];
        }
    }
    v
}
