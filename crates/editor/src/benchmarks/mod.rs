//! The editor measured in its real window, apart from the product: the
//! app calls [`Benchmarks`] at the start and end of each frame and prints
//! its report on exit; nothing else knows about it.
//! - `frames` (`--benchmark SECONDS [--continuous] [--export]`): frame
//!   time and interval, UI time, edit-to-preview latency, photons/s; with
//!   `--export`, exports one after another instead of edits.
//! - `drag` (`--benchmark-drag SECONDS`): a scripted drag of the main
//!   generator parameter, preview age and lag, previews per second.

mod drag;
mod frames;

use std::path::PathBuf;
use std::time::{Duration, Instant};

use drag::DragBenchmark;
pub use drag::DragTarget;
use frames::FrameBenchmark;

use crate::export_dialog::ExportDialog;
use crate::state::{Command, EditorState};

/// Which benchmark a window runs.
#[derive(Debug, Clone, PartialEq)]
pub enum BenchmarkOptions {
    /// Frames in use for `duration`: every frame repainted with
    /// `continuous`; exports into `export_into` instead of edits.
    Frames {
        duration: Duration,
        continuous: bool,
        export_into: Option<PathBuf>,
    },
    /// A scripted drag lasting `duration`.
    Drag { duration: Duration },
}

/// The running benchmark.
#[derive(Debug)]
pub(crate) enum Benchmarks {
    Frames(FrameBenchmark),
    Drag(DragBenchmark),
}

impl Benchmarks {
    pub fn new(options: BenchmarkOptions) -> Benchmarks {
        match options {
            BenchmarkOptions::Frames {
                duration,
                continuous,
                export_into,
            } => {
                let mut b = FrameBenchmark::new(duration);
                b.continuous = continuous;
                b.export_into = export_into;
                Benchmarks::Frames(b)
            }
            BenchmarkOptions::Drag { duration } => Benchmarks::Drag(DragBenchmark::new(duration)),
        }
    }

    /// At the start of a frame: the scripted edit, drag step or export,
    /// the measurements, the repaint the benchmark needs, and the quit
    /// once it is over.
    pub fn begin_frame(
        &mut self,
        state: &mut EditorState,
        export: &mut ExportDialog,
        ctx: &egui::Context,
        frame_start: Instant,
    ) {
        match self {
            Benchmarks::Frames(b) => {
                // Whether last frame's export still runs, before the next starts.
                let running = export.is_exporting();
                let started = b
                    .export_into
                    .as_ref()
                    .is_some_and(|dir| export.start_benchmark_export(state, dir, ctx));
                b.begin_frame(state, frame_start, running, started);
                if b.is_finished() {
                    // Its nudges are no one's unsaved changes: no question,
                    // no recovery file left behind.
                    state.push(Command::QuitDiscarding);
                } else if b.continuous {
                    ctx.request_repaint();
                } else {
                    // Frames come as in use; the next edit is due within 2 s.
                    ctx.request_repaint_after(Duration::from_millis(250));
                }
            }
            Benchmarks::Drag(b) => {
                b.begin_frame(state, frame_start);
                if b.is_finished() {
                    state.push(Command::QuitDiscarding);
                } else {
                    // A dragging hand moves the pointer every frame.
                    ctx.request_repaint();
                }
                state.scripted_pointer = b.holds_pointer();
            }
        }
    }

    /// eframe's CPU time of the last frame.
    pub fn frame_cost(&mut self, seconds: f32) {
        if let Benchmarks::Frames(b) = self {
            b.frame_cost(seconds);
        }
    }

    /// At the end of a frame, after `ui_time` of UI.
    pub fn end_frame(&mut self, ui_time: Duration) {
        if let Benchmarks::Frames(b) = self {
            b.end_frame(ui_time);
        }
    }

    /// The figures, as printed on exit.
    pub fn report(&self) -> String {
        match self {
            Benchmarks::Frames(b) => b.report(),
            Benchmarks::Drag(b) => b.report(),
        }
    }
}

/// Median, 95th percentile and maximum of durations, in milliseconds (the
/// nearest rank; NaN when there are none).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Quantiles {
    pub median_ms: f64,
    pub p95_ms: f64,
    pub max_ms: f64,
    pub count: usize,
}

impl Quantiles {
    pub fn of(durations: &[Duration]) -> Quantiles {
        let mut v: Vec<f64> = durations.iter().map(|d| d.as_secs_f64() * 1e3).collect();
        v.sort_by(f64::total_cmp);
        let at = |q: f64| {
            v.get(((v.len() as f64 - 1.0) * q).round() as usize)
                .copied()
                .unwrap_or(f64::NAN)
        };
        Quantiles {
            median_ms: at(0.5),
            p95_ms: at(0.95),
            max_ms: at(1.0),
            count: v.len(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_take_the_nearest_rank() {
        let d: Vec<Duration> = (1..=100).map(Duration::from_millis).collect();
        let q = Quantiles::of(&d);
        assert_eq!(
            (q.median_ms, q.p95_ms, q.max_ms, q.count),
            (51.0, 95.0, 100.0, 100)
        );
        assert!(Quantiles::of(&[]).median_ms.is_nan());
    }
}
