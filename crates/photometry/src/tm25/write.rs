//! Writing a TM-25 file: the reader's layout, field for field, so that a
//! file that reads, written again, reads back with the same rays.

use super::{COLUMN_NAME_BYTES, FILE_HEADER_BYTES, MAGIC, RaySet, TEXT_FIELD_CHARS, VERSION};

fn push_i32(out: &mut Vec<u8>, v: i32) {
    out.extend_from_slice(&v.to_le_bytes());
}

fn push_f32(out: &mut Vec<u8>, v: f32) {
    out.extend_from_slice(&v.to_le_bytes());
}

/// An unknown value: a quiet NaN.
fn push_optional(out: &mut Vec<u8>, v: Option<f32>) {
    push_f32(out, v.unwrap_or(f32::NAN));
}

/// `text` as `chars` UTF-32 characters, padded with NULs (a text that
/// fills its field has none: the reader stops at the field's end).
fn push_text(out: &mut Vec<u8>, text: &str, chars: usize) {
    let mut written = 0;
    for c in text.chars().filter(|&c| c != '\0').take(chars) {
        out.extend_from_slice(&u32::from(c).to_le_bytes());
        written += 1;
    }
    out.resize(out.len() + 4 * (chars - written), 0);
}

/// The file's bytes.
pub fn write_ray_file(set: &RaySet) -> Vec<u8> {
    let h = &set.header;
    let columns = h.columns();
    let mut out = Vec::with_capacity(40_000 + 4 * set.records.len());
    out.extend_from_slice(&MAGIC);
    push_i32(&mut out, VERSION);
    push_i32(&mut out, h.creation_method.code());
    push_optional(&mut out, h.luminous_flux_lm);
    push_optional(&mut out, h.radiant_flux_w);
    out.extend_from_slice(&(set.records.len() as u64 / columns.count as u64).to_le_bytes());
    // Cut at a character's boundary: a date of more than 28 bytes loses
    // whole characters, never half of one.
    let mut cut = h.date_time.len().min(28);
    while !h.date_time.is_char_boundary(cut) {
        cut -= 1;
    }
    let mut date = h.date_time.as_bytes()[..cut].to_vec();
    date.resize(28, 0);
    out.extend_from_slice(&date);
    push_i32(&mut out, h.start_position);
    push_i32(&mut out, h.spectrum.code());
    push_optional(&mut out, h.wavelength_nm);
    push_optional(&mut out, h.min_wavelength_nm);
    push_optional(&mut out, h.max_wavelength_nm);
    push_i32(&mut out, h.spectral_tables.len() as i32);
    push_i32(&mut out, h.additional_columns.len() as i32);
    let text_chars = if h.additional_text.is_empty() {
        0
    } else {
        // Whole 32-byte units, with room for the terminating NUL.
        (h.additional_text.chars().count() + 1).div_ceil(8) * 8
    };
    push_i32(&mut out, 4 * text_chars as i32);
    out.resize(FILE_HEADER_BYTES, 0);
    for flag in [
        true,
        true,
        h.known.radiant_flux,
        h.known.wavelength,
        h.known.luminous_flux,
        h.known.stokes,
        h.known.tristimulus,
        h.known.spectrum_index,
    ] {
        push_i32(&mut out, i32::from(flag));
    }
    for text in h.description.fields() {
        push_text(&mut out, text, TEXT_FIELD_CHARS);
    }
    let tables_start = out.len();
    for table in &h.spectral_tables {
        push_i32(&mut out, table.wavelengths_nm.len() as i32);
        for (&l, &w) in table.wavelengths_nm.iter().zip(&table.weights) {
            push_f32(&mut out, l);
            push_f32(&mut out, w);
        }
    }
    let table_bytes = out.len() - tables_start;
    if !table_bytes.is_multiple_of(32) {
        out.resize(out.len() + 32 - table_bytes % 32, 0);
    }
    for name in &h.additional_columns {
        push_text(&mut out, name, COLUMN_NAME_BYTES / 4);
    }
    if text_chars > 0 {
        push_text(&mut out, &h.additional_text, text_chars);
    }
    for &v in &set.records {
        push_f32(&mut out, v);
    }
    out
}
