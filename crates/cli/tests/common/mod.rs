//! Helpers shared by the end-to-end tests: run the `lucerna` binary, find
//! the repository's assets, read its output.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

pub fn lucerna(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_lucerna"))
        .args(args)
        .output()
        .expect("the lucerna binary runs")
}

pub fn assets() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets")
}

pub fn text(o: &[u8]) -> String {
    String::from_utf8_lossy(o).into_owned()
}
