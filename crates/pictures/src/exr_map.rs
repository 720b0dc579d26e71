//! The raw intensity map as OpenEXR: one layer of N × 6N texels (faces
//! stacked +X, −X, +Y, −Y, +Z, −Z from the top), channels `candela` (f32)
//! and `count` (u32, where every count fits), with the bake's bookkeeping
//! as header attributes.

use exr::prelude::*;
use lucerna_photometry::IntensityMap;

#[derive(Debug, thiserror::Error)]
#[error("cannot encode the intensity map as EXR")]
pub struct ExrError(#[from] exr::error::Error);

/// EXR bytes of `map`; `extra` attributes (name, text) are added as given
/// (seed, scene name, date).
pub fn intensity_map_exr(
    map: &IntensityMap,
    extra: &[(&str, String)],
) -> std::result::Result<Vec<u8>, ExrError> {
    let n = map.layout.resolution as usize;
    let size = (n, 6 * n);
    let candela: Vec<f32> = map.candela().iter().map(|&v| v as f32).collect();
    let mut channels = smallvec::SmallVec::<[AnyChannel<FlatSamples>; 4]>::new();
    channels.push(AnyChannel::new("candela", FlatSamples::F32(candela)));
    if map.counts.iter().all(|&c| c <= u64::from(u32::MAX)) {
        let counts = map.counts.iter().map(|&c| c as u32).collect();
        channels.push(AnyChannel::new("count", FlatSamples::U32(counts)));
    }
    let mut attributes = LayerAttributes::named("intensity");
    let mut put = |k: &str, v: String| {
        attributes
            .other
            .insert(Text::from(k), AttributeValue::Text(Text::from(v.as_str())));
    };
    put("lucernaPhotonsEmitted", map.photons_emitted.to_string());
    put("lucernaPhotonsAbsorbed", map.photons_absorbed.to_string());
    put("lucernaPhotonsCutOff", map.photons_cut_off.to_string());
    put("lucernaEmitterFluxLm", map.emitter_flux_lm.to_string());
    put(
        "lucernaFaceOrder",
        "+X -X +Y -Y +Z -Z, each N rows from the top".to_owned(),
    );
    for (k, v) in extra {
        put(k, v.clone());
    }
    let layer = Layer::new(
        size,
        attributes,
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(channels),
    );
    let mut bytes = Vec::new();
    Image::from_layer(layer)
        .write()
        .to_buffered(std::io::Cursor::new(&mut bytes))?;
    sort_header_attributes(&mut bytes);
    Ok(bytes)
}

/// Puts the header's attributes in name order, in place. The exr crate
/// writes custom attributes in the order of a `HashMap`, which differs
/// from one process to the next, so two bakes of the same photons would
/// differ in bytes (and a split bake's merge from the bake on one
/// machine). OpenEXR leaves attribute order free, and the header keeps
/// its length, so the chunk offsets after it stay right. A header that
/// does not parse as a single-part one is left as it is.
fn sort_header_attributes(bytes: &mut [u8]) {
    const HEADER_START: usize = 8; // magic number and version field
    let mut attributes: Vec<&[u8]> = Vec::new();
    let mut at = HEADER_START;
    let cstr_end = |from: usize| bytes[from..].iter().position(|&b| b == 0).map(|i| from + i);
    loop {
        let Some(&first) = bytes.get(at) else { return };
        if first == 0 {
            break; // the header's end
        }
        let Some(name_end) = cstr_end(at) else { return };
        let Some(type_end) = cstr_end(name_end + 1) else {
            return;
        };
        let Some(size) = bytes
            .get(type_end + 1..type_end + 5)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize)
        else {
            return;
        };
        let end = type_end + 5 + size;
        if end > bytes.len() {
            return;
        }
        attributes.push(&bytes[at..end]);
        at = end;
    }
    let mut sorted: Vec<&[u8]> = attributes.clone();
    sorted.sort_by_key(|a| a.split(|&b| b == 0).next().unwrap_or_default());
    let header: Vec<u8> = sorted.concat();
    bytes[HEADER_START..HEADER_START + header.len()].copy_from_slice(&header);
}
