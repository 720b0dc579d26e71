#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: tests may panic

use super::*;

/// Rays as records of x, y, z, kx, ky, kz and the flagged columns.
fn set(header: RayFileHeader, records: Vec<f32>) -> RaySet {
    RaySet {
        header,
        records,
        luminous_flux_lm: Vec::new(),
    }
}

fn luminous_set() -> RaySet {
    let mut header = RayFileHeader::luminous(3, 6.0);
    header.date_time = "2026-12-04T12:00:00+00:00".to_owned();
    header.description.name = "LED Ø3 — test".to_owned();
    header.description.manufacturer = "Lucerna".to_owned();
    header.description.ray_file_creator = "Lucerna 0.1.0".to_owned();
    set(
        header,
        vec![
            0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 1.0, //
            0.5, -0.25, 0.0, 0.6, 0.0, -0.8, 2.0, //
            -1.0, 1.0, 0.1, 0.0, -3.0, -4.0, 3.0,
        ],
    )
}

fn bytes_of(set: &RaySet) -> Vec<u8> {
    write_ray_file(set)
}

fn read(bytes: &[u8]) -> Result<RaySet, ReadRayFileError> {
    parse_ray_file(bytes, "test.tm25ray")
}

fn message(bytes: &[u8]) -> String {
    read(bytes).unwrap_err().to_string()
}

#[test]
fn a_written_file_reads_back_with_the_same_header_and_rays() {
    let original = luminous_set();
    let bytes = bytes_of(&original);
    assert_eq!(&bytes[..4], b"TM25");
    assert_eq!(bytes.len(), FIXED_HEADER_BYTES + 3 * 7 * 4);
    let back = read(&bytes).unwrap();
    assert_eq!(back.header, original.header);
    assert_eq!(back.records, original.records);
    assert_eq!(back.luminous_flux_lm, [1.0, 2.0, 3.0]);
    assert_eq!(back.total_luminous_flux_lm(), 6.0);
    assert_eq!(back.position_mm(2), [-1.0, 1.0, 0.1]);
    assert_eq!(back.direction(1), [0.6, 0.0, -0.8]);
    assert_eq!(
        back.extent_mm(),
        Some(([-1.0, -0.25, 0.0], [0.5, 1.0, 0.1]))
    );
    // Written again: the same bytes.
    assert_eq!(bytes_of(&back), bytes);
}

#[test]
fn spectral_tables_additional_columns_and_text_round_trip() {
    let mut header = RayFileHeader::luminous(2, 0.0);
    header.luminous_flux_lm = None;
    header.radiant_flux_w = Some(0.5);
    header.known = KnownData {
        radiant_flux: true,
        spectrum_index: true,
        ..KnownData::default()
    };
    header.spectrum = SpectrumType::PerRayTable;
    header.spectral_tables = vec![
        SpectralTable {
            wavelengths_nm: vec![555.0],
            weights: vec![1.0],
        },
        SpectralTable {
            wavelengths_nm: vec![450.0, 555.0, 650.0],
            weights: vec![1.0, 2.0, 1.0],
        },
    ];
    header.additional_columns = vec!["die".to_owned()];
    header.additional_text = "measured at 25 °C".to_owned();
    let records = vec![
        0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.25, 1.0, 7.0, //
        0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.25, 2.0, 8.0,
    ];
    let original = set(header, records);
    let bytes = bytes_of(&original);
    let back = read(&bytes).unwrap();
    assert_eq!(back.header, original.header);
    assert_eq!(back.records, original.records);
    // 683 lm/W at 555 nm; the second table's efficacy is its weighted mean.
    let v = |l: f64| luminous_efficacy_lm_per_w(l);
    let second = (v(450.0) + 2.0 * v(555.0) + v(650.0)) / 4.0;
    assert!((f64::from(back.luminous_flux_lm[0]) - 0.25 * 683.0).abs() < 1e-3);
    assert!((f64::from(back.luminous_flux_lm[1]) - 0.25 * second).abs() < 1e-3);
    assert_eq!(bytes_of(&back), bytes);
}

#[test]
fn radiant_flux_with_a_wavelength_per_ray_weighs_by_v_lambda() {
    let mut header = RayFileHeader::luminous(2, 0.0);
    header.luminous_flux_lm = None;
    header.known = KnownData {
        radiant_flux: true,
        wavelength: true,
        ..KnownData::default()
    };
    header.spectrum = SpectrumType::PerRayWavelength;
    let records = vec![
        0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 1.0, 555.0, //
        0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 1.0, 800.0,
    ];
    let back = read(&bytes_of(&set(header, records))).unwrap();
    assert_eq!(back.luminous_flux_lm, [683.0, 0.0]);
}

#[test]
fn vendor_variants_read_missing_column_names_and_signalling_nans() {
    let mut header = RayFileHeader::luminous(1, 1.0);
    header.additional_columns = vec!["a".to_owned(), "b".to_owned()];
    let records = vec![0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 1.0, 5.0, 6.0];
    let mut bytes = bytes_of(&set(header, records.clone()));
    // Without the column-name block.
    let names = FIXED_HEADER_BYTES;
    bytes.drain(names..names + 2 * COLUMN_NAME_BYTES);
    // A signalling NaN as "unknown" radiant flux.
    bytes[16..20].copy_from_slice(&0x7fa0_0000u32.to_le_bytes());
    let back = read(&bytes).unwrap();
    assert_eq!(back.header.additional_columns, ["column 1", "column 2"]);
    assert_eq!(back.header.radiant_flux_w, None);
    assert_eq!(back.records, records);
}

#[test]
fn bad_files_are_refused_naming_the_file_and_the_field() {
    let good = bytes_of(&luminous_set());
    let mut wrong_magic = good.clone();
    wrong_magic[..4].copy_from_slice(b"TM26");
    let e = message(&wrong_magic);
    assert!(
        e.contains("test.tm25ray") && e.contains("file type") && e.contains("TM26"),
        "{e}"
    );

    let e = message(&good[..good.len() - 5]);
    assert!(e.contains("ray data") && e.contains("truncated"), "{e}");
    let e = message(&good[..100]);
    assert!(e.contains("the file ends here"), "{e}");

    let mut more_rays = good.clone();
    more_rays[20..28].copy_from_slice(&4u64.to_le_bytes());
    let e = message(&more_rays);
    assert!(e.contains("4 rays of 7 values need 112 bytes"), "{e}");

    let mut trillion = good.clone();
    trillion[20..28].copy_from_slice(&1_000_000_000_000u64.to_le_bytes());
    let e = message(&trillion);
    assert!(e.contains("1000000000000 rays"), "{e}");

    // Flags that announce a column the rays do not have.
    let mut flags = good.clone();
    flags[FILE_HEADER_BYTES + 8..FILE_HEADER_BYTES + 12].copy_from_slice(&1i32.to_le_bytes());
    let e = message(&flags);
    assert!(e.contains("flags announce 8 values per ray"), "{e}");

    let mut flag_two = good.clone();
    flag_two[FILE_HEADER_BYTES + 16..FILE_HEADER_BYTES + 20].copy_from_slice(&2i32.to_le_bytes());
    let e = message(&flag_two);
    assert!(
        e.contains("luminous flux flag") && e.contains("0 or 1"),
        "{e}"
    );

    let ray = |i: usize, column: usize| FIXED_HEADER_BYTES + 4 * (7 * i + column);
    for (i, column, value, says) in [
        (1, 0, f32::NAN, "not finite"),
        (2, 4, f32::INFINITY, "not finite"),
        (1, 6, -1.0, "not negative"),
    ] {
        let mut bad = good.clone();
        bad[ray(i, column)..ray(i, column) + 4].copy_from_slice(&value.to_le_bytes());
        let e = message(&bad);
        assert!(e.contains(&format!("ray {i}")) && e.contains(says), "{e}");
    }
    let mut dark = good.clone();
    for i in 0..3 {
        dark[ray(i, 6)..ray(i, 6) + 4].copy_from_slice(&0f32.to_le_bytes());
    }
    assert!(message(&dark).contains("carry no flux"));
    let mut negative_total = good.clone();
    negative_total[12..16].copy_from_slice(&(-5f32).to_le_bytes());
    assert!(message(&negative_total).contains("luminous flux (4.7.1.4)"));
}

#[test]
fn a_file_over_the_limit_is_refused_before_it_is_read() {
    let dir = std::env::temp_dir().join(format!("lucerna-tm25-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("huge.tm25ray");
    let file = std::fs::File::create(&path).unwrap();
    // Sparse: no disk is used.
    file.set_len(MAX_RAY_FILE_BYTES + 1).unwrap();
    let e = read_ray_file(&path).unwrap_err().to_string();
    std::fs::remove_dir_all(&dir).unwrap();
    assert!(
        e.contains("huge.tm25ray") && e.contains("1073741824 bytes (1 GiB)"),
        "{e}"
    );
}

/// Rays from a point in the directions of a cosine law about −z, flux
/// equal: the far field is Lambertian, I(γ) = Φ/π · cos γ.
fn lambertian(n: usize, flux: f32) -> RaySet {
    let mut records = Vec::with_capacity(7 * n);
    // A cosine-weighted hemisphere, r = sqrt(u), φ = 2πv, over the R2
    // low-discrepancy sequence (no empty rings at the pole).
    let (a1, a2) = (0.754_877_666_246_692_7, 0.569_840_290_998_053_3);
    for i in 0..n {
        let u = (0.5 + a1 * i as f64).fract();
        let v = (0.5 + a2 * i as f64).fract();
        let (r, phi) = (u.sqrt(), std::f64::consts::TAU * v);
        let z = -(1.0 - r * r).sqrt();
        records.extend([0.0, 0.0, 0.0]);
        records.extend([(r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32]);
        records.push(flux / n as f32);
    }
    set(RayFileHeader::luminous(n as u64, flux), records)
}

#[test]
fn the_far_field_of_cosine_rays_is_lambertian() {
    let rays = read(&bytes_of(&lambertian(250_000, 1000.0))).unwrap();
    let table = rays.far_field_table();
    // The flux within γ is Φ sin²γ; the intensity, averaged over C,
    // Φ/π cos γ.
    for gamma in [10.0f64, 30.0, 45.0, 60.0, 80.0] {
        let want = 1000.0 * gamma.to_radians().sin().powi(2);
        let got = table.flux_between_lm(0.0, gamma);
        assert!(
            (got - want).abs() < 0.005 * want + 0.5,
            "γ < {gamma}: {got} vs {want} lm"
        );
        let g = table.gammas_deg.iter().position(|&x| x == gamma).unwrap();
        let n = table.c_planes_deg.len();
        let mean = (0..n)
            .map(|c| table.candela[c * table.gammas_deg.len() + g])
            .sum::<f64>()
            / n as f64;
        let want = 1000.0 / std::f64::consts::PI * gamma.to_radians().cos();
        assert!(
            (mean - want).abs() < 0.02 * 1000.0 / std::f64::consts::PI,
            "γ {gamma}: {mean} vs {want} cd"
        );
    }
    let photometry = rays.far_field_photometry("cosine.tm25ray");
    let flux = photometry.table.flux_lm();
    assert!((flux - 1000.0).abs() < 5.0, "{flux}");
    assert!(photometry.meta.absolute);
}
