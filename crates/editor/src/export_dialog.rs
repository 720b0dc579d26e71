//! The export dialog: IES (LM-63-2019 or 2002), EULUMDAT, the map's EXR
//! and PNGs, with the keywords, grid, symmetry and raw or filtered choice;
//! the files are those `lucerna bake` writes for the same settings, since
//! both write through `lucerna_simulation::ExportRequest`.
//!
//! The keywords are fields of the scene (its name, manufacturer and
//! `[export]` section), edited in place like any panel's: each edit is an
//! undo step, saved with the scene, and never restarts the run.
//!
//! An export runs on its own thread ([`ExportJob`]): with the automatic
//! filter it chooses its rule afresh (about a second at 256²), which in
//! the dialog's frame froze the window. The dialog shows its stage and
//! time meanwhile, and the result when it ends.

use std::path::{Path, PathBuf};
use std::time::Duration;

use egui::Ui;
use lucerna_photometry::{CPlaneSymmetry, IesVersion};
use lucerna_simulation::{
    ExportFormats, ExportOptions, ExportRequest, FilterChoice, Labels, TableGrid,
};

use crate::command::DialogKind;
use crate::export_job::{ExportJob, current_snapshot};
use crate::state::{Command, EditorState};
use crate::widgets::{flag, labelled, length_mm, number};

/// The usual γ steps of datasheet files (degrees); `None` is the
/// automatic grid (2.5° refined until the table holds the flux).
const GAMMA_STEPS_DEG: [Option<f64>; 4] = [None, Some(1.0), Some(2.5), Some(5.0)];
/// The usual C-plane steps (degrees).
const C_STEPS_DEG: [f64; 3] = [5.0, 15.0, 22.5];

/// The symmetry the files declare.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
enum Declared {
    /// What the photons were pooled over, found in the geometry.
    #[default]
    Automatic,
    Imposed(CPlaneSymmetry),
}

impl Declared {
    const ALL: [Declared; 6] = [
        Declared::Automatic,
        Declared::Imposed(CPlaneSymmetry::None),
        Declared::Imposed(CPlaneSymmetry::AboutC0C180),
        Declared::Imposed(CPlaneSymmetry::AboutC90C270),
        Declared::Imposed(CPlaneSymmetry::Quadrant),
        Declared::Imposed(CPlaneSymmetry::Rotational),
    ];

    fn name(self) -> &'static str {
        match self {
            Declared::Automatic => "Automatic (as detected)",
            Declared::Imposed(CPlaneSymmetry::None) => "None (C0-C360)",
            Declared::Imposed(CPlaneSymmetry::AboutC0C180) => "C0-C180 mirror",
            Declared::Imposed(CPlaneSymmetry::AboutC90C270) => "C90-C270 mirror",
            Declared::Imposed(CPlaneSymmetry::Quadrant) => "Both planes (quadrant)",
            Declared::Imposed(CPlaneSymmetry::Rotational) => "Full rotational",
        }
    }

    fn imposed(self) -> Option<CPlaneSymmetry> {
        match self {
            Declared::Automatic => None,
            Declared::Imposed(s) => Some(s),
        }
    }
}

/// The export dialog's own state while it is open (the keywords live in
/// the scene).
#[derive(Debug, Default)]
pub struct ExportDialog {
    pub open: bool,
    /// Filled from the scene and settings when the dialog opens.
    initialised: bool,
    ies: bool,
    ies_version: Option<IesVersion>,
    ldt: bool,
    exr: bool,
    cube_png: bool,
    polar_png: bool,
    /// The datasheet (HTML, PDF, JSON), and its UGR table at S/H = 1 too.
    datasheet: bool,
    ugr_standard_spacing: bool,
    /// Opened by "Datasheet…": only the datasheet is ticked.
    datasheet_only: bool,
    /// The TM-25 ray file of the rays leaving the luminaire, and how many.
    tm25: bool,
    rays: u32,
    filtered: bool,
    grid: Option<TableGrid>,
    declared: Declared,
    /// `[ISSUEDATE]` and EULUMDAT's date: today unless typed.
    date: String,
    folder: String,
    base_name: String,
    /// What the last export wrote, or why it failed.
    result: Option<Result<Vec<PathBuf>, String>>,
    /// The export running now.
    job: Option<ExportJob>,
}

impl ExportDialog {
    /// The defaults when the dialog opens: every file a bake writes, the
    /// simulation's filter and grid, the scene's folder and name.
    fn initialise(&mut self, state: &EditorState) {
        self.initialised = true;
        self.ies = true;
        self.ies_version = Some(IesVersion::Lm63_2019);
        self.ldt = true;
        self.exr = true;
        self.cube_png = true;
        self.polar_png = true;
        self.datasheet = false;
        self.tm25 = false;
        self.rays = lucerna_simulation::DEFAULT_TM25_RAYS;
        if std::mem::take(&mut self.datasheet_only) {
            self.ies = false;
            self.ldt = false;
            self.exr = false;
            self.cube_png = false;
            self.polar_png = false;
            self.datasheet = true;
        }
        self.filtered = state.settings().filter != FilterChoice::Raw;
        self.grid = Some(state.settings().table);
        self.date = chrono::Local::now().format("%Y-%m-%d").to_string();
        // Absolute: a relative folder is taken from the scene's (as its
        // other paths), so a scene opened by a relative path would have
        // written into assets/luminaires/assets/luminaires/.
        self.folder = std::path::absolute(state.scene_dir())
            .unwrap_or_else(|_| state.scene_dir().to_path_buf())
            .display()
            .to_string();
        self.base_name = state.path().and_then(Path::file_stem).map_or_else(
            || "luminaire".to_owned(),
            |s| s.to_string_lossy().into_owned(),
        );
        self.result = None;
    }

    /// Opens the dialog with only the datasheet ticked ("Datasheet…").
    pub(crate) fn open_for_datasheet(&mut self) {
        self.open = true;
        self.initialised = false;
        self.datasheet_only = true;
    }

    /// Whether an export is running now.
    pub(crate) fn is_exporting(&self) -> bool {
        self.job.is_some()
    }

    /// The frame benchmark's export (`--benchmark S --export`): the dialog
    /// opened on its defaults, the automatic filter (the heavy case: it
    /// cross-validates afresh), into `out_dir`, started as its Export
    /// button would. Whether one started (not while one runs, nor before
    /// the run shows the current scene).
    pub(crate) fn start_benchmark_export(
        &mut self,
        state: &EditorState,
        out_dir: &Path,
        ctx: &egui::Context,
    ) -> bool {
        if self.job.is_some() || current_snapshot(state).is_err() {
            return false;
        }
        if !self.open || !self.initialised {
            self.open = true;
            self.initialise(state);
        }
        self.filtered = true;
        self.folder = out_dir.display().to_string();
        let ctx = ctx.clone();
        match start_export(state, self, move || ctx.request_repaint()) {
            Ok(job) => {
                self.job = Some(job);
                self.result = None;
                true
            }
            Err(e) => {
                self.result = Some(Err(e));
                false
            }
        }
    }

    fn formats(&self) -> ExportFormats {
        ExportFormats {
            ies: self
                .ies
                .then_some(self.ies_version.unwrap_or(IesVersion::Lm63_2019)),
            ldt: self.ldt,
            exr: self.exr,
            cube_png: self.cube_png,
            polar_png: self.polar_png,
            datasheet: self.datasheet,
            tm25_rays: self.tm25.then_some(self.rays),
        }
    }
}

/// Draws the dialog as a window when it is open.
pub fn export_dialog_ui(ctx: &egui::Context, state: &mut EditorState, dialog: &mut ExportDialog) {
    if !dialog.open {
        dialog.initialised = false;
        return;
    }
    if !dialog.initialised {
        dialog.initialise(state);
    }
    let mut open = dialog.open;
    egui::Window::new("Export photometry")
        .open(&mut open)
        .default_pos([330.0, 60.0])
        .resizable(false)
        .show(ctx, |ui| {
            // On a 768-pixel screen the whole form is taller than the window.
            let room = (ctx.content_rect().height() - 140.0).max(200.0);
            egui::ScrollArea::vertical()
                .max_height(room)
                .min_scrolled_height(room)
                .show(ui, |ui| dialog_ui(ui, state, dialog));
        });
    dialog.open = open;
}

fn dialog_ui(ui: &mut Ui, state: &mut EditorState, dialog: &mut ExportDialog) {
    ui.strong("Files");
    ui.horizontal(|ui| {
        flag(ui, "IES", &mut dialog.ies);
        labelled(ui, "IES edition", |ui| {
            let name = |v: Option<IesVersion>| match v {
                Some(IesVersion::Lm63_2002) => "LM-63-2002",
                _ => "LM-63-2019",
            };
            egui::ComboBox::from_id_salt("ies edition")
                .selected_text(name(dialog.ies_version))
                .show_ui(ui, |ui| {
                    for v in [IesVersion::Lm63_2019, IesVersion::Lm63_2002] {
                        ui.selectable_value(&mut dialog.ies_version, Some(v), name(Some(v)));
                    }
                })
                .response
        });
        flag(ui, "EULUMDAT", &mut dialog.ldt);
    });
    ui.horizontal(|ui| {
        flag(ui, "EXR of the map", &mut dialog.exr);
        flag(ui, "Cube map PNG", &mut dialog.cube_png);
        flag(ui, "Polar diagram PNG", &mut dialog.polar_png);
    });
    ui.horizontal(|ui| {
        flag(ui, "Datasheet (HTML, PDF, JSON)", &mut dialog.datasheet).on_hover_text(
            "Luminaire data, polar, cartesian and isocandela diagrams, zonal lumens, luminance and the CIE 190 UGR table: what lucerna report writes",
        );
        ui.add_enabled_ui(dialog.datasheet, |ui| {
            flag(ui, "UGR also at S/H = 1", &mut dialog.ugr_standard_spacing)
                .on_hover_text("CIE 190's standard table beside the catalogue's S/H = 0.25");
        });
    });
    ui.horizontal(|ui| {
        flag(ui, "TM-25 ray file", &mut dialog.tm25).on_hover_text(
            "The rays leaving the luminaire (position of their last interaction in mm, direction, luminous flux): its near field for other optics tools",
        );
        ui.add_enabled_ui(dialog.tm25, |ui| {
            labelled(ui, "Rays", |ui| {
                ui.add(
                    egui::DragValue::new(&mut dialog.rays)
                        .range(1..=50_000_000)
                        .speed(10_000.0),
                )
            })
        });
    });

    ui.separator();
    ui.strong("Table");
    let grid = dialog.grid.get_or_insert(state.settings().table);
    ui.horizontal(|ui| {
        labelled(ui, "Map", |ui| {
            let name = |f: bool| if f { "Filtered" } else { "Raw" };
            egui::ComboBox::from_id_salt("export map")
                .selected_text(name(dialog.filtered))
                .show_ui(ui, |ui| {
                    for f in [false, true] {
                        ui.selectable_value(&mut dialog.filtered, f, name(f));
                    }
                })
                .response
                .on_hover_text(
                    "Filtered: the simulation's filter, or the automatic rule when it runs raw",
                )
        });
        labelled(ui, "γ step", |ui| {
            let name =
                |s: Option<f64>| s.map_or_else(|| "Automatic".to_owned(), |s| format!("{s}°"));
            egui::ComboBox::from_id_salt("export gamma step")
                .selected_text(name(grid.gamma_step_deg))
                .show_ui(ui, |ui| {
                    for s in GAMMA_STEPS_DEG {
                        ui.selectable_value(&mut grid.gamma_step_deg, s, name(s));
                    }
                })
                .response
        });
        labelled(ui, "C step", |ui| {
            egui::ComboBox::from_id_salt("export c step")
                .selected_text(format!("{}°", grid.c_step_deg))
                .show_ui(ui, |ui| {
                    for s in C_STEPS_DEG {
                        ui.selectable_value(&mut grid.c_step_deg, s, format!("{s}°"));
                    }
                })
                .response
        });
    });
    let detected = state
        .snapshot()
        .map(|s| s.pooled_file_symmetry().describe());
    labelled(ui, "Symmetry", |ui| {
        egui::ComboBox::from_id_salt("export symmetry")
            .selected_text(dialog.declared.name())
            .show_ui(ui, |ui| {
                for d in Declared::ALL {
                    ui.selectable_value(&mut dialog.declared, d, d.name());
                }
            })
            .response
            .on_hover_text(format!(
                "The table is averaged over the symmetry declared. Detected: {}",
                detected.unwrap_or("not yet known")
            ))
    });

    ui.separator();
    ui.strong("Keywords (saved in the scene)");
    keywords_ui(ui, state);

    ui.separator();
    ui.strong("Output");
    text_field(ui, "Issue date", &mut dialog.date, "");
    if let Some(chosen) = state.chosen_export_folder.take() {
        dialog.folder = chosen.display().to_string();
    }
    ui.horizontal(|ui| {
        text_field(ui, "Output folder", &mut dialog.folder, "");
        if ui
            .add_enabled(
                !state.files.dialogs.is_open(),
                egui::Button::new("Choose folder…"),
            )
            .on_hover_text("Choose the folder in a dialog")
            .clicked()
        {
            state.push(Command::FileDialog(DialogKind::ExportFolder));
        }
    });
    text_field(ui, "Base name", &mut dialog.base_name, "");
    if let Some(result) = dialog.job.as_ref().and_then(ExportJob::finished) {
        dialog.job = None;
        dialog.result = Some(result);
    }
    if ui
        .add_enabled(dialog.job.is_none(), egui::Button::new("Export"))
        .on_hover_text("Write the chosen files, all or none")
        .clicked()
    {
        let ctx = ui.ctx().clone();
        match start_export(state, dialog, move || ctx.request_repaint()) {
            Ok(job) => {
                dialog.job = Some(job);
                dialog.result = None;
            }
            Err(e) => dialog.result = Some(Err(e)),
        }
    }
    if let Some(job) = &dialog.job {
        ui.horizontal(|ui| {
            ui.spinner();
            ui.label(format!(
                "Exporting: {} ({:.1} s)",
                job.stage(),
                job.started.elapsed().as_secs_f64()
            ));
        });
        // The elapsed time moves on between the job's own repaints.
        ui.ctx().request_repaint_after(Duration::from_millis(200));
    }
    crate::widgets::export_result_ui(ui, dialog.result.as_ref());
}

/// A single-line text field with a hint shown while it is empty.
fn text_field(ui: &mut Ui, label: &str, value: &mut String, hint: &str) {
    labelled(ui, label, |ui| {
        ui.add(
            egui::TextEdit::singleline(value)
                .hint_text(hint)
                .desired_width(260.0),
        )
    });
}

/// The scene's labels, edited in place: the frame's end makes each edit
/// an undo step, and the simulation goes on (`Scene::same_light`).
/// The luminous opening shown is the traced luminaire's, found once when
/// it was built (`Luminaire::luminous_opening`), not in a frame.
fn keywords_ui(ui: &mut Ui, state: &mut EditorState) {
    let opening = state
        .snapshot()
        .map(|s| describe_opening(s.luminaire.luminous_opening));
    let Some(scene) = state.doc.scene.as_mut() else {
        ui.label("No scene.");
        return;
    };
    let name = scene.name.clone();
    let k = &mut scene.export;
    egui::Grid::new("export keywords")
        .num_columns(1)
        .show(ui, |ui| {
            text_field(ui, "Manufacturer", &mut scene.manufacturer, "");
            ui.end_row();
            text_field(ui, "Luminaire name", &mut k.luminaire, &name);
            ui.end_row();
            text_field(ui, "Catalogue number", &mut k.catalogue_number, &name);
            ui.end_row();
            text_field(
                ui,
                "Test report",
                &mut k.test_report,
                "Lucerna simulation of …",
            );
            ui.end_row();
            text_field(ui, "Test lab", &mut k.test_lab, "Lucerna photon tracer");
            ui.end_row();
            text_field(ui, "Lamp", &mut k.lamp, "the emitters' names");
            ui.end_row();
            text_field(
                ui,
                "Lamp catalogue number",
                &mut k.lamp_catalogue_number,
                "",
            );
            ui.end_row();
            text_field(
                ui,
                "Colour temperature",
                &mut k.colour_temperature,
                "e.g. 3000 K",
            );
            ui.end_row();
            text_field(
                ui,
                "Colour rendering",
                &mut k.colour_rendering,
                "e.g. Ra 90",
            );
            ui.end_row();
            number(ui, "Input power", &mut k.input_watts, 0.0..=1e6, 0.1, " W");
            ui.end_row();
        });
    opening_ui(ui, scene);
    ui.label(format!(
        "Declared: {}",
        opening.unwrap_or_else(|| "known once the scene is traced".to_owned())
    ));
}

/// The scene's luminous opening, which the files declare and the preview
/// room lights through (so changing it restarts the run).
fn opening_ui(ui: &mut Ui, scene: &mut lucerna_scene::Scene) {
    use lucerna_scene::LuminousOpening as O;
    let kind = |o: &Option<O>| match o {
        None => "Footprint (default)",
        Some(O::Rectangle { .. }) => "Rectangle",
        Some(O::Disk { .. }) => "Disk",
        Some(O::PartAperture { .. }) => "Part aperture",
        Some(O::None) => "None (point source)",
    };
    let first_part = scene.parts.first().map(|p| p.name.clone());
    let mut chosen = kind(&scene.opening);
    labelled(ui, "Luminous opening", |ui| {
        egui::ComboBox::from_id_salt("export opening")
            .selected_text(chosen)
            .show_ui(ui, |ui| {
                for k in [
                    "Footprint (default)",
                    "Rectangle",
                    "Disk",
                    "Part aperture",
                    "None (point source)",
                ] {
                    ui.selectable_value(&mut chosen, k, k);
                }
            })
            .response
    });
    if chosen != kind(&scene.opening) {
        scene.opening = match chosen {
            "Rectangle" => Some(O::Rectangle {
                length_m: 0.1,
                width_m: 0.1,
                height_m: 0.0,
            }),
            "Disk" => Some(O::Disk {
                diameter_m: 0.1,
                height_m: 0.0,
            }),
            "Part aperture" => first_part.map(|part| O::PartAperture { part }),
            "None (point source)" => Some(O::None),
            _ => None,
        };
    }
    let part_names: Vec<String> = scene.parts.iter().map(|p| p.name.clone()).collect();
    match &mut scene.opening {
        Some(O::Rectangle {
            length_m,
            width_m,
            height_m,
        }) => {
            ui.horizontal(|ui| {
                length_mm(ui, "Opening length (C0-C180)", length_m, 50_000.0);
                length_mm(ui, "Opening width (C90-C270)", width_m, 50_000.0);
                length_mm(ui, "Opening height", height_m, 50_000.0);
            });
        }
        Some(O::Disk {
            diameter_m,
            height_m,
        }) => {
            ui.horizontal(|ui| {
                length_mm(ui, "Opening diameter", diameter_m, 50_000.0);
                length_mm(ui, "Opening height", height_m, 50_000.0);
            });
        }
        Some(O::PartAperture { part }) => {
            labelled(ui, "Aperture part", |ui| {
                egui::ComboBox::from_id_salt("export aperture part")
                    .selected_text(part.as_str())
                    .show_ui(ui, |ui| {
                        for name in &part_names {
                            ui.selectable_value(part, name.clone(), name);
                        }
                    })
                    .response
            });
        }
        Some(O::None) | None => {}
    }
}

fn describe_opening(d: lucerna_photometry::Dimensions) -> String {
    let mm = |m: f64| format!("{:.1}", m * 1000.0);
    if d.circular {
        format!("round, {} mm across", mm(d.length_m))
    } else if d.length_m == 0.0 && d.width_m == 0.0 {
        "none (a point source)".to_owned()
    } else {
        format!(
            "{} × {} mm (C0-C180 × C90-C270)",
            mm(d.length_m),
            mm(d.width_m)
        )
    }
}

/// Starts writing the chosen files of the current snapshot on their own
/// thread, or says why not.
fn start_export(
    state: &EditorState,
    dialog: &ExportDialog,
    repaint: impl Fn() + Send + 'static,
) -> Result<ExportJob, String> {
    let scene = state.scene().ok_or("no scene".to_owned())?;
    let snapshot = current_snapshot(state)?;
    let folder = dialog.folder.trim();
    if folder.is_empty() {
        return Err("type an output folder".to_owned());
    }
    // A relative folder is the scene's, as its other relative paths.
    let out_dir = state.scene_dir().join(folder);
    std::fs::create_dir_all(&out_dir)
        .map_err(|e| format!("cannot create the output folder {}: {e}", out_dir.display()))?;
    let run = &snapshot.settings;
    let filter = match (dialog.filtered, run.filter) {
        (false, _) => FilterChoice::Raw,
        (true, FilterChoice::Raw) => FilterChoice::Automatic,
        (true, chosen) => chosen,
    };
    let options = ExportOptions {
        symmetrise: dialog.declared.imposed(),
        date: dialog.date.trim().to_owned(),
        seed: run.seed,
        scene_file: state.path().and_then(Path::file_name).map_or_else(
            || "an unsaved scene".to_owned(),
            |n| n.to_string_lossy().into_owned(),
        ),
        labels: Some(Labels::of(scene)),
    };
    let mut request = ExportRequest::new(snapshot, options, &out_dir, dialog.base_name.trim());
    request.formats = dialog.formats();
    request.filter = filter;
    request.grid = dialog.grid.unwrap_or(run.table);
    if dialog.ugr_standard_spacing {
        request.datasheet.ugr_spacings = vec![0.25, 1.0];
    }
    ExportJob::start(request, snapshot.clone(), repaint)
}
