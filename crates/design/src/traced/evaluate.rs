//! A candidate scene traced and tabulated: every candidate with the same
//! photon stream (common random numbers: photon k of the seed's stream is
//! the same photon whatever the geometry), pooled over the luminaire's
//! symmetry, on one fixed C-γ grid the merit is measured on. A candidate
//! outside what can be built is refused, not an error.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::DVec3;
use lucerna_photometry::resample::CellBinning;
use lucerna_photometry::{
    AxialSymmetry, CandelaTable, CubeMapLayout, Dimensions, IntensityMap, TexelSymmetry,
};
use lucerna_scene::profile::sample_profile;
use lucerna_scene::{EmitterShape, Scene, Shape, SurfaceKind, validate};
use lucerna_simulation::Luminaire;
use lucerna_tracer::Session;
use lucerna_tracer::cpu::TraceSettings;

use crate::variables::Variable;

/// The grid candidates are tabulated on for a spec: 5° C-planes, 0.25° γ.
/// (A distribution's candidates are tabulated on its own grid.)
pub const MERIT_C_STEP_DEG: f64 = 5.0;
pub const MERIT_GAMMA_STEP_DEG: f64 = 0.25;

/// The merit grid of a spec: C-planes and γ angles (degrees).
pub fn merit_grid() -> (Vec<f64>, Vec<f64>) {
    (
        lucerna_photometry::table::uniform_c_planes(MERIT_C_STEP_DEG),
        lucerna_photometry::table::uniform_gammas(MERIT_GAMMA_STEP_DEG, 180.0),
    )
}

/// Why a candidate was not traced.
#[derive(Debug, Clone, PartialEq)]
pub enum Refused {
    /// The scene does not validate (the first problem).
    Invalid(String),
    /// A profile crosses itself.
    SelfIntersecting(String),
    /// A part passes through an emitter.
    CutsEmitter { part: String, emitter: String },
    /// Tessellation or preparation failed.
    Unbuildable(String),
}

impl std::fmt::Display for Refused {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Refused::Invalid(why) => write!(f, "invalid: {why}"),
            Refused::SelfIntersecting(part) => write!(f, "the profile of '{part}' crosses itself"),
            Refused::CutsEmitter { part, emitter } => {
                write!(f, "part '{part}' passes through emitter '{emitter}'")
            }
            Refused::Unbuildable(why) => write!(f, "cannot be built: {why}"),
        }
    }
}

/// A traced candidate.
#[derive(Debug, Clone)]
pub struct Traced {
    /// Pooled candela on the evaluator's grid.
    pub table: CandelaTable,
    /// The photons' map (unpooled counts).
    pub map: IntensityMap,
    /// The candidate's luminous opening (for its UGR).
    pub opening: Dimensions,
}

/// Traces candidates of one scene.
#[derive(Debug)]
pub struct Evaluator {
    scene_dir: PathBuf,
    seed: u32,
    layout: CubeMapLayout,
    symmetry: TexelSymmetry,
    c_planes_deg: Vec<f64>,
    gammas_deg: Vec<f64>,
    band_edges_deg: Vec<f64>,
    /// The last candidate built, whose BVH a candidate with the same
    /// triangles (only moved) refits.
    previous: Option<Arc<Luminaire>>,
    /// Parts the variables change (checked against the emitters), and
    /// whether they move an emitter (then every part is checked).
    varied_parts: Vec<usize>,
    moves_emitter: bool,
}

impl Evaluator {
    /// An evaluator of a scene's candidates at `resolution` per face,
    /// pooled over `symmetry` (the start scene's, which the variables keep
    /// when they change only surfaces of revolution about the axis),
    /// tabulated on `grid` (C-planes and γ angles) as a bake tabulates:
    /// each cell the mean of its solid angle.
    pub fn new(
        scene_dir: &Path,
        seed: u32,
        resolution: u32,
        symmetry: AxialSymmetry,
        variables: &[Variable],
        (c_planes_deg, gammas_deg): (Vec<f64>, Vec<f64>),
    ) -> Evaluator {
        let layout = CubeMapLayout::new(resolution);
        let band_edges_deg = lucerna_photometry::resample::gamma_cell_edges(&gammas_deg);
        // A moved emitter may meet any part.
        let moves_emitter = variables.iter().any(|v| v.place.part().is_none());
        let mut varied_parts: Vec<usize> =
            variables.iter().filter_map(|v| v.place.part()).collect();
        varied_parts.sort_unstable();
        varied_parts.dedup();
        Evaluator {
            scene_dir: scene_dir.to_path_buf(),
            seed,
            layout,
            symmetry: TexelSymmetry::new(layout, symmetry),
            c_planes_deg,
            gammas_deg,
            band_edges_deg,
            previous: None,
            varied_parts,
            moves_emitter,
        }
    }

    pub fn seed(&self) -> u32 {
        self.seed
    }

    /// The same evaluator with another photon stream (the merit's noise
    /// is the difference between two streams).
    pub fn with_seed(&self, seed: u32) -> Evaluator {
        Evaluator {
            scene_dir: self.scene_dir.clone(),
            seed,
            layout: self.layout,
            symmetry: self.symmetry.clone(),
            c_planes_deg: self.c_planes_deg.clone(),
            gammas_deg: self.gammas_deg.clone(),
            band_edges_deg: self.band_edges_deg.clone(),
            previous: self.previous.clone(),
            varied_parts: self.varied_parts.clone(),
            moves_emitter: self.moves_emitter,
        }
    }

    /// Whether `scene` can be built: valid, no profile crossing itself,
    /// no varied part through an emitter.
    pub fn check(&self, scene: &Scene) -> Result<(), Refused> {
        if let Some(problem) = validate(scene).first() {
            return Err(Refused::Invalid(format!(
                "{}: {}",
                problem.field, problem.message
            )));
        }
        for &p in &self.varied_parts {
            let part = &scene.parts[p];
            if let Some(points) = crate::variables::profile(&part.shape) {
                let (interpolation, per_span) = match &part.shape {
                    Shape::Revolved(s) => (s.interpolation, s.segments_per_span),
                    Shape::Extruded(s) => (s.interpolation, s.segments_per_span),
                    _ => unreachable!("a profile's shape"),
                };
                let polyline: Vec<[f64; 2]> = sample_profile(points, interpolation, per_span)
                    .iter()
                    .flatten()
                    .map(|s| [s.point.x, s.point.y])
                    .collect();
                if crosses_itself(&polyline) {
                    return Err(Refused::SelfIntersecting(part.name.clone()));
                }
            }
        }
        Ok(())
    }

    /// Traces `scene` with the seed's first `photons` photons.
    pub fn trace(&mut self, scene: &Scene, photons: u64) -> Result<Traced, Refused> {
        self.check(scene)?;
        let luminaire = Luminaire::for_edit(
            scene.clone(),
            &self.scene_dir,
            &|| false,
            self.previous.as_deref(),
        )
        .map_err(|e| Refused::Unbuildable(e.to_string()))?
        .ok_or_else(|| Refused::Unbuildable("stale".to_owned()))?;
        self.check_emitters(&luminaire)?;
        let luminaire = Arc::new(luminaire);
        let settings = TraceSettings {
            seed: self.seed,
            max_bounces: 64,
            layout: self.layout,
        };
        let mut session = Session::start(luminaire.prepared.clone(), settings);
        while session.map().photons_emitted < photons {
            let left = photons - session.map().photons_emitted;
            session.set_next_iteration_photons(u32::try_from(left).unwrap_or(u32::MAX));
            session
                .iterate_at_most(left)
                .map_err(|e| Refused::Unbuildable(e.to_string()))?;
        }
        let map = session.snapshot();
        let opening = luminaire.luminous_opening;
        self.previous = Some(luminaire);
        let table = self.tabulate(&map);
        Ok(Traced {
            table,
            map,
            opening,
        })
    }

    /// The pooled map on the evaluator's grid.
    pub fn tabulate(&self, map: &IntensityMap) -> CandelaTable {
        let candela = map.symmetrised(&self.symmetry).candela();
        match CellBinning::shared(self.layout, &self.c_planes_deg, &self.band_edges_deg) {
            Ok(binning) => binning.integrate(&candela).table(&self.gammas_deg),
            Err(_) => lucerna_photometry::table_from_cube_map(
                self.layout,
                &candela,
                &self.c_planes_deg,
                &self.gammas_deg,
            ),
        }
    }

    /// Refuses a candidate whose varied parts pass through an emitter:
    /// a triangle within the emitter's bounding sphere.
    fn check_emitters(&self, luminaire: &Luminaire) -> Result<(), Refused> {
        let scene = &luminaire.scene;
        let mesh = &luminaire.tessellated.mesh;
        for emitter in scene.emitters.iter().filter(|e| e.enabled) {
            let centre = DVec3::from_array(emitter.transform.translate);
            let scale = emitter
                .transform
                .scale
                .iter()
                .map(|s| s.abs())
                .fold(0.0, f64::max);
            let radius = scale
                * match emitter.shape {
                    EmitterShape::Disk { radius } => radius,
                    EmitterShape::Rectangle { width, depth } => 0.5 * width.hypot(depth),
                    EmitterShape::Sphere { radius } => radius,
                    EmitterShape::Cylinder { radius, height } => radius.hypot(0.5 * height),
                    // Its rays' starts are in the file: the emitter's origin.
                    EmitterShape::RayFile { .. } => 0.0,
                };
            let all: Vec<usize>;
            let parts = if self.moves_emitter {
                all = (0..scene.parts.len()).collect();
                &all
            } else {
                &self.varied_parts
            };
            for &p in parts {
                let name = &scene.parts[p].name;
                for surface in luminaire
                    .tessellated
                    .surfaces
                    .iter()
                    .filter(|s| s.kind == SurfaceKind::Part && s.index == p)
                {
                    for t in &mesh.triangles[surface.triangles.clone()] {
                        let [a, b, c] = t.map(|v| mesh.positions[v as usize].as_dvec3());
                        if point_triangle_distance(centre, a, b, c) < radius {
                            return Err(Refused::CutsEmitter {
                                part: name.clone(),
                                emitter: emitter.name.clone(),
                            });
                        }
                    }
                }
            }
        }
        Ok(())
    }
}

/// Whether two non-adjacent segments of a polyline cross.
fn crosses_itself(points: &[[f64; 2]]) -> bool {
    let n = points.len();
    if n < 4 {
        return false;
    }
    let orient = |a: [f64; 2], b: [f64; 2], c: [f64; 2]| {
        (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    };
    for i in 0..n - 1 {
        for j in i + 2..n - 1 {
            let (a, b, c, d) = (points[i], points[i + 1], points[j], points[j + 1]);
            let (d1, d2) = (orient(c, d, a), orient(c, d, b));
            let (d3, d4) = (orient(a, b, c), orient(a, b, d));
            if d1 * d2 < 0.0 && d3 * d4 < 0.0 {
                return true;
            }
        }
    }
    false
}

/// The distance from `p` to the triangle `abc`.
fn point_triangle_distance(p: DVec3, a: DVec3, b: DVec3, c: DVec3) -> f64 {
    // Ericson, Real-Time Collision Detection, 5.1.5: the closest point by
    // Voronoi regions.
    let (ab, ac, ap) = (b - a, c - a, p - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return (p - a).length();
    }
    let bp = p - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return (p - b).length();
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        let v = d1 / (d1 - d3);
        return (p - (a + v * ab)).length();
    }
    let cp = p - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return (p - c).length();
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        let w = d2 / (d2 - d6);
        return (p - (a + w * ac)).length();
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        let w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return (p - (b + w * (c - b))).length();
    }
    let denom = 1.0 / (va + vb + vc);
    let (v, w) = (vb * denom, vc * denom);
    (p - (a + ab * v + ac * w)).length()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_figure_eight_crosses_itself_and_an_arc_does_not() {
        let arc: Vec<[f64; 2]> = (0..20)
            .map(|k| {
                let t = f64::from(k) * 0.1;
                [t.cos(), t.sin()]
            })
            .collect();
        assert!(!crosses_itself(&arc));
        assert!(crosses_itself(&[
            [0.0, 0.0],
            [1.0, 1.0],
            [1.0, 0.0],
            [0.0, 1.0]
        ]));
    }

    #[test]
    fn the_distance_to_a_triangle_is_to_its_face_edge_or_corner() {
        let (a, b, c) = (DVec3::ZERO, DVec3::X, DVec3::Y);
        assert!((point_triangle_distance(DVec3::new(0.2, 0.2, 0.5), a, b, c) - 0.5).abs() < 1e-12);
        assert!((point_triangle_distance(DVec3::new(-1.0, 0.0, 0.0), a, b, c) - 1.0).abs() < 1e-12);
        let d = point_triangle_distance(DVec3::new(1.0, 1.0, 0.0), a, b, c);
        assert!((d - 0.5f64.sqrt()).abs() < 1e-12);
    }
}
