//! A direct evaluation of the UGR formula in the standard rooms, as a
//! check on the tabular method ([`crate::ugr`]) by different means: every
//! luminaire of the array placed and summed on its own (its own direction
//! to the eye, both sides of the line of sight), and the background from
//! a radiosity solution of the room instead of CIE 190's transfer
//! factors.
//!
//! The room is the cavity the method describes: the reference plane at
//! eye height (reflectance "floor"), the walls up to the luminaires'
//! plane H above it, the ceiling at that plane; luminaires hang just
//! below it. Surfaces are split into patches (H/2 square on floor and
//! ceiling, H/2 × H/4 on the walls), form factors between patches are
//! integrated on 2 × 2 points of each, the direct illuminance on 2 × 2
//! points of each patch from every luminaire, and the exitances solved by
//! Gauss–Seidel. The background luminance is the mean indirect wall
//! illuminance over π, as in CIE 190; the indirect vertical illuminance
//! at the eye itself is reported beside it.

use glam::DVec3;
use lucerna_photometry::CandelaTable;
use serde::Serialize;

use crate::guth::position_index;
use crate::luminance::Opening;
use crate::ugr::{H_M, REFLECTANCES, ROOMS};

/// One patch: centre, unit normal (into the room), two half-edge vectors.
#[derive(Debug, Clone, Copy)]
struct Patch {
    centre: DVec3,
    normal: DVec3,
    u: DVec3,
    v: DVec3,
    area: f64,
    /// 0 floor, 1 walls, 2 ceiling.
    surface: usize,
}

impl Patch {
    /// The 2 × 2 Gauss-like sample points (at the quarter points).
    fn points(&self) -> [DVec3; 4] {
        let h = 0.5;
        [(-h, -h), (h, -h), (-h, h), (h, h)].map(|(a, b)| self.centre + self.u * a + self.v * b)
    }
}

/// A rectangle from `origin` spanned by `a` and `b`, cut into na × nb
/// patches facing `normal`.
fn rectangle(
    origin: DVec3,
    a: DVec3,
    b: DVec3,
    na: usize,
    nb: usize,
    normal: DVec3,
    surface: usize,
    out: &mut Vec<Patch>,
) {
    let (da, db) = (a / na as f64, b / nb as f64);
    let area = da.length() * db.length();
    for i in 0..na {
        for j in 0..nb {
            let centre = origin + da * (i as f64 + 0.5) + db * (j as f64 + 0.5);
            out.push(Patch {
                centre,
                normal,
                u: da * 0.5,
                v: db * 0.5,
                area,
                surface,
            });
        }
    }
}

/// The room's patches: X across (x), Y along the line of sight (y), H up.
fn room_patches(x_m: f64, y_m: f64) -> Vec<Patch> {
    let h = H_M;
    let (nx, ny, nz) = (
        ((x_m / (0.5 * h)).round() as usize).max(1),
        ((y_m / (0.5 * h)).round() as usize).max(1),
        4,
    );
    let mut p = Vec::new();
    rectangle(
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(x_m, 0.0, 0.0),
        DVec3::new(0.0, y_m, 0.0),
        nx,
        ny,
        DVec3::new(0.0, 0.0, 1.0),
        0,
        &mut p,
    );
    rectangle(
        DVec3::new(0.0, 0.0, h),
        DVec3::new(x_m, 0.0, 0.0),
        DVec3::new(0.0, y_m, 0.0),
        nx,
        ny,
        DVec3::new(0.0, 0.0, -1.0),
        2,
        &mut p,
    );
    rectangle(
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(x_m, 0.0, 0.0),
        DVec3::new(0.0, 0.0, h),
        nx,
        nz,
        DVec3::new(0.0, 1.0, 0.0),
        1,
        &mut p,
    );
    rectangle(
        DVec3::new(0.0, y_m, 0.0),
        DVec3::new(x_m, 0.0, 0.0),
        DVec3::new(0.0, 0.0, h),
        nx,
        nz,
        DVec3::new(0.0, -1.0, 0.0),
        1,
        &mut p,
    );
    rectangle(
        DVec3::new(0.0, 0.0, 0.0),
        DVec3::new(0.0, y_m, 0.0),
        DVec3::new(0.0, 0.0, h),
        ny,
        nz,
        DVec3::new(1.0, 0.0, 0.0),
        1,
        &mut p,
    );
    rectangle(
        DVec3::new(x_m, 0.0, 0.0),
        DVec3::new(0.0, y_m, 0.0),
        DVec3::new(0.0, 0.0, h),
        ny,
        nz,
        DVec3::new(-1.0, 0.0, 0.0),
        1,
        &mut p,
    );
    p
}

/// Form factor from patch i to patch j (fraction of i's diffuse exitance
/// that reaches j), on the patches' sample points.
fn form_factor(i: &Patch, j: &Patch) -> f64 {
    let mut f = 0.0;
    for a in i.points() {
        for b in j.points() {
            let d = b - a;
            let r2 = d.dot(d);
            let ci = i.normal.dot(d);
            let cj = -j.normal.dot(d);
            if ci > 0.0 && cj > 0.0 && r2 > 1e-12 {
                f += ci * cj / (std::f64::consts::PI * r2 * r2);
            }
        }
    }
    f * j.area / 16.0
}

/// Luminaire positions (m) of the array at spacing `s` (in H).
fn luminaires(x: f64, y: f64, s: f64) -> Vec<DVec3> {
    let (nx, ny) = ((x / s).round() as usize, (y / s).round() as usize);
    let mut v = Vec::with_capacity(nx * ny);
    for i in 0..nx {
        for j in 0..ny {
            v.push(DVec3::new(
                (i as f64 + 0.5) * s * H_M,
                (j as f64 + 0.5) * s * H_M,
                H_M,
            ));
        }
    }
    v
}

/// The luminaire's (C, γ) towards a point `d` away from it, with its C0
/// axis along `c0_axis` (unit, horizontal).
fn c_gamma(d: DVec3, c0_axis: [f64; 2]) -> (f64, f64) {
    let horizontal = d[0].hypot(d[1]);
    let gamma = horizontal.atan2(-d[2]).to_degrees();
    let c90_axis = [-c0_axis[1], c0_axis[0]];
    let along = d[0] * c0_axis[0] + d[1] * c0_axis[1];
    let across = d[0] * c90_axis[0] + d[1] * c90_axis[1];
    (across.atan2(along).to_degrees().rem_euclid(360.0), gamma)
}

/// One room's direct evaluation.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct DirectRoom {
    pub room: [f64; 2],
    /// Per reflectance set: mean indirect wall illuminance (lx).
    pub wall_indirect_lux: [f64; 5],
    /// Per reflectance set: indirect vertical illuminance at the eye (lx).
    pub eye_indirect_lux: [f64; 5],
    /// UGR with the mean wall background, crosswise and endwise.
    pub crosswise: [f64; 5],
    pub endwise: [f64; 5],
}

/// The direct evaluation of every standard room for `klm` (cd per 1000 lm
/// of lamps) at spacing `s` (in H).
pub fn direct_ugr(klm: &CandelaTable, opening: &Opening, s: f64) -> Vec<DirectRoom> {
    ROOMS
        .iter()
        .map(|&(x, y)| direct_room(klm, opening, x, y, s))
        .collect()
}

pub fn direct_room(klm: &CandelaTable, opening: &Opening, x: f64, y: f64, s: f64) -> DirectRoom {
    let (x_m, y_m) = (x * H_M, y * H_M);
    let patches = room_patches(x_m, y_m);
    let lights = luminaires(x, y, s);
    // Crosswise: the luminaires' C0 axis along the line of sight (+y).
    let c0_axis = [0.0, 1.0];
    // Direct illuminance on each patch (lx), sampled on its 4 points;
    // the upward flux lands on the ceiling patch above each luminaire.
    let upward_lm = klm.flux_between_lm(90.0, 180.0);
    let mut direct: Vec<f64> = patches
        .iter()
        .map(|p| {
            let mut e = 0.0;
            for point in p.points() {
                for l in &lights {
                    let d = point - *l;
                    let r2 = d.dot(d);
                    let cos_in = -p.normal.dot(d) / r2.sqrt();
                    if cos_in <= 0.0 || d[2] >= 0.0 {
                        continue;
                    }
                    let (c, g) = c_gamma(d, c0_axis);
                    e += klm.intensity(c, g) * cos_in / r2;
                }
            }
            0.25 * e
        })
        .collect();
    for l in &lights {
        if let Some(k) = patches.iter().position(|p| {
            p.surface == 2
                && (l[0] - p.centre[0]).abs() <= p.u[0].abs() + 1e-9
                && (l[1] - p.centre[1]).abs() <= p.v[1].abs() + 1e-9
        }) {
            direct[k] += upward_lm / patches[k].area;
        }
    }
    let n = patches.len();
    let mut factors = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            if i != j {
                factors[i * n + j] = form_factor(&patches[i], &patches[j]);
            }
        }
    }
    // The eye: at the middle of the wall y = 0, at eye height, facing +y;
    // a hair inside the room.
    let eye = DVec3::new(0.5 * x_m, 1e-3, 1e-3);
    let eye_factor: Vec<f64> = patches
        .iter()
        .map(|p| {
            p.points()
                .iter()
                .map(|&b| {
                    let d = b - eye;
                    let r2 = d.dot(d);
                    let ce = d[1] / r2.sqrt();
                    let cp = -p.normal.dot(d) / r2.sqrt();
                    if ce > 0.0 && cp > 0.0 {
                        ce * cp / (std::f64::consts::PI * r2)
                    } else {
                        0.0
                    }
                })
                .sum::<f64>()
                * p.area
                / 4.0
        })
        .collect();
    let mut wall_indirect_lux = [0.0; 5];
    let mut eye_indirect_lux = [0.0; 5];
    for (k, rho) in REFLECTANCES.iter().enumerate() {
        let reflectance = |p: &Patch| match p.surface {
            0 => rho[2],
            1 => rho[1],
            _ => rho[0],
        };
        let mut exitance: Vec<f64> = patches
            .iter()
            .zip(&direct)
            .map(|(p, e)| reflectance(p) * e)
            .collect();
        for _ in 0..200 {
            let mut change = 0.0f64;
            for i in 0..n {
                let incident: f64 = (0..n).map(|j| factors[i * n + j] * exitance[j]).sum();
                let b = reflectance(&patches[i]) * (direct[i] + incident);
                change = change.max((b - exitance[i]).abs());
                exitance[i] = b;
            }
            if change < 1e-9 {
                break;
            }
        }
        // Indirect illuminance on the walls: what arrives from the other
        // patches' exitance (area-weighted mean).
        let (mut sum, mut area) = (0.0, 0.0);
        for i in 0..n {
            if patches[i].surface == 1 {
                let incident: f64 = (0..n).map(|j| factors[i * n + j] * exitance[j]).sum();
                sum += incident * patches[i].area;
                area += patches[i].area;
            }
        }
        wall_indirect_lux[k] = sum / area;
        eye_indirect_lux[k] = eye_factor.iter().zip(&exitance).map(|(f, b)| f * b).sum();
    }
    let sum = |endwise: bool| glare_sum_direct(klm, opening, &lights, eye, endwise);
    let (cross, end) = (sum(false), sum(true));
    let ugr = |g: f64, e: f64| 8.0 * (std::f64::consts::PI / 4.0 * g / e).log10();
    DirectRoom {
        room: [x, y],
        wall_indirect_lux,
        eye_indirect_lux,
        crosswise: wall_indirect_lux.map(|e| ugr(cross, e)),
        endwise: wall_indirect_lux.map(|e| ugr(end, e)),
    }
}

/// Σ I² / (A_p D² p²) over the luminaires, each at its own place, with
/// the eye looking along +y.
fn glare_sum_direct(
    klm: &CandelaTable,
    opening: &Opening,
    lights: &[DVec3],
    eye: DVec3,
    endwise: bool,
) -> f64 {
    // Endwise the luminaires are turned a quarter: their C0 axis across
    // the line of sight.
    let c0_axis = if endwise { [1.0, 0.0] } else { [0.0, 1.0] };
    let mut sum = 0.0;
    for l in lights {
        let to_eye = DVec3::new(eye.x, eye.y, 0.0) - DVec3::new(l.x, l.y, H_M);
        let (r, t, h) = (-to_eye[1], to_eye[0].abs(), H_M);
        if r <= 0.0 {
            continue;
        }
        let Some(p) = position_index(h / r, t / r) else {
            continue;
        };
        let d2 = to_eye.dot(to_eye);
        let (c, g) = c_gamma(to_eye, c0_axis);
        let i = klm.intensity(c, g);
        let area = opening.projected_area_m2(c, g);
        if i > 0.0 && area > 0.0 {
            sum += i * i / (area * d2 * p * p);
        }
    }
    sum
}
