//! `lucerna edit`: runs the editor, a separate binary, so that this one
//! stays free of egui and winit (`tests/layers.rs`) and builds fast.

use std::path::Path;
use std::process::Command;

use anyhow::{Context, Result, bail};

/// The editor's binary name beside `lucerna`.
const EDITOR: &str = "lucerna-editor";

pub fn edit(scene: Option<&Path>) -> Result<()> {
    let exe = std::env::current_exe().context("cannot find the lucerna executable")?;
    let editor = exe
        .parent()
        .map(|dir| dir.join(format!("{EDITOR}{}", std::env::consts::EXE_SUFFIX)));
    let Some(editor) = editor.filter(|p| p.is_file()) else {
        bail!(
            "the editor ({EDITOR}) is not installed beside {}: build it with \
             `cargo build -p lucerna-editor` or run `cargo run -p lucerna-editor -- SCENE.toml`; \
             for headless use run `lucerna bake SCENE.toml`",
            exe.display()
        );
    };
    let mut command = Command::new(&editor);
    if let Some(scene) = scene {
        command.arg(scene);
    }
    let status = command
        .status()
        .with_context(|| format!("cannot start {}", editor.display()))?;
    if !status.success() {
        // The editor has printed its own error.
        bail!("{EDITOR} exited with {status}");
    }
    Ok(())
}
