//! The tolerance commands on the editor's state: Run (the pane's
//! tolerances and the Design pane's spec checked, `lucerna tolerance`'s
//! library started on a thread of its own), Stop (the samples done are
//! kept), each frame's news (a sample at a time, so the histograms and
//! the yield fill in), and opening a sample as the scene (one undo step).
//! The data they work on is in tolerance_state.rs.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{TryRecvError, channel};
use std::time::Instant;

use lucerna_design::Target;
use lucerna_tolerance::analysis::{Budget, Settings, Setup, Stopped, Streams};
use lucerna_tolerance::report::Report;

use crate::state::EditorState;
use crate::tolerance_state::{Message, ToleranceOutcome, ToleranceRun};

impl EditorState {
    /// Whether a tolerance analysis runs.
    pub fn is_analysing_tolerances(&self) -> bool {
        self.tolerance.is_running()
    }

    /// The samples of the running or last tolerance analysis, and how
    /// many of them meet every term.
    pub fn tolerance_samples(&self) -> (usize, usize) {
        let records = self.tolerance.records();
        (records.len(), records.iter().filter(|r| r.passes()).count())
    }

    /// Starts an analysis of the current scene as the pane set it up; a
    /// refusal is shown in the pane and nothing changes.
    pub(crate) fn start_tolerance(&mut self) {
        if self.tolerance.is_running() {
            return;
        }
        match self.begin_tolerance() {
            Ok(run) => {
                self.tolerance.run = Some(run);
                self.tolerance.error = None;
                self.tolerance.outcome = None;
            }
            Err(why) => self.tolerance.error = Some(why),
        }
    }

    fn begin_tolerance(&mut self) -> Result<ToleranceRun, String> {
        let scene = self.doc.scene.clone().ok_or("no scene to analyse")?;
        if !self.doc.problems.is_empty() {
            return Err("the scene is invalid: fix it first (the scene panel lists why)".into());
        }
        if self.design.is_running() {
            return Err("a design is running: the scene is its until it ends".into());
        }
        let setup = &self.tolerance.setup;
        if setup.samples == 0 || setup.photons == 0 {
            return Err("samples and photons must be at least 1".into());
        }
        let text = setup.to_toml();
        if text.is_empty() {
            return Err("set a tolerance first: select a part or an emitter and give its σ".into());
        }
        let tolerances = lucerna_tolerance::tolerances::parse(&text, &scene)
            .map_err(|(_, field, why)| format!("{field}: {why}"))?;
        let spec = self
            .design
            .setup
            .spec
            .spec()
            .map_err(|why| format!("the spec (Design pane): {why}"))?;
        let settings = Settings {
            seed: setup.seed,
            photons: setup.photons,
            resolution: lucerna_tolerance::analysis::Settings::default().resolution,
            streams: Streams::Common,
            noise_runs: 4,
        };
        let analysis = Arc::new(
            Setup::new(
                scene,
                &self.scene_dir(),
                Target::Spec(spec),
                None,
                tolerances,
                settings,
            )
            .map_err(|e| crate::error_text::error_chain(&e))?,
        );
        let samples = setup.samples;
        let interrupt = Arc::new(AtomicBool::new(false));
        let (send, messages) = channel();
        let ctx = self.ctx.clone();
        let stop = interrupt.clone();
        let worker = analysis.clone();
        std::thread::Builder::new()
            .name("tolerance".to_owned())
            .spawn(move || {
                let repaint = || {
                    if let Some(ctx) = &ctx {
                        ctx.request_repaint();
                    }
                };
                let reference = worker
                    .reference()
                    .map(Box::new)
                    .map_err(|e| crate::error_text::error_chain(&e));
                let failed = reference.is_err();
                let _ = send.send(Message::Reference(reference));
                repaint();
                if failed {
                    return;
                }
                let budget = Budget {
                    samples: Some(samples),
                    ..Budget::default()
                };
                let (_, stopped) = worker.run(0..samples, &budget, &stop, &mut |_, record| {
                    let _ = send.send(Message::Sample(Box::new(record.clone())));
                    repaint();
                });
                let _ = send.send(Message::Done(stopped));
                repaint();
            })
            .map_err(|e| format!("cannot start the analysis: {e}"))?;
        Ok(ToleranceRun {
            interrupt,
            messages,
            setup: analysis,
            began: Instant::now(),
            reference: None,
            records: Vec::new(),
            stopping: false,
        })
    }

    /// Stop: the samples done are kept.
    pub(crate) fn stop_tolerance(&mut self) {
        if let Some(run) = &mut self.tolerance.run {
            run.interrupt.store(true, Ordering::Relaxed);
            run.stopping = true;
        }
    }

    /// Takes the analysis thread's news (each frame).
    pub(crate) fn poll_tolerance(&mut self) {
        let Some(run) = &mut self.tolerance.run else {
            return;
        };
        let mut done: Option<Stopped> = None;
        loop {
            match run.messages.try_recv() {
                Ok(Message::Reference(Ok(r))) => run.reference = Some(*r),
                Ok(Message::Reference(Err(why))) => {
                    self.tolerance.error = Some(why);
                    self.tolerance.run = None;
                    return;
                }
                Ok(Message::Sample(r)) => run.records.push(*r),
                Ok(Message::Done(stopped)) => {
                    done = Some(stopped);
                    break;
                }
                Err(TryRecvError::Empty) => break,
                Err(TryRecvError::Disconnected) => {
                    done = Some(Stopped::Interrupted);
                    break;
                }
            }
        }
        let Some(stopped) = done else { return };
        let Some(run) = self.tolerance.run.take() else {
            return;
        };
        let Some(reference) = run.reference else {
            self.tolerance.error = Some("the analysis stopped before its nominal".to_owned());
            return;
        };
        if run.records.is_empty() {
            self.tolerance.error = Some("stopped before the first sample".to_owned());
            return;
        }
        let report = Report::new(
            &run.setup,
            &reference,
            &run.records,
            stopped,
            run.began.elapsed().as_secs_f64(),
        );
        self.tolerance.outcome = Some(ToleranceOutcome {
            setup: run.setup,
            reference,
            records: run.records,
            report,
        });
    }

    /// Sample `index` of the analysis as the scene: one undo step back
    /// to the scene before.
    pub(crate) fn open_tolerance_sample(&mut self, index: u32) {
        let Some(setup) = self.tolerance.analysis().cloned() else {
            return;
        };
        let (Some(before), Ok(sample)) = (
            self.doc.scene.clone(),
            setup.model.scene(&setup.model.draw(index)),
        ) else {
            self.tolerance.error = Some(format!("sample {index} cannot be built"));
            return;
        };
        self.doc.replace_as_one_step(&before, sample);
        self.scene_changed();
    }
}
