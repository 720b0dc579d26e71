//! The luminaire's geometry for CAD and other tools (`lucerna
//! export-geometry`, the editor's File ▸ Export geometry…).
//!
//! - STEP (AP214): each part and emitter its own named body, with the
//!   exact surfaces its tessellation samples ([`lucerna_scene::exact`]):
//!   profiles revolved and extruded as B-spline and rational curves,
//!   disks and polygons as planes; faceted shapes and OBJ meshes as the
//!   planar triangles the tracer intersects.
//! - STL (binary) and OBJ: the traced triangles.
//!
//! Millimetres, luminaire coordinates: light leaves towards −z, C0 along
//! +x. Sheets are written as surfaces, not offset into solids.

pub mod brep;
mod mesh_files;
pub mod step;

use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;

use glam::DAffine3;
use lucerna_scene::exact::ExactSurface;
use lucerna_scene::finish_layout::finish_feature_size;
use lucerna_scene::{
    FinishSplit, Scene, SurfaceKind, TessellateError, TriangleMesh, emitter_exact, tessellate,
    tessellate_with, write_all_atomically,
};

pub use brep::BrepError;
pub use mesh_files::{obj_text, stl_bytes};

/// A file format `export-geometry` writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum GeometryFormat {
    Step,
    Stl,
    Obj,
}

impl GeometryFormat {
    pub const ALL: [GeometryFormat; 3] = [
        GeometryFormat::Step,
        GeometryFormat::Stl,
        GeometryFormat::Obj,
    ];

    /// The file extension, which is also the name on the command line.
    pub fn extension(self) -> &'static str {
        match self {
            GeometryFormat::Step => "step",
            GeometryFormat::Stl => "stl",
            GeometryFormat::Obj => "obj",
        }
    }
}

impl fmt::Display for GeometryFormat {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.extension())
    }
}

/// An unknown name in a format list.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown geometry format '{0}': expected step, stl or obj")]
pub struct UnknownFormat(pub String);

impl FromStr for GeometryFormat {
    type Err = UnknownFormat;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s.trim().to_ascii_lowercase().as_str() {
            "step" | "stp" => Ok(GeometryFormat::Step),
            "stl" => Ok(GeometryFormat::Stl),
            "obj" => Ok(GeometryFormat::Obj),
            _ => Err(UnknownFormat(s.to_owned())),
        }
    }
}

/// What to export.
#[derive(Debug, Clone, PartialEq)]
pub struct GeometryRequest {
    pub formats: Vec<GeometryFormat>,
    /// Part and emitter names as in the scene; `None` exports every
    /// enabled part and emitter.
    pub parts: Option<Vec<String>>,
    /// How a part's finish (hammered, rippled) goes into the files.
    pub finish: FinishExport,
}

impl Default for GeometryRequest {
    fn default() -> Self {
        GeometryRequest {
            formats: GeometryFormat::ALL.to_vec(),
            parts: None,
            finish: FinishExport::Named,
        }
    }
}

/// How a part's finish goes into geometry files.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum FinishExport {
    /// The smooth surface, the finish named in the part's product
    /// description (STEP) for the toolmaker to cut.
    #[default]
    Named,
    /// The finish cut into the part as triangles no longer than this
    /// edge (m); None: a sixteenth of the finest feature of any finish.
    Geometry { edge: Option<f64> },
}

/// Edges per finest feature of a finish exported as geometry: a dimple
/// of 2 mm pitch gets 0.125 mm triangles.
pub const FINISH_EDGES_PER_FEATURE: f64 = 16.0;

#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ExportGeometryError {
    #[error("the scene does not tessellate")]
    Tessellate(#[source] TessellateError),
    #[error("the scene has no part or emitter named '{name}'; it has: {}", known.join(", "))]
    UnknownPart { name: String, known: Vec<String> },
    #[error(
        "'{name}' is disabled in the scene, so it is not part of the luminaire; enable it to export it"
    )]
    DisabledPart { name: String },
    #[error("nothing to export: no enabled part or emitter was chosen")]
    NothingChosen,
    #[error("no format chosen: choose one or more of step, stl, obj")]
    NoFormat,
    #[error("'{body}': {source}")]
    Brep {
        body: String,
        #[source]
        source: BrepError,
    },
    #[error("cannot write the STL file")]
    Stl(#[source] std::io::Error),
    #[error("cannot write {}", path.display())]
    Write {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
}

/// Whether a body is a part or an emitter.
pub type BodyKind = SurfaceKind;

/// One part or emitter: its traced triangles and, where its shape states
/// them, its exact surfaces.
#[derive(Debug, Clone)]
pub struct Body {
    /// The name as in the scene.
    pub name: String,
    pub kind: BodyKind,
    /// The traced triangles, luminaire coordinates (metres).
    pub traced: TriangleMesh,
    /// The exact surfaces in the body's frame (metres) and the frame's
    /// placement; `None` where the triangles are the surface.
    pub exact: Option<(Vec<ExactSurface>, DAffine3)>,
    /// What the product's description says: a finish not in the surface.
    pub description: String,
}

impl Body {
    /// The body's name in exported files: emitters say that they are.
    pub fn label(&self) -> String {
        match self.kind {
            SurfaceKind::Part => self.name.clone(),
            SurfaceKind::Emitter => format!("{} (emitter)", self.name),
        }
    }
}

/// The enabled parts and emitters `parts` names (all of them for `None`),
/// in scene order, parts first.
pub fn bodies(
    scene: &Scene,
    scene_dir: &Path,
    parts: Option<&[String]>,
    finish: FinishExport,
) -> Result<Vec<Body>, ExportGeometryError> {
    if let Some(names) = parts {
        for name in names {
            let part = scene
                .parts
                .iter()
                .find(|p| &p.name == name)
                .map(|p| p.enabled);
            let emitter = scene
                .emitters
                .iter()
                .find(|e| &e.name == name)
                .map(|e| e.enabled);
            match part.or(emitter) {
                Some(true) => {}
                Some(false) => {
                    return Err(ExportGeometryError::DisabledPart { name: name.clone() });
                }
                None => {
                    let known = scene
                        .parts
                        .iter()
                        .map(|p| p.name.clone())
                        .chain(scene.emitters.iter().map(|e| e.name.clone()))
                        .collect();
                    return Err(ExportGeometryError::UnknownPart {
                        name: name.clone(),
                        known,
                    });
                }
            }
        }
    }
    let chosen = |name: &str| parts.is_none_or(|names| names.iter().any(|n| n == name));
    let tessellated = match finish {
        // The smooth surface the finish is named on.
        FinishExport::Named => tessellate(&without_finishes(scene), scene_dir),
        FinishExport::Geometry { edge } => {
            let edge = edge.or_else(|| {
                scene
                    .parts
                    .iter()
                    .filter(|p| p.enabled && chosen(&p.name))
                    .filter_map(|p| p.finish.as_ref())
                    .map(finish_feature_size)
                    .filter(|s| *s > 0.0)
                    .reduce(f64::min)
                    .map(|s| s / FINISH_EDGES_PER_FEATURE)
            });
            let split = FinishSplit {
                geometry_edge: edge,
                normals_from: None,
            };
            tessellate_with(scene, scene_dir, split)
        }
    }
    .map_err(ExportGeometryError::Tessellate)?;
    let mut out: Vec<Body> = Vec::new();
    for range in &tessellated.surfaces {
        if parts.is_some_and(|names| !names.contains(&range.name)) {
            continue;
        }
        // An OBJ part is several ranges (one per group): one body.
        let body = match out
            .iter_mut()
            .find(|b| b.name == range.name && b.kind == range.kind)
        {
            Some(body) => body,
            None => {
                let (exact, description) = match range.kind {
                    SurfaceKind::Part => {
                        let part = &scene.parts[range.index];
                        let cut = matches!(finish, FinishExport::Geometry { .. })
                            && part
                                .finish
                                .as_ref()
                                .is_some_and(|f| f.height(0.0, 0.0).is_some());
                        let exact = if cut {
                            // The triangles carry the finish; the smooth
                            // exact surface would lose it.
                            None
                        } else {
                            part.shape
                                .generator()
                                .exact()
                                .map(|s| (s, part.transform.matrix()))
                        };
                        let description = match &part.finish {
                            Some(f) if cut => {
                                format!("finish cut into the surface: {}", f.describe())
                            }
                            Some(f) => format!("finish: {}", f.describe()),
                            None => String::new(),
                        };
                        (exact, description)
                    }
                    SurfaceKind::Emitter => {
                        let emitter = &scene.emitters[range.index];
                        (
                            Some((emitter_exact(&emitter.shape), emitter.transform.matrix())),
                            String::new(),
                        )
                    }
                };
                out.push(Body {
                    name: range.name.clone(),
                    kind: range.kind,
                    traced: TriangleMesh::default(),
                    exact,
                    description,
                });
                out.last_mut().expect("just pushed")
            }
        };
        body.traced
            .append(&triangles_of(&tessellated.mesh, range.triangles.clone()));
    }
    if out.is_empty() {
        return Err(ExportGeometryError::NothingChosen);
    }
    Ok(out)
}

/// `scene` with every part's finish taken off.
fn without_finishes(scene: &Scene) -> Scene {
    let mut plain = scene.clone();
    for p in &mut plain.parts {
        p.finish = None;
    }
    plain
}

/// The triangles in `range` of `mesh` with the vertices they use.
fn triangles_of(mesh: &TriangleMesh, range: std::ops::Range<usize>) -> TriangleMesh {
    let mut out = TriangleMesh::default();
    let mut index = std::collections::HashMap::new();
    let shaded = mesh.normals.len() == mesh.positions.len();
    for t in &mesh.triangles[range] {
        let tri = t.map(|v| {
            *index.entry(v).or_insert_with(|| {
                out.positions.push(mesh.positions[v as usize]);
                if shaded {
                    out.normals.push(mesh.normals[v as usize]);
                }
                (out.positions.len() - 1) as u32
            })
        });
        out.triangles.push(tri);
    }
    out
}

/// The files `request` asks for, named `STEM.EXT`, as bytes: what the
/// command line and the editor both write.
pub fn geometry_files(
    scene: &Scene,
    scene_dir: &Path,
    stem: &str,
    request: &GeometryRequest,
) -> Result<Vec<(String, Vec<u8>)>, ExportGeometryError> {
    if request.formats.is_empty() {
        return Err(ExportGeometryError::NoFormat);
    }
    let bodies = bodies(scene, scene_dir, request.parts.as_deref(), request.finish)?;
    let traced: Vec<(String, &TriangleMesh)> =
        bodies.iter().map(|b| (b.label(), &b.traced)).collect();
    let mut files = Vec::new();
    let mut formats = request.formats.clone();
    formats.dedup();
    for format in formats {
        let name = format!("{stem}.{}", format.extension());
        let bytes = match format {
            GeometryFormat::Step => {
                let shells = bodies
                    .iter()
                    .map(|b| {
                        let shell = match &b.exact {
                            Some((surfaces, placement)) => brep::exact_shell(surfaces, placement)
                                .map_err(|source| {
                                ExportGeometryError::Brep {
                                    body: b.name.clone(),
                                    source,
                                }
                            })?,
                            None => brep::triangle_shell(&b.traced),
                        };
                        Ok((b.label(), b.description.clone(), shell))
                    })
                    .collect::<Result<Vec<_>, ExportGeometryError>>()?;
                step::step_text(&scene.name, &name, &shells).into_bytes()
            }
            GeometryFormat::Stl => stl_bytes(&traced).map_err(ExportGeometryError::Stl)?,
            GeometryFormat::Obj => obj_text(&scene.name, &traced).into_bytes(),
        };
        files.push((name, bytes));
    }
    Ok(files)
}

/// Writes [`geometry_files`] into `out_dir` (created if missing), all or
/// none; returns the paths written.
pub fn write_geometry(
    scene: &Scene,
    scene_dir: &Path,
    out_dir: &Path,
    stem: &str,
    request: &GeometryRequest,
) -> Result<Vec<PathBuf>, ExportGeometryError> {
    let files = geometry_files(scene, scene_dir, stem, request)?;
    let created = !out_dir.exists();
    std::fs::create_dir_all(out_dir).map_err(|source| ExportGeometryError::Write {
        path: out_dir.to_owned(),
        source,
    })?;
    let files: Vec<(PathBuf, Vec<u8>)> = files
        .into_iter()
        .map(|(name, bytes)| (out_dir.join(name), bytes))
        .collect();
    if let Err((path, source)) = write_all_atomically(&files) {
        if created {
            let _ = std::fs::remove_dir(out_dir);
        }
        return Err(ExportGeometryError::Write { path, source });
    }
    Ok(files.into_iter().map(|(path, _)| path).collect())
}
