//! A scene's stated luminous opening reaches the IES file (width, length,
//! height; negative for round), the EULUMDAT file (luminous area) and the
//! preview room's polygonal light.

use std::path::Path;
use std::sync::Arc;

use lucerna_photometry::{
    Dimensions, IesVersion, read_photometry, to_latin1, write_ies, write_ldt,
};
use lucerna_room::light::Opening;
use lucerna_room::scene::opening_from_dimensions;
use lucerna_scene::{LuminousOpening, load_scene};
use lucerna_simulation::{
    BackendRequest, ExportOptions, Luminaire, SimulationSettings, StoppingRule, bake, photometry,
};

fn baked_with(name: &str, opening: Option<LuminousOpening>) -> (Dimensions, Dimensions) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets/luminaires")
        .join(name);
    let mut scene = load_scene(&path).expect("loads");
    scene.opening = opening;
    assert!(lucerna_scene::validate(&scene).is_empty());
    let luminaire =
        Arc::new(Luminaire::new(scene, path.parent().expect("a folder")).expect("prepares"));
    let settings = SimulationSettings {
        resolution: 32,
        backend: BackendRequest::Cpu,
        stop: StoppingRule {
            photons: Some(20_000),
            ..Default::default()
        },
        ..Default::default()
    };
    let snapshot = bake(luminaire, settings).expect("bakes");
    let p = photometry(
        &snapshot,
        &ExportOptions {
            symmetrise: None,
            date: String::new(),
            seed: 1,
            scene_file: name.to_owned(),
            labels: None,
        },
    );
    let ies = read_photometry(
        write_ies(&p, IesVersion::Lm63_2019)
            .expect("writes")
            .as_bytes(),
    )
    .expect("IES");
    let ldt = read_photometry(&to_latin1(&write_ldt(&p).expect("writes"))).expect("LDT");
    (ies.meta.luminous_area, ldt.meta.luminous_area)
}

#[test]
fn a_stated_rectangle_reaches_both_files_and_the_room() {
    let stated = LuminousOpening::Rectangle {
        length_m: 0.05,
        width_m: 0.6,
        height_m: 0.01,
    };
    let (ies, ldt) = baked_with("linear_louvre.toml", Some(stated));
    let expected = Dimensions {
        length_m: 0.05,
        width_m: 0.6,
        height_m: 0.01,
        circular: false,
    };
    assert_eq!(ies, expected);
    assert_eq!(ldt, expected);
    assert_eq!(
        opening_from_dimensions(ldt),
        Opening::Rectangle {
            length_m: 0.05,
            width_m: 0.6
        }
    );
}

#[test]
fn a_reflector_s_exit_aperture_is_a_disk_of_its_rim() {
    // The spot's paraboloid has a 100 mm rim.
    let (ies, ldt) = baked_with(
        "parabolic_spot.toml",
        Some(LuminousOpening::PartAperture {
            part: "reflector".to_owned(),
        }),
    );
    for d in [ies, ldt] {
        assert!(d.circular, "{d:?}");
        assert!((d.length_m - 0.1).abs() < 1e-3, "{d:?}");
    }
    assert!(
        matches!(opening_from_dimensions(ies), Opening::Disk { diameter_m } if (diameter_m - 0.1).abs() < 1e-3)
    );
}

#[test]
fn no_opening_declares_a_point_source() {
    let (ies, ldt) = baked_with("opal_bell.toml", Some(LuminousOpening::None));
    assert_eq!(ies, Dimensions::default());
    assert_eq!(ldt.length_m, 0.0);
    assert_eq!(opening_from_dimensions(ies), Opening::Point);
}

#[test]
fn a_mesh_reflectors_round_rim_is_a_disk_and_a_square_plate_is_not() {
    // The OBJ cone with its baffle ring: 110 mm across and round, though
    // it is a mesh and not a generated surface of revolution (it was
    // declared a 110 × 110 mm rectangle).
    let (ies, _) = baked_with(
        "obj_cone.toml",
        Some(LuminousOpening::PartAperture {
            part: "reflector".to_owned(),
        }),
    );
    assert!(ies.circular, "{ies:?}");
    assert!((ies.length_m - 0.11).abs() < 1e-4, "{ies:?}");
    // A square plate beside it: its corners reach √2 of its inscribed
    // circle.
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires/obj_cone.toml");
    let mut scene = load_scene(&path).expect("loads");
    let mut plate = scene.parts[0].clone();
    plate.name = "plate".to_owned();
    plate.transform = Default::default();
    plate.shape = lucerna_scene::Shape::Plate(lucerna_scene::shapes::Plate {
        width: 0.05,
        depth: 0.05,
    });
    plate.transform.translate = [0.0, 0.0, -0.05];
    scene.parts.push(plate);
    scene.opening = Some(LuminousOpening::PartAperture {
        part: "plate".to_owned(),
    });
    let luminaire = Luminaire::new(scene, path.parent().expect("a folder")).expect("prepares");
    let d = luminaire.luminous_opening;
    assert!(!d.circular, "{d:?}");
    assert!(
        (d.length_m - 0.05).abs() < 1e-6 && (d.width_m - 0.05).abs() < 1e-6,
        "{d:?}"
    );
}
