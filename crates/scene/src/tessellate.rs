//! The whole luminaire as one triangle soup in luminaire coordinates, with
//! a material per triangle: what the tracer's BVH is built from.

use std::ops::Range;
use std::path::{Path, PathBuf};

use glam::DVec2;

use crate::check::{MAX_PART_TRIANGLES, MAX_SCENE_TRIANGLES};
use crate::exact::{ExactSurface, elliptic_arc};
use crate::finish_layout::{FinishLayout, SurfaceFinish, finished_mesh, split_by_scale};
use crate::generators::revolve;
use crate::mesh::{MeshDefect, TriangleMesh};
use crate::model::{EmitterShape, Material, Scene};
use crate::obj::LoadObjError;
use crate::profile::sample_curve;
use crate::shapes::{Cylinder, Disk, Plate, ShapeGenerator, revolution_triangle_count};

/// Name of the implicit material of emitters that name none.
pub const EMITTER_ABSORBER: &str = "<emitter absorber>";

/// Whether a range of triangles is a reflector part or an emitter's surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SurfaceKind {
    Part,
    Emitter,
}

/// A named range of triangles in [`TessellatedScene::mesh`].
#[derive(Debug, Clone, PartialEq)]
pub struct SurfaceRange {
    pub name: String,
    pub kind: SurfaceKind,
    /// Index into `Scene::parts` or `Scene::emitters`.
    pub index: usize,
    pub triangles: Range<usize>,
}

/// The enabled parts and emitter surfaces, transformed to luminaire
/// coordinates.
#[derive(Debug, Clone)]
pub struct TessellatedScene {
    pub mesh: TriangleMesh,
    /// Index into `materials` for every triangle.
    pub triangle_material: Vec<u32>,
    /// Materials by index, with their scene names.
    pub materials: Vec<(String, Material)>,
    pub surfaces: Vec<SurfaceRange>,
    /// Per material (parallel to `materials`): the finish its triangles
    /// are traced with. A finished part's surfaces get materials of
    /// their own, so a material index names one finish.
    pub material_finish: Vec<Option<std::sync::Arc<SurfaceFinish>>>,
    /// Per triangle, its corners' surface coordinates [u, v, radius]
    /// under its part's finish layout ([`crate::finish_layout`]), where
    /// some finish is traced as shading normals; empty otherwise.
    pub finish_corners: Vec<[[f32; 3]; 3]>,
}

/// Where a finish's scales are cut (see
/// [`crate::finish_layout::split_by_scale`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct FinishSplit {
    /// Features at least this long (m) that the mesh does not resolve
    /// are traced as shading normals; None: all of them as the BRDF
    /// (the far field is the same; normals keep where each feature is).
    pub normals_from: Option<f64>,
    /// Cut every finish with a geometry into its part's mesh, split to
    /// triangles of at most this edge (m): the real surface, for a
    /// toolmaker's file or a reference trace.
    pub geometry_edge: Option<f64>,
}

#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum TessellateError {
    #[error("part '{part}': OBJ file {path}")]
    Obj {
        part: String,
        path: PathBuf,
        #[source]
        source: LoadObjError,
    },
    #[error("part '{part}'{}: unusable mesh", group.as_ref().map(|g| format!(", OBJ group '{g}'")).unwrap_or_default())]
    Mesh {
        part: String,
        group: Option<String>,
        #[source]
        defect: MeshDefect,
    },
    #[error("part '{part}' uses material '{material}', which the scene does not define")]
    UnknownMaterial { part: String, material: String },
    /// Caught here too for scenes that did not come through validation,
    /// before the part's mesh is allocated.
    #[error("part '{part}' would have {triangles} triangles, at most {max}")]
    PartTriangles {
        part: String,
        triangles: u64,
        max: u64,
    },
    /// The luminaire grew past [`MAX_SCENE_TRIANGLES`] at this surface
    /// (OBJ parts are only counted once read).
    #[error("the luminaire would have {triangles} triangles with '{surface}', at most {max}")]
    SceneTriangles {
        surface: String,
        triangles: u64,
        max: u64,
    },
}

impl TessellatedScene {
    pub fn triangle_count(&self) -> usize {
        self.mesh.triangle_count()
    }
}

/// Steps around an emitter's disk, sphere or cylinder: emitters are
/// sampled analytically, their mesh only catches returning photons.
const EMITTER_SEGMENTS_AROUND: u32 = 32;
/// Steps from pole to pole of a spherical emitter.
const EMITTER_SPHERE_SEGMENTS_ALONG: u32 = 16;

/// The emitter's surface as a part shape, where there is one (not the
/// sphere, a full revolution no part shape makes).
fn emitter_shape(shape: &EmitterShape) -> Option<Box<dyn ShapeGenerator>> {
    match *shape {
        EmitterShape::Disk { radius } => Some(Box::new(Disk {
            radius,
            segments_around: EMITTER_SEGMENTS_AROUND,
        })),
        EmitterShape::Rectangle { width, depth } => Some(Box::new(Plate { width, depth })),
        EmitterShape::Sphere { .. } | EmitterShape::RayFile { .. } => None,
        EmitterShape::Cylinder { radius, height } => Some(Box::new(Cylinder {
            radius,
            height,
            cap_top: false,
            cap_bottom: false,
            segments_around: EMITTER_SEGMENTS_AROUND,
        })),
    }
}

/// The emitter's surface in its local frame, normals along the emission.
pub fn emitter_mesh(shape: &EmitterShape) -> TriangleMesh {
    if let EmitterShape::RayFile { .. } = shape {
        // Rays start in the air: no surface to come back to.
        return TriangleMesh::default();
    }
    if let EmitterShape::Sphere { radius } = *shape {
        // South pole to north pole: the right-hand normal points out.
        let strip = sample_curve(
            -std::f64::consts::FRAC_PI_2,
            std::f64::consts::FRAC_PI_2,
            EMITTER_SPHERE_SEGMENTS_ALONG,
            |t| DVec2::new(radius * t.cos(), radius * t.sin()),
            |t| DVec2::new(-t.sin(), t.cos()),
        );
        return revolve(&[strip], EMITTER_SEGMENTS_AROUND, false);
    }
    emitter_shape(shape)
        .and_then(|g| g.generate())
        .unwrap_or_default()
}

/// The emitter's exact surface in its local frame (metres), for CAD
/// export: what [`emitter_mesh`] samples.
pub fn emitter_exact(shape: &EmitterShape) -> Vec<ExactSurface> {
    if let EmitterShape::Sphere { radius } = *shape {
        return vec![ExactSurface::Revolution(elliptic_arc(
            0.0,
            radius,
            radius,
            0.0,
            std::f64::consts::PI,
        ))];
    }
    emitter_shape(shape)
        .and_then(|g| g.exact())
        .unwrap_or_default()
}

/// The most triangles [`emitter_mesh`] builds for `shape`.
pub fn emitter_triangle_count(shape: &EmitterShape) -> u64 {
    if let EmitterShape::RayFile { .. } = shape {
        return 0;
    }
    match emitter_shape(shape) {
        Some(generator) => generator.triangle_count().unwrap_or(0),
        None => revolution_triangle_count(
            EMITTER_SEGMENTS_AROUND,
            u64::from(EMITTER_SPHERE_SEGMENTS_ALONG),
        ),
    }
}

/// Tessellates every enabled part and emitter. `scene_dir` resolves the
/// relative paths of OBJ meshes. Each part's mesh is checked, so a NaN,
/// a degenerate triangle or an absurd size is reported, never traced.
pub fn tessellate(scene: &Scene, scene_dir: &Path) -> Result<TessellatedScene, TessellateError> {
    tessellate_with(scene, scene_dir, FinishSplit::default())
}

/// [`tessellate`] with finishes split at `split`.
pub fn tessellate_with(
    scene: &Scene,
    scene_dir: &Path,
    split: FinishSplit,
) -> Result<TessellatedScene, TessellateError> {
    let mut materials: Vec<(String, Material)> = scene
        .materials
        .iter()
        .map(|(k, v)| (k.clone(), v.clone()))
        .collect();
    let material_index = |materials: &Vec<(String, Material)>, part: &str, name: &str| {
        materials
            .iter()
            .position(|(n, _)| n == name)
            .map(|i| i as u32)
            .ok_or_else(|| TessellateError::UnknownMaterial {
                part: part.to_owned(),
                material: name.to_owned(),
            })
    };
    let mut out = TessellatedScene {
        mesh: TriangleMesh::default(),
        triangle_material: Vec::new(),
        materials: Vec::new(),
        surfaces: Vec::new(),
        material_finish: Vec::new(),
        finish_corners: Vec::new(),
    };
    // Finished surfaces: (material index, triangles, finish).
    let mut finished: Vec<(u32, Range<usize>, std::sync::Arc<SurfaceFinish>)> = Vec::new();
    let push = |out: &mut TessellatedScene,
                name: &str,
                kind: SurfaceKind,
                index: usize,
                mesh: &TriangleMesh,
                material: u32| {
        let first = out.mesh.triangle_count();
        out.mesh.append(mesh);
        out.triangle_material
            .extend(std::iter::repeat_n(material, mesh.triangle_count()));
        out.surfaces.push(SurfaceRange {
            name: name.to_owned(),
            kind,
            index,
            triangles: first..out.mesh.triangle_count(),
        });
    };
    let mesh_error = |part: &str, group: Option<&str>, defect| TessellateError::Mesh {
        part: part.to_owned(),
        group: group.map(str::to_owned),
        defect,
    };
    let within_scene_limit = |out: &TessellatedScene, surface: &str, adding: u64| {
        let triangles = (out.mesh.triangle_count() as u64).saturating_add(adding);
        if triangles > MAX_SCENE_TRIANGLES {
            Err(TessellateError::SceneTriangles {
                surface: surface.to_owned(),
                triangles,
                max: MAX_SCENE_TRIANGLES,
            })
        } else {
            Ok(())
        }
    };
    for (index, part) in scene.parts.iter().enumerate().filter(|(_, p)| p.enabled) {
        let luminaire_from_part = part.transform.matrix();
        if let Some(triangles) = part.shape.generator().triangle_count() {
            if triangles > MAX_PART_TRIANGLES {
                return Err(TessellateError::PartTriangles {
                    part: part.name.clone(),
                    triangles,
                    max: MAX_PART_TRIANGLES,
                });
            }
            within_scene_limit(&out, &part.name, triangles)?;
        }
        let surfaces =
            part.shape
                .generator()
                .tessellate(scene_dir)
                .map_err(|e| TessellateError::Obj {
                    part: part.name.clone(),
                    path: e.path,
                    source: e.source,
                })?;
        for surface in &surfaces {
            within_scene_limit(&out, &part.name, surface.mesh.triangle_count() as u64)?;
            let mut mesh = surface.mesh.transformed(&luminaire_from_part);
            mesh.check()
                .map_err(|d| mesh_error(&part.name, surface.group.as_deref(), d))?;
            let material = surface.material.as_deref().unwrap_or(&part.material);
            let mut m = material_index(&materials, &part.name, material)?;
            if let Some(finish) = &part.finish {
                let layout = FinishLayout::of_shape(&part.shape);
                let (bands, max_edge) = match split.geometry_edge {
                    Some(edge) if finish.height(0.0, 0.0).is_some() => (
                        crate::finish_layout::FinishBands {
                            geometry: Some(finish.clone()),
                            ..Default::default()
                        },
                        edge,
                    ),
                    _ => (
                        split_by_scale(finish, mean_edge(&mesh), split.normals_from),
                        f64::INFINITY,
                    ),
                };
                if let Some(geometry) = &bands.geometry
                    && let Some(cut) = finished_mesh(&surface.mesh, &layout, geometry, max_edge)
                        .map_err(|e| TessellateError::SceneTriangles {
                            surface: part.name.clone(),
                            triangles: e.triangles,
                            max: MAX_SCENE_TRIANGLES,
                        })?
                {
                    within_scene_limit(
                        &out,
                        &part.name,
                        (cut.triangle_count() - surface.mesh.triangle_count()) as u64,
                    )?;
                    let cut = cut.transformed(&luminaire_from_part);
                    cut.check()
                        .map_err(|d| mesh_error(&part.name, surface.group.as_deref(), d))?;
                    mesh = cut;
                }
                if bands.normals.is_some() || bands.brdf.is_some() {
                    let own = materials[m as usize].1.clone();
                    materials.push((format!("{material} (finish of '{}')", part.name), own));
                    m = (materials.len() - 1) as u32;
                    let f =
                        SurfaceFinish::new(&part.name, &bands, layout, luminaire_from_part, &mesh);
                    let first = out.mesh.triangle_count();
                    finished.push((m, first..first + mesh.triangle_count(), f.into()));
                }
            }
            push(&mut out, &part.name, SurfaceKind::Part, index, &mesh, m);
        }
    }
    for (index, emitter) in scene.emitters.iter().enumerate().filter(|(_, e)| e.enabled) {
        within_scene_limit(&out, &emitter.name, emitter_triangle_count(&emitter.shape))?;
        let mesh = emitter_mesh(&emitter.shape).transformed(&emitter.transform.matrix());
        if mesh.triangle_count() == 0 {
            continue;
        }
        mesh.check()
            .map_err(|d| mesh_error(&emitter.name, None, d))?;
        let m = match &emitter.material {
            Some(name) => material_index(&materials, &emitter.name, name)?,
            None => {
                if let Some(i) = materials.iter().position(|(n, _)| n == EMITTER_ABSORBER) {
                    i as u32
                } else {
                    materials.push((EMITTER_ABSORBER.to_owned(), Material::Absorber));
                    (materials.len() - 1) as u32
                }
            }
        };
        push(
            &mut out,
            &emitter.name,
            SurfaceKind::Emitter,
            index,
            &mesh,
            m,
        );
    }
    out.material_finish = vec![None; materials.len()];
    out.materials = materials;
    for (m, _, f) in &finished {
        out.material_finish[*m as usize] = Some(f.clone());
    }
    if finished.iter().any(|(_, _, f)| f.normals.is_some()) {
        out.finish_corners = vec![[[0.0; 3]; 3]; out.mesh.triangle_count()];
        for (_, range, f) in finished.iter().filter(|(_, _, f)| f.normals.is_some()) {
            let part_from_luminaire = f.luminaire_from_part.inverse();
            for t in range.clone() {
                let corners = out.mesh.corners(t).map(|p| {
                    let c = f
                        .layout
                        .coordinates(part_from_luminaire.transform_point3(p));
                    [c.u as f32, c.v as f32, c.radius.unwrap_or(0.0) as f32]
                });
                out.finish_corners[t] = corners;
            }
        }
    }
    Ok(out)
}

/// The mean edge length of a mesh's triangles (m).
fn mean_edge(mesh: &TriangleMesh) -> f64 {
    let n = mesh.triangle_count();
    if n == 0 {
        return 0.0;
    }
    let total: f64 = (0..n)
        .map(|t| {
            let [a, b, c] = mesh.corners(t);
            ((b - a).length() + (c - b).length() + (a - c).length()) / 3.0
        })
        .sum();
    total / n as f64
}
