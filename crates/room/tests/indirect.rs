#![allow(clippy::unwrap_used, clippy::expect_used)]
//! The uniform (integrating-sphere) indirect estimate and the profile flux
//! it rests on.

use std::path::Path;
use std::sync::Arc;

use glam::{DMat3, DVec3};
use lucerna_photometry::read_photometry;
use lucerna_room::gpu::GpuRoomRenderer;
use lucerna_room::model::parse_room;
use lucerna_room::{Opening, PlacedLight, ProfileGrid, RoomScene, Shading, render_cpu};

#[test]
fn grid_flux_matches_the_table_flux() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/profiles");
    for dir in ["examples", "samples"] {
        for entry in std::fs::read_dir(root.join(dir)).unwrap() {
            let path = entry.unwrap().path();
            if !matches!(
                path.extension().and_then(|e| e.to_str()),
                Some("ies" | "ldt")
            ) {
                continue;
            }
            let phot = read_photometry(&std::fs::read(&path).unwrap()).unwrap();
            let table = phot.table.flux_lm();
            let grid = ProfileGrid::from_table(&phot.table).flux_lm();
            assert!(
                (grid - table).abs() / table < 0.01,
                "{}: grid {grid} table {table}",
                path.display()
            );
        }
    }
}

/// A downward-only light in a 5 × 4 × 3 box: the ceiling receives no
/// direct light, so its luminance is exactly ρ/π × the sphere estimate
/// Φ ρ̄ / (A (1 − ρ̄)), computed here by hand; CPU and GPU alike.
#[test]
fn the_ceiling_shows_exactly_the_uniform_indirect_light() {
    let text = r#"
version = 1
[room]
width_m = 5.0
depth_m = 4.0
height_m = 3.0
floor = { reflectance = 0.2 }
walls = { reflectance = 0.5 }
ceiling = { reflectance = 0.8 }
indirect = "uniform"
[camera]
position = [2.5, 2.0, 1.5]
look_at = [2.5, 2.0, 3.0]
fov_deg = 40
[[luminaire]]
profile = "unused.ies"
position = [2.5, 2.0, 2.9]
"#;
    let room = parse_room(text, Path::new("box.toml")).unwrap();
    let mut scene = RoomScene::new(&room, &[]);
    let profile = Arc::new(ProfileGrid::from_fn(true, |_, g| {
        if g <= 90.0 {
            1000.0 * g.to_radians().cos()
        } else {
            0.0
        }
    }));
    let flux = profile.flux_lm();
    assert!((flux - 1000.0 * std::f64::consts::PI).abs() < 1.0, "{flux}");
    scene.lights = vec![PlacedLight {
        profile,
        opening: Opening::Rectangle {
            length_m: 0.3,
            width_m: 0.3,
        },
        position: DVec3::new(2.5, 2.0, 2.9),
        rotation: DMat3::IDENTITY,
    }];
    let areas = [20.0, 20.0, 2.0 * 15.0 + 2.0 * 12.0];
    let rho_bar = (areas[0] * 0.2 + areas[1] * 0.8 + areas[2] * 0.5) / 94.0;
    let expected = flux * rho_bar / (94.0 * (1.0 - rho_bar));
    assert!((scene.indirect_lux() - expected).abs() < 1e-9 * expected);
    // Looking straight up at the ceiling, away from the opening.
    let frame = render_cpu(&scene, 16, 16, Shading::Cubature);
    let corner = 0; // top-left pixel: ceiling, far from the light
    assert!((frame.illuminance[corner] as f64 - expected).abs() < 1e-4 * expected);
    let luminance = 0.8 / std::f64::consts::PI * expected;
    assert!((frame.luminance[corner] as f64 - luminance).abs() < 1e-4 * luminance);
    if let Some(ctx) = lucerna_gpu::open_for_tests() {
        let renderer = GpuRoomRenderer::new(ctx).unwrap();
        let (gpu, _) = renderer
            .render(
                &scene,
                &renderer.upload(&scene).unwrap(),
                16,
                16,
                Shading::Cubature,
            )
            .unwrap();
        assert!((gpu.luminance[corner] as f64 - luminance).abs() < 1e-4 * luminance);
    }
    // Direct only: the same pixel is black.
    scene.indirect = lucerna_room::model::Indirect::None;
    let frame = render_cpu(&scene, 16, 16, Shading::Cubature);
    assert_eq!(frame.luminance[corner], 0.0);
}
