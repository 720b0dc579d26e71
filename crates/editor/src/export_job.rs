//! An export on its own thread, and the snapshot it may export: the
//! export dialog starts one and shows its stage; the window never waits.

use std::path::PathBuf;
use std::sync::mpsc::{Receiver, TryRecvError, channel};
use std::sync::{Arc, Mutex, PoisonError};
use std::time::Instant;

use lucerna_simulation::{ExportRequest, ExportStage, Snapshot};

use crate::error_text::error_chain;
use crate::state::EditorState;

/// An export on its own thread: its stage as it goes, its result at the
/// end.
#[derive(Debug)]
pub struct ExportJob {
    pub(crate) started: Instant,
    stage: Arc<Mutex<ExportStage>>,
    done: Receiver<Result<Vec<PathBuf>, String>>,
}

impl ExportJob {
    /// Starts writing `request` of `snapshot`; `repaint` is called at each
    /// stage and at the end.
    pub(crate) fn start(
        request: ExportRequest,
        snapshot: Arc<Snapshot>,
        repaint: impl Fn() + Send + 'static,
    ) -> Result<ExportJob, String> {
        let stage = Arc::new(Mutex::new(ExportStage::Tabulating));
        let (send, done) = channel();
        let reported = stage.clone();
        std::thread::Builder::new()
            .name("lucerna-export".to_owned())
            .spawn(move || {
                let report = |s: ExportStage| {
                    *reported.lock().unwrap_or_else(PoisonError::into_inner) = s;
                    repaint();
                };
                let result = request
                    .write_reporting(&snapshot, &report)
                    .map_err(|e| error_chain(&e));
                let _ = send.send(result);
                repaint();
            })
            .map_err(|e| format!("cannot start the export: {e}"))?;
        Ok(ExportJob {
            started: Instant::now(),
            stage,
            done,
        })
    }

    pub(crate) fn stage(&self) -> ExportStage {
        *self.stage.lock().unwrap_or_else(PoisonError::into_inner)
    }

    /// The result, once the job has ended.
    pub(crate) fn finished(&self) -> Option<Result<Vec<PathBuf>, String>> {
        match self.done.try_recv() {
            Ok(result) => Some(result),
            Err(TryRecvError::Empty) => None,
            Err(TryRecvError::Disconnected) => {
                Some(Err("the export stopped without a result".to_owned()))
            }
        }
    }
}

/// The snapshot to export, if it shows the scene as edited now.
pub(crate) fn current_snapshot(state: &EditorState) -> Result<&Arc<Snapshot>, String> {
    if !state.problems().is_empty() {
        return Err(
            "the scene has problems (see the scene panel); the result shown is of an earlier version"
                .to_owned(),
        );
    }
    let snapshot = state
        .snapshot()
        .ok_or("nothing has been traced yet".to_owned())?;
    let current = state
        .simulation()
        .is_some_and(|sim| sim.generation() == snapshot.generation);
    if !current || state.is_coarse_preview() {
        return Err(
            "the simulation is restarting after an edit: export once it shows the current scene"
                .to_owned(),
        );
    }
    if snapshot.photons == 0 || snapshot.map.photons_escaped() == 0 {
        return Err("no photon has left the luminaire yet".to_owned());
    }
    Ok(snapshot)
}
