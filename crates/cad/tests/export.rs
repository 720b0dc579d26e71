#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! `export-geometry`'s files read back: STEP through truck's reader (its
//! surfaces on the model, its extent and areas those of the traced
//! luminaire), STL and OBJ as the traced triangles.

use std::f64::consts::TAU;
use std::path::{Path, PathBuf};

use glam::DVec3;
use lucerna_cad::{
    ExportGeometryError, FinishExport, GeometryFormat, GeometryRequest, bodies, geometry_files,
    write_geometry,
};
use lucerna_scene::{Scene, load_scene, parse_scene};
use truck_modeling::{
    BoundedCurve, InnerSpace, ParametricCurve, ParametricSurface, Point3, Vector3,
};
use truck_stepio::r#in::alias::{Curve3D, Surface, SweptCurve};
use truck_stepio::r#in::{Table, ruststep};
use truck_topology::compress::CompressedShell;

type ReadShell = CompressedShell<Point3, Curve3D, Surface>;

fn luminaires_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires")
}

fn luminaires() -> Vec<PathBuf> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(luminaires_dir())
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    files
}

fn only(format: GeometryFormat) -> GeometryRequest {
    GeometryRequest {
        formats: vec![format],
        parts: None,
        ..Default::default()
    }
}

/// The STEP text of `scene`, read back by truck's reader: one shell per
/// body, in the file's order (which is the bodies' order).
fn read_step(text: &str) -> Vec<ReadShell> {
    let exchange = ruststep::parser::parse(text).expect("the STEP file parses");
    let table = Table::from_data_section(&exchange.data[0]);
    let mut ids: Vec<u64> = table.shell.keys().copied().collect();
    ids.sort();
    ids.iter()
        .map(|id| {
            table
                .to_compressed_shell(&table.shell[id])
                .expect("the shell converts")
        })
        .collect()
}

fn step_of(scene: &Scene, dir: &Path) -> String {
    let files = geometry_files(scene, dir, "x", &only(GeometryFormat::Step)).unwrap();
    String::from_utf8(files[0].1.clone()).unwrap()
}

fn v(p: Point3) -> DVec3 {
    DVec3::new(p.x, p.y, p.z)
}

/// Points along an edge's curve, in the order it is used.
fn edge_points(shell: &ReadShell, edge: usize, samples: usize) -> Vec<DVec3> {
    let curve = &shell.edges[edge].curve;
    let (t0, t1) = curve.range_tuple();
    (0..=samples)
        .map(|i| v(curve.subs(t0 + (t1 - t0) * i as f64 / samples as f64)))
        .collect()
}

/// Points spread over a surface's parameter range (bounded surfaces; a
/// surface of revolution over its curve's range and a full turn).
fn surface_points(surface: &Surface, n: usize) -> Vec<DVec3> {
    let (ur, vr) = surface.try_range_tuple();
    let (u0, u1) = ur.unwrap_or((0.0, 1.0));
    let (v0, v1) = vr.unwrap_or((0.0, TAU));
    let mut points = Vec::with_capacity((n + 1) * (n + 1));
    for i in 0..=n {
        for j in 0..=n {
            let (u, w) = (
                u0 + (u1 - u0) * i as f64 / n as f64,
                v0 + (v1 - v0) * j as f64 / n as f64,
            );
            points.push(v(surface.subs(u, w)));
        }
    }
    points
}

fn is_plane(surface: &Surface) -> bool {
    matches!(surface, Surface::ElementarySurface(s) if matches!(**s, truck_stepio::r#in::alias::ElementarySurface::Plane(_)))
}

/// The extent of a shell: its edges, and the surfaces that are not planes
/// (planar faces lie within their edges).
fn step_bounds(shells: &[ReadShell]) -> (DVec3, DVec3) {
    let (mut lo, mut hi) = (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY));
    for shell in shells {
        let mut points: Vec<DVec3> = (0..shell.edges.len())
            .flat_map(|e| edge_points(shell, e, 200))
            .collect();
        for face in shell.faces.iter().filter(|f| !is_plane(&f.surface)) {
            points.extend(surface_points(&face.surface, 200));
        }
        for p in points {
            lo = lo.min(p);
            hi = hi.max(p);
        }
    }
    (lo, hi)
}

/// A face's area: planes from their boundary polygon (Newell), surfaces
/// of revolution by quadrature over the turn their boundary spans, other
/// surfaces over their whole parameter range.
fn face_area(shell: &ReadShell, face: usize) -> f64 {
    let face = &shell.faces[face];
    if is_plane(&face.surface) {
        let mut total = DVec3::ZERO;
        for boundary in &face.boundaries {
            let mut ring: Vec<DVec3> = Vec::new();
            for e in boundary {
                let mut points = edge_points(shell, e.index, 400);
                if !e.orientation {
                    points.reverse();
                }
                ring.extend(points);
            }
            for i in 0..ring.len() {
                total += ring[i].cross(ring[(i + 1) % ring.len()]);
            }
        }
        return 0.5 * total.length();
    }
    let surface = &face.surface;
    let span = match surface {
        Surface::SweptCurve(s) if matches!(**s, SweptCurve::RevolutedCurve(_)) => {
            // The turn the face covers: 2π less the widest gap between its
            // boundary's angles about z (our surfaces revolve about z).
            let mut angles: Vec<f64> = face
                .boundaries
                .iter()
                .flatten()
                .flat_map(|e| edge_points(shell, e.index, 64))
                .filter(|p| p.x.hypot(p.y) > 1e-6)
                .map(|p| p.y.atan2(p.x).rem_euclid(TAU))
                .collect();
            angles.sort_by(f64::total_cmp);
            let mut widest = TAU - (angles[angles.len() - 1] - angles[0]);
            for w in angles.windows(2) {
                widest = widest.max(w[1] - w[0]);
            }
            (TAU - widest) / TAU
        }
        _ => 1.0,
    };
    let (ur, vr) = surface.try_range_tuple();
    let (u0, u1) = ur.unwrap_or((0.0, 1.0));
    let (v0, v1) = vr.unwrap_or((0.0, TAU));
    let n = 400;
    let (du, dv) = ((u1 - u0) / n as f64, (v1 - v0) / n as f64);
    let mut area = 0.0;
    for i in 0..n {
        for j in 0..n {
            let (u, w) = (u0 + (i as f64 + 0.5) * du, v0 + (j as f64 + 0.5) * dv);
            let n: Vector3 = surface.uder(u, w).cross(surface.vder(u, w));
            area += n.magnitude() * du * dv;
        }
    }
    area * span
}

#[test]
fn every_example_scene_exports_and_its_step_reads_back() {
    let keep = std::env::var_os("LUCERNA_KEEP_GEOMETRY").map(PathBuf::from);
    for path in luminaires() {
        let scene = load_scene(&path).unwrap();
        let dir = path.parent().unwrap();
        let stem = path.file_stem().unwrap().to_str().unwrap();
        let files = geometry_files(&scene, dir, stem, &GeometryRequest::default())
            .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
        let names: Vec<&str> = files.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(
            names,
            [
                format!("{stem}.step"),
                format!("{stem}.stl"),
                format!("{stem}.obj")
            ]
        );
        let bodies = bodies(&scene, dir, None, Default::default()).unwrap();
        let shells = read_step(std::str::from_utf8(&files[0].1).unwrap());
        assert_eq!(
            shells.len(),
            bodies.len(),
            "{}: one shell per body",
            path.display()
        );
        if let Some(keep) = &keep {
            write_geometry(&scene, dir, keep, stem, &GeometryRequest::default()).unwrap();
        }
    }
}

#[test]
fn the_paraboloids_step_faces_lie_on_the_paraboloid() {
    let path = luminaires_dir().join("parabolic_spot.toml");
    let scene = load_scene(&path).unwrap();
    let shells = read_step(&step_of(&scene, path.parent().unwrap()));
    let reflector = &shells[0];
    let f_mm = 25.0;
    let mut worst = 0.0f64;
    let mut sampled = 0;
    for face in &reflector.faces {
        assert!(
            matches!(&face.surface, Surface::SweptCurve(s) if matches!(**s, SweptCurve::RevolutedCurve(_))),
            "the paraboloid is a surface of revolution, not {:?}",
            face.surface
        );
        // 2 000 points or more over the three faces.
        for p in surface_points(&face.surface, 26) {
            let r2 = p.x * p.x + p.y * p.y;
            worst = worst.max((p.z - (f_mm - r2 / (4.0 * f_mm))).abs());
            sampled += 1;
        }
    }
    assert!(sampled >= 2000, "{sampled}");
    // Exact surfaces: rounding only. The scene's own 48 × 192 facets are
    // 0.0093 mm off, so triangles fail here.
    assert!(worst < 1e-3, "worst deviation {worst} mm");
    eprintln!("paraboloid: {sampled} points, worst deviation {worst:e} mm");
}

#[test]
fn step_extent_and_areas_match_the_traced_luminaire() {
    for path in luminaires() {
        let scene = load_scene(&path).unwrap();
        let dir = path.parent().unwrap();
        let bodies = bodies(&scene, dir, None, Default::default()).unwrap();
        let shells = read_step(&step_of(&scene, dir));
        // The extent against the traced triangles' (what `lucerna
        // validate --json` reports as the luminaire's bounds).
        let (lo, hi) = step_bounds(&shells);
        let traced = lucerna_scene::tessellate(&scene, dir).unwrap();
        let (tlo, thi) = traced.mesh.bounds().unwrap();
        let (tlo, thi) = (tlo.as_dvec3() * 1000.0, thi.as_dvec3() * 1000.0);
        let off = (lo - tlo).abs().max((hi - thi).abs()).max_element();
        assert!(
            off < 0.5,
            "{}: bounds {lo}..{hi} vs traced {tlo}..{thi}",
            path.display()
        );
        for (body, shell) in bodies.iter().zip(&shells) {
            let area: f64 = (0..shell.faces.len()).map(|f| face_area(shell, f)).sum();
            let traced_area = body.traced.area() * 1e6;
            let rel = (area - traced_area).abs() / traced_area;
            eprintln!(
                "{} {}: STEP {area:.3} mm², traced {traced_area:.3} mm² ({rel:.2e}); bounds off {off:.2e} mm",
                path.file_name().unwrap().display(),
                body.name
            );
            if body.exact.is_some() {
                assert!(
                    rel < 0.02,
                    "{} '{}': {area} vs {traced_area} mm²",
                    path.display(),
                    body.name
                );
            } else {
                // Planar triangles: the same facets.
                assert!(
                    rel < 1e-6,
                    "{} '{}': {area} vs {traced_area} mm²",
                    path.display(),
                    body.name
                );
            }
        }
    }
}

#[test]
fn the_stl_holds_the_traced_triangles_in_millimetres() {
    let path = luminaires_dir().join("faceted_downlight.toml");
    let scene = load_scene(&path).unwrap();
    let dir = path.parent().unwrap();
    let files = geometry_files(&scene, dir, "x", &only(GeometryFormat::Stl)).unwrap();
    let stl = stl_io::read_stl(&mut std::io::Cursor::new(&files[0].1)).unwrap();
    let traced = lucerna_scene::tessellate(&scene, dir).unwrap().mesh;
    assert_eq!(stl.faces.len(), traced.triangle_count());
    for (t, face) in stl.faces.iter().enumerate() {
        let corners = traced.corners(t);
        for k in 0..3 {
            let got = DVec3::from_array(stl.vertices[face.vertices[k]].0.map(f64::from));
            let want = corners[k] * 1000.0;
            assert!(
                got.distance(want) <= 1e-6 * want.length().max(1.0),
                "{t}: {got} vs {want}"
            );
        }
    }
}

#[test]
fn only_the_chosen_parts_are_exported_and_emitters_say_so() {
    let path = luminaires_dir().join("parabolic_spot.toml");
    let scene = load_scene(&path).unwrap();
    let dir = path.parent().unwrap();
    let all = geometry_files(&scene, dir, "x", &only(GeometryFormat::Obj)).unwrap();
    let all = String::from_utf8(all[0].1.clone()).unwrap();
    assert!(all.contains("\no reflector\n") && all.contains("\no LED (emitter)\n"));
    let step = step_of(&scene, dir);
    assert!(step.contains("PRODUCT('reflector','reflector'"));
    assert!(step.contains("PRODUCT('LED (emitter)','LED (emitter)'"));
    assert!(step.contains("PRODUCT('Parabolic spot f25','Parabolic spot f25'"));
    let request = GeometryRequest {
        formats: vec![GeometryFormat::Obj, GeometryFormat::Step],
        parts: Some(vec!["reflector".to_owned()]),
        ..Default::default()
    };
    let files = geometry_files(&scene, dir, "x", &request).unwrap();
    let obj = String::from_utf8(files[0].1.clone()).unwrap();
    assert!(obj.contains("\no reflector\n") && !obj.contains("emitter"));
    assert_eq!(
        read_step(std::str::from_utf8(&files[1].1).unwrap()).len(),
        1
    );
}

#[test]
fn bad_requests_are_refused_and_write_nothing() {
    let path = luminaires_dir().join("parabolic_spot.toml");
    let scene = load_scene(&path).unwrap();
    let dir = path.parent().unwrap();
    let out = tempfile::tempdir().unwrap();
    let target = out.path().join("new");
    let unknown = GeometryRequest {
        formats: GeometryFormat::ALL.to_vec(),
        parts: Some(vec!["reflecter".to_owned()]),
        ..Default::default()
    };
    let e = write_geometry(&scene, dir, &target, "x", &unknown).unwrap_err();
    assert!(matches!(e, ExportGeometryError::UnknownPart { .. }), "{e}");
    assert!(
        e.to_string().contains("reflecter") && e.to_string().contains("reflector, LED"),
        "{e}"
    );
    let none = GeometryRequest {
        formats: vec![],
        parts: None,
        ..Default::default()
    };
    assert!(matches!(
        write_geometry(&scene, dir, &target, "x", &none).unwrap_err(),
        ExportGeometryError::NoFormat
    ));
    assert!(
        "iges"
            .parse::<GeometryFormat>()
            .unwrap_err()
            .to_string()
            .contains("step, stl or obj")
    );
    // A disabled part is not part of the luminaire.
    let mut disabled = scene.clone();
    disabled.parts[0].enabled = false;
    let only_reflector = GeometryRequest {
        formats: GeometryFormat::ALL.to_vec(),
        parts: Some(vec!["reflector".to_owned()]),
        ..Default::default()
    };
    assert!(matches!(
        write_geometry(&disabled, dir, &target, "x", &only_reflector).unwrap_err(),
        ExportGeometryError::DisabledPart { .. }
    ));
    // A scene whose OBJ mesh is missing does not tessellate.
    let broken = parse_scene(
        &std::fs::read_to_string(dir.join("obj_cone.toml"))
            .unwrap()
            .replace("cone_reflector.obj", "missing.obj"),
        &dir.join("obj_cone.toml"),
    )
    .unwrap();
    assert!(matches!(
        write_geometry(&broken, dir, &target, "x", &GeometryRequest::default()).unwrap_err(),
        ExportGeometryError::Tessellate(_)
    ));
    assert!(!target.exists(), "nothing was written");
    // An output folder that cannot be written: a file in its place.
    let blocked = out.path().join("file");
    std::fs::write(&blocked, b"keep").unwrap();
    let e = write_geometry(
        &scene,
        dir,
        &blocked.join("sub"),
        "x",
        &GeometryRequest::default(),
    )
    .unwrap_err();
    assert!(matches!(e, ExportGeometryError::Write { .. }), "{e}");
    assert_eq!(std::fs::read(&blocked).unwrap(), b"keep");
    // Written all or none: a folder where one of the files would go.
    let partial = out.path().join("partial");
    std::fs::create_dir_all(partial.join("x.obj")).unwrap();
    let e = write_geometry(&scene, dir, &partial, "x", &GeometryRequest::default()).unwrap_err();
    assert!(matches!(e, ExportGeometryError::Write { .. }), "{e}");
    let left: Vec<_> = std::fs::read_dir(&partial)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(left, ["x.obj"], "no STEP or STL left beside the failure");
}

/// Escaped photon counts per texel of `scene` traced with `seed`.
fn traced_counts(scene: Scene, dir: &Path, seed: u32, photons: u64) -> Vec<u64> {
    use lucerna_tracer::Session;
    use lucerna_tracer::cpu::TraceSettings;
    let luminaire = lucerna_simulation::Luminaire::new(scene, dir).unwrap();
    let settings = TraceSettings {
        seed,
        max_bounces: 64,
        layout: lucerna_photometry::CubeMapLayout::new(64),
    };
    let mut session = Session::start(luminaire.prepared.clone(), settings);
    while session.map().photons_emitted < photons {
        session
            .iterate_at_most(photons - session.map().photons_emitted)
            .unwrap();
    }
    session.snapshot().counts
}

#[test]
fn the_exported_obj_reimported_bakes_the_same_distribution() {
    let path = luminaires_dir().join("parabolic_spot.toml");
    let scene = load_scene(&path).unwrap();
    let dir = path.parent().unwrap();
    let out = tempfile::tempdir().unwrap();
    let request = GeometryRequest {
        formats: vec![GeometryFormat::Obj],
        parts: Some(vec!["reflector".to_owned()]),
        ..Default::default()
    };
    write_geometry(&scene, dir, out.path(), "spot", &request).unwrap();
    // The reflector replaced by the OBJ, read in millimetres.
    let mut reimported = scene.clone();
    reimported.parts[0].shape = lucerna_scene::Shape::Mesh(lucerna_scene::shapes::Mesh {
        path: "spot.obj".to_owned(),
        group_materials: [("reflector".to_owned(), "polished_alu".to_owned())].into(),
    });
    reimported.parts[0].transform.scale = [0.001; 3];
    let photons = 400_000;
    let original = traced_counts(scene, dir, 7, photons);
    let again = traced_counts(reimported, out.path(), 8, photons);
    // Two independent Poisson samples of one distribution: Σ (a−b)²/(a+b)
    // is about the number of texels hit.
    let (mut chi2, mut dof) = (0.0, 0usize);
    for (a, b) in original.iter().zip(&again) {
        if a + b > 0 {
            chi2 += (*a as f64 - *b as f64).powi(2) / (a + b) as f64;
            dof += 1;
        }
    }
    let per_dof = chi2 / dof as f64;
    eprintln!("OBJ re-import: chi²/dof = {per_dof:.3} over {dof} texels");
    assert!(per_dof < 1.5, "chi²/dof {per_dof} over {dof} texels");
}

#[test]
fn a_finish_is_named_on_the_smooth_surface_or_cut_into_it_when_asked() {
    let text = r#"
format_version = 1
name = "hammered"
[materials.alu]
type = "mirror"
reflectance = 0.9
[[emitter]]
name = "LED"
flux_lm = 1000.0
shape = { type = "disk", radius = 0.001 }
[[part]]
name = "reflector"
material = "alu"
shape = { type = "paraboloid", focal_length = 0.01, aperture_diameter = 0.03, neck_diameter = 0.006, segments_around = 48, segments_along = 12 }
finish = { type = "dimples", pitch = 0.002, depth = 0.00015, radius = 0.0034 }
"#;
    let scene = parse_scene(text, Path::new("h.toml")).unwrap();
    let dir = Path::new(".");
    let reflector = Some(vec!["reflector".to_owned()]);
    let named = bodies(&scene, dir, reflector.as_deref(), FinishExport::Named).unwrap();
    let cut = bodies(
        &scene,
        dir,
        reflector.as_deref(),
        FinishExport::Geometry { edge: None },
    )
    .unwrap();
    // Named: the smooth paraboloid, exact, its description the finish.
    assert!(named[0].exact.is_some());
    assert!(
        named[0].description.starts_with("finish: hammered"),
        "{}",
        named[0].description
    );
    // Cut: triangles of at most pitch/16 carrying dimples 0.15 mm deep.
    assert!(cut[0].exact.is_none());
    assert!(
        cut[0]
            .description
            .starts_with("finish cut into the surface")
    );
    assert!(cut[0].traced.triangle_count() > 100 * named[0].traced.triangle_count());
    let f: f64 = 0.01;
    let (mut deepest, mut land) = (0.0f64, 0usize);
    for p in &cut[0].traced.positions {
        let p = p.as_dvec3();
        let r = p.x.hypot(p.y);
        // Distance from the paraboloid along its normal (a dimple is
        // a hollow into the mirror side, towards the focus... either sign).
        let z = f - r * r / (4.0 * f);
        let slope = r / (2.0 * f);
        let depth = (p.z - z).abs() / (1.0 + slope * slope).sqrt();
        deepest = deepest.max(depth);
        if depth < 1e-7 {
            land += 1;
        }
    }
    assert!((deepest - 0.15e-3).abs() < 0.01e-3, "{deepest}");
    assert!(land > 0, "some land stays on the surface");
    // The STEP names it; a bad edge is refused by the tessellation.
    let request = GeometryRequest {
        formats: vec![GeometryFormat::Step],
        parts: reflector.clone(),
        finish: FinishExport::Named,
    };
    let files = geometry_files(&scene, dir, "h", &request).unwrap();
    let step = String::from_utf8(files[0].1.clone()).unwrap();
    assert!(step.contains("finish: hammered: spherical dimples 0.150 mm deep"));
    let too_fine = bodies(
        &scene,
        dir,
        reflector.as_deref(),
        FinishExport::Geometry { edge: Some(1e-6) },
    );
    assert!(
        matches!(too_fine, Err(ExportGeometryError::Tessellate(_))),
        "{too_fine:?}"
    );
}
