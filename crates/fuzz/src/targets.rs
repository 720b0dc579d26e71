//! What each target feeds its input to, and the invariants it checks.

use std::path::{Path, PathBuf};

use lucerna_photometry::{
    IesVersion, Photometry, read_photometry, to_latin1, write_ies, write_ldt,
};

use crate::{Finding, Target, assets, corpus_dir, run_case};

/// A case: files by path relative to a scratch folder.
pub type Case = Vec<(String, Vec<u8>)>;

fn read(path: &Path) -> Vec<u8> {
    std::fs::read(path).unwrap_or_default()
}

fn files_under(dir: &Path, keep: impl Fn(&Path) -> bool) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        let Ok(entries) = std::fs::read_dir(&d) else {
            continue;
        };
        for e in entries.flatten() {
            let p = e.path();
            if p.is_dir() {
                stack.push(p);
            } else if keep(&p) {
                out.push(p);
            }
        }
    }
    out.sort();
    out
}

fn extension_in(p: &Path, extensions: &[&str]) -> bool {
    p.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| extensions.contains(&e.to_ascii_lowercase().as_str()))
}

/// The cases a campaign starts from: the assets, then the regression
/// corpus (a file per case for photometry; a folder per case otherwise,
/// laid out like the assets: `luminaires/`, `meshes/`, `rooms/`).
pub fn seeds(target: Target) -> Vec<Case> {
    let assets = assets();
    let mut cases: Vec<Case> = Vec::new();
    match target {
        Target::Photometry => {
            for p in files_under(&assets.join("profiles"), |p| {
                extension_in(p, &["ies", "ldt"])
            }) {
                cases.push(vec![("profile".to_owned(), read(&p))]);
            }
            for p in files_under(&corpus_dir(target), |_| true) {
                cases.push(vec![("profile".to_owned(), read(&p))]);
            }
        }
        Target::Scene => {
            let meshes: Case = files_under(&assets.join("meshes"), |_| true)
                .into_iter()
                .filter_map(|p| {
                    let name = p.file_name()?.to_str()?.to_owned();
                    Some((format!("meshes/{name}"), read(&p)))
                })
                .collect();
            for p in files_under(&assets.join("luminaires"), |p| extension_in(p, &["toml"])) {
                let name = p
                    .file_name()
                    .and_then(|n| n.to_str())
                    .unwrap_or("scene.toml");
                let mut case = vec![(format!("luminaires/{name}"), read(&p))];
                case.extend(meshes.iter().cloned());
                cases.push(case);
            }
            cases.extend(corpus_cases(target));
        }
        Target::RayFile => {
            for p in files_under(&assets.join("rayfiles"), |p| extension_in(p, &["tm25ray"])) {
                cases.push(vec![("rays.tm25ray".to_owned(), read(&p))]);
            }
            for p in files_under(&corpus_dir(target), |_| true) {
                cases.push(vec![("rays.tm25ray".to_owned(), read(&p))]);
            }
        }
        Target::Room => {
            let rooms = assets.join("rooms");
            let meshes: Case = files_under(&rooms, |p| extension_in(p, &["obj", "mtl"]))
                .into_iter()
                .filter_map(|p| {
                    let name = p.file_name()?.to_str()?.to_owned();
                    Some((format!("rooms/{name}"), read(&p)))
                })
                .collect();
            for p in files_under(&rooms, |p| extension_in(p, &["toml"])) {
                let name = p
                    .file_name()
                    .and_then(|n| n.to_str())
                    .unwrap_or("room.toml");
                let mut case = vec![(format!("rooms/{name}"), read(&p))];
                case.extend(meshes.iter().cloned());
                cases.push(case);
            }
            cases.extend(corpus_cases(target));
        }
    }
    cases
}

/// Each sub-folder of the target's corpus is a case.
fn corpus_cases(target: Target) -> Vec<Case> {
    let dir = corpus_dir(target);
    let Ok(entries) = std::fs::read_dir(&dir) else {
        return Vec::new();
    };
    let mut folders: Vec<PathBuf> = entries
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.is_dir())
        .collect();
    folders.sort();
    folders
        .into_iter()
        .map(|case| {
            files_under(&case, |_| true)
                .into_iter()
                .filter_map(|p| {
                    let rel = p.strip_prefix(&case).ok()?.to_str()?.replace('\\', "/");
                    Some((rel, read(&p)))
                })
                .collect()
        })
        .collect()
}

/// Runs one case through its target.
pub fn run(target: Target, case: Case) -> Option<Finding> {
    match target {
        Target::Photometry => run_case(target, case, |files| photometry(&files[0].1)),
        Target::Scene => run_case(target, case, |files| in_scratch(files, scene)),
        Target::Room => run_case(target, case, |files| in_scratch(files, room)),
        Target::RayFile => run_case(target, case, |files| ray_file(&files[0].1)),
    }
}

/// A ray file that reads has finite far-field figures, and written again
/// reads back with the same header and rays.
pub fn ray_file(bytes: &[u8]) -> Result<(), String> {
    ray_file_read(bytes).map(|_| ())
}

/// [`ray_file`]'s checks; the set and its far field's flux where it read.
fn ray_file_read(bytes: &[u8]) -> Result<Option<(f64, f64, usize)>, String> {
    use lucerna_photometry::tm25::{parse_ray_file, write_ray_file};
    let Ok(set) = parse_ray_file(bytes, "fuzzed.tm25ray") else {
        return Ok(None);
    };
    let photometry = set.far_field_photometry("fuzzed.tm25ray");
    finite_figures(&photometry, "the ray file's far field")?;
    let again = write_ray_file(&set);
    let back = parse_ray_file(&again, "written.tm25ray")
        .map_err(|e| format!("a ray file that read, written again, does not read: {e}"))?;
    let bits = |r: &[f32]| r.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    if back.header != set.header || bits(&back.records) != bits(&set.records) {
        return Err("a ray file written again reads back with other rays".to_owned());
    }
    Ok(Some((
        set.total_luminous_flux_lm(),
        photometry.figures().flux_lm,
        set.len(),
    )))
}

/// [`ray_file`], and where the generator promised it, the far field's
/// flux within its share of the rays'.
pub fn ray_file_promised(bytes: &[u8], promise: &crate::rays::Promise) -> Result<(), String> {
    let read = ray_file_read(bytes)?;
    let (Some(share), Some((rays, table, _))) = (promise.far_field_flux, read) else {
        return Ok(());
    };
    if (table / rays - 1.0).abs() > share {
        return Err(format!(
            "a ray file's far field does not keep its flux: {table} lm against its rays' {rays} lm ({})",
            promise.built
        ));
    }
    Ok(())
}

/// Lays the files out in a scratch folder and runs `check` on it.
fn in_scratch(
    files: &[(String, Vec<u8>)],
    check: fn(&Path, &str) -> Result<(), String>,
) -> Result<(), String> {
    let dir = tempfile::tempdir().map_err(|e| format!("scratch folder: {e}"))?;
    for (name, bytes) in files {
        let path = dir.path().join(name);
        if let Some(parent) = path.parent() {
            std::fs::create_dir_all(parent).map_err(|e| e.to_string())?;
        }
        std::fs::write(&path, bytes).map_err(|e| e.to_string())?;
    }
    check(dir.path(), &files[0].0)
}

/// The figures a report prints must be numbers.
fn finite_figures(p: &Photometry, what: &str) -> Result<(), String> {
    let f = p.figures();
    let mut values = vec![f.flux_lm, f.peak_cd, f.downward_fraction];
    values.extend(f.light_output_ratio);
    values.extend(f.beam_angle_deg.iter().flatten());
    values.extend(f.field_angle_deg.iter().flatten());
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(format!("{what}: a figure is not finite: {f:?}"))
    }
}

/// The line-level rules of a written file: nothing but ASCII, LM-63's
/// lines under 256 characters, EULUMDAT's fixed layout (one field a
/// line, as many lines as its counts say) with free text within its
/// fields' widths.
fn layout(format: &str, bytes: &[u8]) -> Result<(), String> {
    if let Some(i) = bytes.iter().position(|b| !b.is_ascii()) {
        return Err(format!(
            "{format} written with a non-ASCII byte {:#04x} at {i}",
            bytes[i]
        ));
    }
    let text = String::from_utf8_lossy(bytes);
    let lines: Vec<&str> = text.split("\r\n").collect();
    let lines = &lines[..lines.len() - usize::from(lines.last() == Some(&""))];
    if let Some(l) = lines.iter().find(|l| l.contains('\r') || l.contains('\n')) {
        return Err(format!("{format}: a bare line break inside \"{l}\""));
    }
    if format.starts_with("IES") {
        if let Some(l) = lines
            .iter()
            .find(|l| l.chars().count() > IES_MAX_LINE_CHARS)
        {
            return Err(format!(
                "{format}: a line of {} characters (LM-63: under 256)",
                l.chars().count()
            ));
        }
        return Ok(());
    }
    // EULUMDAT: 26 header lines, 6 per lamp set, 10 direct ratios, the C
    // and γ lists, and the stored planes' intensities.
    let sets: usize = lines
        .get(25)
        .and_then(|l| l.trim().parse().ok())
        .ok_or("LDT: no lamp-set count on line 26")?;
    let mc: usize = lines
        .get(3)
        .and_then(|l| l.trim().parse().ok())
        .ok_or("LDT: no Mc on line 4")?;
    let ng: usize = lines
        .get(5)
        .and_then(|l| l.trim().parse().ok())
        .ok_or("LDT: no Ng on line 6")?;
    let isym: usize = lines
        .get(2)
        .and_then(|l| l.trim().parse().ok())
        .ok_or("LDT: no Isym on line 3")?;
    let stored = match isym {
        1 => 1,
        2 | 3 => mc / 2 + 1,
        4 => mc / 4 + 1,
        _ => mc,
    };
    let expected = 26 + 6 * sets + 10 + mc + ng + stored * ng;
    if lines.len() != expected {
        return Err(format!(
            "LDT: {} lines where its counts make {expected}",
            lines.len()
        ));
    }
    use lucerna_photometry::ldt::field_width as w;
    let mut fields = vec![
        (0, w::COMPANY),
        (7, w::REPORT),
        (8, w::LUMINAIRE_NAME),
        (9, w::LUMINAIRE_NUMBER),
        (10, w::FILE_NAME),
        (11, w::DATE_USER),
    ];
    for k in 0..sets {
        let base = 26 + 6 * k;
        fields.extend([
            (base + 1, w::LAMP_TYPE),
            (base + 3, w::COLOUR_APPEARANCE),
            (base + 4, w::COLOUR_RENDERING),
        ]);
    }
    for (line, width) in fields {
        let n = lines[line].chars().count();
        if n > width {
            return Err(format!(
                "LDT line {}: {n} characters in a field of {width}",
                line + 1
            ));
        }
    }
    Ok(())
}

/// The longest line LM-63 allows (lines under 256 characters).
const IES_MAX_LINE_CHARS: usize = 255;

/// Whether a written file keeps the declared symmetry, but for the two
/// cases the writers change it by design: an IES mirror about C90-C270 is
/// written over the whole circle (`WriteOptions::full_circle_for_c90_mirror`,
/// since independent readers refuse LM-63's 90°-270° range), and an
/// EULUMDAT whose listed planes the format's index arithmetic cannot
/// halve is written whole (Isym 0).
fn symmetry_kept(format: &str, p: &Photometry, back: &Photometry) -> Result<(), String> {
    use lucerna_photometry::CPlaneSymmetry as S;
    let by_design = match (format, p.symmetry, back.symmetry) {
        (f, S::AboutC90C270, S::None) if f.starts_with("IES") => true,
        ("LDT", declared, S::None) => !lucerna_photometry::ldt::states_symmetry(declared, &p.table),
        _ => false,
    };
    if back.symmetry == p.symmetry || by_design {
        Ok(())
    } else {
        Err(format!(
            "{format}: declared {:?}, read back {:?}",
            p.symmetry, back.symmetry
        ))
    }
}

/// Reads; if the file reads, its figures are finite and every file
/// Lucerna writes from it either is refused with a reason, or reads back
/// with the same flux and peak (0.1 %), the declared symmetry, and the
/// format's line rules (`layout`).
pub fn photometry(bytes: &[u8]) -> Result<(), String> {
    let Ok(p) = read_photometry(bytes) else {
        return Ok(());
    };
    finite_figures(&p, "as read")?;
    written_files(&p)
}

/// The writers' side of the round-trip invariant on a model, however it
/// was made (read from a file, or generated by the property test of
/// `tests/model.rs`): every file Lucerna writes from it either is refused
/// with a reason, or reads back with the same flux and peak (0.1 %), the
/// same lamp flux (what cd/klm and the LOR are per), the declared
/// symmetry, and the format's line rules.
pub fn written_files(p: &Photometry) -> Result<(), String> {
    let (flux, peak) = (p.table.flux_lm(), p.table.peak().0);
    let written: Vec<(&str, Option<Vec<u8>>)> = vec![
        (
            "IES 2002",
            write_ies(p, IesVersion::Lm63_2002)
                .ok()
                .map(String::into_bytes),
        ),
        (
            "IES 2019",
            write_ies(p, IesVersion::Lm63_2019)
                .ok()
                .map(String::into_bytes),
        ),
        ("LDT", write_ldt(p).ok().map(|t| to_latin1(&t))),
    ];
    for (format, bytes) in written {
        // A writer may refuse (and say why); what it writes must read.
        let Some(bytes) = bytes else { continue };
        let back =
            read_photometry(&bytes).map_err(|e| format!("{format} written, unreadable: {e}"))?;
        // Flux and peak straight from the table: the beam angles' walk
        // (most of a figures() call) is checked on the file as read.
        let (f_flux, f_peak) = (back.table.flux_lm(), back.table.peak().0);
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-3 * b.abs().max(a.abs()) + 1e-9;
        let kept =
            f_flux.is_finite() && f_peak.is_finite() && close(f_flux, flux) && close(f_peak, peak);
        if !kept {
            return Err(format!(
                "{format} round trip: flux {flux} -> {f_flux}, peak {peak} -> {f_peak}"
            ));
        }
        // The lamp flux keeps its meaning: LM-63's lumens per lamp × lamps
        // and EULUMDAT's set total are the same first set's flux.
        if let (Some(lamp), Some(back_lamp)) = (p.lamp_flux_lm(), back.lamp_flux_lm())
            && !close(back_lamp, lamp)
        {
            return Err(format!(
                "{format} round trip: lamp flux {lamp} -> {back_lamp}"
            ));
        }
        layout(format, &bytes)?;
        symmetry_kept(format, p, &back)?;
    }
    Ok(())
}

/// Loads, validates and tessellates a scene; a tessellated scene has
/// finite vertices.
fn scene(dir: &Path, file: &str) -> Result<(), String> {
    let path = dir.join(file);
    let Ok(scene) = lucerna_scene::load_scene(&path) else {
        return Ok(());
    };
    // What the editor saves, it opens again as the same scene.
    let saved = lucerna_scene::scene_to_toml(&scene)
        .map_err(|e| format!("a loaded scene cannot be saved: {e}"))?;
    let reopened = lucerna_scene::parse_scene(&saved, &path)
        .map_err(|e| format!("a saved scene does not open again: {e}"))?;
    if reopened != scene {
        return Err("save then open gives another scene".to_owned());
    }
    let Ok(tessellated) = lucerna_scene::tessellate(&scene, path.parent().unwrap_or(dir)) else {
        return Ok(());
    };
    if tessellated.mesh.positions.iter().all(|p| p.is_finite()) {
        Ok(())
    } else {
        Err("a tessellated vertex is not finite".to_owned())
    }
}

/// Loads and validates a room, builds its scene with a plain profile and
/// lays out its work plane and mesh.
fn room(dir: &Path, file: &str) -> Result<(), String> {
    let path = dir.join(file);
    let Ok(room) = lucerna_room::model::load_room(&path) else {
        return Ok(());
    };
    let profile = plain_profile();
    let profiles = vec![profile; room.luminaires.len()];
    let scene = lucerna_room::RoomScene::new(&room, &profiles);
    let (xs, ys) = lucerna_room::work_plane::grid_points(&scene);
    if xs.iter().chain(&ys).any(|v| !v.is_finite()) {
        return Err("a work-plane point is not finite".to_owned());
    }
    let _ = lucerna_room::scene::load_room_mesh(&room, path.parent().unwrap_or(dir));
    Ok(())
}

/// A Lambertian profile for rooms (their own profiles are not the target).
fn plain_profile() -> Photometry {
    let text = "IESNA:LM-63-2002\r\nTILT=NONE\r\n1 1000 1 3 1 1 2 0.1 0.1 0\r\n1 1 0\r\n0 45 90\r\n0\r\n318 225 0\r\n";
    read_photometry(text.as_bytes())
        .unwrap_or_else(|e| unreachable!("the plain profile reads: {e}"))
}
