//! `lucerna-editor --benchmark SECONDS`: the real window while tracing,
//! measured. Frames come as they do in use (paced snapshot repaints);
//! every two seconds a scripted edit (the first part nudged 0.5 mm up or
//! down, which restarts the run) is made, and the time until a frame shows
//! the new run's first snapshot is taken. At the end the window closes and
//! the figures are printed: frame time (eframe's CPU time per frame: ui,
//! tessellation, paint) and the interval between frames (median, 95th
//! percentile), edit-to-preview latency, photons/s while the UI runs.
//! With `--continuous` every frame asks for the next, as while the user
//! drags: the frame interval is then what a frame takes end to end.
//! With `--export` no edit is made: exports of the current run (all
//! files, the automatic filter) follow one another through the export
//! dialog, and the longest frame while one runs is reported: an export
//! must never block a frame.

use std::time::{Duration, Instant};

use super::Quantiles;
use crate::state::EditorState;

/// Time between scripted edits: long enough for the run to settle.
const EDIT_EVERY: Duration = Duration::from_secs(2);
/// The nudge each edit gives the first part (m).
const NUDGE_M: f64 = 0.0005;

/// A running benchmark of the editor's frames.
#[derive(Debug)]
pub struct FrameBenchmark {
    duration: Duration,
    /// Repaint every frame, as while the user drags: the frame interval
    /// is then the time a frame takes.
    pub continuous: bool,
    started: Option<Instant>,
    last_frame: Option<Instant>,
    frame_intervals: Vec<Duration>,
    frame_costs: Vec<Duration>,
    ui_times: Vec<Duration>,
    last_edit: Option<Instant>,
    /// The edit waiting for its first preview: when, and the generation
    /// shown before it.
    waiting: Option<(Instant, u64)>,
    latencies: Vec<Duration>,
    /// Photons/s of the last snapshot of each run segment.
    photons_per_second: Vec<f64>,
    edits: u32,
    /// The snapshot repaint interval the pacer keeps, as last seen.
    repaint_interval: Duration,
    finished: bool,
    /// Export instead of editing (`--export`): into this folder.
    pub export_into: Option<std::path::PathBuf>,
    /// An export was running at the start of the last frame.
    exporting_since: Option<Instant>,
    /// Frame time, UI time and frame interval of the frames that began
    /// while an export ran.
    export_frame_costs: Vec<Duration>,
    export_ui_times: Vec<Duration>,
    export_intervals: Vec<Duration>,
    /// How long each finished export took.
    export_durations: Vec<Duration>,
    /// The frame now being measured began while an export ran.
    frame_during_export: bool,
}

impl FrameBenchmark {
    pub fn new(duration: Duration) -> Self {
        FrameBenchmark {
            duration,
            continuous: false,
            started: None,
            last_frame: None,
            frame_intervals: Vec::new(),
            frame_costs: Vec::new(),
            ui_times: Vec::new(),
            last_edit: None,
            waiting: None,
            latencies: Vec::new(),
            photons_per_second: Vec::new(),
            edits: 0,
            repaint_interval: Duration::ZERO,
            finished: false,
            export_into: None,
            exporting_since: None,
            export_frame_costs: Vec::new(),
            export_ui_times: Vec::new(),
            export_intervals: Vec::new(),
            export_durations: Vec::new(),
            frame_during_export: false,
        }
    }

    pub fn is_finished(&self) -> bool {
        self.finished
    }

    /// Called at the start of a frame, after the state took the newest
    /// snapshot and before the panels: measures, and may edit the scene
    /// (as a panel would, so the frame's end restarts the run).
    ///
    /// `export_running`: the export seen last frame still runs;
    /// `export_started`: one was started as this frame began.
    pub fn begin_frame(
        &mut self,
        state: &mut EditorState,
        now: Instant,
        export_running: bool,
        export_started: bool,
    ) {
        let shown = state
            .snapshot()
            .map(|s| (s.generation, s.photons_per_second));
        // Measure from the first snapshot on: loading is not a frame cost.
        let Some((generation, photons_per_second)) = shown else {
            return;
        };
        let started = *self.started.get_or_insert(now);
        self.repaint_interval = state.run.pacer.interval();
        if let Some(last) = self.last_frame {
            self.frame_intervals.push(now - last);
            if self.frame_during_export {
                self.export_intervals.push(now - last);
            }
        }
        self.last_frame = Some(now);
        if let Some(since) = self.exporting_since
            && !export_running
        {
            self.export_durations.push(now - since);
            self.exporting_since = None;
        }
        if export_started || (export_running && self.exporting_since.is_none()) {
            self.exporting_since = Some(now);
        }
        self.frame_during_export = export_running || export_started;
        if let Some((at, before)) = self.waiting
            && generation > before
        {
            self.latencies.push(now - at);
            self.waiting = None;
        }
        if now - started >= self.duration {
            self.photons_per_second.push(photons_per_second);
            self.finished = true;
            return;
        }
        let due = self
            .last_edit
            .map_or(now - started >= EDIT_EVERY, |e| now - e >= EDIT_EVERY);
        if due && self.waiting.is_none() && self.export_into.is_none() {
            if let Some(part) = state.doc.scene.as_mut().and_then(|s| s.parts.first_mut()) {
                self.photons_per_second.push(photons_per_second);
                let sign = if self.edits.is_multiple_of(2) {
                    1.0
                } else {
                    -1.0
                };
                part.transform.translate[2] += sign * NUDGE_M;
                self.edits += 1;
                self.waiting = Some((now, generation));
            }
            self.last_edit = Some(now);
        }
    }

    /// The previous frame's cost as eframe measured it.
    pub fn frame_cost(&mut self, seconds: f32) {
        if self.started.is_some() && seconds.is_finite() && seconds >= 0.0 {
            let cost = Duration::from_secs_f32(seconds);
            self.frame_costs.push(cost);
            // eframe reports the frame before this one.
            if self.frame_during_export {
                self.export_frame_costs.push(cost);
            }
        }
    }

    pub fn end_frame(&mut self, ui_time: Duration) {
        if self.started.is_some() {
            self.ui_times.push(ui_time);
            if self.frame_during_export {
                self.export_ui_times.push(ui_time);
            }
        }
    }

    /// The figures, as the benchmark prints them.
    pub fn report(&self) -> String {
        let ms = |d: Duration| d.as_secs_f64() * 1e3;
        let stats = |v: &[Duration]| {
            let q = Quantiles::of(v);
            format!(
                "median {:.1} ms, p95 {:.1} ms, max {:.1} ms over {}",
                q.median_ms, q.p95_ms, q.max_ms, q.count
            )
        };
        let mut pps = self.photons_per_second.clone();
        pps.sort_by(f64::total_cmp);
        let median_pps = pps.get(pps.len() / 2).copied().unwrap_or(f64::NAN);
        let mut report = format!(
            "frame time (ui, tessellation, paint): {}\nframe interval: {}\nUI time per frame: {}\nedit to first preview: {} ({} edits)\nphotons/s while the UI runs: median {:.3e} over {} runs\nsnapshot repaint interval: {:.0} ms",
            stats(&self.frame_costs),
            stats(&self.frame_intervals),
            stats(&self.ui_times),
            stats(&self.latencies),
            self.edits,
            median_pps,
            pps.len(),
            ms(self.repaint_interval)
        );
        if self.export_into.is_some() {
            report.push_str(&format!(
                "\nexports (all files, automatic filter): {} finished, each {}\nwhile an export ran: frame time {}\nwhile an export ran: UI time {}\nwhile an export ran: frame interval {}",
                self.export_durations.len(),
                stats(&self.export_durations),
                stats(&self.export_frame_costs),
                stats(&self.export_ui_times),
                stats(&self.export_intervals),
            ));
        }
        report
    }
}
