//! Where a finish's structure lies on its part: the surface coordinates
//! its pattern is laid out in, and its geometry on the part's surface
//! (for a finish traced as normals or as triangles, and for the
//! toolmaker's STEP/STL).
//!
//! A revolved part is laid out along its profile's arc length u and
//! around its axis: dimples in rings at the pattern's row pitch, each ring
//! holding a whole number of dimples as near the pitch as its
//! circumference allows, so the pattern stays the pitch the toolmaker
//! names everywhere on the part (a pattern on (u, r·φ) would shear by
//! φ·dr/du away from φ = 0). An extruded part is laid out along its
//! profile and along the extrusion, which is exact (the surface is
//! developable); any other part on its own x and y.

use glam::{DVec2, DVec3};

use crate::exact::{ExactSurface, ProfileCurve};
use crate::finish::{DimplePattern, Finish, dimple_rim};
use crate::mesh::TriangleMesh;
use crate::model::Shape;

/// How a part's surface is parametrised for its finish.
#[derive(Debug, Clone, PartialEq)]
pub enum FinishLayout {
    /// About the part's z axis: u along the profile (arc length, m), v
    /// the angle around (rad).
    Revolution(ProfileArc),
    /// Along y: u along the profile (arc length, m), v = y (m).
    Extrusion(ProfileArc),
    /// u = x, v = y (m) in the part's frame.
    Plane,
}

/// A profile sampled densely, with its arc length at each sample.
#[derive(Debug, Clone, PartialEq)]
pub struct ProfileArc {
    points: Vec<DVec2>,
    arc: Vec<f64>,
}

/// Samples per profile curve: a quadratic or cubic span's arc length
/// within 1e-6 of its length, and a nearest point within a micrometre on
/// a reflector of 100 mm.
const SAMPLES_PER_CURVE: usize = 512;

/// Samples between the first pass's points of [`ProfileArc::nearest`].
const COARSE_STRIDE: usize = 16;

impl ProfileArc {
    fn of(curves: &[ProfileCurve]) -> Option<ProfileArc> {
        let mut points: Vec<DVec2> = Vec::new();
        for c in curves {
            for k in 0..=SAMPLES_PER_CURVE {
                let p = c.point(k as f64 / SAMPLES_PER_CURVE as f64);
                if points.last().is_none_or(|q| (*q - p).length() > 0.0) {
                    points.push(p);
                }
            }
        }
        if points.len() < 2 {
            return None;
        }
        let mut arc = Vec::with_capacity(points.len());
        let mut s = 0.0;
        arc.push(0.0);
        for w in points.windows(2) {
            s += (w[1] - w[0]).length();
            arc.push(s);
        }
        Some(ProfileArc { points, arc })
    }

    /// The profile's whole length (m).
    pub fn length(&self) -> f64 {
        *self.arc.last().unwrap_or(&0.0)
    }

    /// The arc length of the profile point nearest `q`: the nearest of
    /// every [`COARSE_STRIDE`]th sample first, then the segments around
    /// it (a profile never comes back within a few of its samples).
    pub fn nearest(&self, q: DVec2) -> f64 {
        let n = self.points.len();
        let coarse = (0..n)
            .step_by(COARSE_STRIDE)
            .chain(std::iter::once(n - 1))
            .min_by(|&a, &b| {
                (self.points[a] - q)
                    .length_squared()
                    .total_cmp(&(self.points[b] - q).length_squared())
            })
            .unwrap_or(0);
        let lo = coarse.saturating_sub(2 * COARSE_STRIDE);
        let hi = (coarse + 2 * COARSE_STRIDE).min(n - 1);
        let mut best = (f64::INFINITY, 0.0);
        for (k, w) in self.points[lo..=hi].windows(2).enumerate() {
            let i = lo + k;
            let d = w[1] - w[0];
            let len2 = d.length_squared();
            let t = if len2 > 0.0 {
                ((q - w[0]).dot(d) / len2).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let dist = (w[0] + d * t - q).length_squared();
            if dist < best.0 {
                best = (dist, self.arc[i] + t * (self.arc[i + 1] - self.arc[i]));
            }
        }
        best.1
    }

    /// The profile point at arc length `s` (clamped to the profile).
    pub fn point_at(&self, s: f64) -> DVec2 {
        let i = self
            .arc
            .partition_point(|&a| a < s)
            .clamp(1, self.arc.len() - 1);
        let (a0, a1) = (self.arc[i - 1], self.arc[i]);
        let t = if a1 > a0 {
            ((s - a0) / (a1 - a0)).clamp(0.0, 1.0)
        } else {
            0.0
        };
        self.points[i - 1].lerp(self.points[i], t)
    }
}

/// A point's surface coordinates under a [`FinishLayout`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePoint {
    /// Along the profile (m), or x.
    pub u: f64,
    /// Around the axis (rad) for a revolution, else along y (m).
    pub v: f64,
    /// The distance from the axis (m) for a revolution.
    pub radius: Option<f64>,
}

impl FinishLayout {
    /// The layout of a part of `shape`: from its exact surface where it
    /// has one surface of revolution or extrusion.
    pub fn of_shape(shape: &Shape) -> FinishLayout {
        let exact = shape.generator().exact().unwrap_or_default();
        match exact.as_slice() {
            [ExactSurface::Revolution(curves)] => ProfileArc::of(curves)
                .map(FinishLayout::Revolution)
                .unwrap_or(FinishLayout::Plane),
            [ExactSurface::Extrusion { profile, .. }, ..] => ProfileArc::of(profile)
                .map(FinishLayout::Extrusion)
                .unwrap_or(FinishLayout::Plane),
            _ => FinishLayout::Plane,
        }
    }

    /// A part-frame point's surface coordinates.
    pub fn coordinates(&self, p: DVec3) -> SurfacePoint {
        match self {
            FinishLayout::Revolution(arc) => {
                let r = p.x.hypot(p.y);
                SurfacePoint {
                    u: arc.nearest(DVec2::new(r, p.z)),
                    v: p.y.atan2(p.x),
                    radius: Some(r),
                }
            }
            FinishLayout::Extrusion(arc) => SurfacePoint {
                u: arc.nearest(DVec2::new(p.x, p.z)),
                v: p.y,
                radius: None,
            },
            FinishLayout::Plane => SurfacePoint {
                u: p.x,
                v: p.y,
                radius: None,
            },
        }
    }

    /// The finish's height (m, along the surface's normal) at `at`;
    /// None for a finish given only by its slopes.
    pub fn height(&self, finish: &Finish, at: SurfacePoint) -> Option<f64> {
        if let Finish::Facets {
            size_along,
            size_around,
        } = finish
        {
            return Some(
                self.facet_at(*size_along, *size_around, at)
                    .map_or(0.0, |f| {
                        -0.5 * (f.curvature[0] * f.offset[0].powi(2)
                            + f.curvature[1] * f.offset[1].powi(2))
                    }),
            );
        }
        let (FinishLayout::Revolution(arc), Some(r)) = (self, at.radius) else {
            return finish.height(at.u, at.v);
        };
        match finish {
            Finish::Dimples {
                pitch,
                depth,
                radius,
                pattern,
            } => Some(ring_dimple_height(
                arc, *pitch, *depth, *radius, *pattern, at.u, at.v, r,
            )),
            Finish::Ripples { .. } => {
                // Around the axis as arc length from φ = 0, within a turn
                // of it (the pattern's seam at φ = ±π).
                finish.height(at.u, r * at.v)
            }
            Finish::Slopes { .. } | Finish::HeightMap { .. } | Finish::Facets { .. } => {
                finish.height(at.u, r * at.v)
            }
        }
    }

    /// The facet holding `at`: its centre's offset (along u, across as
    /// arc length) and the smooth surface's principal curvatures there
    /// (1/m, magnitudes: a facet's slopes are symmetric either way); None
    /// on a plane, where facets are flat.
    fn facet_at(&self, along: f64, around: f64, at: SurfacePoint) -> Option<Facet> {
        match (self, at.radius) {
            (FinishLayout::Revolution(arc), Some(r)) => {
                let rings = Rings {
                    arc,
                    pitch: around,
                    footprint: f64::INFINITY,
                    row_pitch: along,
                    hexagonal: false,
                    rows: Vec::new(),
                };
                let offset = rings.nearest(at.u, at.v, r)?;
                Some(Facet {
                    offset,
                    curvature: arc.curvatures(at.u),
                })
            }
            (FinishLayout::Extrusion(arc), _) => {
                let centre = |x: f64, size: f64| ((x / size).floor() + 0.5) * size;
                Some(Facet {
                    offset: [at.u - centre(at.u, along), at.v - centre(at.v, around)],
                    curvature: [arc.curvatures(at.u)[0], 0.0],
                })
            }
            _ => None,
        }
    }

    /// The finish's slope (∂h/∂u, ∂h/∂v per metre of surface) at `at`,
    /// by central differences over a thousandth of its finest feature.
    pub fn slope(&self, finish: &Finish, at: SurfacePoint) -> Option<[f64; 2]> {
        if let Finish::Facets {
            size_along,
            size_around,
        } = finish
        {
            // Within its facet, in closed form: where facets of rings of
            // different counts meet, their tangent planes do not, and a
            // difference across the seam would be a cliff.
            return Some(
                self.facet_at(*size_along, *size_around, at)
                    .map_or([0.0, 0.0], |f| {
                        [-f.curvature[0] * f.offset[0], -f.curvature[1] * f.offset[1]]
                    }),
            );
        }
        let step = 1e-3 * finish_feature_size(finish);
        let dv = match at.radius {
            Some(r) => step / r.max(1e-9),
            None => step,
        };
        let h = |du: f64, dvv: f64| {
            self.height(
                finish,
                SurfacePoint {
                    u: at.u + du,
                    v: at.v + dvv,
                    radius: at.radius,
                },
            )
        };
        Some([
            (h(step, 0.0)? - h(-step, 0.0)?) / (2.0 * step),
            (h(0.0, dv)? - h(0.0, -dv)?) / (2.0 * step),
        ])
    }
}

/// Where a point lies in its facet, and how the smooth surface curves.
struct Facet {
    offset: [f64; 2],
    curvature: [f64; 2],
}

impl ProfileArc {
    /// The principal curvatures (1/m, magnitudes) at arc length `s` of
    /// the surface this profile revolves into: along the profile its
    /// turning per length; around the axis the normal's radial part over
    /// the radius (for an extrusion only the first counts).
    fn curvatures(&self, s: f64) -> [f64; 2] {
        let h = (1e-3 * self.length()).max(1e-9);
        // The stencil kept on the profile (its ends have no outside).
        let s = s.clamp(1.5 * h, (self.length() - 1.5 * h).max(1.5 * h));
        let tangent = |s: f64| {
            let d = self.point_at(s + 0.5 * h) - self.point_at(s - 0.5 * h);
            d.normalize_or(DVec2::X)
        };
        let (t0, t1) = (tangent(s - h), tangent(s + h));
        let along = (t0.perp_dot(t1)).abs() / (2.0 * h);
        let t = tangent(s);
        let r = self.point_at(s).x.abs();
        // The unit normal's radial part is the tangent's z part.
        let around = if r > 1e-12 { t.y.abs() / r } else { along };
        [along, around]
    }
}

/// The finest structure of a finish (m): the dimples' pitch, the
/// shortest wavelength; a slope-only finish has none (0).
pub fn finish_feature_size(finish: &Finish) -> f64 {
    match finish {
        Finish::Dimples { pitch, .. } => *pitch,
        Finish::Ripples { waves } => waves
            .iter()
            .map(|w| w.wavelength)
            .fold(f64::INFINITY, f64::min),
        Finish::Slopes { .. } => 0.0,
        Finish::Facets {
            size_along,
            size_around,
        } => size_along.min(*size_around),
        // A measured map's finest feature is its pixel: exported as
        // geometry at a pixel per edge.
        Finish::HeightMap { pixel_size, .. } => 16.0 * pixel_size,
    }
}

impl FinishLayout {
    /// Facets' slopes over the part (area weighted): at each point the
    /// smooth surface's normal turned against the facet's by curvature ×
    /// offset; a plane's facets are flat.
    fn facet_statistics(&self, along: f64, around: f64) -> crate::finish::SlopeStatistics {
        let arc = match self {
            FinishLayout::Revolution(arc) | FinishLayout::Extrusion(arc) => arc,
            FinishLayout::Plane => {
                return Finish::Facets {
                    size_along: along,
                    size_around: around,
                }
                .statistics();
            }
        };
        let revolution = matches!(self, FinishLayout::Revolution(_));
        let length = arc.length();
        let size = along.min(around);
        let r_max = arc.points.iter().map(|p| p.x.abs()).fold(0.0, f64::max);
        // An extrusion's facets repeat along it: one row of them.
        let span = if revolution {
            std::f64::consts::TAU * r_max
        } else {
            around
        };
        let per_size = LAYOUT_SAMPLES_PER_PITCH
            .min((LAYOUT_MAX_SAMPLES * size * size / (length * span).max(1e-18)).sqrt())
            .max(4.0);
        let step = size / per_size;
        let n_u = ((length / step).ceil() as usize).max(1);
        let mut samples = Vec::new();
        let mut steepest: f64 = 0.0;
        for i in 0..n_u {
            let u = (i as f64 + 0.5) / n_u as f64 * length;
            let r = arc.point_at(u).x.abs();
            let width = if revolution {
                std::f64::consts::TAU * r
            } else {
                around
            };
            let n_v = ((width / step).ceil() as usize).max(1);
            for k in 0..n_v {
                let t = (k as f64 + 0.5) / n_v as f64;
                let at = if revolution {
                    SurfacePoint {
                        u,
                        v: t * std::f64::consts::TAU,
                        radius: Some(r),
                    }
                } else {
                    SurfacePoint {
                        u,
                        v: t * around,
                        radius: None,
                    }
                };
                let slope = self.facet_at(along, around, at).map_or([0.0, 0.0], |f| {
                    [-f.curvature[0] * f.offset[0], -f.curvature[1] * f.offset[1]]
                });
                steepest = steepest.max(slope[0].abs()).max(slope[1].abs());
                // Each sample stands for its share of the ring's area.
                samples.push((slope, width / n_v as f64));
            }
        }
        crate::finish::statistics_of_samples(steepest.max(1e-9) * 1.0001, samples)
    }
}

/// Triangle edges per feature from which a part's own mesh carries a
/// finish's feature as geometry: a sine sampled by eight edges per
/// wavelength keeps its rms slope within 3 % (sin(π/8)/(π/8)).
pub const GEOMETRY_EDGES_PER_FEATURE: f64 = 8.0;

/// A finish split by scale against its part's tessellation (the paper's
/// §4): what the mesh resolves is geometry, what is larger than the cut
/// the shading normals, the rest the BRDF's slope distribution.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FinishBands {
    pub geometry: Option<Finish>,
    pub normals: Option<Finish>,
    pub brdf: Option<Finish>,
}

/// Splits `finish` for a part whose triangles' edges are `edge` (m)
/// long: features of at least [`GEOMETRY_EDGES_PER_FEATURE`] edges are
/// geometry; of at least `normals_from` (m) normals; the rest BRDF.
/// Waves split one by one; dimples are one feature; measured slopes are
/// always BRDF.
pub fn split_by_scale(finish: &Finish, edge: f64, normals_from: Option<f64>) -> FinishBands {
    #[derive(Clone, Copy, PartialEq)]
    enum Band {
        Geometry,
        Normals,
        Brdf,
    }
    let band = |size: f64| {
        if size >= GEOMETRY_EDGES_PER_FEATURE * edge {
            Band::Geometry
        } else if normals_from.is_some_and(|c| size >= c) {
            Band::Normals
        } else {
            Band::Brdf
        }
    };
    let mut out = FinishBands::default();
    let mut put = |b: Band, f: Finish| match b {
        Band::Geometry => out.geometry = Some(f),
        Band::Normals => out.normals = Some(f),
        Band::Brdf => out.brdf = Some(f),
    };
    match finish {
        Finish::Dimples { pitch, .. } => put(band(*pitch), finish.clone()),
        Finish::Facets { .. } => put(band(finish_feature_size(finish)), finish.clone()),
        Finish::Ripples { waves } => {
            for b in [Band::Geometry, Band::Normals, Band::Brdf] {
                let mine: Vec<_> = waves
                    .iter()
                    .filter(|w| band(w.wavelength) == b)
                    .cloned()
                    .collect();
                if !mine.is_empty() {
                    put(b, Finish::Ripples { waves: mine });
                }
            }
        }
        // Measured finishes hold every scale: their whole spectrum in the
        // BRDF (cut into the mesh only when asked, `geometry_edge`).
        Finish::Slopes { .. } | Finish::HeightMap { .. } => put(Band::Brdf, finish.clone()),
    }
    out
}

/// How the finish's u and v directions are found at a point of the part
/// in luminaire coordinates: v around an axis, along one, or a fixed
/// direction; u across v in the surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TangentRule {
    /// v = axis × (p − origin), normalised (increasing angle).
    Around { axis: DVec3, origin: DVec3 },
    /// v = the direction, less its part along the normal.
    Along { direction: DVec3 },
}

impl TangentRule {
    fn of(layout: &FinishLayout, luminaire_from_part: &glam::DAffine3) -> TangentRule {
        let m = luminaire_from_part.matrix3;
        match layout {
            FinishLayout::Revolution(_) => TangentRule::Around {
                axis: (m * DVec3::Z).normalize_or(DVec3::Z),
                origin: luminaire_from_part.translation,
            },
            FinishLayout::Extrusion(_) | FinishLayout::Plane => TangentRule::Along {
                direction: (m * DVec3::Y).normalize_or(DVec3::Y),
            },
        }
    }

    /// The unit v direction at `p` on a surface of normal `n`; None
    /// where it is undefined (on the axis, or v along the normal).
    pub fn v_direction(&self, p: DVec3, n: DVec3) -> Option<DVec3> {
        let v = match *self {
            TangentRule::Around { axis, origin } => axis.cross(p - origin),
            TangentRule::Along { direction } => direction - n * direction.dot(n),
        };
        let v = v - n * v.dot(n);
        (v.length_squared() > 1e-20).then(|| v.normalize())
    }
}

/// A finished part as the tracer needs it: the bands it traces (not the
/// geometry, which is in the mesh), and how to find the finish's
/// directions and coordinates at a hit.
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceFinish {
    pub part: String,
    pub normals: Option<Finish>,
    pub brdf: Option<Finish>,
    pub layout: FinishLayout,
    pub luminaire_from_part: glam::DAffine3,
    pub tangents: TangentRule,
    /// ±1: u = handedness · (v × n) for the part's own normals n.
    pub handedness: f64,
    /// The BRDF band's slope statistics as laid out on this part.
    pub brdf_statistics: Option<crate::finish::SlopeStatistics>,
}

impl SurfaceFinish {
    /// The finish of a part whose mesh (luminaire coordinates, the
    /// part's own normals) is `mesh`.
    pub fn new(
        part: &str,
        bands: &FinishBands,
        layout: FinishLayout,
        luminaire_from_part: glam::DAffine3,
        mesh: &TriangleMesh,
    ) -> SurfaceFinish {
        let tangents = TangentRule::of(&layout, &luminaire_from_part);
        let handedness = handedness(&layout, &tangents, mesh, &luminaire_from_part);
        SurfaceFinish {
            part: part.to_owned(),
            brdf_statistics: bands.brdf.as_ref().map(|f| layout.statistics(f)),
            normals: bands.normals.clone(),
            brdf: bands.brdf.clone(),
            layout,
            luminaire_from_part,
            tangents,
            handedness,
        }
    }
}

/// ±1: the sense of u against v × n for a part's mesh (luminaire
/// coordinates, the part's own normals), from the vertex whose frame is
/// best defined.
fn handedness(
    layout: &FinishLayout,
    rule: &TangentRule,
    mesh: &TriangleMesh,
    luminaire_from_part: &glam::DAffine3,
) -> f64 {
    let part_from_luminaire = luminaire_from_part.inverse();
    let mut handedness = 1.0;
    let mut best = 0.0;
    for (p, n) in mesh.positions.iter().zip(&mesh.normals).step_by(7) {
        let (p, n) = (p.as_dvec3(), n.as_dvec3().normalize_or_zero());
        let Some(v) = rule.v_direction(p, n) else {
            continue;
        };
        let across = v.cross(n);
        let step = 1e-5;
        let at = |q: DVec3| {
            layout
                .coordinates(part_from_luminaire.transform_point3(q))
                .u
        };
        let du = at(p + across * step) - at(p - across * step);
        if du.abs() > best {
            best = du.abs();
            handedness = du.signum();
        }
    }
    handedness
}

/// Dimples in rings about the axis: ring j centred at u = (j + ½)·row
/// pitch holds n = round(2π r_j / pitch) dimples at equal angles, every
/// other ring turned by half a step on a hexagonal pattern. Rings of
/// different counts drift in and out of step around the part, so their
/// dimples overlap in places: the part's slope statistics are taken from
/// this layout ([`FinishLayout::statistics`]), not from a plane lattice.
struct Rings<'a> {
    arc: &'a ProfileArc,
    pitch: f64,
    footprint: f64,
    row_pitch: f64,
    hexagonal: bool,
    /// Each ring's (radius, angular step) from ring 0 on, where worked
    /// out ahead (a whole part's statistics); else found per call.
    rows: Vec<(f64, f64)>,
}

impl Rings<'_> {
    /// Ring `j`'s radius and angular step: a whole number of dimples
    /// as near the pitch as its circumference allows.
    fn ring(&self, j: i64) -> (f64, f64) {
        let s_j = (j as f64 + 0.5) * self.row_pitch;
        let r_j = self.arc.point_at(s_j).x.abs().max(1e-9);
        let n = (std::f64::consts::TAU * r_j / self.pitch).round().max(1.0);
        (r_j, std::f64::consts::TAU / n)
    }

    /// The rings worked out ahead over the whole profile.
    fn with_rows(mut self) -> Self {
        let count = (self.arc.length() / self.row_pitch).ceil() as i64 + 2;
        self.rows = (0..count).map(|j| self.ring(j)).collect();
        self
    }

    /// The offset (along u, around as arc length at the point's radius
    /// `r`) of the nearest dimple centre within a footprint, if any.
    fn nearest(&self, u: f64, phi: f64, r: f64) -> Option<[f64; 2]> {
        let j0 = (u / self.row_pitch).floor() as i64;
        let mut best: Option<(f64, [f64; 2])> = None;
        for j in j0 - 1..=j0 + 1 {
            let s_j = (j as f64 + 0.5) * self.row_pitch;
            let du = u - s_j;
            if du.abs() >= self.footprint {
                continue;
            }
            let step = match usize::try_from(j).ok().and_then(|j| self.rows.get(j)) {
                Some(&(_, step)) => step,
                None => self.ring(j).1,
            };
            let offset = if self.hexagonal && j.rem_euclid(2) == 1 {
                0.5
            } else {
                0.0
            };
            // The nearest centre of the ring by angle (wrapped once),
            // and its two neighbours.
            let k = (phi / step - offset).round();
            let near = (phi - (k + offset) * step + std::f64::consts::PI)
                .rem_euclid(std::f64::consts::TAU)
                - std::f64::consts::PI;
            let reach2 = self.footprint * self.footprint;
            for dphi in [near - step, near, near + step] {
                let d = [du, r * dphi];
                let rho2 = d[0] * d[0] + d[1] * d[1];
                if rho2 < reach2 && best.is_none_or(|b| rho2 < b.0) {
                    best = Some((rho2, d));
                }
            }
        }
        best.map(|b| b.1)
    }
}

fn rings(
    arc: &ProfileArc,
    pitch: f64,
    depth: f64,
    radius: f64,
    pattern: DimplePattern,
) -> Rings<'_> {
    Rings {
        arc,
        pitch,
        footprint: dimple_rim(radius, depth, pitch),
        row_pitch: match pattern {
            DimplePattern::Hexagonal => 0.5 * 3f64.sqrt() * pitch,
            DimplePattern::Square => pitch,
        },
        hexagonal: pattern == DimplePattern::Hexagonal,
        rows: Vec::new(),
    }
}

#[allow(clippy::too_many_arguments)] // reason: one dimple pattern, spelt out
fn ring_dimple_height(
    arc: &ProfileArc,
    pitch: f64,
    depth: f64,
    radius: f64,
    pattern: DimplePattern,
    u: f64,
    phi: f64,
    r: f64,
) -> f64 {
    match rings(arc, pitch, depth, radius, pattern).nearest(u, phi, r) {
        Some(d) => {
            let rho2 = d[0] * d[0] + d[1] * d[1];
            -((radius * radius - rho2).sqrt() - (radius - depth))
        }
        None => 0.0,
    }
}

/// Samples per pitch, each way, of a revolved part's dimple statistics.
const LAYOUT_SAMPLES_PER_PITCH: f64 = 48.0;
/// At most this many samples in all (a large part is sampled more
/// coarsely: its rings repeat).
const LAYOUT_MAX_SAMPLES: f64 = 6.0e5;

impl FinishLayout {
    /// The slope statistics of `finish` as laid out on this part: a
    /// revolved part's dimple rings integrated over its surface (area
    /// weighted, slopes in closed form); any other finish or layout has
    /// its plane pattern's ([`Finish::statistics`]).
    pub fn statistics(&self, finish: &Finish) -> crate::finish::SlopeStatistics {
        if let Finish::Facets {
            size_along,
            size_around,
        } = finish
        {
            return self.facet_statistics(*size_along, *size_around);
        }
        let (
            FinishLayout::Revolution(arc),
            Finish::Dimples {
                pitch,
                depth,
                radius,
                pattern,
            },
        ) = (self, finish)
        else {
            return finish.statistics();
        };
        let rings = rings(arc, *pitch, *depth, *radius, *pattern).with_rows();
        let length = arc.length();
        let r_max = arc.points.iter().map(|p| p.x.abs()).fold(0.0, f64::max);
        let area_in_pitches = length * std::f64::consts::TAU * r_max / (pitch * pitch);
        let per_pitch = LAYOUT_SAMPLES_PER_PITCH
            .min((LAYOUT_MAX_SAMPLES / area_in_pitches.max(1e-9)).sqrt())
            .max(4.0);
        let step = pitch / per_pitch;
        let n_u = ((length / step).ceil() as usize).max(1);
        let footprint = rings.footprint;
        let steepest = footprint / (radius * radius - footprint * footprint).max(1e-300).sqrt();
        let samples = (0..n_u).flat_map(|i| {
            let u = (i as f64 + 0.5) / n_u as f64 * length;
            let r = arc.point_at(u).x.abs();
            let n_phi = ((std::f64::consts::TAU * r / step).ceil() as usize).max(1);
            let rings = &rings;
            (0..n_phi).map(move |k| {
                let phi = (k as f64 + 0.5) / n_phi as f64 * std::f64::consts::TAU;
                // Each sample stands for r·dφ·du of surface.
                let w = r / n_phi as f64 * std::f64::consts::TAU;
                let slope = match rings.nearest(u, phi, r) {
                    Some(d) => {
                        let g = 1.0 / (radius * radius - d[0] * d[0] - d[1] * d[1]).sqrt();
                        [d[0] * g, d[1] * g]
                    }
                    None => [0.0, 0.0],
                };
                (slope, w)
            })
        });
        crate::finish::statistics_of_samples(steepest.max(1e-9) * 1.0001, samples)
    }
}

/// `mesh` (the part's own, in its frame) with the finish cut into it:
/// triangles split until no edge is longer than `max_edge` (m), each new
/// vertex put back on the layout's exact surface, then every vertex moved
/// along its normal by the finish's height, and the normals made those
/// of the finished surface. None for a finish given only by its slopes.
/// A finished mesh would need more triangles than a luminaire may have.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct TooFine {
    /// About how many it would need.
    pub triangles: u64,
}

pub fn finished_mesh(
    mesh: &TriangleMesh,
    layout: &FinishLayout,
    finish: &Finish,
    max_edge: f64,
) -> Result<Option<TriangleMesh>, TooFine> {
    cut_mesh(mesh, layout, finish, max_edge, true)
}

/// [`finished_mesh`] with the vertices left on the smooth surface: the
/// finish shown by its normals alone, as a normal-mapped preview does.
pub fn finish_shading_mesh(
    mesh: &TriangleMesh,
    layout: &FinishLayout,
    finish: &Finish,
    max_edge: f64,
) -> Result<Option<TriangleMesh>, TooFine> {
    cut_mesh(mesh, layout, finish, max_edge, false)
}

fn cut_mesh(
    mesh: &TriangleMesh,
    layout: &FinishLayout,
    finish: &Finish,
    max_edge: f64,
    displace: bool,
) -> Result<Option<TriangleMesh>, TooFine> {
    if finish.height(0.0, 0.0).is_none() {
        return Ok(None);
    }
    let mut m = mesh.clone();
    let limit2 = (max_edge * max_edge) as f32;
    // Split every edge longer than the limit at its midpoint, pass after
    // pass: both triangles of an edge share its midpoint, so the mesh
    // stays watertight where it was.
    for _ in 0..64 {
        if m.triangles.len() as u64 > crate::check::MAX_SCENE_TRIANGLES {
            // Each halving of the longest edge about doubles the count.
            let longest = m
                .triangles
                .iter()
                .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
                .map(|(a, b)| (m.positions[a as usize] - m.positions[b as usize]).length_squared())
                .fold(0.0f32, f32::max);
            let halvings = (f64::from(longest / limit2)).log2().max(0.0);
            return Err(TooFine {
                triangles: (m.triangles.len() as f64 * 4f64.powf(halvings.ceil() / 2.0)) as u64,
            });
        }
        match split_long_edges(&m, layout, limit2) {
            Some(next) => m = next,
            None => break,
        }
    }
    let mut out = m.clone();
    // The finish's directions in the part's frame, u's sense found once.
    let rule = TangentRule::of(layout, &glam::DAffine3::IDENTITY);
    let handedness = handedness(layout, &rule, &m, &glam::DAffine3::IDENTITY);
    for (i, p) in m.positions.iter().enumerate() {
        let p = p.as_dvec3();
        let at = layout.coordinates(p);
        let h = layout.height(finish, at).unwrap_or(0.0);
        let n = m.normals[i].as_dvec3().normalize_or_zero();
        if displace {
            out.positions[i] = (p + n * h).as_vec3();
        }
        // The finished surface's normal, n − s_u·u − s_v·v, from the
        // finish's slope where the vertex lies.
        if let (Some(v), Some([su, sv])) = (rule.v_direction(p, n), layout.slope(finish, at)) {
            let u = v.cross(n) * handedness;
            out.normals[i] = (n - u * su - v * sv).normalize_or(n).as_vec3();
        }
    }
    Ok(Some(out))
}

/// One pass of splitting each triangle's longest edge, where longer
/// than √`limit2`, at its midpoint, put back on the layout's surface (a revolution's profile
/// turned to the midpoint's angle); None where no edge is too long.
fn split_long_edges(m: &TriangleMesh, layout: &FinishLayout, limit2: f32) -> Option<TriangleMesh> {
    use std::collections::{HashMap, HashSet};
    let length2 =
        |a: u32, b: u32| (m.positions[a as usize] - m.positions[b as usize]).length_squared();
    // Each triangle's longest edge, where too long (Rivara's bisection:
    // a thin triangle is split across, not into more thin ones); a
    // neighbour splits a marked edge too, so the mesh stays conforming.
    let key = |a: u32, b: u32| (a.min(b), a.max(b));
    // Each triangle turned so its longest edge comes first.
    let turned: Vec<[u32; 3]> = m
        .triangles
        .iter()
        .map(|&[a, b, c]| {
            let turns = [[a, b, c], [b, c, a], [c, a, b]];
            let k = (0..3)
                .max_by(|&x, &y| {
                    let [p, q, _] = turns[x];
                    let [u, v, _] = turns[y];
                    length2(p, q).total_cmp(&length2(u, v))
                })
                .unwrap_or(0);
            turns[k]
        })
        .collect();
    let mut marked: HashSet<(u32, u32)> = turned
        .iter()
        .filter(|t| length2(t[0], t[1]) > limit2)
        .map(|t| key(t[0], t[1]))
        .collect();
    if marked.is_empty() {
        return None;
    }
    // Closure: a triangle with any edge split splits its longest too.
    loop {
        let before = marked.len();
        for t in &turned {
            if marked.contains(&key(t[1], t[2])) || marked.contains(&key(t[2], t[0])) {
                marked.insert(key(t[0], t[1]));
            }
        }
        if marked.len() == before {
            break;
        }
    }
    let long = |a: u32, b: u32| marked.contains(&(a.min(b), a.max(b)));
    let mut out = TriangleMesh {
        positions: m.positions.clone(),
        normals: m.normals.clone(),
        triangles: Vec::with_capacity(m.triangles.len() * 3),
    };
    let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
    let mut midpoint = |out: &mut TriangleMesh, a: u32, b: u32| -> Option<u32> {
        if !long(a, b) {
            return None;
        }
        let key = (a.min(b), a.max(b));
        if let Some(&k) = midpoints.get(&key) {
            return Some(k);
        }
        let (pa, pb) = (
            m.positions[a as usize].as_dvec3(),
            m.positions[b as usize].as_dvec3(),
        );
        let mut p = 0.5 * (pa + pb);
        if let FinishLayout::Revolution(arc) = layout {
            let r = p.x.hypot(p.y);
            if r > 0.0 {
                let s = arc.nearest(DVec2::new(r, p.z));
                let q = arc.point_at(s);
                p = DVec3::new(p.x / r * q.x, p.y / r * q.x, q.y);
            }
        }
        let n = (m.normals[a as usize] + m.normals[b as usize]).normalize_or_zero();
        out.positions.push(p.as_vec3());
        out.normals.push(n);
        let k = (out.positions.len() - 1) as u32;
        midpoints.insert(key, k);
        Some(k)
    };
    for &[p, q, r] in &turned {
        // p–q is the longest edge: split it first, then the halves.
        let a = midpoint(&mut out, p, q);
        let b = midpoint(&mut out, q, r);
        let c = midpoint(&mut out, r, p);
        match (a, b, c) {
            (None, _, _) => out.triangles.push([p, q, r]),
            (Some(a), None, None) => out.triangles.extend([[p, a, r], [a, q, r]]),
            (Some(a), Some(b), None) => out.triangles.extend([[p, a, r], [a, q, b], [a, b, r]]),
            (Some(a), None, Some(c)) => out.triangles.extend([[p, a, c], [a, r, c], [a, q, r]]),
            (Some(a), Some(b), Some(c)) => {
                out.triangles
                    .extend([[p, a, c], [a, r, c], [a, q, b], [a, b, r]]);
            }
        }
    }
    Some(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::finish::WaveShape;
    use crate::shapes::{Extruded, Paraboloid};

    fn paraboloid() -> Shape {
        Shape::Paraboloid(Paraboloid {
            focal_length: 10e-3,
            aperture_diameter: 60e-3,
            neck_diameter: 12e-3,
            segments_around: 96,
            segments_along: 32,
            faceted: false,
        })
    }

    #[test]
    fn a_revolutions_coordinates_are_its_profiles_arc_length_and_angle() {
        let layout = FinishLayout::of_shape(&paraboloid());
        let FinishLayout::Revolution(arc) = &layout else {
            panic!("{layout:?}");
        };
        // z = f − r²/4f from r 6 to 30 mm: arc length ∫√(1 + (r/2f)²) dr.
        let f: f64 = 10e-3;
        let exact = |r: f64| {
            let x = r / (2.0 * f);
            f * (x * (1.0 + x * x).sqrt() + x.asinh())
        };
        let want = exact(30e-3) - exact(6e-3);
        assert!((arc.length() / want - 1.0).abs() < 1e-6, "{}", arc.length());
        let r = 20e-3;
        let p = DVec3::new(0.0, r, f - r * r / (4.0 * f));
        let c = layout.coordinates(p);
        assert!((c.u - (exact(r) - exact(6e-3))).abs() < 1e-7, "{c:?}");
        assert!((c.v - std::f64::consts::FRAC_PI_2).abs() < 1e-12);
    }

    #[test]
    fn ring_dimples_statistics_are_the_parts_own() {
        // Over the whole part, the land's share of the area (sampled
        // uniformly over the surface) is the pattern's own within the
        // ring count's rounding.
        let shape = paraboloid();
        let layout = FinishLayout::of_shape(&shape);
        let finish = Finish::Dimples {
            pitch: 2e-3,
            depth: 0.15e-3,
            radius: 3.4e-3,
            pattern: DimplePattern::Hexagonal,
        };
        let FinishLayout::Revolution(arc) = &layout else {
            panic!()
        };
        let (mut flat, mut total) = (0.0, 0.0);
        // Random points (a test's own generator), weighted by radius.
        let mut x = 12345u64;
        let mut uniform = move || {
            x = x
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((x >> 11) as f64 + 0.5) / (1u64 << 53) as f64
        };
        for _ in 0..400 {
            for _ in 0..400 {
                let u = uniform() * arc.length();
                let r = arc.point_at(u).x;
                let v = uniform() * std::f64::consts::TAU;
                let h = layout
                    .height(
                        &finish,
                        SurfacePoint {
                            u,
                            v,
                            radius: Some(r),
                        },
                    )
                    .unwrap();
                total += r;
                if h == 0.0 {
                    flat += r;
                }
            }
        }
        // The part's own statistics see the same land.
        let want = layout.statistics(&finish).flat_share;
        assert!(
            (flat / total - want).abs() < 0.005,
            "{} vs {want}",
            flat / total
        );
        // Rings of different counts overlap in places: more land than
        // the plane lattice's, which a test of the part must not assume.
        let lattice = finish.statistics().flat_share;
        assert!(want > lattice, "{want} vs {lattice}");
    }

    #[test]
    fn facets_on_a_sphere_turn_the_normal_by_curvature_times_offset() {
        // On a sphere of radius R every facet a × b touching it has
        // slopes uniform over ±a/2R × ±b/2R: mean square (a² + b²)/12R²;
        // a plane's facets are flat.
        let (big_r, a, b) = (50e-3, 3e-3, 2e-3);
        let dome = Shape::Dome(crate::shapes::Dome {
            radius: big_r,
            height: 20e-3,
            segments_around: 96,
            segments_along: 24,
        });
        let layout = FinishLayout::of_shape(&dome);
        let f = Finish::Facets {
            size_along: a,
            size_around: b,
        };
        let s = layout.statistics(&f);
        let want = (a * a + b * b) / (12.0 * big_r * big_r);
        let got = s.covariance[0] + s.covariance[2];
        assert!((got / want - 1.0).abs() < 0.03, "{got} vs {want}");
        // Along and around apart (the rings' counts round the width).
        let along = a * a / (12.0 * big_r * big_r);
        assert!(
            (s.covariance[0] / along - 1.0).abs() < 0.03,
            "{:?}",
            s.covariance
        );
        assert!(s.flat_share < 0.01);
        assert_eq!(f.statistics().flat_share, 1.0);
        assert_eq!(
            FinishLayout::Plane.height(
                &f,
                SurfacePoint {
                    u: 0.1,
                    v: 0.2,
                    radius: None
                }
            ),
            Some(0.0)
        );
        // The facet's height: a tangent plane below the sphere by
        // offset²/2R at its edge, zero at its centre.
        let FinishLayout::Revolution(arc) = &layout else {
            panic!()
        };
        let u = 10.5 * a;
        let r = arc.point_at(u).x;
        let h = layout
            .height(
                &f,
                SurfacePoint {
                    u,
                    v: 0.0,
                    radius: Some(r),
                },
            )
            .unwrap();
        assert!(h.abs() < 1e-9, "{h}");
        let h = layout
            .height(
                &f,
                SurfacePoint {
                    u: u + 0.49 * a,
                    v: 0.0,
                    radius: Some(r),
                },
            )
            .unwrap();
        let want = -0.5 * (0.49 * a).powi(2) / big_r;
        assert!((h / want - 1.0).abs() < 0.02, "{h} vs {want}");
    }

    #[test]
    fn each_feature_goes_to_the_band_its_size_and_the_mesh_allow() {
        let dimples = Finish::Dimples {
            pitch: 2e-3,
            depth: 0.15e-3,
            radius: 3.4e-3,
            pattern: DimplePattern::Hexagonal,
        };
        // Edges of 1 mm: a 2 mm pitch is 2 edges, not the 8 of geometry.
        let b = split_by_scale(&dimples, 1e-3, None);
        assert_eq!((b.geometry.is_some(), b.normals.is_some()), (false, false));
        assert_eq!(b.brdf.as_ref(), Some(&dimples));
        assert_eq!(
            split_by_scale(&dimples, 1e-3, Some(1.5e-3))
                .normals
                .as_ref(),
            Some(&dimples)
        );
        assert_eq!(
            split_by_scale(&dimples, 0.25e-3, Some(1.5e-3))
                .geometry
                .as_ref(),
            Some(&dimples)
        );
        // Waves one by one: 4 mm geometry, 1 mm normals, 0.2 mm BRDF.
        let wave = |wavelength: f64| crate::finish::Ripple {
            amplitude: 1e-6,
            wavelength,
            direction_deg: 0.0,
            shape: WaveShape::Sine,
        };
        let ripples = Finish::Ripples {
            waves: vec![wave(4e-3), wave(1e-3), wave(0.2e-3)],
        };
        let b = split_by_scale(&ripples, 0.5e-3, Some(0.5e-3));
        let lengths = |f: &Option<Finish>| match f {
            Some(Finish::Ripples { waves }) => waves.iter().map(|w| w.wavelength).collect(),
            _ => Vec::new(),
        };
        assert_eq!(lengths(&b.geometry), vec![4e-3]);
        assert_eq!(lengths(&b.normals), vec![1e-3]);
        assert_eq!(lengths(&b.brdf), vec![0.2e-3]);
        // Measured slopes have no geometry: always the BRDF.
        let slopes = Finish::Slopes {
            sigma_u: 0.1,
            sigma_v: 0.1,
            orientation_deg: 0.0,
        };
        assert!(split_by_scale(&slopes, 1e-9, Some(0.0)).brdf.is_some());
    }

    #[test]
    fn a_finished_mesh_carries_the_finish_and_stays_on_the_surface() {
        let shape = Shape::Extruded(Extruded {
            profile: vec![[-20e-3, 0.0], [20e-3, 0.0]],
            length: 40e-3,
            interpolation: Default::default(),
            segments_per_span: 4,
            end_caps: false,
        });
        let mesh = shape.generator().generate().unwrap();
        let layout = FinishLayout::of_shape(&shape);
        let finish = Finish::Ripples {
            waves: vec![crate::finish::Ripple {
                amplitude: 0.1e-3,
                wavelength: 4e-3,
                direction_deg: 90.0,
                shape: WaveShape::Sine,
            }],
        };
        let out = finished_mesh(&mesh, &layout, &finish, 0.25e-3)
            .unwrap()
            .unwrap();
        assert!(out.triangle_count() > 16 * 16 * 4);
        out.check().unwrap();
        // Every vertex is displaced by the wave's height along z (the
        // flat sheet's normal), to float precision.
        for p in &out.positions {
            let want = 0.1e-3 * (std::f64::consts::TAU * f64::from(p.y) / 4e-3).sin();
            let z = f64::from(p.z);
            assert!((z.abs() - want.abs()).abs() < 1e-8, "{p:?}: {want}");
        }
        // A slope-only finish has no geometry.
        let slopes = Finish::Slopes {
            sigma_u: 0.1,
            sigma_v: 0.1,
            orientation_deg: 0.0,
        };
        assert_eq!(finished_mesh(&mesh, &layout, &slopes, 1e-3), Ok(None));
    }
}
