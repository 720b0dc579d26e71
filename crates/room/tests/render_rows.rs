#![allow(clippy::unwrap_used)] // reason: tests may panic
//! A view rendered in bands of rows is the whole view: the editor's preview
//! renders its fine picture band by band so it can give up for a newer one.

mod common;

use lucerna_room::render::render_cpu_rows;
use lucerna_room::{RoomScene, Shading, render_cpu};

#[test]
fn bands_of_rows_put_together_are_the_whole_frame() {
    let (room, phot) = common::example_room("office.toml");
    let scene = RoomScene::new(&room, &phot);
    let (w, h) = (40, 25);
    let whole = render_cpu(&scene, w, h, Shading::Cubature);
    let mut luminance = Vec::new();
    let mut illuminance = Vec::new();
    for rows in [0..7, 7..8, 8..20, 20..25, 25..30] {
        let band = render_cpu_rows(&scene, w, h, rows.clone(), Shading::Cubature);
        let expected = rows.end.min(h).saturating_sub(rows.start.min(h));
        assert_eq!((band.width, band.height), (w, expected));
        luminance.extend(band.luminance);
        illuminance.extend(band.illuminance);
    }
    assert_eq!(luminance, whole.luminance);
    assert_eq!(illuminance, whole.illuminance);
}
