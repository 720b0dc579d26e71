//! The IES TM-15-11 (Addendum A) BUG rating of an outdoor luminaire:
//! backlight, uplight and glare from the lumens in its secondary solid
//! angles.
//!
//! Zones (vertical angle from nadir): low 0–30°, mid 30–60°, high 60–80°,
//! very high 80–90°, front and back; uplight low 90–100°, high 100–180°.
//! Front (the street side) is the half of the C circle centred on
//! [`BugOrientation`]: C0 for IES files (TM-15 and LM-63's type C: the
//! street side runs from 270° through 0° to 90°, the AGi32 Photometric
//! Toolbox's "Street Side"), C90 for EULUMDAT road luminaires, whose C0
//! lies along the kerb. The lumen limits are TM-15-11 Addendum A, tables
//! A-1 (backlight), A-2 (uplight) and A-3 (glare); the separate glare
//! table of type V and quadrilateral-symmetric luminaires is not applied.

use lucerna_photometry::CandelaTable;
use serde::Serialize;

/// Lumens in each zone of TM-15-11 figure A-1.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct BugZones {
    pub fl: f64,
    pub fm: f64,
    pub fh: f64,
    pub fvh: f64,
    pub bl: f64,
    pub bm: f64,
    pub bh: f64,
    pub bvh: f64,
    pub ul: f64,
    pub uh: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BugRating {
    pub orientation: BugOrientation,
    pub backlight: u8,
    pub uplight: u8,
    pub glare: u8,
    /// "B1 U0 G1".
    pub label: String,
    pub zones_lm: BugZones,
}

/// Backlight limits (lm), ratings B0..B4: BH, BM, BL (table A-1).
const BACKLIGHT: [[f64; 3]; 5] = [
    [110.0, 220.0, 110.0],
    [500.0, 1000.0, 500.0],
    [1000.0, 2500.0, 1000.0],
    [2500.0, 5000.0, 2500.0],
    [5000.0, 8500.0, 5000.0],
];
/// Uplight limits (lm), ratings U0..U4: UH, UL (table A-2).
const UPLIGHT: [[f64; 2]; 5] = [
    [0.0, 0.0],
    [10.0, 10.0],
    [50.0, 50.0],
    [500.0, 500.0],
    [1000.0, 1000.0],
];
/// Glare limits (lm), ratings G0..G4: FVH, BVH, FH, BH (table A-3).
const GLARE: [[f64; 4]; 5] = [
    [10.0, 10.0, 660.0, 110.0],
    [100.0, 100.0, 1800.0, 500.0],
    [225.0, 225.0, 5000.0, 1000.0],
    [500.0, 500.0, 7500.0, 2500.0],
    [750.0, 750.0, 12000.0, 5000.0],
];

/// The lowest rating whose limits all hold; 5 beyond the last.
fn rating(values: &[f64], limits: &[impl AsRef<[f64]>]) -> u8 {
    limits
        .iter()
        .position(|l| values.iter().zip(l.as_ref()).all(|(v, max)| *v <= *max))
        .unwrap_or(limits.len()) as u8
}

/// Flux (lm) in γ ∈ [g0, g1] and C ∈ [c0, c1] (degrees), by the midpoint
/// rule on 0.25° × 0.5° cells of the table's interpolant.
fn zone_flux(table: &CandelaTable, g0: f64, g1: f64, c0: f64, c1: f64) -> f64 {
    let (dg, dc) = (0.25f64, 0.5f64);
    let (ng, nc) = (
        ((g1 - g0) / dg).round() as usize,
        ((c1 - c0) / dc).round() as usize,
    );
    let mut sum = 0.0;
    for i in 0..ng {
        let g = g0 + (i as f64 + 0.5) * dg;
        // Exact band solid angle per unit C (rad).
        let band = (g - 0.5 * dg).to_radians().cos() - (g + 0.5 * dg).to_radians().cos();
        let mut row = 0.0;
        for j in 0..nc {
            row += table.intensity(c0 + (j as f64 + 0.5) * dc, g);
        }
        sum += row * band * dc.to_radians();
    }
    sum
}

/// Where the street side of an outdoor luminaire's C circle is centred.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum BugOrientation {
    /// Front centred on C0 (IES type C road data).
    FrontAtC0,
    /// Front centred on C90 (EULUMDAT road data, luminaire along C0-C180).
    FrontAtC90,
}

impl BugOrientation {
    fn front_centre_deg(self) -> f64 {
        match self {
            BugOrientation::FrontAtC0 => 0.0,
            BugOrientation::FrontAtC90 => 90.0,
        }
    }
}

/// The BUG rating of a table in absolute lumens (scale relative
/// photometry to the rated lamp flux before).
pub fn bug_rating(table: &CandelaTable, orientation: BugOrientation) -> BugRating {
    let centre = orientation.front_centre_deg();
    let front = |g0, g1| zone_flux(table, g0, g1, centre - 90.0, centre + 90.0);
    let back = |g0, g1| zone_flux(table, g0, g1, centre + 90.0, centre + 270.0);
    let all = |g0, g1| front(g0, g1) + back(g0, g1);
    let z = BugZones {
        fl: front(0.0, 30.0),
        fm: front(30.0, 60.0),
        fh: front(60.0, 80.0),
        fvh: front(80.0, 90.0),
        bl: back(0.0, 30.0),
        bm: back(30.0, 60.0),
        bh: back(60.0, 80.0),
        bvh: back(80.0, 90.0),
        ul: all(90.0, 100.0),
        uh: all(100.0, 180.0),
    };
    let backlight = rating(&[z.bh, z.bm, z.bl], &BACKLIGHT);
    let uplight = rating(&[z.uh, z.ul], &UPLIGHT);
    let glare = rating(&[z.fvh, z.bvh, z.fh, z.bh], &GLARE);
    BugRating {
        orientation,
        backlight,
        uplight,
        glare,
        label: format!("B{backlight} U{uplight} G{glare}"),
        zones_lm: z,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An isotropic source of 4π·I lm puts (cos g0 − cos g1)·π·I in each
    /// half-circle zone: the zones hold the exact closed form.
    #[test]
    fn zones_of_an_isotropic_source_are_exact() {
        let i = 100.0;
        let table = CandelaTable::from_fn(5.0, 1.0, |_, _| i);
        let r = bug_rating(&table, BugOrientation::FrontAtC0);
        let exact = |g0: f64, g1: f64| {
            std::f64::consts::PI * i * (g0.to_radians().cos() - g1.to_radians().cos())
        };
        let z = r.zones_lm;
        for (got, want) in [
            (z.fl, exact(0.0, 30.0)),
            (z.bh, exact(60.0, 80.0)),
            (z.fvh, exact(80.0, 90.0)),
            (z.ul, 2.0 * exact(90.0, 100.0)),
            (z.uh, 2.0 * exact(100.0, 180.0)),
        ] {
            assert!((got - want).abs() < 1e-5 * want, "{got} vs {want}");
        }
        // 628 lm upwards of 100°: U4 allows 1000.
        assert_eq!(r.uplight, 4);
    }

    #[test]
    fn a_full_cutoff_forward_throw_is_b0_u0() {
        // 200 cd towards the street (C90) only, below 60°: 0 lm back and up.
        let table = CandelaTable::from_fn(5.0, 1.0, |c, g| {
            if g < 60.0 && c > 5.0 && c < 175.0 {
                200.0
            } else {
                0.0
            }
        });
        let r = bug_rating(&table, BugOrientation::FrontAtC90);
        assert_eq!(
            (r.backlight, r.uplight, r.glare),
            (0, 0, 0),
            "{:?}",
            r.zones_lm
        );
        assert_eq!(r.label, "B0 U0 G0");
        // Read as IES road data, the same light is half backlight.
        let r = bug_rating(&table, BugOrientation::FrontAtC0);
        let z = r.zones_lm;
        assert!(
            z.bl > 30.0 && (z.bl - z.fl).abs() < 1e-9 && (z.bm - z.fm).abs() < 1e-9,
            "{z:?}"
        );
    }
}
