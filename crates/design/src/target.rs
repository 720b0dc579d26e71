//! What a design aims at: a photometric distribution (an IES or EULUMDAT
//! file) or a spec of figures (a TOML file: beam, field, cut-off, LOR,
//! UGR, and what to maximise).

use std::path::Path;

use lucerna_photometry::{CandelaTable, read_photometry};
use serde::Deserialize;

use crate::DesignError;

/// The light a design aims at.
#[derive(Debug, Clone)]
pub enum Target {
    /// A distribution to match: its shape (both scaled to the same flux)
    /// or, with `absolute`, its candela.
    Distribution {
        table: CandelaTable,
        absolute: bool,
        /// The file's name, for reports.
        name: String,
    },
    /// Figures to meet.
    Spec(Spec),
}

impl Target {
    /// Reads a target file: IES or EULUMDAT by content, else a spec
    /// (TOML). Nothing but a file that reads as one of them is taken.
    pub fn load(path: &Path, absolute: bool) -> Result<Target, DesignError> {
        let bytes = lucerna_scene::read_limited(path, lucerna_scene::io::MAX_PROFILE_FILE_BYTES)
            .map_err(|e| DesignError::Target {
                path: path.display().to_string(),
                why: e.to_string(),
            })?;
        let name = path
            .file_name()
            .map_or(String::new(), |n| n.to_string_lossy().into_owned());
        let is_toml = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("toml"));
        if !is_toml {
            let p = read_photometry(&bytes).map_err(|e| DesignError::Target {
                path: path.display().to_string(),
                why: format!("not a photometric file: {e}"),
            })?;
            if !(p.table.flux_lm() > 0.0) {
                return Err(DesignError::Target {
                    path: path.display().to_string(),
                    why: "the distribution holds no light".to_owned(),
                });
            }
            return Ok(Target::Distribution {
                table: p.table,
                absolute,
                name,
            });
        }
        let text = String::from_utf8(bytes).map_err(|_| DesignError::Target {
            path: path.display().to_string(),
            why: "a spec file must be UTF-8 text".to_owned(),
        })?;
        let spec = Spec::parse(&text).map_err(|why| DesignError::Target {
            path: path.display().to_string(),
            why,
        })?;
        Ok(Target::Spec(spec))
    }

    /// Whether the target's light is the same in every C-plane, so a
    /// direct design of a revolved profile can aim at it.
    pub fn rotationally_symmetric(&self) -> bool {
        match self {
            Target::Distribution { table, .. } => {
                table.c_planes_deg.len() == 1 || rotational_asymmetry(table) < SYMMETRIC_ENOUGH
            }
            Target::Spec(_) => true,
        }
    }
}

/// The spec a design must meet (README, "Design"): every key optional but
/// at least one term; angles in degrees.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Spec {
    /// Full beam angle (50 % of the peak), in both main planes.
    pub beam_angle_deg: Option<f64>,
    /// How far the beam may be from `beam_angle_deg` (default 1°).
    #[serde(default = "default_beam_tolerance")]
    pub beam_tolerance_deg: f64,
    /// The full field angle (10 % of the peak) may be at most this.
    pub field_angle_max_deg: Option<f64>,
    /// Above this γ (from nadir) …
    pub cutoff_gamma_deg: Option<f64>,
    /// … the intensity is at most this fraction of the peak (0.01: 1 %).
    pub cutoff_max_fraction: Option<f64>,
    /// The light output ratio is at least this (%).
    pub lor_min_percent: Option<f64>,
    /// The corrected UGR (CIE 190's table plus 8·log10(Φ/1000)) is at
    /// most this in `ugr_room`, crosswise and endwise.
    pub ugr_max: Option<f64>,
    /// The room in H units, as CIE 190's table lists it (default 4H × 8H).
    #[serde(default = "default_ugr_room")]
    pub ugr_room: [f64; 2],
    /// Ceiling, walls, floor (default 0.7, 0.5, 0.2).
    #[serde(default = "default_ugr_reflectances")]
    pub ugr_reflectances: [f64; 3],
    /// What to make as large as the other terms allow.
    pub maximise: Option<Maximise>,
    /// The cone of `maximise = "cone_flux"` (half-angle, degrees).
    pub cone_half_angle_deg: Option<f64>,
}

/// What a spec makes as large as it can.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Maximise {
    /// The light output ratio.
    Lor,
    /// The flux inside `cone_half_angle_deg` of nadir, as a share of the
    /// lamp flux.
    ConeFlux,
}

fn default_beam_tolerance() -> f64 {
    1.0
}

fn default_ugr_room() -> [f64; 2] {
    [4.0, 8.0]
}

fn default_ugr_reflectances() -> [f64; 3] {
    [0.7, 0.5, 0.2]
}

impl Spec {
    /// Parses and checks a spec: every value in its range, at least one
    /// term, no two terms that contradict each other.
    pub fn parse(text: &str) -> Result<Spec, String> {
        let spec: Spec = toml::from_str(text).map_err(|e| format!("not a valid spec: {e}"))?;
        spec.check()?;
        Ok(spec)
    }

    fn check(&self) -> Result<(), String> {
        let angle = |what: &str, v: Option<f64>, lo: f64, hi: f64| -> Result<(), String> {
            match v {
                Some(x) if !(x.is_finite() && x > lo && x <= hi) => Err(format!(
                    "{what} must be above {lo} and at most {hi}, got {x}"
                )),
                _ => Ok(()),
            }
        };
        angle("beam_angle_deg", self.beam_angle_deg, 0.0, 360.0)?;
        angle("field_angle_max_deg", self.field_angle_max_deg, 0.0, 360.0)?;
        angle("cutoff_gamma_deg", self.cutoff_gamma_deg, 0.0, 180.0)?;
        angle("cone_half_angle_deg", self.cone_half_angle_deg, 0.0, 180.0)?;
        angle("lor_min_percent", self.lor_min_percent, 0.0, 100.0)?;
        angle("ugr_max", self.ugr_max, 0.0, 40.0)?;
        if !(self.beam_tolerance_deg.is_finite() && self.beam_tolerance_deg > 0.0) {
            return Err(format!(
                "beam_tolerance_deg must be positive, got {}",
                self.beam_tolerance_deg
            ));
        }
        match (self.cutoff_gamma_deg, self.cutoff_max_fraction) {
            (Some(_), Some(f)) if !(f.is_finite() && f > 0.0 && f < 1.0) => {
                return Err(format!(
                    "cutoff_max_fraction must be between 0 and 1 (0.01 is 1 % of the peak), got {f}"
                ));
            }
            (Some(_), None) | (None, Some(_)) => {
                return Err(
                    "a cut-off needs both cutoff_gamma_deg and cutoff_max_fraction".to_owned(),
                );
            }
            _ => {}
        }
        let ugr_room_known = lucerna_datasheet::ugr::ROOMS
            .iter()
            .any(|&(x, y)| [x, y] == self.ugr_room);
        if self.ugr_max.is_some() && !ugr_room_known {
            return Err(format!(
                "ugr_room {:?} is not a room of CIE 190's table (e.g. [4, 8])",
                self.ugr_room
            ));
        }
        let reflectances_known =
            lucerna_datasheet::ugr::REFLECTANCES.contains(&self.ugr_reflectances);
        if self.ugr_max.is_some() && !reflectances_known {
            return Err(format!(
                "ugr_reflectances {:?} is not a column of CIE 190's table (e.g. [0.7, 0.5, 0.2])",
                self.ugr_reflectances
            ));
        }
        if self.maximise == Some(Maximise::ConeFlux) && self.cone_half_angle_deg.is_none() {
            return Err("maximise = \"cone_flux\" needs cone_half_angle_deg".to_owned());
        }
        let terms = [
            self.beam_angle_deg.is_some(),
            self.field_angle_max_deg.is_some(),
            self.cutoff_gamma_deg.is_some(),
            self.lor_min_percent.is_some(),
            self.ugr_max.is_some(),
            self.maximise.is_some(),
        ];
        if !terms.iter().any(|&t| t) {
            return Err("the spec states no term (beam_angle_deg, field_angle_max_deg, cutoff_gamma_deg, lor_min_percent, ugr_max or maximise)".to_owned());
        }
        // Terms that cannot hold together.
        if let (Some(beam), Some(field)) = (self.beam_angle_deg, self.field_angle_max_deg)
            && beam - self.beam_tolerance_deg >= field
        {
            return Err(format!(
                "the beam ({beam}° ± {}°) cannot be wider than the field ({field}° at most): the field angle (10 %) is always wider than the beam (50 %)",
                self.beam_tolerance_deg
            ));
        }
        if let (Some(beam), Some(cut)) = (self.beam_angle_deg, self.cutoff_gamma_deg)
            && 0.5 * (beam - self.beam_tolerance_deg) >= cut
        {
            return Err(format!(
                "a {beam}° beam reaches γ {}° at half its peak, beyond the cut-off at γ {cut}° where it must be below {} of it",
                0.5 * beam,
                self.cutoff_max_fraction.unwrap_or(0.0)
            ));
        }
        Ok(())
    }
}

/// The asymmetry (see [`rotational_asymmetry`]) below which a target
/// counts as the same in every C-plane: a bake of a surface of
/// revolution keeps a few per cent of photon noise across C... of its
/// peak's texels only, so its root mean square over γ stays below this.
pub const SYMMETRIC_ENOUGH: f64 = 0.02;

/// The table's mean over C (C-weighted), as one plane.
pub fn c_mean(table: &CandelaTable) -> CandelaTable {
    CandelaTable {
        c_planes_deg: vec![0.0],
        gammas_deg: table.gammas_deg.clone(),
        candela: axial_nodes(table),
    }
}

/// A table's mean over C (C-weighted) at each of its γ nodes.
pub fn axial_nodes(table: &CandelaTable) -> Vec<f64> {
    let n = table.gammas_deg.len();
    let weights = table.c_weights();
    let total: f64 = weights.iter().sum();
    (0..n)
        .map(|j| {
            weights
                .iter()
                .enumerate()
                .map(|(i, w)| w * table.candela[i * n + j])
                .sum::<f64>()
                / total
        })
        .collect()
}

/// How far a table's intensity varies across C: the root mean square,
/// over the γ angles where the light is (the mean over C at 1 % of the
/// peak or more), of each angle's spread around its mean across C, over
/// the peak. 0 for a distribution the same in every C-plane; a bake of a
/// surface of revolution keeps a little photon noise; a beam whose planes
/// differ by a tenth of its peak where it is lit, 0.1.
pub fn rotational_asymmetry(table: &CandelaTable) -> f64 {
    let peak = table.peak().0;
    if !(peak > 0.0) {
        return 0.0;
    }
    let n = table.gammas_deg.len();
    let planes = table.c_planes_deg.len();
    let (mut sum, mut lit) = (0.0, 0usize);
    for j in 0..n {
        let column: Vec<f64> = (0..planes).map(|i| table.candela[i * n + j]).collect();
        let mean = column.iter().sum::<f64>() / planes as f64;
        if mean < 0.01 * peak {
            continue;
        }
        sum += column.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / planes as f64;
        lit += 1;
    }
    if lit == 0 {
        return 0.0;
    }
    (sum / lit as f64).sqrt() / peak
}
