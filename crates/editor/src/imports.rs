//! Files brought into a scene as parts or emitters: an OBJ mesh as a
//! part (its units guessed, its groups' materials added), a TM-25 ray file
//! as an emitter; each read and checked before the scene changes.

use std::path::{Path, PathBuf};

use lucerna_scene::obj::{LoadObjError, load_obj};
use lucerna_scene::shapes::Mesh;
use lucerna_scene::{
    Emission, Emitter, EmitterShape, Material, Part, Scene, Shape, TessellateError, Transform,
    tessellate,
};

use crate::modelling::unique_name;
use crate::scene_paths::{folder_of, stored_path};

/// Why an OBJ file could not be imported.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ImportMeshError {
    #[error("cannot import {path}")]
    Load {
        path: PathBuf,
        #[source]
        source: Box<LoadObjError>,
    },
    #[error("cannot import {path}")]
    Unusable {
        path: PathBuf,
        #[source]
        source: Box<TessellateError>,
    },
    #[error("cannot import {path}: scene files store paths as UTF-8")]
    NotUtf8 { path: PathBuf },
}

/// Extent (m) above which an OBJ file is taken to be in millimetres: CAD
/// exports usually are, and no luminaire part is this large.
const MILLIMETRE_GUESS_M: f32 = 5.0;

/// A mesh part for the OBJ file at `obj` (relative paths from the working
/// directory), checked by tessellating it alone. The file's path is
/// stored relative to the scene's folder where the scene has one.
pub fn mesh_part(
    scene: &Scene,
    scene_path: Option<&Path>,
    obj: &Path,
) -> Result<(Part, Option<String>), ImportMeshError> {
    let absolute = std::path::absolute(obj).unwrap_or_else(|_| obj.to_path_buf());
    let groups = load_obj(&absolute).map_err(|source| ImportMeshError::Load {
        path: obj.to_owned(),
        source: Box::new(source),
    })?;
    let (mut lo, mut hi) = ([f32::MAX; 3], [f32::MIN; 3]);
    for p in groups.iter().flat_map(|g| &g.mesh.positions) {
        for (k, x) in [p.x, p.y, p.z].into_iter().enumerate() {
            lo[k] = lo[k].min(x);
            hi[k] = hi[k].max(x);
        }
    }
    let extent = (0..3).map(|k| hi[k] - lo[k]).fold(0.0_f32, f32::max);
    let (scale, notice) = if extent > MILLIMETRE_GUESS_M {
        (
            0.001,
            Some(format!(
                "{} is {extent:.0} units across: read as millimetres (scale 0.001)",
                obj.display()
            )),
        )
    } else {
        (1.0, None)
    };
    let scene_dir = scene_path.map(folder_of);
    let stored_text =
        stored_path(scene_path, absolute).ok_or_else(|| ImportMeshError::NotUtf8 {
            path: obj.to_owned(),
        })?;
    let stem = obj
        .file_stem()
        .map_or_else(|| "mesh".to_owned(), |s| s.to_string_lossy().into_owned());
    let mut alone = scene.clone();
    if alone.materials.is_empty() {
        alone.materials.insert(
            "white_paint".to_owned(),
            Material::Lambertian { albedo: 0.8 },
        );
    }
    let material = alone.materials.keys().next().cloned().unwrap_or_default();
    let part = Part {
        name: unique_name(&stem, |n| scene.parts.iter().any(|p| p.name == n)),
        shape: Shape::Mesh(Mesh {
            path: stored_text,
            group_materials: Default::default(),
        }),
        material,
        enabled: true,
        transform: Transform {
            scale: [scale; 3],
            ..Transform::default()
        },
        finish: None,
    };
    alone.parts = vec![part.clone()];
    alone.emitters.clear();
    alone.opening = None;
    let dir = scene_dir.map_or_else(|| PathBuf::from("."), Path::to_path_buf);
    tessellate(&alone, &dir).map_err(|source| ImportMeshError::Unusable {
        path: obj.to_owned(),
        source: Box::new(source),
    })?;
    Ok((part, notice))
}

/// Why a ray file cannot be added as an emitter.
#[derive(Debug, thiserror::Error)]
pub enum RayFileEmitterError {
    #[error("cannot add {path} as an emitter")]
    Read {
        path: PathBuf,
        #[source]
        source: Box<lucerna_photometry::tm25::ReadRayFileError>,
    },
    #[error("the path {path} is not UTF-8, which a scene file cannot hold")]
    NotUtf8 { path: PathBuf },
}

/// An emitter for the TM-25 ray file at `file` (relative paths from the
/// working directory), read and checked first: named after the file,
/// at the origin, with the file's own luminous flux (declared, else its
/// rays' sum). The path is stored relative to the scene's folder where
/// the scene has one.
pub fn ray_file_emitter(
    scene: &Scene,
    scene_path: Option<&Path>,
    file: &Path,
) -> Result<Emitter, RayFileEmitterError> {
    let absolute = std::path::absolute(file).unwrap_or_else(|_| file.to_path_buf());
    let rays = lucerna_photometry::tm25::read_ray_file(&absolute).map_err(|source| {
        RayFileEmitterError::Read {
            path: file.to_owned(),
            source: Box::new(source),
        }
    })?;
    let flux_lm = rays
        .header
        .luminous_flux_lm
        .map_or_else(|| rays.total_luminous_flux_lm(), f64::from);
    let path = stored_path(scene_path, absolute).ok_or_else(|| RayFileEmitterError::NotUtf8 {
        path: file.to_owned(),
    })?;
    let stem = file.file_stem().map_or_else(
        || "ray file".to_owned(),
        |s| s.to_string_lossy().into_owned(),
    );
    Ok(Emitter {
        name: unique_name(&stem, |n| scene.emitters.iter().any(|e| e.name == n)),
        shape: EmitterShape::RayFile { path },
        flux_lm,
        emission: Emission::Lambertian,
        material: None,
        enabled: true,
        transform: Transform::default(),
    })
}
