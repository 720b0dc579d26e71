//! A room file as loaded and then edited: what `lucerna render` lights
//! with each luminaire's own profile and the editor's preview lights with
//! the edited luminaire. Loading, the edits (a resize that keeps the
//! layout inside) and the scene to shade live here once for both.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use glam::DVec3;
use lucerna_photometry::Photometry;

use crate::light::{Opening, PlacedLight};
use crate::model::{RoomFile, RoomFileError, load_room, validate};
use crate::profile::ProfileGrid;
use crate::scene::{RoomMesh, RoomScene, load_room_mesh};

/// A room file, its OBJ's triangles (loaded once with the file) and where
/// it came from.
#[derive(Debug, Clone, PartialEq)]
pub struct RoomSetup {
    pub path: PathBuf,
    pub file: RoomFile,
    pub mesh: Option<Arc<RoomMesh>>,
}

impl RoomSetup {
    /// Reads and validates a room file and its OBJ, if it names one.
    pub fn load(path: &Path) -> Result<RoomSetup, RoomFileError> {
        let file = load_room(path)?;
        let mesh = load_room_mesh(&file, Self::base_of(path))?.map(Arc::new);
        Ok(RoomSetup {
            path: path.to_owned(),
            file,
            mesh,
        })
    }

    fn base_of(path: &Path) -> &Path {
        path.parent().unwrap_or(Path::new("."))
    }

    /// The folder the file's relative paths (profiles, OBJ) start from.
    pub fn base(&self) -> &Path {
        Self::base_of(&self.path)
    }

    /// The edits' problems as "field: problem" (none: it can be rendered).
    pub fn problems(&self) -> Vec<String> {
        validate(&self.file)
    }

    /// Changes the box's size (m), moving the luminaires, their array
    /// spacing and the camera with the walls (each coordinate scaled by its
    /// axis' ratio) so the layout stays inside the room; the work plane
    /// keeps its height.
    pub fn resize(&mut self, size_m: [f64; 3]) {
        let r = &mut self.file.room;
        let old = [r.width_m, r.depth_m, r.height_m];
        let ratio: [f64; 3] = std::array::from_fn(|k| {
            if old[k] > 0.0 && size_m[k].is_finite() {
                size_m[k] / old[k]
            } else {
                1.0
            }
        });
        [r.width_m, r.depth_m, r.height_m] = size_m;
        let scale = |p: &mut [f64; 3]| {
            for k in 0..3 {
                p[k] *= ratio[k];
            }
        };
        for l in &mut self.file.luminaires {
            scale(&mut l.position);
            if let Some(a) = &mut l.array {
                a.spacing_m[0] *= ratio[0];
                a.spacing_m[1] *= ratio[1];
            }
        }
        scale(&mut self.file.camera.position);
        scale(&mut self.file.camera.look_at);
    }

    /// The room lit by each luminaire's own profile: `photometry[i]` is
    /// that of the file's luminaire `i` (`lucerna render`).
    pub fn scene_with_profiles(&self, photometry: &[Photometry]) -> RoomScene {
        let mut scene = RoomScene::new(&self.file, photometry);
        scene.mesh = self.mesh.as_deref().cloned();
        scene
    }

    /// The room lit by one luminaire at every place the file puts one (the
    /// editor's preview): `profile(flux_factor)` gives its profile grid
    /// scaled by a place's factor (one grid shared by all copies), and
    /// `opening` is that luminaire's own, not the one the file gives.
    pub fn scene_lit_by(
        &self,
        mut profile: impl FnMut(f64) -> Arc<ProfileGrid>,
        opening: Opening,
    ) -> RoomScene {
        let mut shell = self.file.clone();
        shell.luminaires.clear();
        let mut scene = RoomScene::new(&shell, &[]);
        for spec in &self.file.luminaires {
            let grid = profile(spec.flux_factor);
            let rotation = PlacedLight::rotation_from_euler_deg(spec.rotation_deg);
            for p in spec.positions() {
                scene.lights.push(PlacedLight {
                    profile: grid.clone(),
                    opening,
                    position: DVec3::from_array(p),
                    rotation,
                });
            }
        }
        scene.mesh = self.mesh.as_deref().cloned();
        scene
    }
}

/// The `*.toml` room files in `dir`, sorted by name (empty if unreadable).
pub fn room_files(dir: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut files: Vec<PathBuf> = entries
        .filter_map(Result::ok)
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    files
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)] // reason: tests may panic
    use super::*;

    fn assets() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets")
    }

    #[test]
    fn a_broken_room_file_is_refused_with_its_line() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("broken.toml");
        std::fs::write(&path, "version = 1\n[room]\nwidth_m = \"wide\"\n").unwrap();
        let error = RoomSetup::load(&path).unwrap_err().to_string();
        assert!(error.contains("line 3"), "{error}");
    }

    #[test]
    fn a_smaller_room_keeps_its_layout_inside() {
        let mut office = RoomSetup::load(&assets().join("rooms/office.toml")).unwrap();
        office.resize([3.0, 2.4, 2.8]);
        assert!(office.problems().is_empty(), "{:?}", office.problems());
        // The 3 × 2 array halves its spacing with the room: still inside.
        for l in &office.file.luminaires {
            for p in l.positions() {
                assert!(
                    p[0] > 0.0 && p[0] < 3.0 && p[1] > 0.0 && p[1] < 2.4,
                    "{p:?}"
                );
            }
        }
    }

    #[test]
    fn one_luminaire_lights_every_place_with_its_own_opening() {
        let office = RoomSetup::load(&assets().join("rooms/office.toml")).unwrap();
        let grid = Arc::new(ProfileGrid::from_fn(true, |_, _| 1.0));
        let disk = Opening::Disk { diameter_m: 0.1 };
        let scene = office.scene_lit_by(|_| grid.clone(), disk);
        assert_eq!(scene.lights.len(), 6);
        assert!(scene.lights.iter().all(|l| l.opening == disk));
        let found = room_files(&assets().join("rooms"));
        assert!(
            found.iter().any(|p| p.ends_with("office.toml")),
            "{found:?}"
        );
        assert!(room_files(Path::new("/no/such/folder")).is_empty());
    }
}
