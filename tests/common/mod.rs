//! Helpers shared by the end-to-end tests: run the `lucerna` binary, find
//! the repository's assets, read its output.
#![allow(dead_code)] // reason: each test binary uses a part

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub fn lucerna(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lucerna"))
        .args(args)
        .output()
        .expect("the lucerna binary runs")
}

/// `lucerna bake SCENE --photons N --resolution R --backend cpu --out DIR`
/// plus `extra` arguments.
pub fn bake_on_cpu(
    scene: &Path,
    photons: u64,
    resolution: u32,
    out: &Path,
    extra: &[&str],
) -> Output {
    let (photons, resolution) = (photons.to_string(), resolution.to_string());
    let mut args = vec![
        "bake",
        scene.to_str().expect("UTF-8 path"),
        "--photons",
        &photons,
        "--resolution",
        &resolution,
        "--backend",
        "cpu",
        "--out",
        out.to_str().expect("UTF-8 path"),
    ];
    args.extend_from_slice(extra);
    lucerna(&args)
}

pub fn assets() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets")
}

pub fn text(o: &[u8]) -> String {
    String::from_utf8_lossy(o).into_owned()
}
