//! Wavefront OBJ import (tobj): one mesh per OBJ object/group, each with
//! the material the scene assigns to it.
//!
//! tobj trusts its input: it panics on an MTL colour with fewer than three
//! numbers and overflows (debug builds) on a relative index before the
//! first element. So the OBJ file and its material libraries are read
//! here, within size limits, and checked line by line; tobj parses only
//! text that passed, through `load_obj_buf` and a material loader that
//! serves the checked libraries.

use std::collections::{BTreeMap, HashMap};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use glam::{DVec3, Vec3};

use crate::check::MAX_PART_TRIANGLES;
use crate::io::{MIB, ReadFileError, read_limited_text};
use crate::mesh::TriangleMesh;

/// Largest OBJ file read: about a million triangles with normals.
pub const MAX_OBJ_FILE_BYTES: u64 = 64 * MIB;
/// Largest material library (MTL) read; only its material names are used.
pub const MAX_MTL_FILE_BYTES: u64 = 16 * MIB;
/// Most triangles in one OBJ file, that of a part. A polygon of n corners
/// makes n − 2; points and lines, which are not imported, count as one
/// each, since the parser holds them in memory all the same.
pub const MAX_OBJ_TRIANGLES: u64 = MAX_PART_TRIANGLES;
/// Most objects/groups with faces in one OBJ file: each becomes a surface
/// of its own, and the parser allocates a mesh for every one.
pub const MAX_OBJ_GROUPS: usize = 10_000;
/// Most `mtllib` statements in one OBJ file (the parser reads the library
/// again for each).
pub const MAX_MTL_LIBRARIES: usize = 8;
/// Most materials (`newmtl`) in one material library.
pub const MAX_MTL_MATERIALS: usize = 4096;

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
    /// The OBJ file or one of its material libraries is unreadable, too
    /// large or not text.
    #[error(transparent)]
    Read(#[from] ReadFileError),
    /// A line of the OBJ file or of a material library that the parser
    /// would misread or crash on.
    #[error("{path}:{line}: {message}")]
    Syntax {
        path: PathBuf,
        line: usize,
        message: String,
    },
    #[error("{path} has {count} {what}, at most {max}")]
    TooMany {
        path: PathBuf,
        what: &'static str,
        count: u64,
        max: u64,
    },
    #[error("cannot parse OBJ file: {0}")]
    Parse(#[from] tobj::LoadError),
    #[error("the OBJ file has no faces")]
    NoFaces,
    #[error("group '{group}': vertex {index} has a non-finite coordinate")]
    NonFinite { group: String, index: usize },
}

/// Loads an OBJ file's triangles (polygons are fan-triangulated). Normals
/// from the file are kept when every vertex has one; otherwise each
/// triangle gets its flat geometric normal. A missing material library is
/// fine (materials are assigned by group name), a broken one is an error.
pub fn load_obj(path: &Path) -> Result<Vec<ObjGroup>, LoadObjError> {
    let text = read_limited_text(path, MAX_OBJ_FILE_BYTES)?;
    let library_names = check_obj(&text, path)?;
    let dir = path.parent().unwrap_or(Path::new(""));
    let mut libraries: HashMap<&str, String> = HashMap::new();
    for name in library_names {
        if libraries.contains_key(name) {
            continue;
        }
        let mtl_path = dir.join(name);
        match read_limited_text(&mtl_path, MAX_MTL_FILE_BYTES) {
            Ok(mtl) => {
                libraries.insert(name, checked_mtl(&mtl, &mtl_path)?);
            }
            Err(ReadFileError::Io { source, .. })
                if source.kind() == std::io::ErrorKind::NotFound => {}
            Err(e) => return Err(e.into()),
        }
    }
    let options = tobj::LoadOptions {
        single_index: true,
        triangulate: true,
        ignore_points: true,
        ignore_lines: true,
    };
    let (models, materials) =
        tobj::load_obj_buf(&mut text.as_bytes(), &options, |name| {
            match name.to_str().and_then(|n| libraries.get(n)) {
                Some(mtl) => tobj::load_mtl_buf(&mut mtl.as_bytes()),
                None => Err(tobj::LoadError::OpenFileFailed),
            }
        })?;
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

/// The statement a line of an OBJ or MTL file makes, as tobj reads it.
fn keyword(line: &str) -> Option<&str> {
    line.split_whitespace().next()
}

/// Which of v, vt, vn an index component refers to.
const ELEMENT_NAMES: [&str; 3] = ["vertex", "texture coordinate", "normal"];

/// Checks what tobj would trust in an OBJ text: every index of a face or
/// line within the elements it refers to (a relative one within those read
/// so far), and the triangles, groups and material libraries within their
/// limits. Returns the material libraries' names as tobj passes them to
/// its loader.
fn check_obj<'t>(text: &'t str, path: &Path) -> Result<Vec<&'t str>, LoadObjError> {
    let mut totals = [0usize; 3];
    for line in text.lines() {
        match keyword(line) {
            Some("v") => totals[0] += 1,
            Some("vt") => totals[1] += 1,
            Some("vn") => totals[2] += 1,
            _ => {}
        }
    }
    let too_many = |what, count: u64, max: u64| LoadObjError::TooMany {
        path: path.to_owned(),
        what,
        count,
        max,
    };
    let mut read_so_far = [0usize; 3];
    let mut triangles: u64 = 0;
    let mut groups: usize = 0;
    let mut faces_in_group = false;
    let mut libraries = Vec::new();
    for (i, line) in text.lines().enumerate() {
        let syntax = |message: String| LoadObjError::Syntax {
            path: path.to_owned(),
            line: i + 1,
            message,
        };
        match keyword(line) {
            Some("v") => read_so_far[0] += 1,
            Some("vt") => read_so_far[1] += 1,
            Some("vn") => read_so_far[2] += 1,
            Some(statement @ ("f" | "l")) => {
                let mut corners: u64 = 0;
                for word in line.split_whitespace().skip(1) {
                    check_indices(word, read_so_far, totals).map_err(syntax)?;
                    corners += 1;
                }
                if corners == 0 {
                    return Err(syntax(format!("`{statement}` without vertices")));
                }
                triangles += corners.max(3) - 2;
                faces_in_group = true;
            }
            // Where tobj starts a new mesh (it may for `usemtl`).
            Some("o" | "g" | "usemtl") if faces_in_group => {
                groups += 1;
                faces_in_group = false;
            }
            Some("mtllib") => {
                // Spelt as tobj reads it: the name may contain spaces.
                let name = line.split_once(' ').unwrap_or_default().1.trim();
                if !name.is_empty() {
                    libraries.push(name);
                }
            }
            _ => {}
        }
    }
    groups += usize::from(faces_in_group);
    if triangles > MAX_OBJ_TRIANGLES {
        return Err(too_many("triangles", triangles, MAX_OBJ_TRIANGLES));
    }
    if groups > MAX_OBJ_GROUPS {
        return Err(too_many(
            "objects/groups with faces",
            groups as u64,
            MAX_OBJ_GROUPS as u64,
        ));
    }
    if libraries.len() > MAX_MTL_LIBRARIES {
        return Err(too_many(
            "mtllib statements",
            libraries.len() as u64,
            MAX_MTL_LIBRARIES as u64,
        ));
    }
    Ok(libraries)
}

/// Checks one corner of a face, `v`, `v/vt`, `v//vn` or `v/vt/vn`: each
/// index is 1-based and refers to an element of the file, a negative
/// (relative) one to an element before it.
fn check_indices(word: &str, read_so_far: [usize; 3], totals: [usize; 3]) -> Result<(), String> {
    let components: Vec<&str> = word.split('/').collect();
    if components.len() > ELEMENT_NAMES.len() {
        return Err(format!("'{word}' has more than v/vt/vn indices"));
    }
    for (k, component) in components.into_iter().enumerate() {
        let (element, so_far, total) = (ELEMENT_NAMES[k], read_so_far[k], totals[k]);
        if component.is_empty() {
            if k == 0 {
                return Err(format!("'{word}' has no vertex index"));
            }
            continue;
        }
        let index: isize = component
            .parse()
            .map_err(|_| format!("'{word}': '{component}' is not an index"))?;
        if index == 0 {
            return Err(format!(
                "'{word}': {element} index 0 (OBJ indices start at 1)"
            ));
        }
        if index < 0 && index.unsigned_abs() > so_far {
            return Err(format!(
                "'{word}': relative {element} index {index} reaches before the first one ({so_far} read so far)"
            ));
        }
        if index > 0 && index.unsigned_abs() > total {
            return Err(format!(
                "'{word}': {element} {index} does not exist (the file has {total})"
            ));
        }
    }
    Ok(())
}

/// Checks a material library and returns the part of it tobj is given:
/// material names, and colours and scalars as tobj parses them (a colour
/// needs three numbers or one for grey, all finite). Texture maps and
/// other statements are left out, since nothing downstream reads them.
fn checked_mtl(text: &str, path: &Path) -> Result<String, LoadObjError> {
    let mut checked = String::new();
    let mut materials = 0usize;
    for (i, line) in text.lines().enumerate() {
        let syntax = |message: String| LoadObjError::Syntax {
            path: path.to_owned(),
            line: i + 1,
            message,
        };
        let Some(statement) = keyword(line) else {
            continue;
        };
        let arguments: Vec<&str> = line.split_whitespace().skip(1).collect();
        match statement {
            "newmtl" => {
                let name = line.trim()[statement.len()..].trim();
                if name.is_empty() {
                    return Err(syntax("`newmtl` without a name".to_owned()));
                }
                materials += 1;
                if materials > MAX_MTL_MATERIALS {
                    return Err(LoadObjError::TooMany {
                        path: path.to_owned(),
                        what: "materials",
                        count: materials as u64,
                        max: MAX_MTL_MATERIALS as u64,
                    });
                }
                let _ = writeln!(checked, "newmtl {name}");
            }
            "Ka" | "Kd" | "Ks" | "Ke" | "Tf" => {
                let rgb = colour(&arguments).map_err(|m| syntax(format!("`{statement}` {m}")))?;
                // tobj knows no `Tf`, nor the spectral and CIE XYZ forms.
                if let Some([r, g, b]) = rgb.filter(|_| statement != "Tf") {
                    let _ = writeln!(checked, "{statement} {r} {g} {b}");
                }
            }
            "Ns" | "Ni" | "d" | "Tr" => {
                let halo = statement == "d" && arguments.first() == Some(&"-halo");
                let value = match numbers(&arguments[usize::from(halo)..]) {
                    Ok(values) if values.len() == 1 => values[0],
                    Ok(values) => {
                        return Err(syntax(format!(
                            "`{statement}` needs one number, got {}",
                            values.len()
                        )));
                    }
                    Err(m) => return Err(syntax(format!("`{statement}` {m}"))),
                };
                // tobj knows neither `Tr` nor the halo form.
                if statement != "Tr" && !halo {
                    let _ = writeln!(checked, "{statement} {value}");
                }
            }
            "illum" => match arguments.as_slice() {
                [model] if model.parse::<u8>().is_ok() => {
                    let _ = writeln!(checked, "illum {model}");
                }
                _ => {
                    return Err(syntax(
                        "`illum` needs one illumination model number".to_owned(),
                    ));
                }
            },
            _ => {}
        }
    }
    Ok(checked)
}

/// The colour of a Ka/Kd/Ks/Ke/Tf statement: `r g b`, `r` for grey, or
/// `None` for the `spectral file` and `xyz x y z` forms.
fn colour(arguments: &[&str]) -> Result<Option<[f32; 3]>, String> {
    let (values, rgb) = match arguments {
        ["spectral", _, ..] => return Ok(None),
        ["xyz", rest @ ..] => (numbers(rest)?, false),
        all => (numbers(all)?, true),
    };
    let colour = match values.as_slice() {
        &[grey] => [grey; 3],
        &[r, g, b] => [r, g, b],
        other => {
            return Err(format!(
                "needs 3 numbers (or 1 for grey), got {}",
                other.len()
            ));
        }
    };
    Ok(rgb.then_some(colour))
}

/// Finite numbers as tobj reads them (f32).
fn numbers(words: &[&str]) -> Result<Vec<f32>, String> {
    words
        .iter()
        .map(|w| match w.parse::<f32>() {
            Ok(v) if v.is_finite() => Ok(v),
            Ok(_) => Err(format!("needs finite numbers, got '{w}'")),
            Err(_) => Err(format!("needs numbers, got '{w}'")),
        })
        .collect()
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
