//! The files the commands read, with errors that name them: photometric
//! files (IES, EULUMDAT, or a ray file's far field) and TM-25 ray files.

use std::path::Path;

use anyhow::{Context, Result};
use lucerna_photometry::Photometry;
use lucerna_photometry::tm25::{RaySet, read_ray_file};

/// Reads an IES or EULUMDAT file (or a ray file's far field), at most
/// `MAX_PROFILE_FILE_BYTES` of it (a photometric file of megabytes is
/// already absurd; `/dev/zero` is not read until memory runs out).
pub fn read_photometry(path: &Path) -> Result<Photometry> {
    if is_ray_file(path) {
        let name = path
            .file_name()
            .map_or_else(String::new, |n| n.to_string_lossy().into_owned());
        return Ok(read_rays(path)?.far_field_photometry(&name));
    }
    let bytes = lucerna_scene::read_limited(path, lucerna_scene::io::MAX_PROFILE_FILE_BYTES)
        .with_context(|| format!("cannot read {}", path.display()))?;
    lucerna_photometry::read_photometry(&bytes)
        .with_context(|| format!("cannot read photometry from {}", path.display()))
}

/// Whether `path` is a TM-25 ray file: its extension, or its first bytes.
pub fn is_ray_file(path: &Path) -> bool {
    let by_name = path
        .extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("tm25ray"));
    by_name || {
        let mut magic = [0u8; 4];
        std::fs::File::open(path)
            .and_then(|mut f| std::io::Read::read_exact(&mut f, &mut magic))
            .is_ok()
            && magic == lucerna_photometry::tm25::MAGIC
    }
}

/// Reads a TM-25 ray file whole.
pub fn read_rays(path: &Path) -> Result<RaySet> {
    read_ray_file(path).with_context(|| format!("cannot read the ray file {}", path.display()))
}
