#![allow(clippy::unwrap_used, clippy::expect_used)]
//! A linear luminaire lights the room the same from its IES and its
//! EULUMDAT file: the near-field cubature depends on the opening, so an
//! opening turned by 90° (EULUMDAT's length lies along C90-C270) shows.

mod common;

use lucerna_photometry::{read_photometry, to_latin1, write_ldt};
use lucerna_room::{RoomScene, Shading, render_cpu};

#[test]
fn the_corridor_renders_the_same_from_the_ies_and_the_ldt() {
    let (room, from_ies) = common::example_room("corridor.toml");
    let from_ldt: Vec<_> = from_ies
        .iter()
        .map(|p| read_photometry(&to_latin1(&write_ldt(p).expect("writes"))).unwrap())
        .collect();
    // The louvre's opening is long along C90-C270 (y) either way.
    for p in &from_ldt {
        let a = p.meta.luminous_area;
        if !a.circular && a.width_m > 0.5 {
            assert!(a.width_m > 10.0 * a.length_m, "{a:?}");
        }
    }
    let (w, h) = (64, 40);
    let a = render_cpu(&RoomScene::new(&room, &from_ies), w, h, Shading::Cubature);
    let b = render_cpu(&RoomScene::new(&room, &from_ldt), w, h, Shading::Cubature);
    let mut worst: f32 = 0.0;
    for (x, y) in a.luminance.iter().zip(&b.luminance) {
        worst = worst.max((x - y).abs() / x.abs().max(1e-3));
    }
    assert!(
        worst <= 0.005,
        "worst pixel differs by {:.3} %",
        100.0 * worst
    );
}
