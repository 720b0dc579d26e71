//! The design commands on the editor's state: Start (the pane's setup
//! checked, `lucerna design`'s library started on a thread of its own),
//! Stop, and each frame's news from that thread — a better candidate
//! shown as the scene, the end one undo step (the data they work on is
//! in design_state.rs).

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{TryRecvError, channel};
use std::time::{Duration, Instant};

use lucerna_design::{
    Budget, DEFAULT_RESOLUTION, Design, DesignError, DesignRequest, StartScene, Target,
};

use crate::design_state::{DesignOutcome, DesignRun, MeritPoint, Message, SHOW_EVERY};
use crate::state::EditorState;

impl EditorState {
    /// Whether a design runs (the scene is its until it ends).
    pub fn is_designing(&self) -> bool {
        self.design.is_running()
    }

    /// Where the design stands, for the status bar.
    pub fn design_status(&self) -> Option<String> {
        if let Some(run) = &self.design.run {
            return Some(match &run.latest {
                Some(p) => format!(
                    "Designing ({}): best {:.4}{}",
                    p.phase.name(),
                    p.best_merit,
                    if p.photons == 0 { " in the model" } else { "" }
                ),
                None => "Designing: what the geometry can reach".to_owned(),
            });
        }
        let o = self.design.outcome.as_ref()?;
        (self.doc.scene.as_ref() == Some(&o.scene)).then(|| match o.target {
            Target::Distribution { .. } => {
                format!(
                    "Designed: remaining difference {:.4} ± {:.4}",
                    o.merit, o.noise
                )
            }
            Target::Spec(_) => format!("Designed: spec merit {:.4}", o.merit),
        })
    }

    /// The last design's scene file as `lucerna design` writes it
    /// (`STEM.toml`), once a design has ended.
    pub fn designed_scene_text(&self) -> Option<&str> {
        self.design.outcome.as_ref().map(|o| o.scene_text.as_str())
    }

    /// Starts a design of the current scene as the pane set it up; a
    /// refusal is shown in the pane and nothing changes.
    pub(crate) fn start_design(&mut self) {
        if self.design.is_running() {
            return;
        }
        match self.begin_design() {
            Ok(run) => {
                // The varied part is shown (its parameters in the scene
                // panel, its profile in the Profile pane) as it changes.
                if let Some(part) = run.variables.iter().find_map(|v| v.place.part()) {
                    self.doc.selection = Some(crate::command::Selection::Part(part));
                }
                self.design.run = Some(run);
                self.design.error = None;
                self.design.outcome = None;
            }
            Err(why) => self.design.error = Some(why),
        }
    }

    fn begin_design(&mut self) -> Result<DesignRun, String> {
        let scene = self.doc.scene.clone().ok_or("no scene to design")?;
        if !self.doc.problems.is_empty() {
            return Err("the scene is invalid: fix it first (the scene panel lists why)".into());
        }
        if self.design.setup.vary.is_empty() {
            return Err(
                "tick what may change: a parameter in the scene panel or a point in the Profile pane"
                    .into(),
            );
        }
        if !(self.design.setup.time_s.is_finite() && self.design.setup.time_s > 0.0) {
            return Err("the time for a design must be positive".into());
        }
        let target = self.design.setup.target()?;
        let variables = lucerna_design::variables::parse(&scene, &self.design.setup.vary, false)
            .map_err(|e| e.to_string())?;
        let dir = self.scene_dir();
        let path = self.files.path.clone();
        // The file's own text where it holds this scene, so the designed
        // file keeps its comments as `lucerna design` keeps them.
        let file_text = path.as_ref().and_then(|p| {
            let text = std::fs::read_to_string(p).ok()?;
            (lucerna_scene::parse_scene(&text, p).ok()? == scene).then_some(text)
        });
        let text = match file_text {
            Some(t) => t,
            None => lucerna_scene::scene_to_toml(&scene)
                .map_err(|e| format!("the scene cannot be written as a file: {e}"))?,
        };
        let target_name = match &target {
            Target::Distribution { name, .. } => name.clone(),
            Target::Spec(_) => "the spec".to_owned(),
        };
        let request = DesignRequest {
            scene_path: path.unwrap_or_else(|| dir.join("unsaved scene.toml")),
            target,
            vary: self.design.setup.vary.clone(),
            free_ends: false,
            budget: Budget {
                time: Duration::from_secs_f64(self.design.setup.time_s),
                evaluations: self.design.setup.evaluations,
                max_photons: None,
            },
            seed: self.design.setup.seed,
            resolution: DEFAULT_RESOLUTION,
            direct: true,
            least_squares: false,
            points: None,
            fallback: Default::default(),
        };
        let interrupt = Arc::new(AtomicBool::new(false));
        let (send, messages) = channel();
        let start = StartScene {
            scene: scene.clone(),
            text,
            dir,
        };
        let ctx = self.ctx.clone();
        let stop = interrupt.clone();
        std::thread::Builder::new()
            .name("design".to_owned())
            .spawn(move || {
                let repaint = || {
                    if let Some(ctx) = &ctx {
                        ctx.request_repaint();
                    }
                };
                let result = lucerna_design::design_scene(start, &request, &stop, &mut |p| {
                    let _ = send.send(Message::Progress(Box::new(p.clone())));
                    repaint();
                });
                let _ = send.send(Message::Done(Box::new(result)));
                repaint();
            })
            .map_err(|e| format!("cannot start the design: {e}"))?;
        Ok(DesignRun {
            interrupt,
            messages,
            start: scene,
            variables,
            target_name,
            began: Instant::now(),
            history: Vec::new(),
            latest: None,
            reach: None,
            shown: None,
            stopping: false,
        })
    }

    /// Stop: the design ends with the best it found so far.
    pub(crate) fn stop_design(&mut self) {
        if let Some(run) = &mut self.design.run {
            run.interrupt.store(true, Ordering::Relaxed);
            run.stopping = true;
        }
    }

    /// Takes the design thread's news (each frame, before the panels):
    /// a better candidate becomes the scene shown; the end, one undo step.
    pub(crate) fn poll_design(&mut self) {
        let Some(run) = &mut self.design.run else {
            return;
        };
        let mut done = None;
        loop {
            match run.messages.try_recv() {
                Ok(Message::Progress(p)) => {
                    if let Some(merit) = p.record.merit {
                        run.history.push(MeritPoint {
                            elapsed_s: p.elapsed.as_secs_f64(),
                            merit,
                            best: p.best_merit,
                            noise: p.noise,
                            stage: p.stage,
                            photons: p.photons,
                            phase: p.phase,
                        });
                    }
                    if p.reach.is_some() {
                        run.reach.clone_from(&p.reach);
                    }
                    run.latest = Some(*p);
                }
                Ok(Message::Done(result)) => {
                    done = Some(*result);
                    break;
                }
                Err(TryRecvError::Empty) => break,
                Err(TryRecvError::Disconnected) => {
                    done = Some(Err(DesignError::Output(
                        "the design stopped without an answer".to_owned(),
                    )));
                    break;
                }
            }
        }
        if let Some(result) = done {
            self.finish_design(result);
            return;
        }
        // The best so far, shown when it changed (at most every
        // SHOW_EVERY: each restarts the live run).
        // In every phase, the model's candidates too: the profile moves
        // from the first seconds.
        let Some(latest) = &run.latest else { return };
        let values = &latest.best_values;
        let due = run
            .shown
            .as_ref()
            .is_none_or(|(v, at)| v != values && at.elapsed() >= SHOW_EVERY);
        if !due {
            return;
        }
        let Some(scene) = latest.frame.scene(values) else {
            return;
        };
        run.shown = Some((values.clone(), Instant::now()));
        self.doc.scene = Some(scene);
        self.scene_changed();
    }

    fn finish_design(&mut self, result: Result<Design, DesignError>) {
        let Some(run) = self.design.run.take() else {
            return;
        };
        match result {
            Ok(design) => {
                let scene_text = lucerna_design::output::scene_text(&design);
                let outcome = DesignOutcome {
                    stopped: design.found.stopped,
                    evaluations: design
                        .found
                        .history
                        .iter()
                        .filter(|r| r.photons > 0)
                        .count(),
                    seconds: run.began.elapsed().as_secs_f64(),
                    start_merit: design.start_merit,
                    merit: design.found.merit,
                    noise: design.found.noise,
                    photons: design.found.photons,
                    variables: design.changes(),
                    history: run.history,
                    reach: design.reach.clone(),
                    survey: design.survey.clone(),
                    points: design.points,
                    scene: design.scene.clone(),
                    scene_text: scene_text.unwrap_or_default(),
                    target: design.aim.target().clone(),
                };
                self.doc.replace_as_one_step(&run.start, design.scene);
                self.design.outcome = Some(outcome);
                self.files.autosave_now = true;
            }
            Err(e) => {
                // Back to the start, as if nothing ran.
                self.doc.scene = Some(run.start);
                self.design.error = Some(crate::error_text::error_chain(&e));
            }
        }
        self.scene_changed();
    }
}
