//! The luminous opening seen from a direction, and the luminance table a
//! datasheet prints (cd/m² at γ 45°–85° in C0, C45, C90) with the
//! EN 12464-1 limits for luminaires reflected in display screens.

use lucerna_photometry::{CandelaTable, Dimensions};
use serde::Serialize;

/// The luminous opening as the glare and luminance figures see it: a
/// box (length along C0-C180, width along C90-C270, height of its
/// luminous sides) or a disk with a luminous rim.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Opening {
    pub length_m: f64,
    pub width_m: f64,
    pub height_m: f64,
    pub circular: bool,
}

/// Why a file's luminous opening cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum OpeningError {
    #[error(
        "the file gives no luminous opening (its luminous length, width and height are 0), so luminances cannot be derived"
    )]
    Missing,
    #[error("the luminous opening has no area seen from below ({0}): luminances would be infinite")]
    NoBottom(String),
}

impl Opening {
    /// From the file's luminous area (LM-63's terms: length along x).
    pub fn from_dimensions(d: &Dimensions) -> Result<Opening, OpeningError> {
        let (l, w, h) = (d.length_m.abs(), d.width_m.abs(), d.height_m.abs());
        if l == 0.0 && w == 0.0 && h == 0.0 {
            return Err(OpeningError::Missing);
        }
        let circular = d.circular;
        let opening = Opening {
            length_m: l,
            width_m: if circular { l } else { w },
            height_m: h,
            circular,
        };
        if opening.bottom_area_m2() <= 0.0 {
            return Err(OpeningError::NoBottom(format!(
                "{} × {} m",
                d.length_m, d.width_m
            )));
        }
        Ok(opening)
    }

    /// Area of the opening's face seen from straight below (m²).
    pub fn bottom_area_m2(&self) -> f64 {
        if self.circular {
            std::f64::consts::FRAC_PI_4 * self.length_m * self.length_m
        } else {
            self.length_m * self.width_m
        }
    }

    /// Area (m²) the opening shows to an eye in direction (C, γ) from it:
    /// the bottom face foreshortened by cos γ, plus the luminous sides
    /// facing that way by sin γ (a box shows one long and one short side,
    /// a drum its diameter × height). Sides do not shine upwards of the
    /// horizontal for a downward opening's bottom face: above γ 90° only
    /// the sides count.
    pub fn projected_area_m2(&self, c_deg: f64, gamma_deg: f64) -> f64 {
        let (sg, cg) = gamma_deg.to_radians().sin_cos();
        let (sc, cc) = c_deg.to_radians().sin_cos();
        let bottom = self.bottom_area_m2() * cg.max(0.0);
        let sides = if self.circular {
            self.length_m * self.height_m
        } else {
            self.height_m * (self.width_m * cc.abs() + self.length_m * sc.abs())
        };
        bottom + sides * sg.abs()
    }
}

/// The γ rows and C columns of the luminance table.
pub const LUMINANCE_GAMMAS_DEG: [f64; 9] = [45.0, 50.0, 55.0, 60.0, 65.0, 70.0, 75.0, 80.0, 85.0];
pub const LUMINANCE_PLANES_DEG: [f64; 3] = [0.0, 45.0, 90.0];

/// EN 12464-1:2011 (4.9.2, table 4, case A): the average luminance of
/// luminaires that can be reflected in a screen, at elevation angles γ ≥
/// 65° radially around the luminaire, for screens of high state luminance
/// above 200 cd/m² (3000 cd/m²) and at most 200 cd/m² (1500 cd/m²).
pub const SCREEN_LIMIT_GAMMA_DEG: f64 = 65.0;
pub const SCREEN_LIMITS_CD_M2: [(f64, &str); 2] = [
    (3000.0, "screens with high state luminance L > 200 cd/m²"),
    (1500.0, "screens with high state luminance L ≤ 200 cd/m²"),
];

/// Luminance (cd/m²) over the projected opening, per γ row and C column.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LuminanceTable {
    pub gammas_deg: Vec<f64>,
    pub c_planes_deg: Vec<f64>,
    /// `rows[γ][C]`, cd/m², for the file's own flux.
    pub cd_per_m2: Vec<Vec<f64>>,
    /// The highest luminance at γ ≥ 65° in any C-plane (every 5° of C).
    pub max_at_screen_angles_cd_per_m2: f64,
    /// Per limit of [`SCREEN_LIMITS_CD_M2`]: whether it is kept.
    pub screen_limits: Vec<ScreenLimit>,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ScreenLimit {
    pub limit_cd_per_m2: f64,
    pub applies_to: String,
    pub kept: bool,
}

pub fn luminance_table(table: &CandelaTable, opening: &Opening) -> LuminanceTable {
    let l = |c: f64, g: f64| table.intensity(c, g) / opening.projected_area_m2(c, g);
    let cd_per_m2 = LUMINANCE_GAMMAS_DEG
        .iter()
        .map(|&g| LUMINANCE_PLANES_DEG.iter().map(|&c| l(c, g)).collect())
        .collect();
    // All around the luminaire, every 5° of C and 1° of γ from 65° to 85°
    // as datasheets evaluate it (towards 90° a flat opening's projected
    // area vanishes and the quotient means nothing).
    let mut max = 0.0f64;
    for ci in 0..72 {
        let c = ci as f64 * 5.0;
        for gi in 0..=20 {
            let g = SCREEN_LIMIT_GAMMA_DEG + gi as f64;
            let a = opening.projected_area_m2(c, g);
            if a > 0.0 {
                max = max.max(table.intensity(c, g) / a);
            }
        }
    }
    LuminanceTable {
        gammas_deg: LUMINANCE_GAMMAS_DEG.to_vec(),
        c_planes_deg: LUMINANCE_PLANES_DEG.to_vec(),
        cd_per_m2,
        max_at_screen_angles_cd_per_m2: max,
        screen_limits: SCREEN_LIMITS_CD_M2
            .iter()
            .map(|&(limit, what)| ScreenLimit {
                limit_cd_per_m2: limit,
                applies_to: what.to_owned(),
                kept: max <= limit,
            })
            .collect(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_lambertian_flat_opening_has_one_luminance() {
        // I = L A cos γ for a flat Lambertian opening: the table is flat.
        let opening = Opening {
            length_m: 0.6,
            width_m: 0.3,
            height_m: 0.0,
            circular: false,
        };
        let luminance = 5000.0;
        let table = CandelaTable::from_fn(15.0, 1.0, |_, g| {
            if g < 90.0 {
                luminance * 0.18 * g.to_radians().cos()
            } else {
                0.0
            }
        });
        let t = luminance_table(&table, &opening);
        for row in &t.cd_per_m2 {
            for v in row {
                assert!((v - luminance).abs() < 1e-6 * luminance, "{v}");
            }
        }
        assert!(!t.screen_limits[0].kept);
    }

    #[test]
    fn sides_show_by_sin_gamma() {
        let o = Opening {
            length_m: 1.0,
            width_m: 0.5,
            height_m: 0.1,
            circular: false,
        };
        // Seen along C0 at the horizon: the short side, 0.5 × 0.1.
        assert!((o.projected_area_m2(0.0, 90.0) - 0.05).abs() < 1e-12);
        assert!((o.projected_area_m2(90.0, 90.0) - 0.1).abs() < 1e-12);
        assert!((o.projected_area_m2(0.0, 0.0) - 0.5).abs() < 1e-12);
        let disk = Opening {
            length_m: 0.2,
            width_m: 0.2,
            height_m: 0.0,
            circular: true,
        };
        assert!(
            (disk.projected_area_m2(30.0, 60.0) - 0.5 * 0.01 * std::f64::consts::PI).abs() < 1e-12
        );
    }

    #[test]
    fn no_opening_is_refused_with_a_reason() {
        let e = Opening::from_dimensions(&Dimensions::default()).unwrap_err();
        assert!(e.to_string().contains("no luminous opening"));
    }
}
