//! What the room tests share: an example room file with its luminaires'
//! photometric files read.

#![allow(dead_code)] // reason: each test file uses a part of it

use std::path::{Path, PathBuf};

use lucerna_photometry::{Photometry, read_photometry};
use lucerna_room::model::{RoomFile, load_room};

/// `assets/rooms`.
pub fn rooms_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/rooms")
}

/// The photometry of each luminaire of `room`, its files found from `base`.
pub fn photometry_of(room: &RoomFile, base: &Path) -> Vec<Photometry> {
    room.luminaires
        .iter()
        .map(|l| {
            let (_, path) = l.source_path(base).expect("a source");
            read_photometry(&std::fs::read(path).expect("readable")).expect("photometry")
        })
        .collect()
}

/// An example room of `assets/rooms` and its luminaires' photometry.
pub fn example_room(name: &str) -> (RoomFile, Vec<Photometry>) {
    let dir = rooms_dir();
    let room = load_room(&dir.join(name)).expect("the example loads");
    let photometry = photometry_of(&room, &dir);
    (room, photometry)
}
