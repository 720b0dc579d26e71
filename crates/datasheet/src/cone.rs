//! The cone diagram of a narrow beam: at 1–5 m straight below the
//! luminaire, the illuminance at the beam's centre and the diameter of the
//! beam (50 % of the peak) in each main plane.

use lucerna_photometry::CandelaTable;
use serde::Serialize;

/// Beams at least this wide get no cone diagram (it would show a wash,
/// not a beam; datasheets print it for spots and narrow floods).
pub const CONE_MAX_BEAM_DEG: f64 = 60.0;
pub const CONE_DISTANCES_M: [f64; 5] = [1.0, 2.0, 3.0, 4.0, 5.0];

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConeRow {
    pub distance_m: f64,
    /// I(γ = 0) / d² (lx), for the file's own flux.
    pub centre_lux: f64,
    /// 2 d tan(beam / 2) in C0-C180 and C90-C270 (m).
    pub beam_diameter_m: [f64; 2],
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ConeDiagram {
    pub beam_angle_deg: [f64; 2],
    pub rows: Vec<ConeRow>,
}

/// The cone diagram, or why there is none.
pub fn cone_diagram(
    table: &CandelaTable,
    beam_angle_deg: [Option<f64>; 2],
) -> Result<ConeDiagram, String> {
    let [Some(a), Some(b)] = beam_angle_deg else {
        return Err(
            "the intensity never falls to half its peak in a main plane: no beam to draw".into(),
        );
    };
    if a.max(b) >= CONE_MAX_BEAM_DEG {
        return Err(format!(
            "beam angle {:.0}° is not under {CONE_MAX_BEAM_DEG:.0}°: a cone diagram is drawn for narrow beams",
            a.max(b)
        ));
    }
    let centre_cd = table.intensity(0.0, 0.0);
    let peak = table.peak().0;
    if centre_cd < 0.5 * peak {
        return Err(format!(
            "the beam is not centred on the nadir (I(γ 0°) is {:.0} % of the peak): a cone diagram would mislead",
            100.0 * centre_cd / peak
        ));
    }
    Ok(ConeDiagram {
        beam_angle_deg: [a, b],
        rows: CONE_DISTANCES_M
            .iter()
            .map(|&d| ConeRow {
                distance_m: d,
                centre_lux: centre_cd / (d * d),
                beam_diameter_m: [a, b].map(|beam| 2.0 * d * (0.5 * beam).to_radians().tan()),
            })
            .collect(),
    })
}
