//! The polygonal-light integral (Luksch et al. 2020, eq. 1–3, with the
//! radiance substitution L = I / (A cos θ)) in polar coordinates around
//! the receiver's foot point on the opening's plane: the near-field rule
//! of the preview room (its exact reference, which sweeps the same
//! triangles, is in [`crate::reference`]).
//!
//! In luminaire coordinates the opening lies in z = 0. A receiver at
//! height h from that plane has its foot point F there; a point of the
//! opening at distance ρ and angle φ from F is seen along an emission
//! direction whose angle θ from the opening's normal depends on ρ only
//! (tan θ = ρ / h) and whose C-plane depends on φ only (C = φ + 180°).
//! E = 1/A ∫ I cos θx / r² dA then reads
//!
//!   E = 1/A ∫ dφ ∫ I(C, θ) [sₙ(φ) (sec θ − cos θ) ± n_z sin θ] dθ,
//!
//! sₙ the receiver normal's component along the ray, n_z the one along
//! the opening's axis. Per C column the two radial integrals are
//! cumulative sums of the profile ([`RadialTables`]), exact for its
//! piecewise-linear interpolant: a narrow beam costs nothing extra. The
//! angular integral is a sum, over the edges of the horizon-clipped
//! opening, of signed triangles (F, a, b). The renderer's rule takes a few
//! Gauss–Legendre nodes per piece of the sweep, pieces cut at vertices and
//! at the profile's kinked C-planes ([`illuminance`]); the reference
//! integrates the same triangles adaptively, with exact cell integrals
//! ([`crate::reference::exact_illuminance`]).

use glam::{DVec2, DVec3};
use smallvec::SmallVec;

use crate::light::{Opening, PlacedLight};
use crate::profile::ProfileGrid;
use crate::radial::{
    Partial, RadialTables, SERIES_FROM_U, angular_moment, inverse_tangent_integral, node_index,
};
use crate::shading::{CubatureResult, point_illuminance};

/// Receivers closer to the opening's plane than this fraction of its size
/// are shaded at that height in front: the front-side limit to 1e-4 beside
/// the opening (E − E₀ = O(h)), a finite value on the opening itself
/// (where E grows as ln(1/h) if the profile is lit at 90°, and the view
/// shows the opening's luminance anyway), and a band wide enough that the
/// shader's f32 heights fall in it as the CPU's do.
pub const IN_PLANE: f64 = 1e-4;

/// Largest angle (seen from the foot point) one group of Gauss–Legendre
/// nodes of the renderer's rule spans; an edge subtending more is split.
pub const MAX_ARC_RAD: f64 = std::f64::consts::FRAC_PI_4;

/// Angles (seen from the foot point) up to which 2 Gauss–Legendre nodes
/// take a piece of the sweep: the far field, where the opening is small.
pub const SMALL_ARC_RAD: f64 = std::f64::consts::PI / 32.0;

/// Angles up to which 3 nodes take a piece of the sweep.
pub const MEDIUM_ARC_RAD: f64 = std::f64::consts::PI / 8.0;

/// cos of the largest turn of the boundary at a vertex across which the
/// rule's pieces are joined (35°).
const SOFT_VERTEX_COS: f64 = 0.819_152_044_288_992;

/// Gauss–Legendre nodes on [0, 1] and their weights, 3 points.
const GAUSS3: [(f64, f64); 3] = [
    (0.112_701_665_379_258_3, 5.0 / 18.0),
    (0.5, 8.0 / 18.0),
    (0.887_298_334_620_741_7, 5.0 / 18.0),
];

/// Gauss–Legendre nodes on [0, 1] and their weights, 2 points.
const GAUSS2: [(f64, f64); 2] = [
    (0.211_324_865_405_187_1, 0.5),
    (0.788_675_134_594_812_9, 0.5),
];

/// Gauss–Legendre nodes on [0, 1] and their weights, 4 points.
const GAUSS4: [(f64, f64); 4] = [
    (0.069_431_844_202_973_7, 0.173_927_422_568_726_9),
    (0.330_009_478_207_571_9, 0.326_072_577_431_273_1),
    (0.669_990_521_792_428_1, 0.326_072_577_431_273_1),
    (0.930_568_155_797_026_3, 0.173_927_422_568_726_9),
];

/// A receiver seen in the opening's frame.
#[derive(Debug, Clone)]
pub(crate) struct PolarSetup {
    /// The horizon-clipped opening, relative to the foot point (m).
    pub(crate) polygon: SmallVec<[DVec2; 16]>,
    /// Distance from the opening's plane (m), at least the plane epsilon.
    pub(crate) height: f64,
    /// In front of the opening (the emitting side).
    front: bool,
    /// The receiver's unit normal in luminaire coordinates.
    normal: DVec3,
}

impl PolarSetup {
    /// ±1: the sign of the axial term, + in front.
    fn side(&self) -> f64 {
        if self.front { 1.0 } else { -1.0 }
    }
}

/// The foot point, side and horizon-clipped opening of receiver x
/// (normal n, room coordinates). In the opening's plane (closer than
/// `IN_PLANE` × size) the receiver takes the front-side limit, as the
/// shader does.
pub(crate) fn setup(light: &PlacedLight, x: DVec3, n: DVec3) -> Option<PolarSetup> {
    let to_luminaire = light.rotation.transpose();
    let xl = to_luminaire * (x - light.position);
    let normal = to_luminaire * n;
    // No radiance substitution is singular here (the radial integrals are
    // finite at any height but 0); the plane is taken as its front-side
    // limit, `IN_PLANE` × size in front.
    let epsilon = IN_PLANE * light.size_m();
    let signed = -xl.z; // the emitting normal is −z
    let (height, front) = if signed.abs() < epsilon {
        (epsilon, true)
    } else {
        (signed.abs(), signed > 0.0)
    };
    let side = if front { 1.0 } else { -1.0 };
    let foot = DVec2::new(xl.x, xl.y);
    let nxy = DVec2::new(normal.x, normal.y);
    // Above x's horizon: (p − x)·n ≥ 0, p on the opening's plane.
    let above = |q: DVec2| q.dot(nxy) + side * height * normal.z;
    let opening = light.opening.polygon();
    let mut polygon: SmallVec<[DVec2; 16]> = SmallVec::new();
    for i in 0..opening.len() {
        let a = opening[i].truncate() - foot;
        let b = opening[(i + 1) % opening.len()].truncate() - foot;
        let (da, db) = (above(a), above(b));
        if da >= 0.0 {
            polygon.push(a);
        }
        if (da >= 0.0) != (db >= 0.0) {
            polygon.push(a + (b - a) * (da / (da - db)));
        }
    }
    // Counter-clockwise in the (x, y) plane, so that the signed triangles
    // of the edges sum to the area inside (the opening's own order is
    // counter-clockwise seen from below, i.e. clockwise here).
    let twice_area: f64 = (0..polygon.len())
        .map(|i| polygon[i].perp_dot(polygon[(i + 1) % polygon.len()]))
        .sum();
    if twice_area < 0.0 {
        polygon.reverse();
    }
    (polygon.len() >= 3).then_some(PolarSetup {
        polygon,
        height,
        front,
        normal,
    })
}

/// A ray's end at tan θ = t: its γ cell and the weights that make the
/// cell's partial radial integrals linear in the cell's I₀ and slope m
/// (see `radial::partial_cell`), shared by the two C columns read.
#[derive(Debug, Clone, Copy)]
struct RayEnd {
    j0: usize,
    du: f64,
    lever: f64,
    moment: f64,
    sin_i0: f64,
    sin_m: f64,
    cos_i0: f64,
    cos_m: f64,
}

impl RayEnd {
    fn new(tables: &RadialTables, step: f64, t: f64, how: Partial) -> RayEnd {
        let half = tables.node_u.len();
        let theta = t.atan();
        let j0 = ((theta / step) as usize).min(half - 1);
        let theta0 = j0 as f64 * step;
        let q = (1.0 + t * t).sqrt();
        let (s1, c1) = (t / q, 1.0 / q);
        let (s0, c0) = (tables.node_sin[j0], tables.node_cos[j0]);
        let u0 = tables.node_u[j0];
        // asinh t = ln(t + √(1 + t²)), and e^−u = 1 / (t + √(1 + t²)).
        let exp_u = t + q;
        let u = exp_u.ln();
        let moment = match how {
            Partial::Exact => angular_moment(u0, u, true),
            Partial::Fast if u0 >= SERIES_FROM_U => {
                inverse_tangent_integral(tables.node_exp[j0])
                    - inverse_tangent_integral(1.0 / exp_u)
            }
            // atan(e^−v) at the midpoint in u, to first order from the
            // node (a cell spans at most 0.03 of u below 74.6°).
            Partial::Fast => {
                let du = u - u0;
                (tables.node_moment[j0] + 0.5 * du * tables.node_moment_slope[j0]) * du
            }
        };
        let dt = theta - theta0;
        RayEnd {
            j0,
            du: u - u0,
            lever: std::f64::consts::FRAC_PI_2 - theta0,
            moment,
            sin_i0: c0 - c1,
            sin_m: s1 - s0 - dt * c1,
            cos_i0: s1 - s0,
            cos_m: dt * s1 + c1 - c0,
        }
    }
}

/// The radial integrand's two integrals (sec − cos kernel, sin kernel)
/// from θ = 0 to atan(`t`) along C-plane `c_deg`: the tables up to the
/// cell, and the partial cell (`partial_cell` with the ray end's weights).
fn radial(
    grid: &ProfileGrid,
    tables: &RadialTables,
    c_deg: f64,
    t: f64,
    front: bool,
    how: Partial,
) -> (f64, f64) {
    let gc = grid.gamma_count;
    let step = grid.gamma_step_deg.to_radians();
    let end = RayEnd::new(tables, step, t, how);
    let (i_lo, i_hi) = (
        node_index(gc, front, end.j0),
        node_index(gc, front, end.j0 + 1),
    );
    let column = |c: usize| -> (f64, f64) {
        let i0 = grid.candela[c * gc + i_lo] as f64;
        let m = (grid.candela[c * gc + i_hi] as f64 - i0) / step;
        let cos_kernel = i0 * end.cos_i0 + m * end.cos_m;
        let sec = (i0 + m * end.lever) * end.du - 2.0 * m * end.moment - cos_kernel;
        (
            tables.sec[c * gc + i_lo] + sec,
            tables.sin[c * gc + i_lo] + i0 * end.sin_i0 + m * end.sin_m,
        )
    };
    if grid.c_count == 1 {
        return column(0);
    }
    let cf = (c_deg.rem_euclid(360.0) / grid.c_step_deg).clamp(0.0, (grid.c_count - 1) as f64);
    let c0 = (cf as usize).min(grid.c_count - 2);
    let tc = cf - c0 as f64;
    let (s0, k0) = column(c0);
    let (s1, k1) = column(c0 + 1);
    (s0 + (s1 - s0) * tc, k0 + (k1 - k0) * tc)
}

impl PolarSetup {
    /// Whether the foot point is inside the clipped opening (or on its
    /// boundary).
    pub(crate) fn foot_inside(&self) -> bool {
        // Convex: inside when the foot point is on one side of every edge.
        let m = self.polygon.len();
        let (mut positive, mut negative) = (false, false);
        for i in 0..m {
            let c = self.polygon[i].perp_dot(self.polygon[(i + 1) % m]);
            positive |= c > 0.0;
            negative |= c < 0.0;
        }
        !(positive && negative)
    }

    /// The directions of the vertices seen from the foot point, increasing,
    /// each with whether its vertex is soft: between two consecutive ones
    /// every ray enters and leaves the opening through the same edges. The whole circle (first + 2π last) when the
    /// foot point is inside, else the span between the two tangent vertices.
    pub(crate) fn sweep(&self, inside: bool) -> SmallVec<[(f64, bool); 18]> {
        let pi = std::f64::consts::PI;
        let m = self.polygon.len();
        // A soft vertex turns the boundary by under 35° (a disk's 12-gon):
        // the integrand's kink there is slight.
        let soft = |i: usize| {
            let e0 = self.polygon[i] - self.polygon[(i + m - 1) % m];
            let e1 = self.polygon[(i + 1) % m] - self.polygon[i];
            e0.dot(e1) >= SOFT_VERTEX_COS * (e0.length() * e1.length())
        };
        let mut angles: SmallVec<[(f64, bool); 18]> = SmallVec::new();
        if inside {
            for (i, v) in self.polygon.iter().enumerate() {
                if v.length_squared() > 0.0 {
                    angles.push((v.y.atan2(v.x), soft(i)));
                }
            }
            angles.sort_by(|a, b| a.0.total_cmp(&b.0));
            if let Some(&(first, soft)) = angles.first() {
                angles.push((first + 2.0 * pi, soft));
            }
        } else {
            let centre = self.polygon.iter().copied().sum::<DVec2>() / m as f64;
            let reference = centre.y.atan2(centre.x);
            let wrap = |x: f64| (x + pi).rem_euclid(2.0 * pi) - pi;
            for (i, v) in self.polygon.iter().enumerate() {
                angles.push((reference + wrap(v.y.atan2(v.x) - reference), soft(i)));
            }
            angles.sort_by(|a, b| a.0.total_cmp(&b.0));
        }
        angles
    }

    /// Where the ray from the foot point along `dir` is inside the opening:
    /// (ρ in, ρ out), ρ in = 0 when the foot point is inside.
    fn span(&self, dir: DVec2, inside: bool) -> Option<(f64, f64)> {
        let m = self.polygon.len();
        let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
        for i in 0..m {
            let a = self.polygon[i];
            let edge = self.polygon[(i + 1) % m] - a;
            let denominator = dir.perp_dot(edge);
            if denominator == 0.0 {
                continue;
            }
            // ρ dir = a + s (b − a).
            let along = a.perp_dot(dir) / denominator;
            if !(-1e-12..=1.0 + 1e-12).contains(&along) {
                continue;
            }
            let rho = (a.perp_dot(edge) / denominator).max(0.0);
            lo = lo.min(rho);
            hi = hi.max(rho);
        }
        if hi < lo {
            return None;
        }
        Some(if inside { (0.0, hi) } else { (lo, hi) })
    }

    /// J(φ): the radial integral over the part of the ray along φ inside
    /// the opening, both ends read in the same C column (so that the part
    /// between a foot point outside and the opening cancels exactly).
    pub(crate) fn ray_integral(
        &self,
        grid: &ProfileGrid,
        phi: f64,
        inside: bool,
        how: Partial,
    ) -> f64 {
        let (sin_phi, cos_phi) = phi.sin_cos();
        let dir = DVec2::new(cos_phi, sin_phi);
        let Some((rho_in, rho_out)) = self.span(dir, inside) else {
            return 0.0;
        };
        let c_deg = phi.to_degrees() + 180.0;
        let tables = &grid.radial;
        let (mut sec, mut sin) =
            radial(grid, tables, c_deg, rho_out / self.height, self.front, how);
        if rho_in > 0.0 {
            let (s0, k0) = radial(grid, tables, c_deg, rho_in / self.height, self.front, how);
            sec -= s0;
            sin -= k0;
        }
        let s_n = dir.x * self.normal.x + dir.y * self.normal.y;
        s_n * sec + self.side() * self.normal.z * sin
    }
}

/// ∫ cos dω over the clipped opening seen from the receiver (sr), Lambert's
/// edge formula: what the specular term divides the illuminance by.
fn cosine_solid_angle(s: &PolarSetup) -> f64 {
    let z = if s.front { -s.height } else { s.height };
    // Vertices relative to the receiver, in luminaire coordinates.
    let v = |q: DVec2| DVec3::new(q.x, q.y, -z).normalize_or_zero();
    let m = s.polygon.len();
    let mut sum = 0.0;
    for i in 0..m {
        let (p, q) = (v(s.polygon[i]), v(s.polygon[(i + 1) % m]));
        let c = p.cross(q);
        let l = c.length();
        if l > 1e-300 {
            sum += l.atan2(p.dot(q)) * c.dot(s.normal) / l;
        }
    }
    0.5 * sum.abs()
}

/// The nodes of the renderer's rule: how finely the sweep is cut.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RuleNodes {
    /// Pieces up to this angle take 2 Gauss–Legendre nodes.
    pub small_arc_rad: f64,
    /// Pieces up to this angle take 3.
    pub medium_arc_rad: f64,
    /// Longer pieces are cut into arcs of at most this, 4 nodes each.
    pub max_arc_rad: f64,
    /// Pieces are also cut where the ray's C-plane crosses a multiple of
    /// this (the profile's kinked C-planes, `ProfileGrid::c_kink_step_deg`);
    /// 0: not cut.
    pub kink_step_rad: f64,
}

impl RuleNodes {
    /// The preview room's rule for a profile.
    pub fn for_profile(grid: &ProfileGrid) -> RuleNodes {
        RuleNodes {
            small_arc_rad: SMALL_ARC_RAD,
            medium_arc_rad: MEDIUM_ARC_RAD,
            max_arc_rad: MAX_ARC_RAD,
            kink_step_rad: grid.c_kink_step_deg.to_radians(),
        }
    }

    /// The draft rule (the editor's room while a drag runs): each piece
    /// takes 2 nodes up to `DRAFT_SMALL_ARC_RAD`, 3 up to twice that, 4 per
    /// `DRAFT_MAX_ARC_RAD`, with the same cuts. About 0.7 of the nodes;
    /// on the section 6 protocol mean-normalised errors up to 0.045 (a
    /// louvre at h = 0.1), against 0.005 for the full rule.
    pub fn draft(grid: &ProfileGrid) -> RuleNodes {
        RuleNodes {
            small_arc_rad: DRAFT_SMALL_ARC_RAD,
            medium_arc_rad: 2.0 * DRAFT_SMALL_ARC_RAD,
            max_arc_rad: DRAFT_MAX_ARC_RAD,
            ..RuleNodes::for_profile(grid)
        }
    }
}

/// The draft rule's largest 2-node piece (π/8).
pub const DRAFT_SMALL_ARC_RAD: f64 = std::f64::consts::PI / 8.0;
/// The draft rule's longest 4-node arc (π/2).
pub const DRAFT_MAX_ARC_RAD: f64 = std::f64::consts::FRAC_PI_2;

/// Illuminance by the polar rule: the sweep between consecutive vertex
/// directions seen from the foot point, cut where the ray's C-plane
/// crosses one of the profile's kinked C-planes (where the angular
/// integrand's slope jumps), each piece taken by 2, 3 or 4 Gauss–Legendre
/// nodes in φ by its size (`SMALL_ARC_RAD`, `MEDIUM_ARC_RAD`, 4 per
/// `MAX_ARC_RAD`), each node an exact radial integral over the ray's part
/// inside the horizon-clipped opening (but for a midpoint in u below
/// 74.6°). The preview room's default; the shader's twin.
pub fn illuminance(light: &PlacedLight, x: DVec3, n: DVec3) -> CubatureResult {
    illuminance_with_nodes(light, x, n, RuleNodes::for_profile(&light.profile)).0
}

/// The polar rule with the given nodes, and how many ray integrals it took.
pub fn illuminance_with_nodes(
    light: &PlacedLight,
    x: DVec3,
    n: DVec3,
    rule: RuleNodes,
) -> (CubatureResult, usize) {
    if light.opening == Opening::Point {
        return (point_illuminance(light, x, n), 1);
    }
    let Some(s) = setup(light, x, n) else {
        return (CubatureResult::default(), 0);
    };
    let grid = &light.profile;
    let inside = s.foot_inside();
    let sweep = s.sweep(inside);
    // Pieces between vertex directions, joined across soft vertices while
    // they span under `MEDIUM_ARC_RAD` (a disk's 12-gon seen from afar is
    // one piece, not eleven): the integrand's kink there is slight, and a
    // rectangle's corners still bound pieces.
    let mut pieces: SmallVec<[(f64, f64); 18]> = SmallVec::new();
    for w in sweep.windows(2) {
        let ((start, start_soft), (end, _)) = (w[0], w[1]);
        match pieces.last_mut() {
            Some(last) if start_soft && end - last.0 <= rule.medium_arc_rad => last.1 = end,
            _ => pieces.push((start, end)),
        }
    }
    let mut count = 0;
    let mut nodes = |lo: f64, width: f64, gauss: &[(f64, f64)]| -> f64 {
        count += gauss.len();
        gauss
            .iter()
            .map(|&(node, weight)| {
                weight * width * s.ray_integral(grid, lo + node * width, inside, Partial::Fast)
            })
            .sum::<f64>()
    };
    let mut piece = |lo: f64, span: f64| -> f64 {
        if span <= 1e-12 {
            0.0
        } else if span <= rule.small_arc_rad {
            nodes(lo, span, &GAUSS2)
        } else if span <= rule.medium_arc_rad {
            nodes(lo, span, &GAUSS3)
        } else {
            let arcs = (span / rule.max_arc_rad).ceil().max(1.0);
            let width = span / arcs;
            (0..arcs as usize)
                .map(|k| nodes(lo + k as f64 * width, width, &GAUSS4))
                .sum()
        }
    };
    let pi = std::f64::consts::PI;
    let mut sum = 0.0;
    for (lo, hi) in pieces {
        if rule.kink_step_rad > 0.0 {
            // C = φ + π: kinked C-planes at φ = k·step − π.
            let step = rule.kink_step_rad;
            let mut start = lo;
            let mut k = ((lo + pi) / step).floor() + 1.0;
            while k * step - pi < hi {
                let cut = k * step - pi;
                sum += piece(start, cut - start);
                start = cut;
                k += 1.0;
            }
            sum += piece(start, hi - start);
        } else {
            sum += piece(lo, hi - lo);
        }
    }
    let result = CubatureResult {
        lux: (sum / light.opening.area_m2()).max(0.0),
        cosine_solid_angle: cosine_solid_angle(&s),
    };
    (result, count)
}
