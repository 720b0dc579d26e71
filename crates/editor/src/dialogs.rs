//! Native file dialogs (rfd: the desktop portal over D-Bus, zenity as its
//! fallback), each on its own thread so the window keeps drawing and the
//! simulation keeps running while one is open. The chosen path comes back
//! as a [`Command`]. Only the "…" buttons start a dialog; the path fields
//! beside them do the same without one (and are what tests use).

use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, TryRecvError, channel};
use std::time::{Duration, Instant};

use crate::state::Command;

/// What a dialog chooses a path for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DialogKind {
    Open,
    SaveAs,
    ImportMesh,
    /// The export dialog's output folder.
    ExportFolder,
}

/// The dialog open now, if any (one at a time).
#[derive(Debug, Default)]
pub(crate) struct Dialogs {
    running: Option<Running>,
}

#[derive(Debug)]
struct Running {
    kind: DialogKind,
    started: Instant,
    chosen: Receiver<Option<PathBuf>>,
}

/// Where to type a path instead, for the messages below.
fn field_for(kind: DialogKind) -> &'static str {
    match kind {
        DialogKind::Open => "Scene file",
        DialogKind::SaveAs => "Save as path",
        DialogKind::ImportMesh => "OBJ file",
        DialogKind::ExportFolder => "Output folder",
    }
}

fn unavailable(kind: DialogKind) -> String {
    format!(
        "no file dialog is available here (no desktop portal on D-Bus, no zenity): \
         type the path into the \"{}\" field instead",
        field_for(kind)
    )
}

/// True where rfd has something to talk to: a D-Bus session (for the
/// portal) or zenity on the PATH.
fn dialogs_possible() -> bool {
    let zenity = std::env::var_os("PATH")
        .is_some_and(|path| std::env::split_paths(&path).any(|dir| dir.join("zenity").is_file()));
    zenity || std::env::var_os("DBUS_SESSION_BUS_ADDRESS").is_some()
}

impl Dialogs {
    pub fn is_open(&self) -> bool {
        self.running.is_some()
    }

    /// Starts a dialog in `start_dir`; `Err` is a message for the user.
    pub fn start(
        &mut self,
        kind: DialogKind,
        start_dir: &Path,
        file_name: Option<String>,
        ctx: Option<egui::Context>,
    ) -> Result<(), String> {
        if self.running.is_some() {
            return Err("a file dialog is already open".to_owned());
        }
        if !dialogs_possible() {
            return Err(unavailable(kind));
        }
        let (send, chosen) = channel();
        let mut dialog = rfd::FileDialog::new().set_directory(start_dir);
        dialog = match kind {
            DialogKind::Open => dialog
                .set_title("Open a scene")
                .add_filter("Lucerna scene", &["toml"]),
            DialogKind::SaveAs => dialog
                .set_title("Save the scene as")
                .add_filter("Lucerna scene", &["toml"]),
            DialogKind::ImportMesh => dialog
                .set_title("Import an OBJ mesh")
                .add_filter("Wavefront OBJ", &["obj"]),
            DialogKind::ExportFolder => dialog.set_title("Choose the export folder"),
        };
        if let Some(name) = file_name {
            dialog = dialog.set_file_name(name);
        }
        std::thread::Builder::new()
            .name("file dialog".to_owned())
            .spawn(move || {
                let path = match kind {
                    DialogKind::SaveAs => dialog.save_file(),
                    DialogKind::Open | DialogKind::ImportMesh => dialog.pick_file(),
                    DialogKind::ExportFolder => dialog.pick_folder(),
                };
                // The editor may have closed meanwhile.
                let _ = send.send(path);
                if let Some(ctx) = ctx {
                    ctx.request_repaint();
                }
            })
            .map_err(|e| format!("cannot start the file dialog: {e}"))?;
        self.running = Some(Running {
            kind,
            started: Instant::now(),
            chosen,
        });
        Ok(())
    }

    /// The command a finished dialog asks for; `Err` is a message.
    pub fn poll(&mut self) -> Option<Result<Command, String>> {
        let running = self.running.as_ref()?;
        let result = match running.chosen.try_recv() {
            Err(TryRecvError::Empty) => return None,
            Ok(Some(path)) => Ok(match running.kind {
                DialogKind::Open => Command::Open(path),
                DialogKind::SaveAs => Command::SaveAs(path),
                DialogKind::ImportMesh => Command::ImportMesh(path),
                DialogKind::ExportFolder => Command::SetExportFolder(path),
            }),
            // rfd answers "cancelled" also when no dialog could be shown;
            // one that closes at once most likely never appeared.
            Ok(None) if running.started.elapsed() < Duration::from_millis(300) => {
                Err(unavailable(running.kind))
            }
            Ok(None) => {
                self.running = None;
                return None;
            }
            // The dialog's thread panicked.
            Err(TryRecvError::Disconnected) => Err(unavailable(running.kind)),
        };
        self.running = None;
        Some(result)
    }
}
