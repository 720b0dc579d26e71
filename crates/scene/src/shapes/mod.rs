//! The part shapes, one file each: a file holds everything its shape
//! knows — the parameters as the scene file spells them, their ranges, the
//! kind name and the tessellation — so that no other module matches a
//! shape field by field.
//!
//! Surfaces of revolution are about the local z axis and face it (the lamp
//! side); closed solids (box, cylinder) face outwards; plates and disks face
//! −z (see the project's ARCHITECTURE.md).
//!
//! # Adding a shape
//!
//! 1. Write `shapes/<name>.rs` with the parameter struct (`Serialize`,
//!    `Deserialize`, `#[serde(deny_unknown_fields)]`, defaults from
//!    [`crate::model`], each field documented with its unit) and its
//!    `impl ShapeGenerator`: `kind` is the `type` written in scene files,
//!    `validate` checks every parameter with the shared [`Checker`] ranges
//!    and the shape's own, `triangle_count` bounds what `generate` builds
//!    (validation holds it to the triangle limits), `generate` builds the
//!    mesh from the helpers in [`crate::generators`] and [`crate::profile`].
//! 2. In this file: `mod <name>;` with its `pub use`, a variant of
//!    [`Shape`] wrapping the struct (the variant's snake_case name is the
//!    `type` tag), and its arm in [`Shape::generator`].
//! 3. Give it an example in `tests/shapes.rs`, which checks that the kind
//!    name and the file's `type` agree, that the example round-trips and
//!    that `triangle_count` bounds the generated mesh closely.
//!
//! Validation, tessellation and the CLI's reports then pick it up through
//! the dispatch.

use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use crate::check::{Checker, FieldPath};
use crate::exact::ExactSurface;
pub use crate::generators::revolution_triangle_count;
use crate::mesh::TriangleMesh;
use crate::obj::LoadObjError;

mod box_shape;
mod cylinder;
pub(crate) mod defaults;
mod disk;
mod dome;
mod ellipsoid;
mod extruded;
mod louvre;
mod mesh;
mod paraboloid;
mod plate;
mod revolved;

pub use box_shape::BoxShape;
pub use cylinder::Cylinder;
pub use disk::Disk;
pub use dome::Dome;
pub use ellipsoid::Ellipsoid;
pub use extruded::Extruded;
pub use louvre::Louvre;
pub use mesh::Mesh;
pub use paraboloid::Paraboloid;
pub use plate::Plate;
pub use revolved::{Revolved, editable_revolution};

/// What every part shape knows about itself.
pub trait ShapeGenerator {
    /// The shape's `type` as written in scene files.
    fn kind(&self) -> &'static str;

    /// Checks every parameter, recording problems under `at` (the part's
    /// `shape` table), so a bad value is reported with its line instead of
    /// tessellating into garbage.
    fn validate(&self, at: &FieldPath, check: &mut Checker<'_>);

    /// The most triangles [`ShapeGenerator::generate`] builds from these
    /// parameters, computed from them alone so that validation refuses a
    /// part over [`crate::validate::MAX_PART_TRIANGLES`] before any of it
    /// is allocated; `None` for a shape whose triangles are in a file.
    /// Parameters need not be valid (the counts saturate).
    fn triangle_count(&self) -> Option<u64>;

    /// The mesh in the part's frame (metres), from the parameters alone;
    /// `None` for a shape whose triangles come from a file ([`Mesh`]).
    /// Parameters must have passed [`ShapeGenerator::validate`].
    fn generate(&self) -> Option<TriangleMesh>;

    /// The exact surfaces [`ShapeGenerator::generate`] samples, in the
    /// part's frame (metres), for CAD export; `None` where the triangles
    /// are the surface (faceted shapes, meshes from files). Parameters
    /// must have passed [`ShapeGenerator::validate`].
    fn exact(&self) -> Option<Vec<ExactSurface>> {
        None
    }

    /// Segments around the axis of a shape generated about its local z
    /// (a surface of revolution, a disk); `None` for the others.
    fn segments_around(&self) -> Option<u32> {
        None
    }

    /// Every surface of the shape in the part's frame, reading files
    /// relative to `scene_dir`. A generated shape is one surface in the
    /// part's material; a file may hold several with their own.
    fn tessellate(&self, _scene_dir: &Path) -> Result<Vec<ShapeSurface>, LoadShapeFileError> {
        Ok(self
            .generate()
            .into_iter()
            .map(|mesh| ShapeSurface {
                group: None,
                material: None,
                mesh,
            })
            .collect())
    }
}

/// A piece of a part's surface, in the part's frame.
#[derive(Debug, Clone)]
pub struct ShapeSurface {
    /// The OBJ object/group it was read from; `None` for a generated shape.
    pub group: Option<String>,
    /// The material the shape assigns to it (an OBJ group's entry in
    /// `group_materials`); `None` is the part's material.
    pub material: Option<String>,
    pub mesh: TriangleMesh,
}

/// A shape's triangles could not be read from its file.
#[derive(Debug, thiserror::Error)]
#[error("cannot load OBJ file {path}")]
pub struct LoadShapeFileError {
    pub path: PathBuf,
    #[source]
    pub source: LoadObjError,
}

/// A part's geometry: one variant per shape, each wrapping the shape's
/// parameters; the `type` key of the `shape` table picks the variant.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", rename_all = "snake_case")]
pub enum Shape {
    Paraboloid(Paraboloid),
    Ellipsoid(Ellipsoid),
    Revolved(Revolved),
    Extruded(Extruded),
    Louvre(Louvre),
    Plate(Plate),
    Disk(Disk),
    Dome(Dome),
    Cylinder(Cylinder),
    Box(BoxShape),
    Mesh(Mesh),
}

impl Shape {
    /// The shape's own knowledge; everything else about a shape goes
    /// through it.
    pub fn generator(&self) -> &dyn ShapeGenerator {
        match self {
            Shape::Paraboloid(s) => s,
            Shape::Ellipsoid(s) => s,
            Shape::Revolved(s) => s,
            Shape::Extruded(s) => s,
            Shape::Louvre(s) => s,
            Shape::Plate(s) => s,
            Shape::Disk(s) => s,
            Shape::Dome(s) => s,
            Shape::Cylinder(s) => s,
            Shape::Box(s) => s,
            Shape::Mesh(s) => s,
        }
    }

    /// The shape's `type` as written in scene files.
    pub fn kind(&self) -> &'static str {
        self.generator().kind()
    }

    /// A surface of revolution its parameters set (paraboloid, ellipsoid,
    /// dome, cylinder): its section is shown read-only and can become an
    /// editable profile ([`editable_revolution`]).
    pub fn has_parametric_section(&self) -> bool {
        matches!(
            self,
            Shape::Paraboloid(_) | Shape::Ellipsoid(_) | Shape::Dome(_) | Shape::Cylinder(_)
        )
    }
}

/// Builds the mesh of a generated shape. `Shape::Mesh` is not generated
/// here (see [`crate::obj`]); it yields `None`.
///
/// Parameters must have passed [`crate::validate()`]; the generators do not
/// re-check them.
pub fn generate(shape: &Shape) -> Option<TriangleMesh> {
    shape.generator().generate()
}
