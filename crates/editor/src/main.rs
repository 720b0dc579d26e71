//! `lucerna-editor [SCENE.toml]`: the editor's window (also reached through
//! `lucerna edit`).

use std::path::PathBuf;

fn main() -> anyhow::Result<()> {
    let scene = std::env::args_os().nth(1).map(PathBuf::from);
    lucerna_editor::run(scene)?;
    Ok(())
}
