//! Wavefront OBJ import (tobj): one mesh per OBJ object/group, each with
//! the material the scene assigns to it.

use std::collections::BTreeMap;
use std::path::Path;

use glam::{DVec3, Vec3};

use crate::mesh::TriangleMesh;

/// One OBJ object or group with its triangles.
#[derive(Debug, Clone)]
pub struct ObjGroup {
    /// The `o`/`g` name.
    pub name: String,
    /// The `usemtl` name, where the .mtl file could be read.
    pub obj_material: Option<String>,
    pub mesh: TriangleMesh,
}

#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum LoadObjError {
    #[error("cannot read OBJ file: {0}")]
    Read(#[from] tobj::LoadError),
    #[error("the OBJ file has no faces")]
    NoFaces,
    #[error("group '{group}': vertex {index} has a non-finite coordinate")]
    NonFinite { group: String, index: usize },
}

/// Loads an OBJ file's triangles (polygons are fan-triangulated). Normals
/// from the file are kept when every vertex has one; otherwise each
/// triangle gets its flat geometric normal.
pub fn load_obj(path: &Path) -> Result<Vec<ObjGroup>, LoadObjError> {
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let (models, materials) = tobj::load_obj(path, &options)?;
    // A missing .mtl is fine: materials are assigned by group name.
    let materials = materials.unwrap_or_default();
    let mut groups = Vec::new();
    for model in models {
        let m = &model.mesh;
        if m.indices.is_empty() {
            continue;
        }
        let positions: Vec<Vec3> = m
            .positions
            .chunks_exact(3)
            .map(|p| Vec3::new(p[0], p[1], p[2]))
            .collect();
        if let Some(index) = positions.iter().position(|p| !p.is_finite()) {
            return Err(LoadObjError::NonFinite {
                group: model.name.clone(),
                index,
            });
        }
        let triangles: Vec<[u32; 3]> = m
            .indices
            .chunks_exact(3)
            .map(|t| [t[0], t[1], t[2]])
            .collect();
        let has_normals = m.normals.len() == m.positions.len();
        let mesh = if has_normals {
            TriangleMesh {
                positions,
                normals: m
                    .normals
                    .chunks_exact(3)
                    .map(|n| Vec3::new(n[0], n[1], n[2]).normalize_or_zero())
                    .collect(),
                triangles,
            }
        } else {
            flat_shaded(&positions, &triangles)
        };
        groups.push(ObjGroup {
            name: model.name.clone(),
            obj_material: m
                .material_id
                .and_then(|i| materials.get(i))
                .map(|mat| mat.name.clone()),
            mesh,
        });
    }
    if groups.is_empty() {
        return Err(LoadObjError::NoFaces);
    }
    Ok(groups)
}

/// Unshares vertices so each triangle carries its own geometric normal.
/// Out-of-range indices are kept as they are for [`TriangleMesh::check`]
/// to report.
fn flat_shaded(positions: &[Vec3], triangles: &[[u32; 3]]) -> TriangleMesh {
    let mut mesh = TriangleMesh::default();
    for t in triangles {
        let Some(corners) = t
            .iter()
            .map(|&i| positions.get(i as usize).copied())
            .collect::<Option<Vec<Vec3>>>()
        else {
            return TriangleMesh {
                positions: positions.to_vec(),
                normals: Vec::new(),
                triangles: triangles.to_vec(),
            };
        };
        let [a, b, c] = [corners[0], corners[1], corners[2]].map(|p| p.as_dvec3());
        // A zero-area triangle keeps a zero normal here; `check` reports
        // the triangle as degenerate, which is the real problem.
        let n = (b - a).cross(c - a).normalize_or(DVec3::Z).as_vec3();
        let base = mesh.positions.len() as u32;
        mesh.positions.extend_from_slice(&corners);
        mesh.normals.extend([n; 3]);
        mesh.triangles.push([base, base + 1, base + 2]);
    }
    mesh
}

/// The material for an OBJ group: by group name, then by its OBJ material
/// name, then the part's default.
pub fn material_for<'a>(
    group: &ObjGroup,
    group_materials: &'a BTreeMap<String, String>,
    default: &'a str,
) -> &'a str {
    assigned_material(group, group_materials).unwrap_or(default)
}

/// The material `group_materials` assigns to an OBJ group, by group name,
/// then by its OBJ material name; `None` leaves it to the part's default.
pub fn assigned_material<'a>(
    group: &ObjGroup,
    group_materials: &'a BTreeMap<String, String>,
) -> Option<&'a str> {
    group_materials
        .get(&group.name)
        .or_else(|| {
            group
                .obj_material
                .as_ref()
                .and_then(|m| group_materials.get(m))
        })
        .map(String::as_str)
}
