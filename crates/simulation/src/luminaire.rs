//! A luminaire scene loaded, tessellated and prepared for tracing, once.

use std::path::{Path, PathBuf};

use lucerna_scene::{Scene, TessellatedScene, load_scene, tessellate};
use lucerna_tracer::{LuminaireSymmetry, PreparedScene, luminaire_symmetry};

use crate::SimulationError;

/// What every run of one scene shares: the model, its triangles, the
/// tracer's BVH and records, and its symmetry about the axis.
#[derive(Debug)]
pub struct Luminaire {
    pub scene: Scene,
    /// The folder relative paths in the scene (meshes, profiles) start from.
    pub scene_dir: PathBuf,
    pub tessellated: TessellatedScene,
    pub prepared: PreparedScene,
    pub symmetry: LuminaireSymmetry,
}

impl Luminaire {
    /// Tessellates and prepares `scene` (validated by its loader or editor).
    pub fn new(scene: Scene, scene_dir: &Path) -> Result<Luminaire, SimulationError> {
        let tessellated = tessellate(&scene, scene_dir)?;
        let prepared = PreparedScene::new(&scene, &tessellated, scene_dir)?;
        let symmetry = luminaire_symmetry(&scene, &tessellated);
        Ok(Luminaire {
            scene,
            scene_dir: scene_dir.to_path_buf(),
            tessellated,
            prepared,
            symmetry,
        })
    }

    /// Loads a scene file and prepares it.
    pub fn load(path: &Path) -> Result<Luminaire, SimulationError> {
        let scene = load_scene(path)?;
        Luminaire::new(scene, path.parent().unwrap_or(Path::new(".")))
    }
}
