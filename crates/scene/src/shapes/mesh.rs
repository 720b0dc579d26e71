//! Triangles imported from a Wavefront OBJ file (CAD reflectors).

use std::collections::BTreeMap;
use std::path::Path;

use serde::{Deserialize, Serialize};

use super::{LoadShapeFileError, ShapeGenerator, ShapeSurface};
use crate::check::{Checker, FieldPath};
use crate::mesh::TriangleMesh;
use crate::obj::{assigned_material, load_obj};

/// Wavefront OBJ mesh, path relative to the scene file. Materials are
/// assigned per OBJ object/group name (or its `usemtl` name) through
/// `group_materials`; the part's `material` is the default.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Mesh {
    /// The OBJ file, relative to the scene file.
    pub path: String,
    /// OBJ object/group (or `usemtl`) name → name of a scene material.
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub group_materials: BTreeMap<String, String>,
}

impl ShapeGenerator for Mesh {
    fn kind(&self) -> &'static str {
        "mesh"
    }

    fn validate(&self, at: &FieldPath, check: &mut Checker<'_>) {
        for (group, material) in &self.group_materials {
            check.material_ref(at.key("group_materials").key(group), material);
        }
        if self.path.trim().is_empty() {
            check.fail(at.key("path"), "must name an OBJ file");
        }
    }

    /// The triangles are in the file, limited when it is read.
    fn triangle_count(&self) -> Option<u64> {
        None
    }

    /// The triangles are in the file, not in the parameters.
    fn generate(&self) -> Option<TriangleMesh> {
        None
    }

    /// One surface per OBJ object/group, in the material `group_materials`
    /// assigns to it. The file's own sanity (NaN, degenerate faces) is left
    /// to [`TriangleMesh::check`] after the part's transform.
    fn tessellate(&self, scene_dir: &Path) -> Result<Vec<ShapeSurface>, LoadShapeFileError> {
        let path = scene_dir.join(&self.path);
        let groups = load_obj(&path).map_err(|source| LoadShapeFileError {
            path: path.clone(),
            source,
        })?;
        Ok(groups
            .into_iter()
            .map(|group| ShapeSurface {
                material: assigned_material(&group, &self.group_materials).map(str::to_owned),
                group: Some(group.name),
                mesh: group.mesh,
            })
            .collect())
    }
}
