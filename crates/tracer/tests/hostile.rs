#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! An emission profile larger than its limit (or an endless one, in
//! `memory_limit.rs`) is refused, naming the emitter and the file.

use std::path::Path;

use lucerna_scene::io::MAX_PROFILE_FILE_BYTES;
use lucerna_scene::{ReadFileError, parse_scene, tessellate};
use lucerna_tracer::PreparedScene;
use lucerna_tracer::prepared::PrepareError;

/// A bare LED whose emission profile is `profile`.
fn led_with_profile(profile: &str) -> String {
    format!(
        "format_version = 1\nname = \"led\"\n\n[[emitter]]\nname = \"LED\"\nflux_lm = 100.0\n\
         shape = {{ type = \"disk\", radius = 0.002 }}\nemission = {{ profile = \"{profile}\" }}\n"
    )
}

#[test]
fn an_emission_profile_larger_than_its_limit_is_refused_unread() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::File::create(dir.path().join("huge.ies"))
        .unwrap()
        .set_len(MAX_PROFILE_FILE_BYTES + 1)
        .unwrap();
    let scene = parse_scene(&led_with_profile("huge.ies"), Path::new("led.toml")).unwrap();
    let t = tessellate(&scene, dir.path()).unwrap();
    match PreparedScene::new(&scene, &t, dir.path()) {
        Err(
            e @ PrepareError::ProfileRead {
                source: ReadFileError::TooLarge { .. },
                ..
            },
        ) => {
            let cause = std::error::Error::source(&e).unwrap().to_string();
            assert!(e.to_string().contains("LED"), "{e}");
            assert!(
                cause.contains("huge.ies") && cause.contains("larger than 16 MiB"),
                "{cause}"
            );
        }
        other => panic!("{:?}", other.err()),
    }
}

#[test]
fn emitters_naming_one_profile_share_one_read_of_it() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("spot.ies"),
        "IESNA:LM-63-2002\n[TEST] t\n[MANUFAC] m\nTILT=NONE\n1 1000 1 3 1 1 2 0 0 0\n1 1 1\n0 10 20\n0\n1000 1000 0\n",
    )
    .unwrap();
    let one = led_with_profile("spot.ies");
    let emitter = &one[one.find("[[emitter]]").unwrap()..];
    let text = format!("{one}\n{}", emitter.replace("\"LED\"", "\"LED 2\""));
    let scene = parse_scene(&text, Path::new("led.toml")).unwrap();
    let t = tessellate(&scene, dir.path()).unwrap();
    let prepared = PreparedScene::new(&scene, &t, dir.path()).unwrap();
    let samplers: Vec<_> = prepared
        .emitters
        .iter()
        .map(|e| match &e.directions {
            lucerna_tracer::prepared::EmitterDirections::Profile(s) => s.clone(),
            other => panic!("{other:?}"),
        })
        .collect();
    assert_eq!(samplers.len(), 2);
    assert!(std::sync::Arc::ptr_eq(&samplers[0], &samplers[1]));
}
