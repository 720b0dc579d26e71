//! The UGR table of a luminaire by the tabular method of CIE 190:2010
//! ("Calculation and presentation of unified glare rating tables for
//! indoor lighting luminaires"), as DIALux and Relux print it.
//!
//! UGR = 8 log10(0.25 / Lb · Σ L² ω / p²) for an observer at the middle of
//! one wall of a room X × Y (in units of H, the luminaires' height above
//! the eye, H = 2 m), looking horizontally along Y across a regular array
//! of luminaires at spacing S (the first row S/2 from the walls). L = I /
//! A_p over the projected luminous opening, ω = A_p / D², p the Guth
//! position index of CIE 117 (`guth`); luminaires outside its table (above
//! about 62° over the line of sight, or far to the side) do not count.
//! Crosswise the line of sight is across the luminaire's long axis (the
//! luminaires' C0-C180 plane contains it); endwise along it (C90-C270).
//! Lb = E_WID / π from the indirect wall illuminance of the method's flux
//! transfer (CIE 190 eqs 7–12): the downward flux in the cones of the CIE
//! flux code, distributed to the floor (reference plane at eye level) by
//! the room's F_GL factors (table 4), and interreflected by the transfer
//! factors of table 5 for each reflectance set.
//!
//! Intensities are for 1000 lm of bare-lamp flux (cd/klm of the lamp flux;
//! of the luminaire's flux for absolute photometry), so the table is
//! "uncorrected": for Φ lm of lamps add 8 log10(Φ / 1000).
//!
//! Tables 4 and 5 below are CIE 190:2010's, transcribed from the two
//! public implementations that carry them, which agree on every value:
//! github.com/patrickjamesbenson/ControlStack_Runtime
//! `packages/lab-kernel/ies-toolkit/iesUgrCie190.js` (commit 558b5d9) and
//! github.com/123VincentB/eulumdat-ugr `src/eulumdat_ugr/background.py`
//! (commit 9f60147). With them this module reproduces CIE 190's worked
//! example (its section 5: 2H × 4H, 70/50/20, 11.0 crosswise, 13.1
//! endwise) and its full S = H table to ±0.1 (tests/ugr.rs).

use lucerna_photometry::CandelaTable;
use serde::Serialize;

use crate::guth::position_index;
use crate::luminance::Opening;

/// Height of the luminaires above the eye (m) in the standard rooms.
pub const H_M: f64 = 2.0;

/// The 19 standard rooms (X, Y in units of H), in the order printed.
pub const ROOMS: [(f64, f64); 19] = [
    (2.0, 2.0),
    (2.0, 3.0),
    (2.0, 4.0),
    (2.0, 6.0),
    (2.0, 8.0),
    (2.0, 12.0),
    (4.0, 2.0),
    (4.0, 3.0),
    (4.0, 4.0),
    (4.0, 6.0),
    (4.0, 8.0),
    (4.0, 12.0),
    (8.0, 4.0),
    (8.0, 6.0),
    (8.0, 8.0),
    (8.0, 12.0),
    (12.0, 4.0),
    (12.0, 6.0),
    (12.0, 8.0),
];

/// The 5 reflectance sets, ceiling / walls / floor (reference plane).
pub const REFLECTANCES: [[f64; 3]; 5] = [
    [0.7, 0.5, 0.2],
    [0.7, 0.3, 0.2],
    [0.5, 0.5, 0.2],
    [0.5, 0.3, 0.2],
    [0.3, 0.3, 0.2],
];

/// CIE 190 table 4: the distribution factors F_GL1..F_GL4 of the flux in
/// the four cones (41.4°, 60°, 75.5°, 90°) onto the floor, per room of
/// [`ROOMS`].
const F_GL: [[f64; 4]; 19] = [
    [0.690, 0.109, 0.085, -0.016],
    [0.578, 0.200, 0.127, -0.018],
    [0.528, 0.218, 0.170, -0.017],
    [0.485, 0.215, 0.222, -0.012],
    [0.466, 0.207, 0.249, -0.006],
    [0.448, 0.198, 0.272, 0.005],
    [0.528, 0.218, 0.170, -0.017],
    [0.394, 0.275, 0.268, -0.020],
    [0.338, 0.257, 0.351, -0.018],
    [0.296, 0.203, 0.449, -0.006],
    [0.280, 0.165, 0.499, 0.006],
    [0.264, 0.125, 0.541, 0.027],
    [0.280, 0.165, 0.499, 0.006],
    [0.248, 0.058, 0.628, 0.032],
    [0.239, -0.012, 0.690, 0.058],
    [0.232, -0.084, 0.740, 0.098],
    [0.264, 0.125, 0.541, 0.027],
    [0.238, -0.003, 0.677, 0.063],
    [0.232, -0.084, 0.740, 0.098],
];

/// CIE 190 table 5: transfer factors (F_T,FW; F_T,WW − 1; F_T,CW) from
/// the floor's, the walls' and the ceiling's first flux to the walls'
/// indirect illuminance, per room of [`ROOMS`] and set of
/// [`REFLECTANCES`].
const F_T: [[[f64; 3]; 5]; 19] = [
    [
        [0.220, 0.422, 0.646],
        [0.188, 0.217, 0.553],
        [0.198, 0.380, 0.445],
        [0.172, 0.198, 0.386],
        [0.157, 0.181, 0.227],
    ],
    [
        [0.199, 0.376, 0.571],
        [0.173, 0.196, 0.497],
        [0.178, 0.338, 0.393],
        [0.157, 0.179, 0.346],
        [0.141, 0.162, 0.203],
    ],
    [
        [0.187, 0.351, 0.531],
        [0.164, 0.184, 0.465],
        [0.166, 0.314, 0.365],
        [0.148, 0.167, 0.324],
        [0.132, 0.151, 0.190],
    ],
    [
        [0.174, 0.322, 0.488],
        [0.154, 0.171, 0.432],
        [0.154, 0.287, 0.335],
        [0.138, 0.155, 0.301],
        [0.123, 0.139, 0.176],
    ],
    [
        [0.167, 0.307, 0.466],
        [0.149, 0.164, 0.415],
        [0.147, 0.273, 0.320],
        [0.133, 0.147, 0.288],
        [0.118, 0.132, 0.169],
    ],
    [
        [0.160, 0.290, 0.443],
        [0.143, 0.156, 0.397],
        [0.141, 0.257, 0.304],
        [0.128, 0.140, 0.276],
        [0.113, 0.124, 0.161],
    ],
    [
        [0.187, 0.351, 0.531],
        [0.164, 0.184, 0.465],
        [0.166, 0.314, 0.364],
        [0.148, 0.167, 0.324],
        [0.132, 0.151, 0.190],
    ],
    [
        [0.158, 0.295, 0.439],
        [0.142, 0.159, 0.393],
        [0.140, 0.263, 0.301],
        [0.126, 0.143, 0.272],
        [0.112, 0.128, 0.159],
    ],
    [
        [0.142, 0.265, 0.389],
        [0.129, 0.144, 0.351],
        [0.125, 0.235, 0.267],
        [0.114, 0.129, 0.244],
        [0.100, 0.115, 0.142],
    ],
    [
        [0.124, 0.230, 0.335],
        [0.114, 0.127, 0.307],
        [0.108, 0.204, 0.230],
        [0.100, 0.113, 0.212],
        [0.087, 0.101, 0.124],
    ],
    [
        [0.115, 0.211, 0.307],
        [0.106, 0.117, 0.283],
        [0.100, 0.187, 0.211],
        [0.093, 0.104, 0.196],
        [0.081, 0.092, 0.114],
    ],
    [
        [0.105, 0.190, 0.279],
        [0.098, 0.106, 0.259],
        [0.091, 0.167, 0.191],
        [0.085, 0.094, 0.179],
        [0.074, 0.083, 0.104],
    ],
    [
        [0.115, 0.211, 0.307],
        [0.106, 0.117, 0.283],
        [0.100, 0.187, 0.211],
        [0.093, 0.104, 0.196],
        [0.081, 0.092, 0.114],
    ],
    [
        [0.094, 0.175, 0.247],
        [0.088, 0.098, 0.231],
        [0.081, 0.154, 0.169],
        [0.076, 0.087, 0.158],
        [0.066, 0.077, 0.092],
    ],
    [
        [0.083, 0.155, 0.215],
        [0.078, 0.088, 0.203],
        [0.071, 0.137, 0.147],
        [0.067, 0.078, 0.140],
        [0.058, 0.069, 0.081],
    ],
    [
        [0.071, 0.133, 0.183],
        [0.067, 0.076, 0.174],
        [0.061, 0.117, 0.125],
        [0.058, 0.067, 0.120],
        [0.049, 0.059, 0.069],
    ],
    [
        [0.105, 0.190, 0.279],
        [0.098, 0.106, 0.259],
        [0.091, 0.167, 0.191],
        [0.085, 0.094, 0.179],
        [0.074, 0.083, 0.104],
    ],
    [
        [0.083, 0.153, 0.216],
        [0.078, 0.086, 0.204],
        [0.071, 0.134, 0.148],
        [0.068, 0.077, 0.140],
        [0.058, 0.067, 0.081],
    ],
    [
        [0.071, 0.133, 0.183],
        [0.067, 0.076, 0.174],
        [0.061, 0.117, 0.125],
        [0.058, 0.067, 0.120],
        [0.049, 0.059, 0.069],
    ],
];

/// Why a luminaire has no UGR table.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum UgrError {
    #[error(
        "UGR is not applicable: the luminaire sends no light downwards (upward-only light cannot be seen as direct glare by the method)"
    )]
    UpwardOnly,
    #[error(
        "UGR is not applicable: the method's flux transfer gives this distribution no indirect light on the walls"
    )]
    NoBackground,
    #[error("UGR spacing-to-height ratio {0} is not one of the method's arrays (0.25, 0.5 or 1)")]
    Spacing(f64),
}

/// The spacing-to-height ratios the tabular method lays arrays out at:
/// 0.25 (catalogues), 0.5, and 1 (CIE 190's standard table). Each puts a
/// whole number of luminaires across every standard room.
pub const SPACINGS: [f64; 3] = [0.25, 0.5, 1.0];

/// Whether `spacing` is one of [`SPACINGS`].
pub fn is_method_spacing(spacing: f64) -> bool {
    SPACINGS.iter().any(|v| (v - spacing).abs() < 1e-9)
}

/// The UGR table, as `lucerna report --json` prints it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct UgrTable {
    /// Spacing-to-height ratio S/H of the luminaire array.
    pub spacing: f64,
    /// Ceiling / walls / floor reflectances of each column.
    pub reflectances: Vec<[f64; 3]>,
    /// Room X, Y in units of H, in the order printed.
    pub rooms: Vec<[f64; 2]>,
    /// `crosswise[room][reflectance set]`, uncorrected UGR for 1000 lm,
    /// to 0.1; `null` where no luminaire in view sends light towards the
    /// eye (a narrow downlight seen from afar: no glare on any scale,
    /// printed "<10" as Relux does for low values).
    pub crosswise: Vec<Vec<Option<f64>>>,
    pub endwise: Vec<Vec<Option<f64>>>,
    /// The lamp flux the correction term is for (lm), and the term
    /// 8 log10(Φ / 1000) to add to every cell for it.
    pub lamp_flux_lm: f64,
    pub correction: f64,
    /// Height of the luminaires above the eye (m).
    pub height_m: f64,
}

/// The background of each room and reflectance set: the indirect wall
/// illuminance E_WID (lx) of the flux transfer, per 1000 lm of lamps.
pub fn indirect_wall_illuminance(klm: &CandelaTable, spacing: f64) -> [[f64; 5]; 19] {
    // Zonal fluxes in 10° zones from mid-zone intensities averaged over C
    // (CIE 190 eq. 7), per 1000 lm of lamps.
    let zone = |k: usize| {
        let gm = 5.0 + 10.0 * k as f64;
        let mean = c_mean(klm, gm);
        std::f64::consts::TAU
            * mean
            * ((gm - 5.0).to_radians().cos() - (gm + 5.0).to_radians().cos())
    };
    let zones: Vec<f64> = (0..18).map(zone).collect();
    let sum = |n: usize| zones[..n].iter().sum::<f64>();
    // Cumulative fluxes in the flux code's cones: 41.4° takes 0.130 of the
    // 40-50° zone, 75.5° 0.547 of the 70-80° zone (eq. 8).
    let phi = [
        sum(4) + 0.130 * zones[4],
        sum(6),
        sum(7) + 0.547 * zones[7],
        sum(9),
    ];
    let upward: f64 = zones[9..].iter().sum();
    let mut e = [[0.0; 5]; 19];
    for (r, &(x, y)) in ROOMS.iter().enumerate() {
        let f_df: f64 = (0..4).map(|i| F_GL[r][i] * phi[i]).sum::<f64>() / 1000.0;
        let f_dw = phi[3] / 1000.0 - f_df;
        let f_dc = upward / 1000.0;
        let n = (x / spacing).round() * (y / spacing).round();
        let wall_area = 2.0 * (x + y) * H_M * H_M;
        let b = n * 1000.0 / wall_area;
        for s in 0..5 {
            let [t_fw, t_ww, t_cw] = F_T[r][s];
            e[r][s] = b * (f_df * t_fw + f_dw * t_ww + f_dc * t_cw);
        }
    }
    e
}

/// The mean intensity over the C circle at γ (every 5°).
fn c_mean(table: &CandelaTable, gamma_deg: f64) -> f64 {
    (0..72)
        .map(|k| table.intensity(5.0 * k as f64, gamma_deg))
        .sum::<f64>()
        / 72.0
}

/// Σ I² / (A_p D² p²) over the luminaires an observer sees in room (X, Y)
/// at `spacing`, viewing crosswise or endwise; I for 1000 lm of lamps.
pub fn glare_sum(
    klm: &CandelaTable,
    opening: &Opening,
    x: f64,
    y: f64,
    spacing: f64,
    endwise: bool,
) -> f64 {
    let (nx, ny) = (
        (x / spacing).round() as usize,
        (y / spacing).round() as usize,
    );
    let mut sum = 0.0;
    for i in 0..nx {
        // Across the line of sight, from the observer's centre line.
        let xt = (i as f64 + 0.5) * spacing - 0.5 * x;
        for j in 0..ny {
            let yr = (j as f64 + 0.5) * spacing;
            let Some(p) = position_index(1.0 / yr, xt.abs() / yr) else {
                continue;
            };
            let (xt_m, yr_m) = (xt.abs() * H_M, yr * H_M);
            let horizontal = xt_m.hypot(yr_m);
            let d2 = horizontal * horizontal + H_M * H_M;
            let gamma = horizontal.atan2(H_M).to_degrees();
            // The azimuth of the eye from the luminaire, 0° along the
            // line of sight; the luminaire's C0 lies along it crosswise.
            let azimuth = xt_m.atan2(yr_m).to_degrees();
            let c = if endwise { 90.0 - azimuth } else { azimuth };
            let i_cd = klm.intensity(c, gamma);
            let area = opening.projected_area_m2(c, gamma);
            if i_cd > 0.0 && area > 0.0 {
                sum += i_cd * i_cd / (area * d2 * p * p);
            }
        }
    }
    sum
}

/// How far the intensities at glare angles (γ 55°–85°) depart from
/// C0-C180 and C90-C270 symmetry, which the method assumes (it reads C in
/// 0°–90° only): the largest difference between a direction and its
/// mirror images, relative to the larger of the two.
pub fn glare_zone_asymmetry(table: &CandelaTable) -> f64 {
    let mut worst = 0.0f64;
    for g in (55..=85).step_by(5) {
        let g = g as f64;
        for c in (0..=90).step_by(15) {
            let c = c as f64;
            let i = table.intensity(c, g);
            for mirror in [180.0 - c, 180.0 + c, 360.0 - c] {
                let j = table.intensity(mirror, g);
                let top = i.max(j);
                if top > 0.0 {
                    worst = worst.max((i - j).abs() / top);
                }
            }
        }
    }
    worst
}

/// The UGR of one cell from its glare sum and background.
fn ugr(sum: f64, e_wid: f64) -> f64 {
    8.0 * (std::f64::consts::PI / 4.0 * sum / e_wid).log10()
}

/// The UGR table of `klm` (cd per 1000 lm of lamps) with the luminous
/// `opening`, at spacing-to-height ratio `spacing`; `lamp_flux_lm` only
/// states the correction term.
pub fn ugr_table(
    klm: &CandelaTable,
    opening: &Opening,
    spacing: f64,
    lamp_flux_lm: f64,
) -> Result<UgrTable, UgrError> {
    if !is_method_spacing(spacing) {
        return Err(UgrError::Spacing(spacing));
    }
    if klm.flux_between_lm(0.0, 90.0) <= 1e-9 * klm.flux_lm().max(1e-30) {
        return Err(UgrError::UpwardOnly);
    }
    let background = indirect_wall_illuminance(klm, spacing);
    let mut crosswise = Vec::with_capacity(ROOMS.len());
    let mut endwise = Vec::with_capacity(ROOMS.len());
    for (r, &(x, y)) in ROOMS.iter().enumerate() {
        let cross = glare_sum(klm, opening, x, y, spacing, false);
        let end = glare_sum(klm, opening, x, y, spacing, true);
        if background[r].iter().any(|e| !(*e > 0.0)) {
            return Err(UgrError::NoBackground);
        }
        let cell = |sum: f64, e: f64| (sum > 0.0).then(|| round1(ugr(sum, e)));
        crosswise.push((0..5).map(|s| cell(cross, background[r][s])).collect());
        endwise.push((0..5).map(|s| cell(end, background[r][s])).collect());
    }
    Ok(UgrTable {
        spacing,
        reflectances: REFLECTANCES.to_vec(),
        rooms: ROOMS.iter().map(|&(x, y)| [x, y]).collect(),
        crosswise,
        endwise,
        lamp_flux_lm,
        correction: 8.0 * (lamp_flux_lm / 1000.0).log10(),
        height_m: H_M,
    })
}

fn round1(v: f64) -> f64 {
    (v * 10.0).round() / 10.0
}
