#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: tests may panic
//! `ExportRequest`: a snapshot exported on another grid or filter gives
//! the files a bake with those settings writes, byte for byte; the
//! scene's keywords reach both formats; files are written all or none.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use lucerna_photometry::{IesVersion, read_photometry};
use lucerna_scene::load_scene;
use lucerna_simulation::{
    BackendRequest, ExportFormats, ExportOptions, ExportRequest, FilterChoice, Labels, Luminaire,
    SimulationSettings, Snapshot, StoppingRule, TableGrid, bake,
};

fn scene_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires/parabolic_spot.toml")
}

fn settings(filter: FilterChoice, table: TableGrid) -> SimulationSettings {
    SimulationSettings {
        resolution: 32,
        backend: BackendRequest::Cpu,
        filter,
        table,
        stop: StoppingRule {
            photons: Some(40_000),
            ..StoppingRule::default()
        },
        ..SimulationSettings::default()
    }
}

fn baked(settings: SimulationSettings) -> Snapshot {
    let luminaire = Arc::new(Luminaire::load(&scene_path()).expect("loads"));
    bake(luminaire, settings).expect("bakes")
}

fn options() -> ExportOptions {
    ExportOptions {
        symmetrise: None,
        date: "2026-01-02".to_owned(),
        seed: 1,
        scene_file: "parabolic_spot.toml".to_owned(),
        labels: None,
    }
}

#[test]
fn an_export_on_another_grid_and_filter_is_the_bake_with_those_settings() {
    let coarse = TableGrid {
        c_step_deg: 15.0,
        gamma_step_deg: Some(2.5),
    };
    let raw_run = baked(settings(FilterChoice::Raw, TableGrid::default()));
    for filter in [FilterChoice::Raw, FilterChoice::Automatic] {
        let other = baked(settings(filter, coarse));
        let dir = tempfile::tempdir().unwrap();
        let mut from_raw = ExportRequest::new(&raw_run, options(), dir.path(), "a");
        from_raw.filter = filter;
        from_raw.grid = coarse;
        let bake_request = ExportRequest::new(&other, options(), dir.path(), "b");
        let a = from_raw.render(&raw_run).unwrap();
        let b = bake_request.render(&other).unwrap();
        assert_eq!(a.files.len(), 5);
        for ((pa, ba), (pb, bb)) in a.files.iter().zip(&b.files) {
            // The EXR holds the raw map, the same in both, but the exr
            // crate writes its header attributes in hash-map order.
            if pa.extension().is_some_and(|e| e == "exr") {
                continue;
            }
            assert!(
                ba == bb,
                "{filter:?}: {} and {} differ",
                pa.display(),
                pb.display()
            );
        }
        assert_eq!(a.photometry.table.c_planes_deg.len(), 24);
    }
}

#[test]
fn keywords_of_the_scene_reach_the_ies_and_ldt_files() {
    let snapshot = baked(settings(FilterChoice::Raw, TableGrid::default()));
    let mut scene = load_scene(&scene_path()).unwrap();
    scene.manufacturer = "Acme Lighting".to_owned();
    scene.export.catalogue_number = "AC-25".to_owned();
    scene.export.luminaire = "Spot 25".to_owned();
    scene.export.test_lab = "Acme photometry lab".to_owned();
    scene.export.lamp = "LED 800 lm".to_owned();
    scene.export.lamp_catalogue_number = "LED-800".to_owned();
    scene.export.colour_temperature = "3000 K".to_owned();
    scene.export.input_watts = 9.0;
    let dir = tempfile::tempdir().unwrap();
    let mut request = ExportRequest::new(
        &snapshot,
        ExportOptions {
            labels: Some(Labels::of(&scene)),
            ..options()
        },
        dir.path(),
        "spot",
    );
    request.formats = ExportFormats {
        ies: Some(IesVersion::Lm63_2002),
        ldt: true,
        exr: false,
        cube_png: false,
        polar_png: false,
        datasheet: false,
        tm25_rays: None,
    };
    let written = request.write(&snapshot).unwrap();
    assert_eq!(written.len(), 2);
    let ies = std::fs::read_to_string(dir.path().join("spot.ies")).unwrap();
    assert!(ies.starts_with("IESNA:LM-63-2002"));
    for line in [
        "[MANUFAC] Acme Lighting",
        "[LUMCAT] AC-25",
        "[LUMINAIRE] Spot 25",
        "[TESTLAB] Acme photometry lab",
        "[LAMP] LED 800 lm",
        "[LAMPCAT] LED-800",
        "[ISSUEDATE] 2026-01-02",
    ] {
        assert!(ies.contains(line), "{line} missing:\n{ies}");
    }
    let ldt = read_photometry(&std::fs::read(dir.path().join("spot.ldt")).unwrap()).unwrap();
    assert_eq!(ldt.meta.manufacturer, "Acme Lighting");
    assert_eq!(ldt.meta.catalog_number, "AC-25");
    assert_eq!(ldt.meta.luminaire, "Spot 25");
    assert_eq!(ldt.meta.lamps[0].colour_temperature, "3000 K");
    assert_eq!(ldt.meta.lamps[0].watts, 9.0);
    let read_ies = read_photometry(ies.as_bytes()).unwrap();
    assert_eq!(read_ies.meta.input_watts, 9.0);
}

#[test]
fn files_are_written_all_or_none() {
    let snapshot = baked(settings(FilterChoice::Raw, TableGrid::default()));
    let dir = tempfile::tempdir().unwrap();
    // A folder where the LDT should go: the IES staged before it must not
    // appear either.
    std::fs::create_dir(dir.path().join("spot.ldt")).unwrap();
    std::fs::write(dir.path().join("spot.ldt/keep"), b"x").unwrap();
    let request = ExportRequest::new(&snapshot, options(), dir.path(), "spot");
    let e = request.write(&snapshot).unwrap_err();
    assert!(e.to_string().contains("spot.ldt"), "{e}");
    let mut left: Vec<String> = std::fs::read_dir(dir.path())
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    left.sort();
    assert_eq!(
        left,
        ["spot.ldt"],
        "nothing else written, no temporary files"
    );

    // A folder under a file cannot be written at all.
    let file = dir.path().join("plain");
    std::fs::write(&file, b"x").unwrap();
    let request = ExportRequest::new(&snapshot, options(), &file.join("sub"), "spot");
    assert!(request.write(&snapshot).is_err());

    // Nonsense requests are refused before anything is drawn.
    let mut none = ExportRequest::new(&snapshot, options(), dir.path(), "spot");
    none.formats = ExportFormats {
        ies: None,
        ldt: false,
        exr: false,
        cube_png: false,
        polar_png: false,
        datasheet: false,
        tm25_rays: None,
    };
    assert!(none.render(&snapshot).is_err());
    for stem in ["", "a/b", ".."] {
        let bad = ExportRequest::new(&snapshot, options(), dir.path(), stem);
        assert!(bad.render(&snapshot).is_err(), "{stem:?}");
    }
    let mut odd_grid = ExportRequest::new(&snapshot, options(), dir.path(), "spot");
    odd_grid.grid.c_step_deg = 7.0;
    assert!(odd_grid.render(&snapshot).is_err());
}

/// The example spot at the default resolution, baked long enough that its
/// beam is smooth.
fn spot(table: TableGrid) -> Snapshot {
    baked(SimulationSettings {
        resolution: 256,
        stop: StoppingRule {
            photons: Some(3_000_000),
            ..StoppingRule::default()
        },
        ..settings(FilterChoice::Raw, table)
    })
}

#[test]
fn the_spots_files_carry_the_maps_photometry_on_the_automatic_grid() {
    use lucerna_photometry::fidelity::{BeamFigures, CONE_HALF_ANGLES_DEG};
    let snapshot = spot(TableGrid::default());
    // The map's own figures, from its texels (not from any table).
    let map = BeamFigures::of_map(snapshot.map.layout, &snapshot.candela);
    let fidelity = &snapshot.table_fidelity;
    eprintln!("{}", fidelity.summary());
    assert!(fidelity.automatic);
    assert!(fidelity.holds(), "{:?}", fidelity.shortfalls());
    let dir = tempfile::tempdir().unwrap();
    let mut request = ExportRequest::new(&snapshot, options(), dir.path(), "spot");
    request.formats = ExportFormats {
        ies: Some(IesVersion::Lm63_2019),
        ldt: true,
        exr: false,
        cube_png: false,
        polar_png: false,
        datasheet: false,
        tm25_rays: None,
    };
    let files = request.render(&snapshot).unwrap();
    assert_eq!(files.fidelity, *fidelity);
    for (path, bytes) in &files.files {
        // Read back as any reader would: linear between the printed angles.
        let read = read_photometry(bytes).unwrap();
        let table = &read.table;
        let name = path.display();
        // The listed γ angles as the automatic grid chose them, within
        // the budget real files keep to.
        assert_eq!(
            lucerna_photometry::fidelity::GammaGridShape::of(&table.gammas_deg, 0.0).angles,
            fidelity.gamma_grid.angles,
            "{name}"
        );
        assert!(table.gammas_deg.len() <= lucerna_photometry::tabulate::MAX_AUTOMATIC_GAMMAS);
        let flux = table.flux_lm();
        assert!(
            (flux / map.flux_lm - 1.0).abs() < 0.0005,
            "{name}: {flux} vs {}",
            map.flux_lm
        );
        for (g, m) in CONE_HALF_ANGLES_DEG.iter().zip(map.cone_flux_lm) {
            let f = table.flux_between_lm(0.0, *g);
            assert!((f / m - 1.0).abs() < 0.003, "{name}, {g}°: {f} vs {m}");
        }
        let peak = table.peak().0;
        assert!(
            (peak / map.peak_cd - 1.0).abs() < 0.005,
            "{name}: peak {peak} vs {}",
            map.peak_cd
        );
        let figures = read.figures();
        for (file, on_map) in [
            (figures.beam_angle_deg, map.beam_angle_deg),
            (figures.field_angle_deg, map.field_angle_deg),
        ] {
            for (a, b) in file.iter().zip(&on_map) {
                let (a, b) = (a.unwrap(), b.unwrap());
                assert!((a - b).abs() < 0.05, "{name}: {a}° vs the map's {b}°");
            }
        }
    }
}

#[test]
fn a_fixed_grid_too_coarse_for_the_spot_is_written_with_a_warning() {
    let snapshot = spot(TableGrid {
        c_step_deg: 5.0,
        gamma_step_deg: Some(5.0),
    });
    let fidelity = &snapshot.table_fidelity;
    assert!(!fidelity.automatic);
    assert_eq!(snapshot.table.uniform_gamma_step(), Some(5.0));
    let warning = snapshot
        .warnings
        .iter()
        .find(|w| w.contains("inside 2°"))
        .expect("the 2° cone is warned about");
    eprintln!("{:#?}", snapshot.warnings);
    assert!(warning.starts_with("the 5° γ grid carries "), "{warning}");
    assert!(warning.contains(" lm against "), "{warning}");
}

/// The datasheet an export writes is the one `lucerna report` draws from
/// the same photometry: the same bytes, twice over (nothing in it
/// depends on the clock), with every figure in its JSON.
#[test]
fn the_datasheet_of_an_export_is_the_reports_to_the_byte() {
    let snapshot = baked(settings(FilterChoice::Raw, TableGrid::default()));
    let dir = tempfile::tempdir().unwrap();
    let mut request = ExportRequest::new(&snapshot, options(), dir.path(), "spot");
    request.formats = ExportFormats {
        datasheet: true,
        ..ExportFormats::NONE
    };
    let first = request.render(&snapshot).unwrap();
    let again = request.render(&snapshot).unwrap();
    let names: Vec<String> = first
        .files
        .iter()
        .map(|(p, _)| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    assert_eq!(
        names,
        [
            "spot_datasheet.html",
            "spot_datasheet.pdf",
            "spot_datasheet.json"
        ]
    );
    assert_eq!(first.files, again.files, "the same export, other bytes");
    let photometry = request.photometry(&snapshot).unwrap();
    let sheet = lucerna_datasheet::Datasheet::new(&photometry, &request.datasheet).unwrap();
    let rendered = sheet.render().unwrap();
    let report = rendered.files(&sheet, dir.path(), "spot_datasheet");
    assert_eq!(
        first.files, report,
        "the editor's and the report's bytes differ"
    );
    let json: serde_json::Value = serde_json::from_slice(&first.files[2].1).unwrap();
    assert_eq!(json["ugr"]["spacing"], 0.25);
    assert_eq!(json["ugr"]["rooms"].as_array().unwrap().len(), 19);
    assert!(first.files[1].1.starts_with(b"%PDF-"));
}

#[test]
fn the_tm25_rays_far_field_is_the_ies_files() {
    // The faceted downlight: a broad beam with structure, many bounces.
    let scene = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets/luminaires/faceted_downlight.toml");
    let luminaire = Arc::new(Luminaire::load(&scene).expect("loads"));
    let mut s = settings(FilterChoice::Raw, TableGrid::default());
    s.stop.photons = Some(400_000);
    let snapshot = bake(luminaire, s).expect("bakes");
    let dir = tempfile::tempdir().unwrap();
    let mut request = ExportRequest::new(&snapshot, options(), dir.path(), "down");
    request.formats = ExportFormats {
        ies: Some(IesVersion::Lm63_2019),
        tm25_rays: Some(200_000),
        ..ExportFormats::NONE
    };
    let exported = request.render(&snapshot).unwrap();
    let (_, ray_bytes) = exported
        .files
        .iter()
        .find(|(p, _)| p.extension().is_some_and(|e| e == "tm25ray"))
        .unwrap();
    let rays = lucerna_photometry::tm25::parse_ray_file(ray_bytes, "down.tm25ray").unwrap();
    assert_eq!(rays.len(), 200_000);
    let h = &rays.header;
    assert_eq!(
        h.creation_method,
        lucerna_photometry::tm25::CreationMethod::Simulation
    );
    assert!(h.description.ray_file_creator.starts_with("Lucerna "));
    let ies = &exported.photometry.table;
    // The luminaire's flux, in the header and in the rays.
    let flux = ies.flux_lm();
    assert!((f64::from(h.luminous_flux_lm.unwrap()) - flux).abs() < 1e-3 * flux);
    assert!((rays.total_luminous_flux_lm() - flux).abs() < 1e-3 * flux);
    // The rays' far field, binned on the bake's cube map and tabulated on
    // the IES's grid: the IES's cone fluxes within the noise of 200 000
    // rays (and the IES's own of 400 000 photons).
    let layout = snapshot.map.layout;
    let far = lucerna_photometry::table_from_cube_map(
        layout,
        &rays.far_field_candela(layout),
        &ies.c_planes_deg,
        &ies.gammas_deg,
    );
    for gamma in [10.0, 20.0, 30.0, 45.0, 60.0, 90.0] {
        let (a, b) = (
            ies.flux_between_lm(0.0, gamma),
            far.flux_between_lm(0.0, gamma),
        );
        let share = a / flux;
        // Binomial noise of the rays' and of the photons' share, and
        // 0.5 % for the two tabulations (the bake's pools and resamples).
        let sigma = (share * (1.0 - share) * (1.0 / 200_000.0 + 1.0 / 400_000.0)).sqrt() * flux;
        assert!(
            (a - b).abs() < 4.0 * sigma + 0.005 * flux,
            "γ < {gamma}: IES {a} lm, rays {b} lm of {flux}"
        );
    }
    // And the beam the same, in both planes.
    let (fi, fr) = (
        lucerna_photometry::figures(ies, None),
        lucerna_photometry::figures(&far, None),
    );
    for k in 0..2 {
        let (a, b) = (fi.beam_angle_deg[k].unwrap(), fr.beam_angle_deg[k].unwrap());
        assert!((a - b).abs() < 1.0, "beam {a}° vs {b}°");
    }
    assert!((fi.peak_cd - fr.peak_cd).abs() < 0.05 * fi.peak_cd);
    // Each ray leaves from a surface of the luminaire: inside its bounds.
    let (lo, hi) = snapshot.luminaire.tessellated.mesh.bounds().unwrap();
    let (lo, hi) = (lo * 1000.0 - 0.01, hi * 1000.0 + 0.01);
    for i in 0..rays.len() {
        let p = rays.position_mm(i);
        assert!(
            (0..3).all(|k| p[k] >= lo[k] && p[k] <= hi[k]),
            "ray {i} at {p:?}"
        );
    }
}
