//! What the viewport draws, as vertex data: the luminaire's surfaces with
//! a look per material, the intensity cube, the photometric solid, photon
//! paths and axes. Pure
//! data, so it is tested without a GPU.

use bytemuck::{Pod, Zeroable};
use glam::Vec3;
use lucerna_photometry::table::direction;
use lucerna_photometry::{CandelaTable, CubeFace, CubeMapLayout};
use lucerna_scene::{Material, SurfaceKind, TessellatedScene};
use lucerna_tracer::{Fate, PhotonPath};

use crate::colour::intensity_colour;

/// Shading looks (the shader's `LOOK_*`).
pub const LOOK_DIFFUSE: u32 = 0;
pub const LOOK_METAL: u32 = 1;
pub const LOOK_GLASS: u32 = 2;
pub const LOOK_EMITTER: u32 = 3;

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable, PartialEq)]
pub struct MeshVertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    /// Linear RGBA.
    pub colour: [f32; 4],
    pub look: u32,
    /// Index into [`TessellatedScene::surfaces`], for the highlight.
    pub surface: u32,
}

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable, PartialEq)]
pub struct CubeVertex {
    /// Corner on the unit cube.
    pub corner: [f32; 3],
    pub outward: [f32; 3],
    pub uv: [f32; 2],
    pub layer: u32,
}

#[repr(C)]
#[derive(Debug, Clone, Copy, Pod, Zeroable, PartialEq)]
pub struct LineVertex {
    pub position: [f32; 3],
    /// Linear RGBA.
    pub colour: [f32; 4],
}

/// Colour (linear) and look of a material: paint is grey by its albedo,
/// metal silvery, plastics pale blue or milky.
pub fn material_look(m: &Material) -> ([f32; 4], u32) {
    match *m {
        Material::Absorber => ([0.03, 0.03, 0.03, 1.0], LOOK_DIFFUSE),
        Material::Lambertian { albedo } => {
            let a = albedo.clamp(0.02, 1.0) as f32;
            ([a, a * 0.98, a * 0.94, 1.0], LOOK_DIFFUSE)
        }
        Material::Mirror { reflectance } => {
            let r = reflectance.clamp(0.05, 1.0) as f32;
            ([0.85 * r, 0.88 * r, 0.93 * r, 1.0], LOOK_METAL)
        }
        Material::RoughConductor { reflectance, .. } => {
            let r = reflectance.clamp(0.05, 1.0) as f32;
            ([0.6 * r, 0.62 * r, 0.66 * r, 1.0], LOOK_METAL)
        }
        Material::Dielectric { .. } => ([0.35, 0.62, 0.75, 1.0], LOOK_GLASS),
        Material::Diffuser { .. } => ([0.8, 0.8, 0.76, 1.0], LOOK_GLASS),
    }
}

/// The warm yellow of an emitter's surface.
const EMITTER_COLOUR: [f32; 4] = [1.0, 0.78, 0.2, 1.0];

/// A finished part's preview holds at most this many triangles: a finish
/// too fine to show within them is left to the traced light.
const MAX_FINISH_PREVIEW_TRIANGLES: f64 = 150_000.0;

/// A finished surface's triangles split to a quarter of the finish's
/// finest feature, their normals tilted by its slopes (luminaire
/// coordinates): the finish shown by its shading where the traced mesh
/// does not carry it; None where it is too fine to show or has no
/// geometry.
fn finish_preview(
    t: &TessellatedScene,
    surface: &lucerna_scene::tessellate::SurfaceRange,
) -> Option<lucerna_scene::TriangleMesh> {
    use lucerna_scene::finish_layout::{finish_feature_size, finish_shading_mesh};
    let first = surface.triangles.start;
    let material = *t.triangle_material.get(first)?;
    let f = t.material_finish.get(material as usize)?.as_ref()?;
    let finish = f.normals.as_ref().or(f.brdf.as_ref())?;
    let feature = finish_feature_size(finish);
    // The surface's triangles with their shared vertices (so a split
    // edge is split on both sides).
    let mut part = lucerna_scene::TriangleMesh::default();
    let mut index = std::collections::HashMap::new();
    for tri in surface.triangles.clone() {
        let corners = t.mesh.triangles[tri].map(|i| {
            *index.entry(i).or_insert_with(|| {
                part.positions.push(t.mesh.positions[i as usize]);
                part.normals
                    .push(t.mesh.normals.get(i as usize).copied().unwrap_or(Vec3::Z));
                (part.positions.len() - 1) as u32
            })
        });
        part.triangles.push(corners);
    }
    let area = part.area();
    let edge = (0.25 * feature).max((area / (0.43 * MAX_FINISH_PREVIEW_TRIANGLES)).sqrt());
    if !(feature > 0.0 && edge <= 0.5 * feature) {
        return None;
    }
    let part_from_luminaire = f.luminaire_from_part.inverse();
    let local = part.transformed(&part_from_luminaire);
    let shaded = finish_shading_mesh(&local, &f.layout, finish, edge).ok()??;
    Some(shaded.transformed(&f.luminaire_from_part))
}

/// Three vertices per triangle (smooth normals, flat material and
/// surface); a finished part's finish shown by its normals.
pub fn luminaire_vertices(t: &TessellatedScene, finishes: bool) -> Vec<MeshVertex> {
    let mesh = &t.mesh;
    let mut vertices = Vec::with_capacity(3 * mesh.triangles.len());
    for (s, surface) in t.surfaces.iter().enumerate() {
        if finishes
            && surface.kind == SurfaceKind::Part
            && let Some(preview) = finish_preview(t, surface)
        {
            let (colour, look) = t
                .triangle_material
                .get(surface.triangles.start)
                .and_then(|&m| t.materials.get(m as usize))
                .map_or(([0.5; 4], LOOK_DIFFUSE), |(_, m)| material_look(m));
            for tri in &preview.triangles {
                for &i in tri {
                    vertices.push(MeshVertex {
                        position: preview.positions[i as usize].to_array(),
                        normal: preview.normals[i as usize].to_array(),
                        colour,
                        look,
                        surface: s as u32,
                    });
                }
            }
            continue;
        }
        for tri in surface.triangles.clone() {
            let Some(corners) = mesh.triangles.get(tri) else {
                continue;
            };
            let (colour, look) = match surface.kind {
                SurfaceKind::Emitter => (EMITTER_COLOUR, LOOK_EMITTER),
                SurfaceKind::Part => t
                    .triangle_material
                    .get(tri)
                    .and_then(|&m| t.materials.get(m as usize))
                    .map_or(([0.5; 4], LOOK_DIFFUSE), |(_, m)| material_look(m)),
            };
            for &i in corners {
                let i = i as usize;
                vertices.push(MeshVertex {
                    position: mesh.positions[i].to_array(),
                    normal: mesh.normals.get(i).copied().unwrap_or(Vec3::Z).to_array(),
                    colour,
                    look,
                    surface: s as u32,
                });
            }
        }
    }
    vertices
}

/// Rays of a ray-file emitter drawn, at most this many.
const MAX_RAY_ORIGINS: usize = 2000;

/// Where the rays of each ray-file emitter start, as a cloud of small
/// emitter-coloured marks (three crossed triangles each, seen from any
/// side; `size` across, metres), placed by the emitter's transform. No
/// surface: they are not picked.
pub fn ray_origin_marks(prepared: &lucerna_tracer::PreparedScene, size: f32) -> Vec<MeshVertex> {
    use lucerna_tracer::prepared::EmitterDirections;
    let mut vertices = Vec::new();
    for e in &prepared.emitters {
        let EmitterDirections::RayFile(sampler) = &e.directions else {
            continue;
        };
        let rays = &sampler.rays;
        let step = rays.len().div_ceil(MAX_RAY_ORIGINS).max(1);
        for i in (0..rays.len()).step_by(step) {
            let local = glam::Vec3A::from_array(rays.position_mm(i)) * 1e-3;
            let p = Vec3::from(e.luminaire_from_emitter.transform_point3a(local));
            let h = 0.5 * size;
            for (a, b, normal) in [
                (Vec3::X, Vec3::Y, Vec3::Z),
                (Vec3::Y, Vec3::Z, Vec3::X),
                (Vec3::Z, Vec3::X, Vec3::Y),
            ] {
                for corner in [p - a * h, p + a * h, p + b * h] {
                    vertices.push(MeshVertex {
                        position: corner.to_array(),
                        normal: normal.to_array(),
                        colour: EMITTER_COLOUR,
                        look: LOOK_EMITTER,
                        surface: u32::MAX,
                    });
                }
            }
        }
    }
    vertices
}

/// The surface (index into `surfaces`) a triangle belongs to.
pub fn surface_of_triangle(t: &TessellatedScene, triangle: usize) -> Option<usize> {
    t.surfaces
        .iter()
        .position(|s| s.triangles.contains(&triangle))
}

/// The faces in the layout's order, so a face's layer is its texel block.
const FACES: [CubeFace; 6] = [
    CubeFace::PosX,
    CubeFace::NegX,
    CubeFace::PosY,
    CubeFace::NegY,
    CubeFace::PosZ,
    CubeFace::NegZ,
];

/// Two triangles per face of the unit cube, with face coordinates: texel
/// (column i, row j) of a face sits at uv ((i + ½)/n, (j + ½)/n).
pub fn cube_vertices() -> Vec<CubeVertex> {
    let mut vertices = Vec::with_capacity(36);
    for face in FACES {
        let layer = face as u32;
        let outward = face.direction(0.0, 0.0).map(|v| v as f32);
        let corner = |a: f64, b: f64| CubeVertex {
            corner: face.direction(a, b).map(|v| v as f32),
            outward,
            uv: [(0.5 * (a + 1.0)) as f32, (0.5 * (b + 1.0)) as f32],
            layer,
        };
        let quad = [
            corner(-1.0, -1.0),
            corner(1.0, -1.0),
            corner(1.0, 1.0),
            corner(-1.0, 1.0),
        ];
        vertices.extend([quad[0], quad[1], quad[2], quad[0], quad[2], quad[3]]);
    }
    vertices
}

/// The cube where no photon went.
const NO_LIGHT: egui::Color32 = egui::Color32::from_rgb(38, 40, 46);

/// Faces across and down the cube texture: a 3 × 2 atlas rather than a
/// six-layer array, which wgpu's GL backend would take for a cube map.
pub const ATLAS_COLUMNS: usize = 3;
pub const ATLAS_ROWS: usize = 2;

/// RGBA8 (sRGB) texels of the cube atlas (3n × 2n): face k at column
/// k mod 3, row k / 3, each in its (column, row) texel order; the
/// cube-map view's log false colour over its decades below `peak`.
pub fn cube_texels(layout: CubeMapLayout, candela: &[f64], peak: f64) -> Vec<u8> {
    let n = layout.resolution as usize;
    let width = ATLAS_COLUMNS * n;
    let mut texels = vec![0u8; 4 * width * ATLAS_ROWS * n];
    for t in 0..layout.texel_count() {
        let v = candela.get(t).copied().unwrap_or(0.0);
        // Directions no light reaches stay a dark grey, so the cube reads
        // as a box and not as the background.
        let c = if v > 0.0 {
            intensity_colour(v, peak)
        } else {
            NO_LIGHT
        };
        let (face, column, row) = layout.texel_coordinates(t);
        let face = face as usize;
        let x = (face % ATLAS_COLUMNS) * n + column as usize;
        let y = (face / ATLAS_COLUMNS) * n + row as usize;
        let at = 4 * (y * width + x);
        texels[at..at + 4].copy_from_slice(&[c.r(), c.g(), c.b(), 255]);
    }
    texels
}

/// The surface id the photometric solid's vertices carry: no part's, and
/// not the "nothing selected" one, so it is never tinted as selected.
pub const SOLID_SURFACE: u32 = u32::MAX - 1;
/// C-planes of the photometric solid: a ring every 5°, whatever the
/// table's own (a round luminaire's table has one).
const SOLID_C_STEP_DEG: f64 = 5.0;

/// The photometric solid of `table`: each direction (C, γ) at a distance
/// from `origin` proportional to its intensity, `radius` (m) at the
/// peak, coloured by the cube's log false colour. C every 5°, γ at the
/// table's own angles (fine where the beam is narrow); smooth normals
/// from the grid's neighbours. Empty for a table without light.
pub fn photometric_solid(table: &CandelaTable, origin: Vec3, radius: f32) -> Vec<MeshVertex> {
    let peak = table.peak().0;
    let gammas = &table.gammas_deg;
    if !(peak > 0.0) || gammas.len() < 2 {
        return Vec::new();
    }
    let rings = (360.0 / SOLID_C_STEP_DEG) as usize;
    let ng = gammas.len();
    // Points ring by ring (C), γ along each; ring `rings` closes the seam.
    let mut points = Vec::with_capacity((rings + 1) * ng);
    let mut candela = Vec::with_capacity((rings + 1) * ng);
    for k in 0..=rings {
        let c = (k % rings) as f64 * SOLID_C_STEP_DEG;
        for &g in gammas {
            let v = table.intensity(c, g).max(0.0);
            let d = direction(c.to_radians(), g.to_radians());
            let r = radius * (v / peak) as f32;
            points.push(origin + r * Vec3::new(d[0] as f32, d[1] as f32, d[2] as f32));
            candela.push(v);
        }
    }
    let at = |k: usize, j: usize| (k % rings) * ng + j;
    let normal = |k: usize, j: usize| -> Vec3 {
        let across = points[at(k + 1, j)] - points[at(k + rings - 1, j)];
        let along = points[at(k, (j + 1).min(ng - 1))] - points[at(k, j.saturating_sub(1))];
        let n = across.cross(along);
        if n.length_squared() > 0.0 {
            n.normalize()
        } else {
            // On the axis or where no light goes: the direction itself.
            (points[at(k, j)] - origin).normalize_or(Vec3::NEG_Z)
        }
    };
    let vertex = |k: usize, j: usize| MeshVertex {
        position: points[at(k, j)].to_array(),
        normal: normal(k, j).to_array(),
        colour: linear(if candela[at(k, j)] > 0.0 {
            intensity_colour(candela[at(k, j)], peak)
        } else {
            NO_LIGHT
        }),
        look: LOOK_DIFFUSE,
        surface: SOLID_SURFACE,
    };
    let mut vertices = Vec::with_capacity(rings * (ng - 1) * 6);
    for k in 0..rings {
        for j in 0..ng - 1 {
            let (a, b, c, d) = (
                vertex(k, j),
                vertex(k + 1, j),
                vertex(k, j + 1),
                vertex(k + 1, j + 1),
            );
            vertices.extend([a, b, d, a, d, c]);
        }
    }
    vertices
}

/// A path's colour by the bounces it took: direct light yellow, then
/// green, cyan, magenta, red for four and more: a stray reflection
/// stands out by its colour.
pub fn bounce_colour(bounces: u32) -> egui::Color32 {
    match bounces {
        0 => egui::Color32::from_rgb(255, 220, 40),
        1 => egui::Color32::from_rgb(60, 220, 80),
        2 => egui::Color32::from_rgb(40, 200, 240),
        3 => egui::Color32::from_rgb(230, 60, 230),
        _ => egui::Color32::from_rgb(240, 50, 40),
    }
}

fn linear(c: egui::Color32) -> [f32; 4] {
    egui::Rgba::from(c).to_array()
}

/// Distance along `d` from `p` (inside) to the box of half edge `half`
/// about `centre`.
fn exit_distance(p: Vec3, d: Vec3, centre: Vec3, half: f32) -> f32 {
    (0..3)
        .filter(|&k| d[k].abs() > 1e-9)
        .map(|k| ((centre[k] + half * d[k].signum()) - p[k]) / d[k])
        .fold(f32::INFINITY, f32::min)
        .max(0.0)
}

/// Line segments of the escaped paths (the ones that make the
/// distribution), each drawn out to the box of half edge `reach` about
/// `centre`.
pub fn path_lines(paths: &[PhotonPath], centre: Vec3, reach: f32) -> Vec<LineVertex> {
    let mut lines = Vec::new();
    for p in paths {
        let Fate::Escaped(d) = p.fate else { continue };
        let colour = linear(bounce_colour(p.bounces));
        let mut push = |a: Vec3, b: Vec3| {
            lines.push(LineVertex {
                position: a.to_array(),
                colour,
            });
            lines.push(LineVertex {
                position: b.to_array(),
                colour,
            });
        };
        for w in p.points.windows(2) {
            push(w[0], w[1]);
        }
        if let Some(&last) = p.points.last() {
            let d = Vec3::from(d);
            push(last, last + d * exit_distance(last, d, centre, reach));
        }
    }
    lines
}

/// The twelve edges of the cube of half edge `half` about `centre`.
pub fn cube_edges(centre: Vec3, half: f32) -> Vec<LineVertex> {
    let colour = linear(egui::Color32::from_gray(110));
    let corner = |i: usize| {
        centre
            + half
                * Vec3::new(
                    if i & 1 == 0 { -1.0 } else { 1.0 },
                    if i & 2 == 0 { -1.0 } else { 1.0 },
                    if i & 4 == 0 { -1.0 } else { 1.0 },
                )
    };
    let mut lines = Vec::with_capacity(24);
    for i in 0..8 {
        for bit in [1, 2, 4] {
            if i & bit == 0 {
                for p in [corner(i), corner(i | bit)] {
                    lines.push(LineVertex {
                        position: p.to_array(),
                        colour,
                    });
                }
            }
        }
    }
    lines
}

/// The luminaire's axes from its origin: x (C0) red, y (C90) green, z (up)
/// blue, `length` long.
pub fn axis_lines(length: f32) -> Vec<LineVertex> {
    [
        (Vec3::X, egui::Color32::from_rgb(230, 60, 60)),
        (Vec3::Y, egui::Color32::from_rgb(70, 200, 70)),
        (Vec3::Z, egui::Color32::from_rgb(70, 120, 240)),
    ]
    .into_iter()
    .flat_map(|(axis, c)| {
        let colour = linear(c);
        [
            LineVertex {
                position: [0.0; 3],
                colour,
            },
            LineVertex {
                position: (axis * length).to_array(),
                colour,
            },
        ]
    })
    .collect()
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]
    use super::*;

    /// A Lambertian emitter facing down: I = I₀ cos γ, none upwards.
    fn lambertian(c_planes_deg: Vec<f64>) -> CandelaTable {
        let gammas_deg: Vec<f64> = (0..=36).map(|k| 5.0 * k as f64).collect();
        let candela = c_planes_deg
            .iter()
            .flat_map(|_| {
                gammas_deg
                    .iter()
                    .map(|g: &f64| 100.0 * g.to_radians().cos().max(0.0))
            })
            .collect();
        CandelaTable {
            c_planes_deg,
            gammas_deg,
            candela,
        }
    }

    #[test]
    fn a_lambertian_solid_is_the_sphere_through_its_origin() {
        // r = R cos γ along each direction: a sphere of diameter R below
        // the origin, touching it.
        let (origin, radius) = (Vec3::new(0.01, -0.02, 0.03), 0.2);
        let centre = origin - Vec3::Z * (0.5 * radius);
        let solid = photometric_solid(&lambertian(vec![0.0]), origin, radius);
        assert_eq!(solid.len(), 72 * 36 * 6);
        let mut deepest = 0.0f32;
        for v in &solid {
            let p = Vec3::from(v.position);
            assert!(
                ((p - centre).length() - 0.5 * radius).abs() < 1e-5,
                "{p} is off the sphere"
            );
            deepest = deepest.max(origin.z - p.z);
            assert_eq!(v.surface, SOLID_SURFACE);
            // Away from the origin the normal is the sphere's.
            if (p - origin).length() > 0.1 * radius {
                let along = Vec3::from(v.normal).dot((p - centre).normalize()).abs();
                assert!(along > 0.99, "normal {:?} at {p}", v.normal);
            }
        }
        // The peak straight down, `radius` away.
        assert!((deepest - radius).abs() < 1e-6, "{deepest}");
    }

    #[test]
    fn a_one_plane_table_gives_the_solid_of_its_plane_all_round() {
        let planes: Vec<f64> = (0..72).map(|k| 5.0 * k as f64).collect();
        let one = photometric_solid(&lambertian(vec![0.0]), Vec3::ZERO, 1.0);
        let all = photometric_solid(&lambertian(planes), Vec3::ZERO, 1.0);
        assert_eq!(one.len(), all.len());
        for (a, b) in one.iter().zip(&all) {
            assert!((Vec3::from(a.position) - Vec3::from(b.position)).length() < 1e-6);
            assert_eq!(a.colour, b.colour);
        }
        // No light, no solid.
        let dark = CandelaTable {
            candela: vec![0.0; 37],
            ..lambertian(vec![0.0])
        };
        assert!(photometric_solid(&dark, Vec3::ZERO, 1.0).is_empty());
    }

    #[test]
    fn cube_texels_sit_where_their_directions_point() {
        let layout = CubeMapLayout::new(4);
        let n = layout.resolution;
        let vertices = cube_vertices();
        for (k, face) in FACES.into_iter().enumerate() {
            // A face's layer is its block of texels in the layout.
            assert_eq!(layout.texel_index(face, 0, 0), k * (n * n) as usize);
            let quad: Vec<&CubeVertex> = vertices.iter().filter(|v| v.layer == k as u32).collect();
            assert_eq!(quad.len(), 6);
            // Corners interpolate face coordinates linearly in uv.
            for v in quad {
                let (a, b) = (2.0 * v.uv[0] as f64 - 1.0, 2.0 * v.uv[1] as f64 - 1.0);
                assert_eq!(v.corner, face.direction(a, b).map(|x| x as f32));
            }
            // The texture's texel at (column i, row j) of the layer shows
            // the direction the layout counts in texel (face, i, j).
            for j in 0..n {
                for i in 0..n {
                    let uv = [
                        (f64::from(i) + 0.5) / f64::from(n),
                        (f64::from(j) + 0.5) / f64::from(n),
                    ];
                    let d = face.direction(2.0 * uv[0] - 1.0, 2.0 * uv[1] - 1.0);
                    let texel = k * (n * n) as usize + (j * n + i) as usize;
                    assert_eq!(layout.texel_of_direction(d), texel, "{face:?} {i} {j}");
                }
            }
        }
        // In the atlas, texel t sits at its face's cell: one bright texel
        // per face lands where the shader's atlas coordinates look.
        let mut candela = vec![0.0; layout.texel_count()];
        for face in FACES {
            candela[layout.texel_index(face, 1, 2)] = 1.0;
        }
        let texels = cube_texels(layout, &candela, 1.0);
        let width = ATLAS_COLUMNS * n as usize;
        assert_eq!(texels.len(), 4 * layout.texel_count());
        let bright: Vec<(usize, usize)> = (0..texels.len() / 4)
            .filter(|&p| texels[4 * p..4 * p + 3] != [38, 40, 46])
            .map(|p| (p % width, p / width))
            .collect();
        let expected: Vec<(usize, usize)> = (0..6)
            .map(|k| ((k % 3) * n as usize + 1, (k / 3) * n as usize + 2))
            .collect();
        let mut sorted = expected.clone();
        sorted.sort_by_key(|&(x, y)| (y, x));
        assert_eq!(bright, sorted);
    }

    #[test]
    fn an_escaped_path_is_drawn_to_the_box() {
        let path = PhotonPath {
            points: vec![Vec3::ZERO, Vec3::new(0.0, 0.0, 0.01)],
            fate: Fate::Escaped(glam::Vec3A::new(0.0, 0.6, -0.8)),
            bounces: 1,
        };
        let lines = path_lines(&[path], Vec3::ZERO, 0.2);
        assert_eq!(lines.len(), 4);
        let end = Vec3::from(lines[3].position);
        // Leaves through the bottom face (z = −0.2).
        assert!((end.z + 0.2).abs() < 1e-5, "{end}");
        assert_eq!(lines[0].colour, linear(bounce_colour(1)));
        let absorbed = PhotonPath {
            points: vec![Vec3::ZERO, Vec3::X],
            fate: Fate::Absorbed,
            bounces: 0,
        };
        assert!(path_lines(&[absorbed], Vec3::ZERO, 1.0).is_empty());
    }
}

#[cfg(test)]
mod ray_file_tests {
    #![allow(clippy::unwrap_used)] // reason: tests may panic
    use super::*;

    #[test]
    fn a_ray_file_emitter_is_drawn_as_its_rays_starts() {
        let scene = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../assets/rayfiles/parabolic_spot_ray_file_led.toml");
        let luminaire = lucerna_simulation::Luminaire::load(&scene).unwrap();
        let marks = ray_origin_marks(&luminaire.prepared, 1e-4);
        // 2000 of the file's 20 000 rays, three triangles each.
        assert_eq!(marks.len(), 2000 * 9);
        // The 1 mm die at the focus, in the z = 0 plane.
        for v in &marks {
            let [x, y, z] = v.position;
            assert!(
                x.abs() <= 0.00056 && y.abs() <= 0.00056 && z.abs() <= 0.00006,
                "{x} {y} {z}"
            );
            assert_eq!(v.surface, u32::MAX);
        }
    }
}
