#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! The data crates stay free of GPU and UI crates (ARCHITECTURE.md layers).

use std::process::Command;

#[test]
fn data_crates_depend_on_no_gpu_or_ui_crate() {
    for krate in [
        "lucerna-scene",
        "lucerna-photometry",
        "lucerna-pictures",
        "lucerna-datasheet",
        "lucerna-cad",
    ] {
        assert_free_of(krate, &["wgpu", "egui", "eframe", "naga", "winit"]);
    }
}

#[test]
fn only_the_editor_knows_egui() {
    // The engine and the simulation library run headless: GPU yes, UI no.
    for krate in [
        "lucerna-gpu",
        "lucerna-tracer",
        "lucerna-filter",
        "lucerna-room",
        "lucerna-simulation",
        "lucerna-design",
        "lucerna-tolerance",
        "lucerna-cli",
    ] {
        assert_free_of(krate, &["egui", "eframe", "winit"]);
    }
}

/// Fails if `krate`'s normal dependency tree holds any of `forbidden`.
fn assert_free_of(krate: &str, forbidden: &[&str]) {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_owned());
    {
        let out = Command::new(&cargo)
            .args([
                "tree",
                "--offline",
                "-p",
                krate,
                "-e",
                "normal",
                "--prefix",
                "none",
            ])
            .current_dir(env!("CARGO_MANIFEST_DIR"))
            .output()
            .expect("cargo tree runs");
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        let tree = String::from_utf8_lossy(&out.stdout);
        assert!(
            tree.contains(krate),
            "cargo tree printed nothing useful: {tree}"
        );
        for forbidden in forbidden {
            assert!(
                !tree.lines().any(|l| l.starts_with(forbidden)),
                "{krate} depends on {forbidden}:\n{tree}"
            );
        }
    }
}
