#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! Hostile input: OBJ and MTL lines the parser would crash on, files that
//! are not what they claim, valid scenes that ask for absurd amounts of
//! memory and generated files with a mistake in every part give bounded
//! errors naming the file and line, never a panic or a runaway allocation.

use std::path::Path;

use lucerna_scene::check::{MAX_LISTED_PROBLEMS, MAX_PART_TRIANGLES, MAX_SCENE_TRIANGLES};
use lucerna_scene::file::MAX_SCENE_FILE_BYTES;
use lucerna_scene::obj::{
    LoadObjError, MAX_MTL_FILE_BYTES, MAX_OBJ_FILE_BYTES, MAX_OBJ_GROUPS, MAX_OBJ_TRIANGLES,
    load_obj,
};
use lucerna_scene::{LoadSceneError, ReadFileError, load_scene, parse_scene, tessellate};

use lucerna_scene::test_support::SMALL_SCENE as GOOD;

const PARABOLOID: &str =
    "shape = { type = \"paraboloid\", focal_length = 0.02, aperture_diameter = 0.08 }";

const TRIANGLE: &str = "v 0 0 0\nv 0.1 0 0\nv 0 0.1 0\n";

fn invalid(text: &str) -> (Vec<lucerna_scene::file::Located>, usize, String) {
    match parse_scene(text, Path::new("lamp.toml")) {
        Err(e @ LoadSceneError::Invalid { .. }) => {
            let shown = e.to_string();
            let LoadSceneError::Invalid {
                problems, unlisted, ..
            } = e
            else {
                unreachable!()
            };
            (problems, unlisted, shown)
        }
        other => panic!("expected an invalid-scene error, got {other:?}"),
    }
}

/// Writes `obj` (and `mtl` as `m.mtl`) into `dir` and loads the OBJ.
fn load(
    dir: &Path,
    obj: &str,
    mtl: Option<&str>,
) -> Result<Vec<lucerna_scene::obj::ObjGroup>, LoadObjError> {
    std::fs::write(dir.join("part.obj"), obj).unwrap();
    if let Some(mtl) = mtl {
        std::fs::write(dir.join("m.mtl"), mtl).unwrap();
    }
    load_obj(&dir.join("part.obj"))
}

fn syntax_line(
    r: Result<Vec<lucerna_scene::obj::ObjGroup>, LoadObjError>,
) -> (String, usize, String) {
    match r {
        Err(LoadObjError::Syntax {
            path,
            line,
            message,
        }) => (
            path.file_name().unwrap().to_string_lossy().into_owned(),
            line,
            message,
        ),
        other => panic!("expected a syntax error, got {other:?}"),
    }
}

/// A file of `bytes` zeros that occupies no disk space.
fn sparse_file(path: &Path, bytes: u64) {
    std::fs::File::create(path).unwrap().set_len(bytes).unwrap();
}

use lucerna_scene::test_support::error_chain as chain;

#[test]
fn an_mtl_colour_with_too_few_numbers_names_the_library_and_line() {
    let dir = tempfile::tempdir().unwrap();
    let obj = format!("mtllib m.mtl\n{TRIANGLE}f 1 2 3\n");
    // tobj unwraps an Err on these (a panic in release builds too).
    for (mtl, line) in [
        ("Ks\n", 1),
        ("newmtl a\nKd 0.5 0.5\n", 2),
        ("# colours\nnewmtl a\n\nKa 0.1 0.2 0.3\nKe 1 2 3 4\n", 5),
    ] {
        let (file, at, message) = syntax_line(load(dir.path(), &obj, Some(mtl)));
        assert_eq!((file.as_str(), at), ("m.mtl", line), "{mtl:?}: {message}");
        assert!(message.contains("3 numbers"), "{message}");
    }
    let (_, _, message) = syntax_line(load(dir.path(), &obj, Some("newmtl a\nKd 1e39 0 0\n")));
    assert!(message.contains("finite"), "{message}");
    let (_, _, message) = syntax_line(load(dir.path(), &obj, Some("newmtl a\nNs\n")));
    assert!(message.contains("one number"), "{message}");
}

#[test]
fn a_broken_mtl_reaches_the_scene_as_an_error_with_its_line() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("part.obj"),
        format!("mtllib m.mtl\n{TRIANGLE}f 1 2 3\n"),
    )
    .unwrap();
    std::fs::write(dir.path().join("m.mtl"), "Ks\n").unwrap();
    let text = GOOD.replace(
        PARABOLOID,
        "shape = { type = \"mesh\", path = \"part.obj\" }",
    );
    let scene = parse_scene(&text, Path::new("lamp.toml")).unwrap();
    let e = tessellate(&scene, dir.path()).unwrap_err();
    let s = chain(&e);
    assert!(s.contains("reflector") && s.contains("m.mtl:1"), "{s}");
}

#[test]
fn grey_colours_and_statements_tobj_cannot_read_are_accepted() {
    let dir = tempfile::tempdir().unwrap();
    let mtl = "newmtl shiny\nKd 0.8\nKs 0.1 0.1 0.1\nKa spectral white.rfl 1.0\nTf xyz 1 1 1\n\
               d -halo 0.5\nTr 0.1\nNs 30\nillum 2\nmap_Kd shiny.png\n";
    let obj = format!("mtllib m.mtl\n{TRIANGLE}usemtl shiny\nf 1 2 3\n");
    let groups = load(dir.path(), &obj, Some(mtl)).unwrap();
    assert_eq!(groups[0].obj_material.as_deref(), Some("shiny"));
}

#[test]
fn a_missing_material_library_is_still_fine() {
    let dir = tempfile::tempdir().unwrap();
    let obj = format!("mtllib nowhere.mtl\n{TRIANGLE}usemtl shiny\nf 1 2 3\n");
    let groups = load(dir.path(), &obj, None).unwrap();
    assert_eq!(groups[0].obj_material, None);
}

#[test]
fn face_indices_outside_the_elements_read_name_the_line() {
    let dir = tempfile::tempdir().unwrap();
    // tobj overflows (debug builds) on the first two, and refers to the
    // wrong vertex or reads out of bounds on the others.
    for (obj, line, words) in [
        (
            "v 9 5 6\nvt 9 1\nf 1/-8 1 1\n",
            3,
            "relative texture coordinate index -8",
        ),
        (
            "v 9 5 6\nvn 0 0 1\nf 1//-2 1 1\n",
            3,
            "relative normal index -2",
        ),
        (
            "v 9 5 6\nvt 9 1\nf 1/99999999999999999 1 1\n",
            3,
            "texture coordinate 99999999999999999",
        ),
        ("v 9 5 6\nvt 9 1\nf 1/0 1 1\n", 3, "index 0"),
        (
            "v 0 0 0\nf -2 1 1\nv 1 0 0\n",
            2,
            "relative vertex index -2",
        ),
        ("v 0 0 0\nf 1 1 4\n", 2, "vertex 4 does not exist"),
        ("v 0 0 0\nf 1/1/1/1 1 1\n", 2, "more than v/vt/vn"),
        ("v 0 0 0\nf 1 x 1\n", 2, "not an index"),
        ("v 0 0 0\n\nf\n", 3, "without vertices"),
    ] {
        let (file, at, message) = syntax_line(load(dir.path(), obj, None));
        assert_eq!(
            (file.as_str(), at),
            ("part.obj", line),
            "{obj:?}: {message}"
        );
        assert!(message.contains(words), "{obj:?}: {message}");
    }
    // A relative index to what precedes it, and a forward one, are valid.
    let groups = load(
        dir.path(),
        "v 0 0 0\nv 0.1 0 0\nf -2 -1 3\nv 0 0.1 0\n",
        None,
    )
    .unwrap();
    assert_eq!(groups[0].mesh.triangle_count(), 1);
}

#[test]
fn an_obj_with_more_triangles_than_a_part_may_have_is_refused_before_parsing() {
    let dir = tempfile::tempdir().unwrap();
    // One polygon of MAX + 3 corners fans into MAX + 1 triangles (4 MB).
    let corners = MAX_OBJ_TRIANGLES as usize + 3;
    let mut obj = String::with_capacity(2 * corners + 64);
    obj.push_str(TRIANGLE);
    obj.push('f');
    for _ in 0..corners {
        obj.push_str(" 1");
    }
    obj.push('\n');
    match load(dir.path(), &obj, None) {
        Err(
            e @ LoadObjError::TooMany {
                what: "triangles", ..
            },
        ) => {
            assert!(
                e.to_string().contains(&MAX_OBJ_TRIANGLES.to_string()),
                "{e}"
            );
        }
        other => panic!("{other:?}"),
    }
    let groups: String = (0..=MAX_OBJ_GROUPS)
        .map(|i| format!("g g{i}\nf 1 2 3\n"))
        .collect();
    match load(dir.path(), &format!("{TRIANGLE}{groups}"), None) {
        Err(LoadObjError::TooMany { count, .. }) => {
            assert_eq!(count, MAX_OBJ_GROUPS as u64 + 1)
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn files_larger_than_their_limit_are_refused_unread() {
    let dir = tempfile::tempdir().unwrap();
    let is_too_large = |e: &ReadFileError, limit: u64| {
        matches!(e, ReadFileError::TooLarge { limit_bytes, .. } if *limit_bytes == limit)
            && e.to_string()
                .contains(&format!("larger than {} MiB", limit >> 20))
    };
    let obj = dir.path().join("huge.obj");
    sparse_file(&obj, MAX_OBJ_FILE_BYTES + 1);
    match load_obj(&obj) {
        Err(LoadObjError::Read(e)) if is_too_large(&e, MAX_OBJ_FILE_BYTES) => {}
        other => panic!("{other:?}"),
    }
    sparse_file(&dir.path().join("m.mtl"), MAX_MTL_FILE_BYTES + 1);
    let r = load(
        dir.path(),
        &format!("mtllib m.mtl\n{TRIANGLE}f 1 2 3\n"),
        None,
    );
    match r {
        Err(LoadObjError::Read(e)) if is_too_large(&e, MAX_MTL_FILE_BYTES) => {}
        other => panic!("{other:?}"),
    }
    let scene = dir.path().join("huge.toml");
    sparse_file(&scene, MAX_SCENE_FILE_BYTES + 1);
    match load_scene(&scene) {
        Err(LoadSceneError::Read(e)) if is_too_large(&e, MAX_SCENE_FILE_BYTES) => {
            assert!(e.to_string().contains("huge.toml"), "{e}");
        }
        other => panic!("{other:?}"),
    }
    // At the limit is fine (and not a scene).
    sparse_file(&scene, 1000);
    assert!(matches!(
        load_scene(&scene),
        Err(LoadSceneError::Syntax { .. })
    ));
}

#[test]
fn a_part_of_too_many_triangles_is_invalid_at_its_shape() {
    // 344 bytes asking for 4096 × 4096 segments: 33M triangles, 3 GB.
    let text = GOOD.replace(
        "aperture_diameter = 0.08 }",
        "aperture_diameter = 0.08, segments_around = 4096, segments_along = 4096 }",
    );
    let (problems, _, _) = invalid(&text);
    assert_eq!(problems.len(), 1, "{problems:?}");
    assert_eq!(problems[0].field, "part[0].shape");
    assert_eq!(problems[0].line, Some(16));
    assert!(
        problems[0]
            .message
            .contains(&(2u64 * 4096 * 4096).to_string())
            && problems[0]
                .message
                .contains(&MAX_PART_TRIANGLES.to_string()),
        "{}",
        problems[0].message
    );
}

#[test]
fn parts_within_their_limit_may_still_exceed_the_scenes() {
    // 2 × 1000 × 999 triangles each, within MAX_PART_TRIANGLES; two and
    // the emitter's 32 are within MAX_SCENE_TRIANGLES, three are not.
    let part = "[[part]]\nname = \"reflector\"\nmaterial = \"alu\"\n\
                shape = { type = \"paraboloid\", focal_length = 0.02, aperture_diameter = 0.08, \
                segments_around = 1000, segments_along = 999 }\n";
    let head = &GOOD[..GOOD.find("[[part]]").unwrap()];
    let text = format!("{head}{part}{part}");
    parse_scene(&text, Path::new("lamp.toml")).expect("two parts are valid");
    let (problems, _, _) = invalid(&format!("{head}{part}{part}{part}"));
    assert_eq!(problems.len(), 1, "{problems:?}");
    assert_eq!(problems[0].field, "part");
    assert!(
        problems[0]
            .message
            .contains(&MAX_SCENE_TRIANGLES.to_string()),
        "{}",
        problems[0].message
    );
    // Disabled parts are not tessellated, so they do not count.
    let disabled = part.replace(
        "material = \"alu\"\n",
        "material = \"alu\"\nenabled = false\n",
    );
    parse_scene(
        &format!("{head}{part}{part}{disabled}"),
        Path::new("lamp.toml"),
    )
    .unwrap();
}

/// A scene with `parts` plates that all name an undefined material.
fn many_bad_parts(parts: usize, materials: usize) -> String {
    let mut s = String::from("format_version = 1\nname = \"generated\"\n\n");
    for i in 0..materials {
        s.push_str(&format!(
            "[materials.m{i}]\ntype = \"mirror\"\nreflectance = 0.9\n\n"
        ));
    }
    s.push_str("[[emitter]]\nname = \"LED\"\nflux_lm = 100.0\nshape = { type = \"disk\", radius = 0.002 }\n\n");
    for i in 0..parts {
        s.push_str(&format!(
            "[[part]]\nname = \"p{i}\"\nmaterial = \"nope\"\nshape = {{ type = \"plate\", width = 0.1, depth = 0.1 }}\n\n"
        ));
    }
    s
}

#[test]
fn thousands_of_problems_are_located_in_one_parse_and_listed_to_a_limit() {
    let parts = 4000;
    let text = many_bad_parts(parts, 1);
    // Re-parsing the file for every problem took 47 s here (debug build);
    // one parse takes milliseconds (speed is the benchmark's to show, this
    // test checks what is reported).
    let (problems, unlisted, _) = invalid(&text);
    assert_eq!(problems.len(), MAX_LISTED_PROBLEMS);
    assert_eq!(problems.len() + unlisted, parts);
    // Still located: part[i] starts on line 13 + 5 i, its material two below.
    for (i, p) in problems.iter().enumerate() {
        assert_eq!(p.field, format!("part[{i}].material"));
        assert_eq!(p.line, Some(15 + 5 * i), "{p:?}");
    }
}

#[test]
fn the_report_of_a_generated_file_stays_smaller_than_the_file() {
    // Every message listed all 700 materials: 100 kB of file, 2.9 MB of errors.
    let text = many_bad_parts(700, 700);
    let (problems, unlisted, shown) = invalid(&text);
    assert!(
        shown.len() < text.len() / 4,
        "{} bytes of errors",
        shown.len()
    );
    assert!(
        shown.contains(&format!("… and {unlisted} more problems")),
        "{shown}"
    );
    let first = &problems[0].message;
    assert!(
        first.contains("m0, m1,") && first.contains("… and 690 more"),
        "{first}"
    );
    // A name as long as the file is cut, not repeated in every message.
    let long = "x".repeat(100_000);
    let text = GOOD.replace("material = \"alu\"", &format!("material = \"{long}\""));
    let (_, _, shown) = invalid(&text);
    assert!(shown.len() < 1000, "{} bytes", shown.len());
}
