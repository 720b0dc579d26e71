//! A luminaire scene loaded, tessellated and prepared for tracing, once.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use lucerna_photometry::Dimensions;
use lucerna_photometry::tabulate::CPooling;
use lucerna_scene::{Scene, TessellatedScene, load_scene, tessellate};
use lucerna_tracer::bvh::BvhQuality;
use lucerna_tracer::{LuminaireSymmetry, PreparedScene, prepared_luminaire_symmetry};

use crate::SimulationError;
use crate::export::luminous_opening;

/// What every run of one scene shares: the model, its triangles, the
/// tracer's BVH and records, and its symmetry about the axis.
#[derive(Debug)]
pub struct Luminaire {
    pub scene: Scene,
    /// The folder relative paths in the scene (meshes, profiles) start from.
    pub scene_dir: PathBuf,
    pub tessellated: TessellatedScene,
    pub prepared: PreparedScene,
    /// The luminous opening the files declare and the preview room lights
    /// from: the scene's, or the footprint of its triangles (found once,
    /// on the thread that built it, not in a frame).
    pub luminous_opening: Dimensions,
    /// Found once: at once by [`Luminaire::new`], later (on another
    /// thread) for [`Luminaire::for_edit`]'s.
    symmetry: OnceLock<LuminaireSymmetry>,
}

impl Luminaire {
    /// Tessellates and prepares `scene` (validated by its loader or
    /// editor), its symmetry found.
    pub fn new(scene: Scene, scene_dir: &Path) -> Result<Luminaire, SimulationError> {
        let Some(luminaire) =
            Luminaire::build(scene, scene_dir, BvhQuality::Final, &|| false, None)?
        else {
            unreachable!("a build that is never stale finishes");
        };
        luminaire.find_symmetry();
        Ok(luminaire)
    }

    /// How its tables pool C-planes: over the whole ring when the scene
    /// is round about its axis (read from the parameters, so also during
    /// a drag) and the settings pool symmetric photons, else not at all.
    pub fn c_pooling(&self, pool_symmetry: bool) -> CPooling {
        if pool_symmetry && self.scene.rotationally_symmetric() {
            CPooling::Rotational
        } else {
            CPooling::Separate
        }
    }

    /// Prepares an edited scene as fast as it can be traced: its BVH at
    /// [`BvhQuality::Preview`] (on the examples as fast to trace as the
    /// final one, built in half the time) and its symmetry not yet looked
    /// for ([`Luminaire::find_symmetry`], which takes longer than the rest
    /// together: 150 ms of the parabolic spot's 170). `None` if `stale`
    /// says, once the scene is tessellated, that a newer edit has come: its
    /// BVH is not built.
    ///
    /// Where `previous` (the scene before the edit) has the same triangles
    /// in the same order, only moved (a focal length or a profile point
    /// dragged), its BVH is refitted instead of built: 1–2 ms instead of
    /// 20–40 on the 18k-triangle parabolic spot.
    pub fn for_edit(
        scene: Scene,
        scene_dir: &Path,
        stale: &dyn Fn() -> bool,
        previous: Option<&Luminaire>,
    ) -> Result<Option<Luminaire>, SimulationError> {
        Luminaire::build(scene, scene_dir, BvhQuality::Preview, stale, previous)
    }

    fn build(
        scene: Scene,
        scene_dir: &Path,
        quality: BvhQuality,
        stale: &dyn Fn() -> bool,
        previous: Option<&Luminaire>,
    ) -> Result<Option<Luminaire>, SimulationError> {
        let tessellated = tessellate(&scene, scene_dir)?;
        if stale() {
            return Ok(None);
        }
        let same_triangles = previous.filter(|p| {
            p.tessellated.mesh.triangles == tessellated.mesh.triangles
                && p.tessellated.triangle_material == tessellated.triangle_material
        });
        let refitted = match same_triangles {
            Some(p) => PreparedScene::refitted(&p.prepared, &scene, &tessellated, scene_dir)?,
            None => None,
        };
        // Once the BVH is built the luminaire is shown, even if a newer
        // edit came meanwhile: edits faster than builds would otherwise
        // never show anything.
        let prepared = match refitted {
            Some(p) => p,
            None => PreparedScene::with_quality(&scene, &tessellated, scene_dir, quality)?,
        };
        let luminous_opening = luminous_opening(&scene, &tessellated);
        Ok(Some(Luminaire {
            luminous_opening,
            scene,
            scene_dir: scene_dir.to_path_buf(),
            tessellated,
            prepared,
            symmetry: OnceLock::new(),
        }))
    }

    /// Loads a scene file and prepares it.
    pub fn load(path: &Path) -> Result<Luminaire, SimulationError> {
        let scene = load_scene(path)?;
        Luminaire::new(scene, path.parent().unwrap_or(Path::new(".")))
    }

    /// The symmetry about the axis, once it has been found.
    pub fn symmetry(&self) -> Option<&LuminaireSymmetry> {
        self.symmetry.get()
    }

    /// Finds the symmetry (from the triangles, materials and emitters), if
    /// not yet found, and returns it.
    pub fn find_symmetry(&self) -> &LuminaireSymmetry {
        self.symmetry.get_or_init(|| {
            prepared_luminaire_symmetry(&self.scene, &self.tessellated, &self.prepared)
        })
    }
}
