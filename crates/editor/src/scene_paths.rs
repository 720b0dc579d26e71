//! How a scene names the files it references: relative to its own
//! folder where it can, and rewritten when the scene is saved elsewhere.

use std::path::{Component, Path, PathBuf};

use lucerna_scene::{Emission, Scene, Shape};

/// How a scene at `scene_path` refers to the file at `absolute`: relative
/// to the scene's folder where it has one; None where the path is not
/// UTF-8 (a scene file cannot hold it).
pub(crate) fn stored_path(scene_path: Option<&Path>, absolute: PathBuf) -> Option<String> {
    let stored = scene_path
        .map(folder_of)
        .and_then(|dir| relative_path(dir, &absolute))
        .unwrap_or(absolute);
    stored.to_str().map(str::to_owned)
}

/// The folder a file is in: "." for a bare file name, whose parent is "".
pub(crate) fn folder_of(path: &Path) -> &Path {
    match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    }
}

/// `file` relative to `dir` (both made canonical), through `..` where
/// needed; `None` when they share no more than the root, where an
/// absolute path says more.
pub(crate) fn relative_path(dir: &Path, file: &Path) -> Option<PathBuf> {
    let dir = std::fs::canonicalize(dir).ok()?;
    let file = std::fs::canonicalize(file).ok()?;
    let d: Vec<Component<'_>> = dir.components().collect();
    let f: Vec<Component<'_>> = file.components().collect();
    let common = d.iter().zip(&f).take_while(|(a, b)| a == b).count();
    if common <= 1 {
        return None;
    }
    let mut relative = PathBuf::new();
    for _ in common..d.len() {
        relative.push("..");
    }
    for c in &f[common..] {
        relative.push(c);
    }
    Some(relative)
}

/// The scene with its relative file paths (OBJ meshes, emitter profiles)
/// rewritten to name the same files from `new_path`'s folder; `None` when
/// nothing changes. Missing files are left as written. The undo history
/// keeps the old paths: undoing across a "Save as" to another folder gives
/// paths the simulation reports as missing, and redo brings them back.
pub(crate) fn rebased_for(scene: &Scene, scene_dir: &Path, new_path: &Path) -> Option<Scene> {
    let to_dir = folder_of(new_path);
    let scene_dir = if scene_dir.as_os_str().is_empty() {
        Path::new(".")
    } else {
        scene_dir
    };
    let same_dir = match (
        std::fs::canonicalize(scene_dir),
        std::fs::canonicalize(to_dir),
    ) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    };
    if same_dir {
        return None;
    }
    let mut out = scene.clone();
    let mut changed = false;
    let mut rebase = |path: &mut String| {
        let old = Path::new(path.as_str());
        if old.is_absolute() {
            return;
        }
        let target = scene_dir.join(old);
        if !target.exists() {
            return;
        }
        let new = relative_path(to_dir, &target)
            .unwrap_or_else(|| std::fs::canonicalize(&target).unwrap_or(target));
        if let Some(text) = new.to_str()
            && text != path
        {
            *path = text.to_owned();
            changed = true;
        }
    };
    for part in &mut out.parts {
        if let Shape::Mesh(mesh) = &mut part.shape {
            rebase(&mut mesh.path);
        }
    }
    for emitter in &mut out.emitters {
        if let Emission::Profile(file) = &mut emitter.emission {
            rebase(file);
        }
    }
    changed.then_some(out)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)] // reason: tests may panic

    use super::*;

    #[test]
    fn relative_paths_go_up_where_needed() {
        let dir = tempfile::tempdir().unwrap();
        let a = dir.path().join("a/luminaires");
        let m = dir.path().join("a/meshes");
        std::fs::create_dir_all(&a).unwrap();
        std::fs::create_dir_all(&m).unwrap();
        std::fs::write(m.join("x.obj"), "").unwrap();
        assert_eq!(
            relative_path(&a, &m.join("x.obj")),
            Some(PathBuf::from("../meshes/x.obj"))
        );
    }
}
