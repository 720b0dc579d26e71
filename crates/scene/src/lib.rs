//! Lucerna's luminaire model: emitters, parts, shape generators and
//! materials; versioned TOML load/save; tessellation into triangles; OBJ
//! import. No GPU, no UI.
//!
//! Units: metres, lumens, degrees at the file boundary. Luminaire
//! coordinates are right-handed with z up; the photometric axis points down.

pub mod axial;
pub mod check;
pub mod exact;
pub mod file;
pub mod finish;
pub mod finish_layout;
pub mod generators;
pub mod io;
pub mod mesh;
pub mod model;
pub mod obj;
pub mod profile;
pub mod section;
pub mod shapes;
pub mod tessellate;
#[cfg(feature = "test-support")]
pub mod test_support;
pub mod validate;

pub use file::{
    LoadSceneError, ReadFileError, SaveSceneError, load_scene, parse_scene, read_limited,
    read_limited_text, save_scene, scene_to_toml, write_all_atomically, write_atomically,
};
pub use mesh::{MeshDefect, TriangleMesh};
pub use model::*;
pub use shapes::ShapeGenerator;
pub use tessellate::{
    FinishSplit, SurfaceKind, TessellateError, TessellatedScene, emitter_exact, emitter_mesh,
    tessellate, tessellate_with,
};
pub use validate::{Invalid, Validation, validate, validation};
