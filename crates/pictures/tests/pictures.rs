#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! Pictures decode, have the documented size, and carry what they claim.

use exr::prelude::*;
use lucerna_photometry::{CandelaTable, CubeMapLayout, IntensityMap};

fn map() -> IntensityMap {
    let layout = CubeMapLayout::new(8);
    let mut m = IntensityMap::new(layout, 1000.0);
    for (t, c) in m.counts.iter_mut().enumerate() {
        *c = (t as u64 * 7) % 13;
    }
    m.photons_emitted = m.photons_escaped() + 5;
    m.photons_absorbed = 5;
    m
}

#[test]
fn the_exr_of_a_map_is_the_same_bytes_every_time() {
    // Its custom attributes come out of a HashMap: each in another order,
    // unless the header is put in order.
    let m = map();
    let extra = [
        ("lucernaSeed", "42".to_owned()),
        ("lucernaScene", "spot".to_owned()),
        ("lucernaDate", "2026-01-31".to_owned()),
    ];
    let first = lucerna_pictures::intensity_map_exr(&m, &extra).unwrap();
    for _ in 0..8 {
        assert!(lucerna_pictures::intensity_map_exr(&m, &extra).unwrap() == first);
    }
}

#[test]
fn the_exr_holds_candela_counts_and_bookkeeping() {
    let m = map();
    let bytes =
        lucerna_pictures::intensity_map_exr(&m, &[("lucernaSeed", "42".to_owned())]).unwrap();
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .first_valid_layer()
        .all_attributes()
        .from_buffered(std::io::Cursor::new(bytes))
        .unwrap();
    let layer = &image.layer_data;
    assert_eq!(
        (layer.size.0, layer.size.1),
        (8, 48),
        "faces stacked vertically"
    );
    let attr = |k: &str| match layer.attributes.other.get(&Text::from(k)) {
        Some(AttributeValue::Text(t)) => t.to_string(),
        other => panic!("{k}: {other:?}"),
    };
    assert_eq!(attr("lucernaPhotonsEmitted"), m.photons_emitted.to_string());
    assert_eq!(attr("lucernaSeed"), "42");
    let channel = |name: &str| {
        layer
            .channel_data
            .list
            .iter()
            .find(|c| c.name.to_string() == name)
            .unwrap()
    };
    let counts: Vec<u32> = match &channel("count").sample_data {
        FlatSamples::U32(v) => v.clone(),
        other => panic!("{other:?}"),
    };
    assert_eq!(
        counts,
        m.counts.iter().map(|&c| c as u32).collect::<Vec<_>>()
    );
    let candela = match &channel("candela").sample_data {
        FlatSamples::F32(v) => v.clone(),
        other => panic!("{other:?}"),
    };
    for (a, b) in candela.iter().zip(m.candela()) {
        assert!((f64::from(*a) - b).abs() <= 1e-6 * b.max(1.0));
    }
}

#[test]
fn the_pngs_decode_at_their_documented_sizes() {
    let m = map();
    let png = lucerna_pictures::cube_map_png(m.layout, &m.candela(), 40, "test").unwrap();
    let img = image::load_from_memory(&png).unwrap();
    assert_eq!(
        (img.width(), img.height()),
        (4 * 40 + 48 + 150, 3 * 40 + 48 + 24)
    );
    let table = CandelaTable::from_fn(15.0, 5.0, |c, g| {
        if g < 90.0 {
            100.0 * g.to_radians().cos() * (1.0 + 0.5 * (2.0 * c.to_radians()).cos())
        } else {
            0.0
        }
    });
    let png = lucerna_pictures::polar_png(&table, 10.0, 300, "polar").unwrap();
    let img = image::load_from_memory(&png).unwrap().to_rgb8();
    assert_eq!((img.width(), img.height()), (300, 340));
    // The C0-C180 curve (red) is drawn: the cosine's tip below the centre.
    let red = img
        .pixels()
        .filter(|p| p.0[0] > 150 && p.0[1] < 90 && p.0[2] < 90)
        .count();
    assert!(red > 100, "{red} red pixels");
}
