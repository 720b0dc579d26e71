//! Native file dialogs (rfd: the desktop portal over D-Bus, zenity as its
//! fallback), each on its own thread so the window keeps drawing and the
//! simulation keeps running while one is open. The chosen path comes back
//! as a [`Command`]. Where the desktop has no dialog (a bare X server, CI)
//! and in tests, which never open one, a path prompt in the window takes
//! its place, so a file can always be opened and saved.

use std::path::{Path, PathBuf};
use std::sync::mpsc::{Receiver, TryRecvError, channel};
use std::time::{Duration, Instant};

use crate::command::{Command, DialogKind};

/// The dialog open now, if any (one at a time).
#[derive(Debug, Default)]
pub(crate) struct Dialogs {
    running: Option<Running>,
    /// The in-window prompt, where no native dialog opens.
    prompt: Option<PathPrompt>,
    /// Try the desktop's dialogs first.
    native: bool,
}

/// A path typed into the window instead of a native dialog.
#[derive(Debug, Clone, PartialEq)]
struct PathPrompt {
    kind: DialogKind,
    text: String,
    /// Why there is no native dialog, shown above the field.
    why: Option<String>,
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
        DialogKind::RayFileEmitter => "Ray file",
        DialogKind::ExportFolder => "Output folder",
        DialogKind::DesignTarget => "Target file",
    }
}

const UNAVAILABLE: &str =
    "no file dialog is available here (no desktop portal on D-Bus, no zenity): type the path";

/// The prompt's title and confirming button.
fn prompt_words(kind: DialogKind) -> (&'static str, &'static str) {
    match kind {
        DialogKind::Open => ("Open a scene", "Open"),
        DialogKind::SaveAs => ("Save the scene as", "Save"),
        DialogKind::ImportMesh => ("Import an OBJ mesh", "Import"),
        DialogKind::RayFileEmitter => ("Add a ray-file emitter", "Add"),
        DialogKind::ExportFolder => ("Choose the export folder", "Choose"),
        DialogKind::DesignTarget => ("Choose the design's target", "Choose"),
    }
}

fn command_for(kind: DialogKind, path: PathBuf) -> Command {
    match kind {
        DialogKind::Open => Command::Open(path),
        DialogKind::SaveAs => Command::SaveAs(path),
        DialogKind::ImportMesh => Command::ImportMesh(path),
        DialogKind::RayFileEmitter => Command::AddRayFileEmitter(path),
        DialogKind::ExportFolder => Command::SetExportFolder(path),
        DialogKind::DesignTarget => Command::SetDesignTarget(path),
    }
}

/// True where rfd has something to talk to: a D-Bus session (for the
/// portal) or zenity on the PATH.
fn dialogs_possible() -> bool {
    let zenity = std::env::var_os("PATH")
        .is_some_and(|path| std::env::split_paths(&path).any(|dir| dir.join("zenity").is_file()));
    zenity || std::env::var_os("DBUS_SESSION_BUS_ADDRESS").is_some()
}

impl Dialogs {
    /// Native dialogs where `native` and the desktop has them, else the
    /// prompt.
    pub fn new(native: bool) -> Dialogs {
        Dialogs {
            native,
            ..Dialogs::default()
        }
    }

    pub fn is_open(&self) -> bool {
        self.running.is_some() || self.prompt.is_some()
    }

    fn open_prompt(&mut self, kind: DialogKind, start: String, why: Option<String>) {
        self.prompt = Some(PathPrompt {
            kind,
            text: start,
            why,
        });
    }

    /// Draws the in-window prompt if one is open; the command its answer
    /// asks for.
    pub fn prompt_ui(&mut self, ctx: &egui::Context) -> Option<Command> {
        let prompt = self.prompt.as_mut()?;
        let (title, confirm) = prompt_words(prompt.kind);
        let mut answer: Option<Option<PathBuf>> = None;
        egui::Window::new(title)
            .collapsible(false)
            .resizable(false)
            .show(ctx, |ui| {
                if let Some(why) = &prompt.why {
                    ui.label(why);
                }
                let field = crate::widgets::labelled(ui, field_for(prompt.kind), |ui| {
                    ui.add(egui::TextEdit::singleline(&mut prompt.text).desired_width(420.0))
                });
                let entered = field.lost_focus() && ui.input(|i| i.key_pressed(egui::Key::Enter));
                ui.horizontal(|ui| {
                    if (ui.button(confirm).clicked() || entered) && !prompt.text.trim().is_empty() {
                        answer = Some(Some(PathBuf::from(prompt.text.trim())));
                    }
                    if ui.button("Cancel").clicked() {
                        answer = Some(None);
                    }
                });
            });
        let answer = answer?;
        let kind = self.prompt.take()?.kind;
        answer.map(|path| command_for(kind, path))
    }

    /// Starts a dialog in `start_dir`; `Err` is a message for the user.
    pub fn start(
        &mut self,
        kind: DialogKind,
        start_dir: &Path,
        file_name: Option<String>,
        ctx: Option<egui::Context>,
    ) -> Result<(), String> {
        if self.is_open() {
            return Err("a file dialog is already open".to_owned());
        }
        let start = match &file_name {
            Some(name) => start_dir.join(name),
            None => start_dir.to_path_buf(),
        };
        if !self.native || !dialogs_possible() {
            let why = self.native.then(|| UNAVAILABLE.to_owned());
            self.open_prompt(kind, start.display().to_string(), why);
            return Ok(());
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
            DialogKind::RayFileEmitter => dialog
                .set_title("Add a ray-file emitter")
                .add_filter("IES TM-25 ray file", &["tm25ray", "TM25RAY"]),
            DialogKind::ExportFolder => dialog.set_title("Choose the export folder"),
            DialogKind::DesignTarget => dialog
                .set_title("Choose the design's target")
                .add_filter("IES or EULUMDAT", &["ies", "IES", "ldt", "LDT"]),
        };
        if let Some(name) = file_name {
            dialog = dialog.set_file_name(name);
        }
        std::thread::Builder::new()
            .name("file dialog".to_owned())
            .spawn(move || {
                let path = match kind {
                    DialogKind::SaveAs => dialog.save_file(),
                    DialogKind::Open
                    | DialogKind::ImportMesh
                    | DialogKind::RayFileEmitter
                    | DialogKind::DesignTarget => dialog.pick_file(),
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

    /// The command a finished dialog asks for; `Err` is a message. A
    /// native dialog that could not be shown hands over to the prompt.
    pub fn poll(&mut self) -> Option<Result<Command, String>> {
        let running = self.running.as_ref()?;
        let (kind, started) = (running.kind, running.started);
        let result = match running.chosen.try_recv() {
            Err(TryRecvError::Empty) => return None,
            Ok(Some(path)) => Ok(command_for(kind, path)),
            // rfd answers "cancelled" also when no dialog could be shown;
            // one that closes at once most likely never appeared.
            Ok(None) if started.elapsed() < Duration::from_millis(300) => {
                self.running = None;
                self.open_prompt(kind, String::new(), Some(UNAVAILABLE.to_owned()));
                return None;
            }
            Ok(None) => {
                self.running = None;
                return None;
            }
            // The dialog's thread panicked.
            Err(TryRecvError::Disconnected) => {
                self.running = None;
                self.open_prompt(kind, String::new(), Some(UNAVAILABLE.to_owned()));
                return None;
            }
        };
        self.running = None;
        Some(result)
    }
}
