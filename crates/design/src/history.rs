//! A design's history: every candidate judged, numbered in order on one
//! clock, each with the phase that judged it; and what the caller hears
//! of it ([`Progress`]).

use std::sync::Arc;
use std::time::{Duration, Instant};

use lucerna_scene::Scene;
use serde::Serialize;

use crate::model::reach::Reachability;
use crate::variables::Variable;

/// The phases of a design, in the order they run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Phase {
    /// The start scene traced as it is.
    Start,
    /// The point-source direct design (energy-balance mapping between the
    /// fixed ends) and what the geometry can reach.
    Direct,
    /// The direct design corrected for the extended source: traced, the
    /// mapping's light changed by what the tracer saw, mapped again.
    Correction,
    /// A local refinement with the tracer in the loop.
    Refinement,
    /// The meridian model's global search, for what the mapping cannot
    /// represent.
    Fallback,
    /// One or two variables traced evenly across their bounds before
    /// the refinement ([`crate::phases::survey`]).
    Survey,
}

impl Phase {
    /// As design.csv and the progress lines name it.
    pub fn name(self) -> &'static str {
        match self {
            Phase::Start => "start",
            Phase::Direct => "direct",
            Phase::Correction => "correction",
            Phase::Refinement => "refinement",
            Phase::Fallback => "fallback",
            Phase::Survey => "survey",
        }
    }
}

/// One judged candidate, as `design.csv` lists it.
#[derive(Debug, Clone, PartialEq)]
pub struct Record {
    pub evaluation: u64,
    pub elapsed_s: f64,
    /// Photons traced (0: judged by a model).
    pub photons: u64,
    /// The merit (None: refused).
    pub merit: Option<f64>,
    /// What the merit measures: "l2" (the relative L2 difference on the
    /// sphere), "meridian model" (the same, of the model's light),
    /// "spec".
    pub measure: String,
    pub phase: Phase,
    pub values: Vec<f64>,
}

/// Where a design stands, for a progress line or a plot.
#[derive(Debug, Clone, PartialEq)]
pub struct Progress {
    pub elapsed: Duration,
    pub phase: Phase,
    pub evaluations: u64,
    /// The refinement's stage (from 0) and its photons.
    pub stage: usize,
    pub photons: u64,
    /// The best traced merit so far (the phase's own where it measures
    /// another way) and its photon noise (one standard deviation, where
    /// known).
    pub best_merit: f64,
    pub noise: f64,
    pub best_values: Vec<f64>,
    /// The newest record.
    pub record: Record,
    /// What the values apply to: the start (its varied profile resampled
    /// to the design's point count once that is chosen) and the
    /// variables.
    pub frame: Arc<Frame>,
    /// What the geometry can reach, once known.
    pub reach: Option<Reachability>,
}

/// The scene a design's values apply to, and its variables.
#[derive(Debug, Clone, PartialEq)]
pub struct Frame {
    pub start: Scene,
    pub variables: Vec<Variable>,
}

impl Frame {
    /// The scene of `values`.
    pub fn scene(&self, values: &[f64]) -> Option<Scene> {
        crate::variables::apply(&self.start, &self.variables, values)
    }
}

/// Every record of a design, numbered in order on the design's clock.
#[derive(Debug)]
pub struct History {
    began: Instant,
    records: Vec<Record>,
    best: Option<(f64, Vec<f64>)>,
    frame: Arc<Frame>,
    reach: Option<Reachability>,
}

impl History {
    pub fn new(began: Instant, frame: Frame) -> History {
        History {
            began,
            records: Vec::new(),
            best: None,
            frame: Arc::new(frame),
            reach: None,
        }
    }

    /// The values recorded from now on apply to `frame` (the best so far
    /// is forgotten: its values were another frame's).
    pub fn set_frame(&mut self, frame: Frame) {
        self.frame = Arc::new(frame);
        self.best = None;
    }

    /// The frame progress reports carry (the tracer's loops report their
    /// own progress with it).
    pub fn frame(&self) -> Arc<Frame> {
        self.frame.clone()
    }

    pub fn set_reach(&mut self, reach: Reachability) {
        self.reach = Some(reach);
    }

    pub fn reach(&self) -> Option<&Reachability> {
        self.reach.as_ref()
    }

    pub fn elapsed(&self) -> Duration {
        self.began.elapsed()
    }

    pub fn began(&self) -> Instant {
        self.began
    }

    pub fn len(&self) -> usize {
        self.records.len()
    }

    /// Candidates traced (not judged by a model).
    pub fn traced(&self) -> usize {
        self.records.iter().filter(|r| r.photons > 0).count()
    }

    pub fn is_empty(&self) -> bool {
        self.records.is_empty()
    }

    /// Adds a candidate and tells `progress`; a traced merit better than
    /// any before becomes the best shown.
    pub fn record(
        &mut self,
        phase: Phase,
        photons: u64,
        merit: Option<f64>,
        measure: &str,
        values: Vec<f64>,
        progress: &mut dyn FnMut(&Progress),
    ) {
        let record = Record {
            evaluation: self.records.len() as u64,
            elapsed_s: self.began.elapsed().as_secs_f64(),
            photons,
            merit,
            measure: measure.to_owned(),
            phase,
            values,
        };
        if let Some(m) = merit.filter(|_| photons > 0)
            && self.best.as_ref().is_none_or(|(b, _)| m < *b)
        {
            self.best = Some((m, record.values.clone()));
        }
        let (best_merit, best_values) = match (&self.best, photons) {
            (Some((m, v)), p) if p > 0 => (*m, v.clone()),
            _ => (merit.unwrap_or(f64::INFINITY), record.values.clone()),
        };
        progress(&Progress {
            elapsed: self.began.elapsed(),
            phase,
            evaluations: self.records.len() as u64 + 1,
            stage: 0,
            photons,
            best_merit,
            noise: 0.0,
            best_values,
            record: record.clone(),
            frame: self.frame.clone(),
            reach: self.reach.clone(),
        });
        self.records.push(record);
    }

    /// Takes the records of a search that kept its own (the tracer's
    /// loops), renumbered after these and put on this clock: `offset` is
    /// when that search began, on this clock.
    pub fn absorb(&mut self, records: Vec<Record>, offset: Duration) {
        for mut r in records {
            r.evaluation = self.records.len() as u64;
            r.elapsed_s += offset.as_secs_f64();
            if let Some(m) = r.merit.filter(|_| r.photons > 0)
                && self.best.as_ref().is_none_or(|(b, _)| m < *b)
            {
                self.best = Some((m, r.values.clone()));
            }
            self.records.push(r);
        }
    }

    pub fn into_records(self) -> Vec<Record> {
        self.records
    }
}
