//! Which of the square's symmetries about the photometric axis a luminaire
//! has ([`AxialSymmetry`]), found from its tessellated geometry, materials
//! and emitters. A symmetric luminaire sends the same light into every
//! image of a direction, so its photons can be pooled over the images
//! (`TexelSymmetry::pool`): |group| times the photons for free.
//!
//! A group is claimed only when every triangle's image under each of its
//! isometries lies on the scene's surface of the same material (emitters:
//! the same flux), facing the image of its direction where the side
//! matters, with the images of its shading normals; see
//! [`luminaire_symmetry`]. Vertices match within a millionth of the
//! luminaire's size (generators round differently at mirrored angles; a
//! modelling error is far larger).

use std::collections::HashMap;

use glam::Vec3;
use lucerna_photometry::{AxialIsometry, AxialSymmetry};
use lucerna_scene::{Emission, Material, Scene, SurfaceKind, TessellatedScene};
use rayon::prelude::*;

use crate::prepared::PreparedScene;

/// The luminaire's symmetry and, when something other than the geometry
/// ruled symmetries out, what.
#[derive(Debug, Clone, PartialEq)]
pub struct LuminaireSymmetry {
    pub symmetry: AxialSymmetry,
    pub limited_by: Option<String>,
}

/// Vertex positions merged within a tolerance, looked up on a hash grid of
/// cells twice the tolerance.
struct Welded {
    tolerance: f32,
    cells: HashMap<[i64; 3], Vec<u32>>,
    points: Vec<Vec3>,
}

impl Welded {
    fn new(tolerance: f32) -> Welded {
        Welded {
            tolerance,
            cells: HashMap::new(),
            points: Vec::new(),
        }
    }

    fn cell(&self, p: Vec3) -> [i64; 3] {
        let s = 2.0 * self.tolerance;
        [
            (p.x / s).floor() as i64,
            (p.y / s).floor() as i64,
            (p.z / s).floor() as i64,
        ]
    }

    /// The merged point within the tolerance of `p`, if any.
    fn find(&self, p: Vec3) -> Option<u32> {
        let c = self.cell(p);
        let near = |cell: &[i64; 3]| {
            self.cells.get(cell).and_then(|ids| {
                ids.iter()
                    .copied()
                    .find(|&i| (self.points[i as usize] - p).abs().max_element() <= self.tolerance)
            })
        };
        if let Some(i) = near(&c) {
            return Some(i);
        }
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    if (dx, dy, dz) == (0, 0, 0) {
                        continue; // looked at first
                    }
                    if let Some(i) = near(&[c[0] + dx, c[1] + dy, c[2] + dz]) {
                        return Some(i);
                    }
                }
            }
        }
        None
    }

    fn insert(&mut self, p: Vec3) -> u32 {
        if let Some(i) = self.find(p) {
            return i;
        }
        let i = self.points.len() as u32;
        self.points.push(p);
        let c = self.cell(p);
        self.cells.entry(c).or_default().push(i);
        i
    }
}

/// Triangles by the cells of a uniform grid their bounding boxes overlap.
struct TriangleGrid {
    cells_per_axis: i64,
    half_width: f32,
    cells: HashMap<[i64; 3], Vec<u32>>,
}

impl TriangleGrid {
    fn new(count: usize, extent: f32, corners: impl Fn(usize) -> [Vec3; 3]) -> TriangleGrid {
        let mut grid = TriangleGrid {
            cells_per_axis: 48,
            half_width: extent.max(1e-6) * 1.001,
            cells: HashMap::new(),
        };
        for t in 0..count {
            let p = corners(t);
            let lo = grid.cell(p[0].min(p[1]).min(p[2]));
            let hi = grid.cell(p[0].max(p[1]).max(p[2]));
            for x in lo[0]..=hi[0] {
                for y in lo[1]..=hi[1] {
                    for z in lo[2]..=hi[2] {
                        grid.cells.entry([x, y, z]).or_default().push(t as u32);
                    }
                }
            }
        }
        grid
    }

    fn cell(&self, p: Vec3) -> [i64; 3] {
        let n = self.cells_per_axis;
        let to = |v: f32| {
            (((v / self.half_width + 1.0) * 0.5 * n as f32).floor() as i64).clamp(0, n - 1)
        };
        [to(p.x), to(p.y), to(p.z)]
    }

    /// Triangles whose bounding boxes overlap the cell of `p`.
    fn near(&self, p: Vec3) -> &[u32] {
        self.cells.get(&self.cell(p)).map_or(&[], Vec::as_slice)
    }
}

/// What must be equal for a surface to be another's image: material and,
/// for an emitter's surface, its flux (bits of the f64 lm).
type Tag = (u32, Option<u64>);

fn apply(g: AxialIsometry, v: Vec3) -> Vec3 {
    let [x, y, z] = g.apply([f64::from(v.x), f64::from(v.y), f64::from(v.z)]);
    Vec3::new(x as f32, y as f32, z as f32)
}

/// Whether `p` lies on triangle `q` (its projection inside, within a
/// little of the plane: a mirrored quad is split along its other
/// diagonal, which on a curved surface leaves the two halves a few
/// thousandths of their size apart).
fn on_triangle(q: [Vec3; 3], normal: Vec3, p: Vec3) -> bool {
    let size = (q[1] - q[0])
        .length()
        .max((q[2] - q[0]).length())
        .max((q[2] - q[1]).length());
    if (p - q[0]).dot(normal).abs() > 0.02 * size {
        return false;
    }
    // Barycentric coordinates of the projection, each edge's side.
    let inside = |a: Vec3, b: Vec3| (b - a).cross(p - a).dot(normal) >= -1e-4 * size * size;
    inside(q[0], q[1]) && inside(q[1], q[2]) && inside(q[2], q[0])
}

/// The largest axial symmetry of the luminaire (the identity group if it
/// has none, or if its emitters have measured profiles, which are not
/// checked).
///
/// An isometry holds when, for every triangle, its vertices' images are
/// vertices of the scene (within a millionth of the luminaire's size), the
/// image of its centroid lies on a scene triangle of the same material (and
/// emitter flux) facing the image of its normal, and the images of its
/// shading normals are shading normals there. The surfaces, not their
/// triangulations, must match: a mirrored quad is split along the other
/// diagonal.
pub fn luminaire_symmetry(scene: &Scene, tessellated: &TessellatedScene) -> LuminaireSymmetry {
    if has_ray_file(scene) {
        return LuminaireSymmetry {
            symmetry: AxialSymmetry::None,
            limited_by: Some("an emitter is a ray file, whose rays were not checked".into()),
        };
    }
    symmetry_where(scene, tessellated, &|_| true)
}

fn has_ray_file(scene: &Scene) -> bool {
    scene
        .emitters
        .iter()
        .any(|e| e.enabled && matches!(e.shape, lucerna_scene::EmitterShape::RayFile { .. }))
}

/// [`luminaire_symmetry`] of a prepared scene, whose ray-file emitters'
/// rays are checked too: an isometry holds for them when the rays,
/// placed in the luminaire, are its own image within the file's sampling
/// noise ([`RayBins::holds`]). A measured file is never exactly
/// symmetric; pooling over a symmetry it has within its own noise moves
/// the result by less than that noise, and over one it lacks would bias
/// it, so the test is strict (a χ² over flux-weighted bins).
pub fn prepared_luminaire_symmetry(
    scene: &Scene,
    tessellated: &TessellatedScene,
    prepared: &PreparedScene,
) -> LuminaireSymmetry {
    if !has_ray_file(scene) {
        return luminaire_symmetry(scene, tessellated);
    }
    let bins = RayBins::of(prepared);
    let of_rays = AxialSymmetry::largest_where(|g| bins.holds(g));
    let mut found = symmetry_where(scene, tessellated, &|g| bins.holds(g));
    if of_rays != AxialSymmetry::Square && found.limited_by.is_none() {
        found.limited_by = Some(if of_rays == AxialSymmetry::None {
            "the ray file's rays have no symmetry of the square (checked within their noise)"
                .to_owned()
        } else {
            format!(
                "the ray file's rays are symmetric only under {} (checked within their noise)",
                of_rays.describe()
            )
        });
    }
    found
}

/// The ray-file emitters' rays in the luminaire, binned by where they
/// start (x, y on a square grid about the axis) and where they go
/// (direction x, y on a square grid, up or down): every isometry of the
/// square maps these bins onto bins, so a symmetric ray set has equal
/// flux in a bin and its image, within the rays' noise.
#[derive(Debug)]
pub struct RayBins {
    /// Flux and flux² per bin.
    flux: Vec<f64>,
    flux_squared: Vec<f64>,
}

/// Cells per axis of the position and direction grids.
const RAY_CELLS: usize = 4;
/// How far above its expectation (1 per bin pair) the mean χ² may be, in
/// its standard deviations, before a symmetry is refused.
const RAY_SIGMAS: f64 = 6.0;

impl RayBins {
    fn bin_count() -> usize {
        RAY_CELLS.pow(4) * 2
    }

    /// The bin of a start `p` (in the grid of half-width `half`) and a
    /// unit direction `d`.
    fn bin(p: [f64; 3], d: [f64; 3], half: f64) -> usize {
        let cell = |v: f64, h: f64| {
            (((v / h + 1.0) * 0.5 * RAY_CELLS as f64).floor() as isize)
                .clamp(0, RAY_CELLS as isize - 1) as usize
        };
        let n = RAY_CELLS;
        let up = usize::from(d[2] > 0.0);
        (((cell(p[0], half) * n + cell(p[1], half)) * n + cell(d[0], 1.0)) * n + cell(d[1], 1.0))
            * 2
            + up
    }

    /// The rays of every ray-file emitter of `prepared`, each weighted by
    /// its share of its emitter's flux.
    pub fn of(prepared: &PreparedScene) -> RayBins {
        use crate::prepared::EmitterDirections;
        let sets: Vec<_> = prepared
            .emitters
            .iter()
            .filter_map(|e| match &e.directions {
                EmitterDirections::RayFile(sampler) => Some((e, sampler.clone())),
                _ => None,
            })
            .collect();
        let start =
            |e: &crate::prepared::TraceEmitter, rays: &lucerna_photometry::tm25::RaySet, i| {
                let p = glam::Vec3A::from_array(rays.position_mm(i)) * 1e-3;
                let q = e.luminaire_from_emitter.transform_point3a(p);
                let d = e
                    .luminaire_from_emitter
                    .matrix3
                    .mul_vec3a(glam::Vec3A::from_array(rays.direction(i)))
                    .normalize_or_zero();
                (q.to_array().map(f64::from), d.to_array().map(f64::from))
            };
        // The grid's half-width: the farthest start from the axis.
        let mut half = 0.0f64;
        for (e, sampler) in &sets {
            for i in 0..sampler.rays.len() {
                let (p, _) = start(e, &sampler.rays, i);
                half = half.max(p[0].abs()).max(p[1].abs());
            }
        }
        let half = if half > 0.0 { half * (1.0 + 1e-6) } else { 1.0 };
        let mut flux = vec![0.0; Self::bin_count()];
        let mut flux_squared = vec![0.0; Self::bin_count()];
        for (e, sampler) in &sets {
            let rays = &sampler.rays;
            let total = sampler.total_lm;
            if !(total > 0.0) {
                continue;
            }
            for i in 0..rays.len() {
                let w = e.flux_lm * f64::from(rays.luminous_flux_lm[i]) / total;
                let (p, d) = start(e, rays, i);
                let b = Self::bin(p, d, half);
                flux[b] += w;
                flux_squared[b] += w * w;
            }
        }
        RayBins { flux, flux_squared }
    }

    /// Whether `g` maps the binned rays onto themselves within their
    /// noise: the mean over bins not their own image of
    /// (F_b − F_g(b))² / (V_b + V_g(b)) is about 1 for a symmetric set.
    pub fn holds(&self, g: AxialIsometry) -> bool {
        let n = RAY_CELLS;
        // A cell's centre on the unit grid.
        let centre = |k: usize| (k as f64 + 0.5) * 2.0 / n as f64 - 1.0;
        let (mut chi2, mut terms) = (0.0, 0usize);
        for b in 0..Self::bin_count() {
            let up = b % 2;
            let rest = b / 2;
            let (dy, dx) = (rest % n, (rest / n) % n);
            let (py, px) = ((rest / n / n) % n, rest / n / n / n);
            let p = g.apply([centre(px), centre(py), 0.0]);
            let d = g.apply([centre(dx), centre(dy), if up == 1 { 0.5 } else { -0.5 }]);
            let image = Self::bin(p, d, 1.0);
            if image == b {
                continue;
            }
            let v = self.flux_squared[b] + self.flux_squared[image];
            if v > 0.0 {
                chi2 += (self.flux[b] - self.flux[image]).powi(2) / v;
                terms += 1;
            }
        }
        if terms == 0 {
            return true;
        }
        // Each pair is counted from both of its bins: half as many
        // independent terms.
        let independent = (terms as f64 / 2.0).max(1.0);
        chi2 / terms as f64 <= 1.0 + RAY_SIGMAS * (2.0 / independent).sqrt()
    }
}

/// The symmetry of the triangles, materials and surface emitters, where
/// `also` holds too.
fn symmetry_where(
    scene: &Scene,
    tessellated: &TessellatedScene,
    also: &(dyn Fn(AxialIsometry) -> bool + Sync),
) -> LuminaireSymmetry {
    let enabled_emitters = || scene.emitters.iter().filter(|e| e.enabled);
    if enabled_emitters().any(|e| matches!(e.emission, Emission::Profile(_))) {
        return LuminaireSymmetry {
            symmetry: AxialSymmetry::None,
            limited_by: Some(
                "an emitter has a measured profile (its symmetry is not checked)".into(),
            ),
        };
    }
    // Brushing at an angle other than 0° or 90° to the circumferential
    // direction turns with the luminaire but is not mirror-symmetric.
    let twisted = tessellated.materials.iter().find(|(_, m)| {
        matches!(m, Material::RoughConductor { roughness_u, roughness_v, orientation_deg, .. }
            if roughness_u != roughness_v && (orientation_deg / 90.0).fract().abs() > 1e-9)
    });
    let mesh = &tessellated.mesh;
    let extent = mesh
        .positions
        .iter()
        .fold(0.0f32, |m, p| m.max(p.abs().max_element()));
    let mut welded = Welded::new(1e-6 * extent.max(1e-6));
    let vertex: Vec<u32> = mesh.positions.iter().map(|&p| welded.insert(p)).collect();
    let mut tag: Vec<Tag> = vec![(0u32, None); mesh.triangle_count()];
    for surface in &tessellated.surfaces {
        let flux = match surface.kind {
            SurfaceKind::Emitter => scene
                .emitters
                .get(surface.index)
                .map(|e| e.flux_lm.to_bits()),
            SurfaceKind::Part => None,
        };
        for t in surface.triangles.clone() {
            tag[t] = (tessellated.triangle_material[t], flux);
        }
    }
    let corners = |t: usize| mesh.triangles[t].map(|i| mesh.positions[i as usize]);
    let normal: Vec<Vec3> = (0..mesh.triangle_count())
        .map(|t| {
            let p = corners(t);
            (p[1] - p[0]).cross(p[2] - p[0]).normalize_or_zero()
        })
        .collect();
    // Which way a surface faces matters for dielectrics (inside and
    // outside) and emitters (the side they emit to); every other material
    // is a two-sided sheet.
    let oriented: Vec<bool> = (0..mesh.triangle_count())
        .map(|t| {
            tag[t].1.is_some()
                || matches!(
                    tessellated.materials.get(tag[t].0 as usize),
                    Some((_, Material::Dielectric { .. }))
                )
        })
        .collect();
    let alike = |t: usize, a: Vec3, b: Vec3, cos: f32| {
        let d = a.dot(b);
        if oriented[t] { d > cos } else { d.abs() > cos }
    };
    // Triangles around each merged vertex.
    let mut around = vec![Vec::new(); welded.points.len()];
    for (t, tri) in mesh.triangles.iter().enumerate() {
        for &i in tri {
            around[vertex[i as usize] as usize].push(t as u32);
        }
    }
    let grid = TriangleGrid::new(mesh.triangle_count(), extent, corners);
    let holds = |g: AxialIsometry| {
        if g.is_mirror() && twisted.is_some() || !also(g) {
            return false;
        }
        // In parallel on rayon's pool (at the editor's low priority).
        (0..mesh.triangle_count()).into_par_iter().all(|t| {
            let tri = mesh.triangles[t];
            let Some(image) = tri
                .iter()
                .map(|&i| welded.find(apply(g, mesh.positions[i as usize])))
                .collect::<Option<Vec<u32>>>()
            else {
                return false;
            };
            let same = |u: &u32| tag[*u as usize] == tag[t];
            // Shading normals: the image of each corner's is a corner's
            // normal at the image vertex, on a surface like this one.
            let shading = tri.iter().zip(&image).all(|(&i, &w)| {
                let expected = apply(g, mesh.normals[i as usize]);
                around[w as usize].iter().filter(|u| same(u)).any(|&u| {
                    mesh.triangles[u as usize].iter().any(|&j| {
                        vertex[j as usize] == w
                            && alike(t, mesh.normals[j as usize], expected, 0.999)
                    })
                })
            });
            // Surface: the image of the centroid lies on a like triangle
            // facing the image of this one's normal (a fan or a quad may be
            // split differently on the other side).
            let p = corners(t);
            let centroid = apply(g, (p[0] + p[1] + p[2]) / 3.0);
            let facing = apply(g, normal[t]);
            let covered = grid.near(centroid).iter().filter(|u| same(u)).any(|&u| {
                alike(t, normal[u as usize], facing, 0.99)
                    && on_triangle(corners(u as usize), normal[u as usize], centroid)
            });
            shading && covered
        })
    };
    let symmetry = AxialSymmetry::largest_where(holds);
    let limited_by = twisted.map(|(name, _)| {
        format!("no mirrors: material '{name}' is brushed at an angle, which mirrors do not keep")
    });
    LuminaireSymmetry {
        symmetry,
        limited_by,
    }
}
