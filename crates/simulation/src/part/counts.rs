//! The counts file of a partial map: exact u64 counts as LEB128 varints,
//! versioned, CRC-checked.

use std::path::Path;

use lucerna_photometry::{CubeMapLayout, IntensityMap};
use serde::{Deserialize, Serialize};

use super::{PARTIAL_MAP_VERSION, ReadPartError};

/// The first 16 bytes of a counts file.
const COUNTS_MAGIC: &[u8; 16] = b"LUCERNA-COUNTS\0\0";

/// Bytes before the counts: magic, version, resolution, emitted, absorbed,
/// cut off, emitter flux, texel count.
const COUNTS_HEADER_BYTES: usize = 16 + 4 + 4 + 8 * 5;

/// The counts file beside a manifest.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct CountsFile {
    /// File name, in the manifest's folder.
    pub file: String,
    pub bytes: u64,
    pub crc32: u32,
}

/// Encodes `map` as a counts file: header, the texels' counts as LEB128
/// varints (a count of 100 takes one byte, not eight), CRC-32 of it all.
pub fn encode_counts(map: &IntensityMap) -> Vec<u8> {
    let mut out = Vec::with_capacity(COUNTS_HEADER_BYTES + map.counts.len() + 4);
    out.extend_from_slice(COUNTS_MAGIC);
    out.extend_from_slice(&PARTIAL_MAP_VERSION.to_le_bytes());
    out.extend_from_slice(&map.layout.resolution.to_le_bytes());
    for v in [
        map.photons_emitted,
        map.photons_absorbed,
        map.photons_cut_off,
        map.emitter_flux_lm.to_bits(),
        map.counts.len() as u64,
    ] {
        out.extend_from_slice(&v.to_le_bytes());
    }
    for &c in &map.counts {
        let mut c = c;
        loop {
            let byte = (c & 0x7f) as u8;
            c >>= 7;
            if c == 0 {
                out.push(byte);
                break;
            }
            out.push(byte | 0x80);
        }
    }
    let crc = crc32fast::hash(&out);
    out.extend_from_slice(&crc.to_le_bytes());
    out
}

/// Decodes a counts file (`path` names it in errors).
pub fn decode_counts(bytes: &[u8], path: &Path) -> Result<IntensityMap, ReadPartError> {
    let corrupt = |why: String| ReadPartError::Corrupt {
        path: path.to_path_buf(),
        why,
    };
    if bytes.len() < 20 || &bytes[..16] != COUNTS_MAGIC {
        return Err(ReadPartError::NotAPart {
            path: path.to_path_buf(),
            why: "it does not start as a counts file".to_owned(),
        });
    }
    let u32_at = |at: usize| u32::from_le_bytes(bytes[at..at + 4].try_into().expect("4 bytes"));
    let version = u32_at(16);
    if version > PARTIAL_MAP_VERSION {
        return Err(ReadPartError::NewerVersion {
            path: path.to_path_buf(),
            version,
        });
    }
    if bytes.len() < COUNTS_HEADER_BYTES + 4 {
        return Err(corrupt(format!(
            "{} bytes is shorter than a counts file's header",
            bytes.len()
        )));
    }
    let (body, crc) = bytes.split_at(bytes.len() - 4);
    let stored = u32::from_le_bytes(crc.try_into().expect("4 bytes"));
    if crc32fast::hash(body) != stored {
        return Err(corrupt("its CRC-32 does not match its bytes".to_owned()));
    }
    let u64_at = |at: usize| u64::from_le_bytes(body[at..at + 8].try_into().expect("8 bytes"));
    let resolution = u32_at(20);
    let (emitted, absorbed, cut_off) = (u64_at(24), u64_at(32), u64_at(40));
    let flux = f64::from_bits(u64_at(48));
    let texels = u64_at(56);
    if !(1..=4096).contains(&resolution) {
        return Err(corrupt(format!("resolution {resolution}")));
    }
    let layout = CubeMapLayout::new(resolution);
    if texels != layout.texel_count() as u64 {
        return Err(corrupt(format!(
            "{texels} texels for a map of {resolution} per face edge"
        )));
    }
    if !(flux.is_finite() && flux > 0.0) {
        return Err(corrupt(format!("emitter flux {flux} lm")));
    }
    let mut counts = Vec::with_capacity(layout.texel_count());
    let mut rest = &body[COUNTS_HEADER_BYTES..];
    for _ in 0..texels {
        let mut value: u64 = 0;
        let mut shift = 0;
        loop {
            let Some((&byte, tail)) = rest.split_first() else {
                return Err(corrupt(format!("it ends after {} texels", counts.len())));
            };
            rest = tail;
            if shift == 63 && byte > 1 || shift > 63 {
                return Err(corrupt(format!("texel {} overflows 64 bits", counts.len())));
            }
            value |= u64::from(byte & 0x7f) << shift;
            shift += 7;
            if byte & 0x80 == 0 {
                break;
            }
        }
        counts.push(value);
    }
    if !rest.is_empty() {
        return Err(corrupt(format!(
            "{} bytes follow the last texel",
            rest.len()
        )));
    }
    let map = IntensityMap {
        layout,
        counts,
        photons_emitted: emitted,
        photons_absorbed: absorbed,
        photons_cut_off: cut_off,
        emitter_flux_lm: flux,
    };
    // Summed in u128: a corrupt file must not overflow the check itself.
    let escaped: u128 = map.counts.iter().map(|&c| u128::from(c)).sum();
    if escaped + u128::from(absorbed) + u128::from(cut_off) != u128::from(emitted) {
        return Err(corrupt(format!(
            "its photons do not add up: {escaped} escaped + {absorbed} absorbed + {cut_off} cut \
             off ≠ {emitted} emitted"
        )));
    }
    Ok(map)
}
