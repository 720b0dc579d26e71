//! From a snapshot to the photometric data set and files a bake writes:
//! the candela table with its declared symmetry and the metadata of a
//! simulation, then IES, LDT, EXR and PNGs, all written or none.
//! [`ExportRequest`] is the one home of an export: `lucerna bake` and the
//! editor's export dialog both write through it, so the same snapshot and
//! request give the same bytes.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use lucerna_photometry::fidelity::TableFidelity;
use lucerna_photometry::tabulate::TableResampler;
use lucerna_photometry::{
    CPlaneSymmetry, CandelaTable, Dimensions, Format, IesVersion, LampSet, Metadata, Photometry,
    TexelSymmetry, to_latin1, write_ies, write_ldt,
};
use lucerna_scene::{
    ExportKeywords, LuminousOpening, Scene, SurfaceKind, TessellatedScene, write_all_atomically,
};

use crate::run::{exported_candela, tabulate};
use crate::{FilterChoice, LiveFilter, RunState, SimulationError, Snapshot, StopReason, TableGrid};

/// What the files say the luminaire is: a scene's name, manufacturer and
/// `[export]` keywords. An editor passes its newest scene's, which may be
/// newer than the snapshot's: label edits never restart a run.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Labels {
    pub name: String,
    pub manufacturer: String,
    pub keywords: ExportKeywords,
}

impl Labels {
    pub fn of(scene: &Scene) -> Labels {
        Labels {
            name: scene.name.clone(),
            manufacturer: scene.manufacturer.clone(),
            keywords: scene.export.clone(),
        }
    }
}

/// How the files of a bake are labelled.
#[derive(Debug, Clone)]
pub struct ExportOptions {
    /// C-plane symmetry to impose on the table by averaging, even one the geometry
    /// lacks. `None` declares what the photons were pooled over (quadrant
    /// or one mirror plane, where the formats can say it), since a pooled
    /// table is exactly symmetric.
    pub symmetrise: Option<CPlaneSymmetry>,
    /// ISO date of the bake.
    pub date: String,
    pub seed: u32,
    /// The scene file's name, for the file-generation info.
    pub scene_file: String,
    /// The labels of the files; `None`: the snapshot's scene's.
    pub labels: Option<Labels>,
}

/// The x and y extent (m) of triangles `range` (all when `None`) seen
/// from below.
fn footprint(tessellated: &TessellatedScene, range: Option<std::ops::Range<usize>>) -> (f64, f64) {
    footprint_box(tessellated, range).map_or((0.0, 0.0), |(lo, hi)| (hi[0] - lo[0], hi[1] - lo[1]))
}

/// The x-y bounding box (m) of triangles `range` (all when `None`); None
/// without triangles.
fn footprint_box(
    tessellated: &TessellatedScene,
    range: Option<std::ops::Range<usize>>,
) -> Option<([f64; 2], [f64; 2])> {
    let mesh = &tessellated.mesh;
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for t in &mesh.triangles[range.unwrap_or(0..mesh.triangles.len())] {
        for &v in t {
            let p = mesh.positions[v as usize];
            for (k, x) in [f64::from(p.x), f64::from(p.y)].into_iter().enumerate() {
                lo[k] = lo[k].min(x);
                hi[k] = hi[k].max(x);
            }
        }
    }
    (lo[0] <= hi[0]).then_some((lo, hi))
}

/// Whether triangles `range` seen from below fill a disk: a square
/// footprint within 2 %, every vertex within 2 % of the inscribed circle
/// about its centre.
fn round_footprint(tessellated: &TessellatedScene, range: std::ops::Range<usize>) -> bool {
    let Some((lo, hi)) = footprint_box(tessellated, Some(range.clone())) else {
        return false;
    };
    let (length_m, width_m) = (hi[0] - lo[0], hi[1] - lo[1]);
    let size = length_m.max(width_m);
    if !(size > 0.0) || (length_m - width_m).abs() > ROUND_TOLERANCE * size {
        return false;
    }
    let mesh = &tessellated.mesh;
    let centre = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    let reach = mesh.triangles[range]
        .iter()
        .flatten()
        .map(|&v| {
            let p = mesh.positions[v as usize];
            (f64::from(p.x) - centre[0]).hypot(f64::from(p.y) - centre[1])
        })
        .fold(0.0, f64::max);
    reach <= (1.0 + ROUND_TOLERANCE) * 0.5 * size
}

/// How far from square and from round a round exit may be (a share).
const ROUND_TOLERANCE: f64 = 0.02;

/// The luminaire's dimensions the files declare: its footprint seen from
/// below, height 0.
pub fn luminaire_dimensions(tessellated: &TessellatedScene) -> Dimensions {
    let (length_m, width_m) = footprint(tessellated, None);
    Dimensions {
        length_m,
        width_m,
        height_m: 0.0,
        circular: false,
    }
}

/// The luminous opening the files declare: the scene's, or by default the
/// luminaire's footprint.
pub fn luminous_opening(scene: &Scene, tessellated: &TessellatedScene) -> Dimensions {
    let rectangle = |length_m, width_m, height_m| Dimensions {
        length_m,
        width_m,
        height_m,
        circular: false,
    };
    let disk = |diameter_m, height_m| Dimensions {
        length_m: diameter_m,
        width_m: 0.0,
        height_m,
        circular: true,
    };
    match &scene.opening {
        None => luminaire_dimensions(tessellated),
        Some(LuminousOpening::Rectangle {
            length_m,
            width_m,
            height_m,
        }) => rectangle(*length_m, *width_m, *height_m),
        Some(LuminousOpening::Disk {
            diameter_m,
            height_m,
        }) => disk(*diameter_m, *height_m),
        Some(LuminousOpening::None) => Dimensions::default(),
        Some(LuminousOpening::PartAperture { part }) => {
            let index = scene.parts.iter().position(|p| &p.name == part);
            let range = tessellated
                .surfaces
                .iter()
                .filter(|s| s.kind == SurfaceKind::Part && Some(s.index) == index)
                .map(|s| s.triangles.clone())
                .reduce(|a, b| a.start.min(b.start)..a.end.max(b.end));
            let range = range.unwrap_or(0..0);
            let (length_m, width_m) = footprint(tessellated, Some(range.clone()));
            // A round exit, whatever the part is made of (a generated
            // surface of revolution or an OBJ mesh): a square footprint
            // whose triangles all lie within its inscribed circle (a
            // square's corners reach √2 of it).
            let revolved = round_footprint(tessellated, range);
            if revolved {
                disk(length_m.max(width_m), 0.0)
            } else {
                rectangle(length_m, width_m, 0.0)
            }
        }
    }
}

/// Relative photometry of a snapshot: lamp lumens = emitter flux, the
/// snapshot's table (raw or filtered, pooled) with the symmetry declared.
pub fn photometry(snapshot: &Snapshot, options: &ExportOptions) -> Photometry {
    photometry_of(snapshot, &snapshot.table, options)
}

/// [`photometry`] of `table`, a table of the snapshot's map.
fn photometry_of(snapshot: &Snapshot, table: &CandelaTable, options: &ExportOptions) -> Photometry {
    let map = &snapshot.map;
    let scene = &snapshot.luminaire.scene;
    let tessellated = &snapshot.luminaire.tessellated;
    let labels = options.labels.clone().unwrap_or_else(|| Labels::of(scene));
    let keywords = &labels.keywords;
    let or = |given: &str, default: String| {
        if given.trim().is_empty() {
            default
        } else {
            given.to_owned()
        }
    };
    let declared = options
        .symmetrise
        .or(Some(snapshot.pooled_file_symmetry()).filter(|&s| s != CPlaneSymmetry::None));
    let (table, symmetry) = match declared {
        Some(s) => (table.symmetrised(s), s),
        None => (table.clone(), CPlaneSymmetry::None),
    };
    let version = env!("CARGO_PKG_VERSION");
    let mut extra_keywords = Vec::new();
    if !keywords.lamp_catalogue_number.trim().is_empty() {
        extra_keywords.push(("LAMPCAT".to_owned(), keywords.lamp_catalogue_number.clone()));
    }
    extra_keywords.push((
        "_SIMULATION".to_owned(),
        format!(
            "{} photons emitted, {} escaped, {} absorbed, {} cut off; LOR {:.4}",
            map.photons_emitted,
            map.photons_escaped(),
            map.photons_absorbed,
            map.photons_cut_off,
            map.light_output_ratio()
        ),
    ));
    let emitters = scene
        .emitters
        .iter()
        .filter(|e| e.enabled)
        .map(|e| e.name.as_str())
        .collect::<Vec<_>>()
        .join(" + ");
    Photometry {
        format: Format::Ies(2019),
        symmetry,
        table,
        meta: Metadata {
            manufacturer: labels.manufacturer.clone(),
            luminaire: or(&keywords.luminaire, labels.name.clone()),
            catalog_number: or(&keywords.catalogue_number, labels.name.clone()),
            test_report: or(
                &keywords.test_report,
                format!("Lucerna simulation of {}", options.scene_file),
            ),
            test_lab: or(
                &keywords.test_lab,
                "Lucerna photon tracer (computer simulation)".to_owned(),
            ),
            issue_date: options.date.clone(),
            file_generation_info: format!(
                "Lucerna {version}; scene {} ({}); {} photons; seed {}; {}",
                options.scene_file, labels.name, snapshot.photons, options.seed, options.date
            ),
            file_generation_type: Some(lucerna_photometry::ies::FILE_GENERATION_SIMULATION),
            keywords: extra_keywords,
            lamps: vec![LampSet {
                count: 1,
                kind: or(&keywords.lamp, emitters),
                flux_lm: map.emitter_flux_lm,
                colour_temperature: keywords.colour_temperature.clone(),
                colour_rendering: keywords.colour_rendering.clone(),
                watts: keywords.input_watts,
            }],
            absolute: false,
            ballast_factor: 1.0,
            input_watts: keywords.input_watts,
            luminous_area: luminous_opening(scene, tessellated),
            luminaire_dimensions: luminaire_dimensions(tessellated),
            ldt_type: None,
            declared_lor_percent: None,
            declared_downward_percent: None,
            tilt: None,
            warnings: Vec::new(),
        },
    }
}

/// Which files an export writes; by default every one a bake writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct ExportFormats {
    /// `STEM.ies` in this LM-63 edition.
    pub ies: Option<IesVersion>,
    /// `STEM.ldt` (EULUMDAT).
    pub ldt: bool,
    /// `STEM.exr`: the raw map with its photon counts.
    pub exr: bool,
    /// `STEM_cube.png`: the false-colour cube map.
    pub cube_png: bool,
    /// `STEM_polar.png`: the polar diagram.
    pub polar_png: bool,
    /// `STEM_datasheet.html`, `.pdf` and `.json`: the photometric
    /// datasheet of the exported table (`lucerna_datasheet`).
    pub datasheet: bool,
    /// `STEM.tm25ray` with this many rays leaving the luminaire: its
    /// near field for other optics tools (IES TM-25).
    pub tm25_rays: Option<u32>,
}

/// Rays in an exported TM-25 file unless told.
pub const DEFAULT_TM25_RAYS: u32 = 1_000_000;

impl Default for ExportFormats {
    fn default() -> Self {
        ExportFormats {
            ies: Some(IesVersion::Lm63_2019),
            ldt: true,
            exr: true,
            cube_png: true,
            polar_png: true,
            datasheet: false,
            tm25_rays: None,
        }
    }
}

impl ExportFormats {
    /// No file: the start of a request for only some.
    pub const NONE: ExportFormats = ExportFormats {
        ies: None,
        ldt: false,
        exr: false,
        cube_png: false,
        polar_png: false,
        datasheet: false,
        tm25_rays: None,
    };

    pub fn is_empty(&self) -> bool {
        !(self.ies.is_some()
            || self.ldt
            || self.exr
            || self.cube_png
            || self.polar_png
            || self.datasheet
            || self.tm25_rays.is_some())
    }
}

/// One export of a snapshot: which files, of which table, labelled how,
/// and where. The table is the snapshot's own when the filter and grid
/// are its run's; otherwise the snapshot's map is filtered and tabulated
/// afresh exactly as a run with them would have done at its end, so the
/// files are those `lucerna bake` writes with those settings.
#[derive(Debug, Clone)]
pub struct ExportRequest {
    pub options: ExportOptions,
    pub formats: ExportFormats,
    pub filter: FilterChoice,
    pub grid: TableGrid,
    pub out_dir: PathBuf,
    /// The files' base name: `STEM.ies`, `STEM_polar.png`, …
    pub stem: String,
    /// What the datasheet shows beyond the table (UGR spacings, outdoor).
    pub datasheet: lucerna_datasheet::DatasheetOptions,
}

/// Where an export stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ExportStage {
    /// Filtering (the automatic rule may be chosen afresh) and tabulating.
    Tabulating,
    /// Drawing one file in memory.
    Drawing(&'static str),
    /// Writing the files, all or none.
    Writing,
}

impl std::fmt::Display for ExportStage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ExportStage::Tabulating => write!(f, "filtering and tabulating"),
            ExportStage::Drawing(what) => write!(f, "drawing the {what} file"),
            ExportStage::Writing => write!(f, "writing the files"),
        }
    }
}

/// What an export writes before anything is written: the table and its
/// photometry, and every file's path and bytes.
#[derive(Debug, Clone)]
pub struct ExportedFiles {
    pub photometry: Photometry,
    /// The table's γ grid and how faithfully it carries the map; a grid
    /// the user fixed that loses the beam is written, and warned about
    /// through [`TableFidelity::shortfalls`].
    pub fidelity: TableFidelity,
    pub files: Vec<(PathBuf, Vec<u8>)>,
}

/// Candela per texel, the table the files hold, and how faithfully it
/// carries the map.
type ExportedTable = (Arc<Vec<f64>>, Arc<CandelaTable>, TableFidelity);

/// Why a request was refused before anything was drawn or written.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[non_exhaustive]
pub enum ExportRequestError {
    #[error("no format is chosen: nothing to export")]
    NoFormat,
    #[error("the base name '{0}' is not a plain file name (no folders, not empty, not . or ..)")]
    BadStem(String),
}

impl ExportRequest {
    /// Every format of the snapshot's own table, as `lucerna bake` writes.
    pub fn new(snapshot: &Snapshot, options: ExportOptions, out_dir: &Path, stem: &str) -> Self {
        ExportRequest {
            formats: ExportFormats::default(),
            filter: snapshot.settings.filter,
            grid: snapshot.settings.table,
            out_dir: out_dir.to_path_buf(),
            stem: stem.to_owned(),
            datasheet: lucerna_datasheet::DatasheetOptions {
                source_name: options.scene_file.clone(),
                ..Default::default()
            },
            options,
        }
    }

    /// Candela per texel and the table the files hold.
    fn candela_and_table(&self, snapshot: &Snapshot) -> Result<ExportedTable, SimulationError> {
        let run = &snapshot.settings;
        // A live snapshot's automatic rule may be an older choice; a final
        // one chose afresh, as a bake does.
        let final_choice = matches!(
            snapshot.state,
            RunState::Finished(r) if r != StopReason::Cancelled
        );
        let same_filter =
            self.filter == run.filter && (self.filter != FilterChoice::Automatic || final_choice);
        if same_filter && self.grid == run.table {
            return Ok((
                snapshot.candela.clone(),
                snapshot.table.clone(),
                snapshot.table_fidelity.clone(),
            ));
        }
        // The same checks as a run's settings.
        crate::SimulationSettings {
            filter: self.filter,
            table: self.grid,
            ..*run
        }
        .validate()?;
        let symmetry = TexelSymmetry::new(snapshot.map.layout, snapshot.symmetry);
        let candela = if same_filter {
            snapshot.candela.clone()
        } else {
            let (candela, _) = exported_candela(
                &mut LiveFilter::new(),
                &snapshot.map,
                self.filter,
                &symmetry,
                false,
            );
            Arc::new(candela)
        };
        let resampled = tabulate(
            &mut TableResampler::new(),
            &snapshot.map,
            &candela,
            symmetry.order(),
            self.grid,
            snapshot
                .luminaire
                .c_pooling(snapshot.settings.pool_symmetry),
            snapshot
                .luminaire
                .prepared
                .ray_file_rays()
                .map(|(rays, _)| rays),
        );
        Ok((candela, Arc::new(resampled.table), resampled.fidelity))
    }

    /// The photometry the files would hold.
    pub fn photometry(&self, snapshot: &Snapshot) -> Result<Photometry, SimulationError> {
        let (_, table, _) = self.candela_and_table(snapshot)?;
        Ok(photometry_of(snapshot, &table, &self.options))
    }

    /// Every file's path and bytes, drawn and written in memory: any
    /// failure comes before a file is touched.
    pub fn render(&self, snapshot: &Snapshot) -> Result<ExportedFiles, SimulationError> {
        self.render_reporting(snapshot, &|_| {})
    }

    /// [`ExportRequest::render`], telling `report` each stage as it starts
    /// (an editor shows them while the export runs on its own thread).
    pub fn render_reporting(
        &self,
        snapshot: &Snapshot,
        report: &dyn Fn(ExportStage),
    ) -> Result<ExportedFiles, SimulationError> {
        if self.formats.is_empty() {
            return Err(ExportRequestError::NoFormat.into());
        }
        let plain = Path::new(&self.stem)
            .file_name()
            .is_some_and(|n| n == self.stem.as_str());
        if self.stem.trim().is_empty() || !plain || self.stem == "." || self.stem == ".." {
            return Err(ExportRequestError::BadStem(self.stem.clone()).into());
        }
        report(ExportStage::Tabulating);
        let (candela, table, fidelity) = self.candela_and_table(snapshot)?;
        let photometry = photometry_of(snapshot, &table, &self.options);
        let map = &snapshot.map;
        let name = self
            .options
            .labels
            .as_ref()
            .map_or(&snapshot.luminaire.scene.name, |l| &l.name);
        // cd/klm of the lamp (emitter) flux, as in the LDT; validation keeps
        // the flux > 0.
        let per_klm = 1000.0 / map.emitter_flux_lm;
        let title = format!("{name} - {} photons", map.photons_emitted);
        let picture = |what: &'static str| {
            move |e: &dyn std::fmt::Display| SimulationError::Picture {
                what,
                message: e.to_string(),
            }
        };
        let stem = &self.stem;
        let mut outputs: Vec<(String, Vec<u8>)> = Vec::new();
        if let Some(version) = self.formats.ies {
            report(ExportStage::Drawing("IES"));
            outputs.push((
                format!("{stem}.ies"),
                write_ies(&photometry, version)?.into_bytes(),
            ));
        }
        if self.formats.ldt {
            report(ExportStage::Drawing("EULUMDAT"));
            outputs.push((format!("{stem}.ldt"), to_latin1(&write_ldt(&photometry)?)));
        }
        if self.formats.exr {
            report(ExportStage::Drawing("EXR"));
            let exr = lucerna_pictures::intensity_map_exr(
                map,
                &[
                    ("lucernaSeed", self.options.seed.to_string()),
                    ("lucernaScene", name.clone()),
                    ("lucernaDate", self.options.date.clone()),
                ],
            )
            .map_err(|e| picture("the EXR map")(&e))?;
            outputs.push((format!("{stem}.exr"), exr));
        }
        if self.formats.cube_png {
            report(ExportStage::Drawing("cube map"));
            let cube = lucerna_pictures::cube_map_png(map.layout, &candela, 200, &title)
                .map_err(|e| picture("the cube map")(&e))?;
            outputs.push((format!("{stem}_cube.png"), cube));
        }
        if self.formats.polar_png {
            report(ExportStage::Drawing("polar diagram"));
            let polar = lucerna_pictures::polar_png(&photometry.table, per_klm, 640, &title)
                .map_err(|e| picture("the polar diagram")(&e))?;
            outputs.push((format!("{stem}_polar.png"), polar));
        }
        if self.formats.datasheet {
            report(ExportStage::Drawing("datasheet"));
            let sheet = lucerna_datasheet::Datasheet::new(&photometry, &self.datasheet)
                .map_err(|e| picture("the datasheet")(&e))?;
            let rendered = sheet.render().map_err(|e| picture("the datasheet")(&e))?;
            let stem = format!("{stem}_datasheet");
            for (path, bytes) in rendered.files(&sheet, Path::new(""), &stem) {
                outputs.push((path.to_string_lossy().into_owned(), bytes));
            }
        }
        if let Some(rays) = self.formats.tm25_rays {
            report(ExportStage::Drawing("TM-25 ray"));
            outputs.push((
                format!("{stem}.tm25ray"),
                self.ray_file(snapshot, &photometry, rays)?,
            ));
        }
        Ok(ExportedFiles {
            photometry,
            fidelity,
            files: outputs
                .into_iter()
                .map(|(name, bytes)| (self.out_dir.join(name), bytes))
                .collect(),
        })
    }

    /// The TM-25 file of `rays` photons leaving the luminaire, traced with
    /// the run's seed (its own first photons): each at its last
    /// interaction (mm), its direction, and an equal share of the
    /// luminaire's flux, so that their far field is the exported table's
    /// within the Monte Carlo noise of `rays` rays.
    fn ray_file(
        &self,
        snapshot: &Snapshot,
        photometry: &Photometry,
        rays: u32,
    ) -> Result<Vec<u8>, SimulationError> {
        use lucerna_photometry::tm25::{RayFileHeader, RaySet, write_ray_file};
        let luminaire = &snapshot.luminaire;
        // Ten thousand photons per ray wanted at most: a luminaire that
        // lets almost nothing out is said so, not traced for ever.
        let max_photons = rays.saturating_mul(10_000);
        let (escaping, traced) = lucerna_tracer::escaping_rays(
            &luminaire.prepared,
            self.options.seed,
            snapshot.settings.max_bounces,
            rays as usize,
            max_photons,
        );
        if escaping.is_empty() {
            return Err(SimulationError::Picture {
                what: "the TM-25 ray file",
                message: format!("no photon of {traced} traced left the luminaire"),
            });
        }
        let flux_lm = photometry.table.flux_lm();
        let mut header = RayFileHeader::luminous(escaping.len() as u64, flux_lm as f32);
        header.date_time = self.options.date.clone();
        let meta = &photometry.meta;
        header.description.name = meta.luminaire.clone();
        header.description.manufacturer = meta.manufacturer.clone();
        header.description.model_creator = meta.test_lab.clone();
        header.description.ray_file_creator = format!("Lucerna {}", env!("CARGO_PKG_VERSION"));
        header.description.equipment = "photon tracer".to_owned();
        header.description.additional_info = format!(
            "rays leave from their last interaction; {} photons traced with seed {} for {} escaping",
            traced,
            self.options.seed,
            escaping.len()
        );
        header.description.data_reference = self.options.scene_file.clone();
        let per_ray = (flux_lm / escaping.len() as f64) as f32;
        let mut records = Vec::with_capacity(7 * escaping.len());
        for ray in &escaping {
            let p = ray.position * 1000.0;
            records.extend([
                p.x,
                p.y,
                p.z,
                ray.direction.x,
                ray.direction.y,
                ray.direction.z,
            ]);
            records.push(per_ray);
        }
        let set = RaySet {
            header,
            records,
            luminous_flux_lm: Vec::new(),
        };
        Ok(write_ray_file(&set))
    }

    /// Renders the files and writes them all or none (each atomically);
    /// returns their paths. The output folder must exist.
    pub fn write(&self, snapshot: &Snapshot) -> Result<Vec<PathBuf>, SimulationError> {
        self.write_reporting(snapshot, &|_| {})
    }

    /// [`ExportRequest::write`], telling `report` each stage as it starts.
    pub fn write_reporting(
        &self,
        snapshot: &Snapshot,
        report: &dyn Fn(ExportStage),
    ) -> Result<Vec<PathBuf>, SimulationError> {
        let exported = self.render_reporting(snapshot, report)?;
        report(ExportStage::Writing);
        write_all_atomically(&exported.files)
            .map_err(|(path, source)| SimulationError::Write { path, source })?;
        Ok(exported.files.into_iter().map(|(path, _)| path).collect())
    }
}

/// Writes `STEM.ies` (LM-63-2019), `STEM.ldt`, `STEM.exr` (the raw map
/// with its photon counts), `STEM_cube.png` and `STEM_polar.png` into
/// `out_dir`, all or none; returns their paths.
pub fn write_bake_files(
    snapshot: &Snapshot,
    options: &ExportOptions,
    out_dir: &Path,
    stem: &str,
) -> Result<Vec<PathBuf>, SimulationError> {
    ExportRequest::new(snapshot, options.clone(), out_dir, stem).write(snapshot)
}
