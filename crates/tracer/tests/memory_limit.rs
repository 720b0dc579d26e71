#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! `/dev/zero` as an emission profile is refused within a 1 GiB address
//! space: a runaway read fails there (and aborts the child process this
//! test runs in) instead of being left to the OOM killer.

#![cfg(target_os = "linux")]

use std::path::Path;

use lucerna_scene::{parse_scene, tessellate};
use lucerna_tracer::PreparedScene;

use lucerna_scene::test_support::in_address_limited_child as in_limited_child;

#[test]
fn an_endless_emission_profile_is_refused_within_1_gib() {
    if !in_limited_child("an_endless_emission_profile_is_refused_within_1_gib") {
        return;
    }
    let text = "format_version = 1\nname = \"led\"\n\n[[emitter]]\nname = \"LED\"\nflux_lm = 100.0\n\
                shape = { type = \"disk\", radius = 0.002 }\nemission = { profile = \"/dev/zero\" }\n";
    let scene = parse_scene(text, Path::new("led.toml")).unwrap();
    let t = tessellate(&scene, Path::new("/")).unwrap();
    let e = PreparedScene::new(&scene, &t, Path::new("/"))
        .err()
        .unwrap();
    let cause = std::error::Error::source(&e).unwrap().to_string();
    assert!(cause.contains("larger than"), "{e}: {cause}");
}
