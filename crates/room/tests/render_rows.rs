#![allow(clippy::unwrap_used)] // reason: tests may panic
//! A view rendered in bands of rows is the whole view: the editor's preview
//! renders its fine picture band by band so it can give up for a newer one.

use std::path::Path;

use lucerna_photometry::read_photometry;
use lucerna_room::model::load_room;
use lucerna_room::render::render_cpu_rows;
use lucerna_room::{RoomScene, Shading, render_cpu};

#[test]
fn bands_of_rows_put_together_are_the_whole_frame() {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/rooms");
    let room = load_room(&dir.join("office.toml")).unwrap();
    let phot: Vec<_> = room
        .luminaires
        .iter()
        .map(|l| {
            let (_, p) = l.source_path(&dir).unwrap();
            read_photometry(&std::fs::read(p).unwrap()).unwrap()
        })
        .collect();
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
