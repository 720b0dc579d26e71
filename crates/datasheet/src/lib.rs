//! The photometric datasheet a luminaire maker publishes beside the IES
//! and LDT files: luminaire data, polar, cartesian and isocandela
//! diagrams, zonal lumens and CIE flux code, beam and field angles, the
//! cone diagram of a narrow beam, the luminance table with the EN 12464-1
//! screen limits, the TM-15 BUG rating of outdoor luminaires and the CIE
//! 190 UGR table.
//!
//! [`Datasheet::new`] computes every figure from a [`Photometry`] (what
//! `--json` prints); [`Datasheet::render`] lays them out as A4 SVG pages,
//! shown by the HTML and drawn into the PDF, so the two show the same
//! sheet. The same photometry and options give the same bytes.

pub mod bug;
pub mod charts;
pub mod cone;
pub mod direct;
pub mod guth;
pub mod luminaire;
pub mod luminance;
pub mod pages;
pub mod pdf;
pub mod section;
pub mod svg;
pub mod ugr;
pub mod zonal;

use std::path::{Path, PathBuf};

use lucerna_photometry::{CandelaTable, Figures, Format, Photometry};
use serde::Serialize;

pub use bug::{BugOrientation, BugRating};
pub use cone::ConeDiagram;
pub use luminaire::LuminaireData;
pub use luminance::{LuminanceTable, Opening};
pub use section::Section;
pub use ugr::UgrTable;
pub use zonal::Zone;

/// Why a datasheet could not be made.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum DatasheetError {
    #[error("the photometry has no flux: a datasheet of darkness says nothing")]
    NoLight,
    #[error("UGR spacing-to-height ratio {0} is not one of 0.25, 0.5 or 1 (the method's arrays)")]
    Spacing(f64),
    #[error("cannot write the PDF: {0}")]
    Pdf(String),
}

/// Whether the luminaire is rated as an outdoor one (BUG).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, serde::Deserialize)]
pub enum Outdoor {
    /// From its name, catalogue number and keywords (road, street, area,
    /// flood, outdoor, bollard, post top, wall pack).
    Auto,
    Yes,
    No,
}

/// What the sheet shows beyond the file.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct DatasheetOptions {
    /// UGR tables at these spacing-to-height ratios: 0.25 as catalogues
    /// print, 1.0 (CIE 190's standard table) on request.
    pub ugr_spacings: Vec<f64>,
    pub outdoor: Outdoor,
    /// The file the photometry came from, named in the footer.
    pub source_name: String,
}

impl Default for DatasheetOptions {
    fn default() -> Self {
        DatasheetOptions {
            ugr_spacings: vec![0.25],
            outdoor: Outdoor::Auto,
            source_name: String::new(),
        }
    }
}

/// Beam and field angles per main plane.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Angles {
    pub beam_angle_deg: [Option<f64>; 2],
    pub field_angle_deg: [Option<f64>; 2],
}

/// The two main planes' curves, cd/klm, at the table's own γ angles.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PolarCurves {
    pub gamma_deg: Vec<f64>,
    pub c0: Vec<f64>,
    pub c180: Vec<f64>,
    pub c90: Vec<f64>,
    pub c270: Vec<f64>,
}

/// Every figure of the sheet (`lucerna report --json`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Datasheet {
    pub luminaire: LuminaireData,
    /// The C-plane symmetry the file declares.
    pub symmetry: String,
    /// cd/klm per cd of the file: 1000 / lamp flux (the luminaire's flux
    /// for absolute photometry).
    pub cd_per_klm_factor: f64,
    /// Peak intensity (cd for the file's flux; cd/klm) and its direction.
    pub peak_cd: f64,
    pub peak_cd_per_klm: f64,
    pub peak_c_deg: f64,
    pub peak_gamma_deg: f64,
    pub downward_flux_fraction_percent: f64,
    pub angles: Angles,
    pub zonal_lumens: Vec<Zone>,
    /// N1 N2 N3 N4 N5.
    pub cie_flux_code: [u32; 5],
    pub polar_curves: PolarCurves,
    pub cone: Section<ConeDiagram>,
    pub luminance: Section<LuminanceTable>,
    pub bug: Section<BugRating>,
    pub ugr: Section<UgrTable>,
    /// Further UGR tables at other spacings (S/H = 1 on request).
    pub ugr_other_spacings: Vec<Section<UgrTable>>,
    /// Remarks the sheet prints (symmetry assumed by UGR, …).
    pub notes: Vec<String>,
    #[serde(skip)]
    table_cd_per_klm: CandelaTable,
    #[serde(skip)]
    options: DatasheetOptions,
}

/// Words in a luminaire's labels that mark it as an outdoor one.
const OUTDOOR_WORDS: [&str; 10] = [
    "road",
    "street",
    "area",
    "flood",
    "outdoor",
    "bollard",
    "post top",
    "post-top",
    "wall pack",
    "roadway",
];

fn looks_outdoor(p: &Photometry) -> Option<String> {
    let mut labels = vec![p.meta.luminaire.clone(), p.meta.catalog_number.clone()];
    labels.extend(p.meta.keywords.iter().map(|(_, v)| v.clone()));
    labels.iter().find_map(|l| {
        let lower = l.to_lowercase();
        OUTDOOR_WORDS
            .iter()
            .find(|w| lower.contains(*w))
            .map(|w| (*w).to_owned())
    })
}

impl Datasheet {
    pub fn new(p: &Photometry, options: &DatasheetOptions) -> Result<Datasheet, DatasheetError> {
        let table = &p.table;
        let flux = table.flux_lm();
        if !(flux > 0.0) {
            return Err(DatasheetError::NoLight);
        }
        for &s in &options.ugr_spacings {
            if !ugr::is_method_spacing(s) {
                return Err(DatasheetError::Spacing(s));
            }
        }
        let lamp_flux = p.lamp_flux_lm();
        let reference_flux = lamp_flux.unwrap_or(flux);
        let factor = 1000.0 / reference_flux;
        let klm = table.scaled(factor);
        let figures: Figures = p.figures();
        let mut notes = Vec::new();

        let gammas = table.gammas_deg.clone();
        let curve = |c: f64| {
            gammas
                .iter()
                .map(|&g| factor * table.intensity(c, g))
                .collect()
        };
        let polar_curves = PolarCurves {
            c0: curve(0.0),
            c180: curve(180.0),
            c90: curve(90.0),
            c270: curve(270.0),
            gamma_deg: gammas.clone(),
        };

        let opening = Opening::from_dimensions(&p.meta.luminous_area);
        let downward = table.flux_between_lm(0.0, 90.0) > 1e-9 * flux;
        let luminance = match &opening {
            Ok(_) if !downward => Section::omitted(
                "Luminance table left out: the luminaire sends no light below the horizontal.",
            ),
            Ok(o) => Section::Shown(luminance::luminance_table(table, o)),
            Err(e) => Section::omitted(format!("Luminance table left out: {e}.")),
        };
        let outdoor = match options.outdoor {
            Outdoor::Yes => Some("asked for".to_owned()),
            Outdoor::No => None,
            Outdoor::Auto => looks_outdoor(p).map(|w| format!("its labels say \"{w}\"")),
        };
        let bug = match outdoor {
            Some(why) => {
                let orientation = match p.format {
                    Format::Eulumdat => BugOrientation::FrontAtC90,
                    Format::Ies(_) | Format::Tm25RayFile => BugOrientation::FrontAtC0,
                };
                notes.push(format!(
                    "BUG rating (IES TM-15-11) shown as for an outdoor luminaire ({why}); street side centred on {}.",
                    match orientation {
                        BugOrientation::FrontAtC0 => "C0 (IES road convention)",
                        BugOrientation::FrontAtC90 => "C90 (EULUMDAT road convention)",
                    }
                ));
                Section::Shown(bug::bug_rating(table, orientation))
            }
            None => Section::omitted(
                "BUG rating left out: an indoor luminaire (its labels name no outdoor use; `--outdoor` rates it).",
            ),
        };
        let ugr_at = |s: f64| -> Section<UgrTable> {
            match &opening {
                Err(e) => Section::omitted(format!("UGR table left out: {e}.")),
                Ok(o) => match ugr::ugr_table(&klm, o, s, reference_flux) {
                    Ok(t) => Section::Shown(t),
                    Err(e) => Section::omitted(format!("UGR table left out: {e}.")),
                },
            }
        };
        let mut spacings = options.ugr_spacings.clone();
        if spacings.is_empty() {
            spacings.push(0.25);
        }
        let ugr_main = ugr_at(spacings[0]);
        let ugr_other_spacings = spacings[1..].iter().map(|&s| ugr_at(s)).collect();
        if ugr_main.shown().is_some() {
            let asymmetry = ugr::glare_zone_asymmetry(table);
            if asymmetry > 0.05 {
                notes.push(format!(
                    "The UGR tables assume C0-C180 and C90-C270 symmetry, as CIE 190 does (it reads the intensities towards the observer in C0°–90°); at glare angles (γ 55°–85°) this distribution departs from it by up to {:.0} %.",
                    100.0 * asymmetry
                ));
            }
        }
        if p.meta.lamps.len() > 1 && lamp_flux.is_some() {
            notes.push(format!(
                "The file lists {} lamp sets: alternative equipments of one luminaire. Every figure and the UGR correction are of set 1; the others are listed as variants.",
                p.meta.lamps.len()
            ));
        }
        notes.extend(p.consistency_warnings().into_iter().map(|w| {
            let mut w = w;
            if let Some(first) = w.get_mut(0..1) {
                first.make_ascii_uppercase();
            }
            w + "."
        }));
        if lamp_flux.is_none() {
            notes.push(
                "Absolute photometry: cd/klm and the UGR tables refer to the luminaire's own flux (LOR taken as 100 %).".to_owned(),
            );
        }
        Ok(Datasheet {
            luminaire: luminaire::luminaire_data(p),
            symmetry: p.symmetry.describe().to_owned(),
            cd_per_klm_factor: factor,
            peak_cd: figures.peak_cd,
            peak_cd_per_klm: factor * figures.peak_cd,
            peak_c_deg: figures.peak_c_deg,
            peak_gamma_deg: figures.peak_gamma_deg,
            downward_flux_fraction_percent: 100.0 * figures.downward_fraction,
            angles: Angles {
                beam_angle_deg: figures.beam_angle_deg,
                field_angle_deg: figures.field_angle_deg,
            },
            zonal_lumens: zonal::zonal_summary(&figures, lamp_flux),
            cie_flux_code: zonal::cie_flux_code(table, lamp_flux),
            polar_curves,
            cone: cone::cone_diagram(table, figures.beam_angle_deg).into(),
            luminance,
            bug,
            ugr: ugr_main,
            ugr_other_spacings,
            notes,
            table_cd_per_klm: klm,
            options: options.clone(),
        })
    }

    /// The table in cd/klm the figures were drawn from.
    pub fn table_cd_per_klm(&self) -> &CandelaTable {
        &self.table_cd_per_klm
    }

    /// Every figure as one JSON document.
    pub fn json(&self) -> String {
        serde_json::to_string_pretty(self).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"))
    }

    /// The sheet's pages (SVG), the HTML that shows them and the PDF.
    pub fn render(&self) -> Result<RenderedDatasheet, DatasheetError> {
        let drawn = pages::pages(self);
        let title = format!("{} – photometric datasheet", self.luminaire.name);
        let pdf = pdf::pdf_of_pages(&drawn, &title)?;
        let pages: Vec<String> = drawn.iter().map(svg::Svg::page).collect();
        let html = pages::html(&pages, &title);
        Ok(RenderedDatasheet { pages, html, pdf })
    }
}

/// A rendered sheet, in memory.
#[derive(Debug, Clone)]
pub struct RenderedDatasheet {
    pub pages: Vec<String>,
    pub html: String,
    pub pdf: Vec<u8>,
}

impl RenderedDatasheet {
    /// The files of the sheet: `STEM.html`, `STEM.pdf` and `STEM.json`
    /// (every figure), to be written all or none.
    pub fn files(&self, sheet: &Datasheet, dir: &Path, stem: &str) -> Vec<(PathBuf, Vec<u8>)> {
        vec![
            (
                dir.join(format!("{stem}.html")),
                self.html.clone().into_bytes(),
            ),
            (dir.join(format!("{stem}.pdf")), self.pdf.clone()),
            (dir.join(format!("{stem}.json")), sheet.json().into_bytes()),
        ]
    }
}
