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
    // 683 lm/W at 555 nm; the second table's efficacy is the integral of
    // its spectrum (linear between its wavelengths) against V(λ) over the
    // integral of the spectrum, here by a fine trapezoid.
    let s = |l: f64| {
        if l < 555.0 {
            1.0 + (l - 450.0) / 105.0
        } else {
            2.0 - (l - 555.0) / 95.0
        }
    };
    let (mut lum, mut pow) = (0.0, 0.0);
    for k in 0..20_000 {
        let (a, b) = (450.0 + 0.01 * f64::from(k), 450.0 + 0.01 * f64::from(k + 1));
        lum +=
            0.005 * (s(a) * luminous_efficacy_lm_per_w(a) + s(b) * luminous_efficacy_lm_per_w(b));
        pow += 0.005 * (s(a) + s(b));
    }
    let second = lum / pow;
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
        0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 1.0, 900.0,
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
    // Counts whose byte size wraps a u64 (4 × 2⁶² is 2⁶⁴): refused, no
    // overflow.
    for huge in [1u64 << 62, (1u64 << 62) + 1, u64::MAX / 4 + 1, u64::MAX] {
        let mut wraps = good.clone();
        wraps[20..28].copy_from_slice(&huge.to_le_bytes());
        let e = message(&wraps);
        assert!(e.contains(&format!("{huge} rays")), "{e}");
    }

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

/// A radiometric file as LED makers ship it: radiant flux per ray and
/// one spectral table of a phosphor-converted white LED on 5 nm steps;
/// the header's lumens computed as a maker computes them, by an
/// independent quadrature of the spectrum against the CIE's 1 nm V(λ)
/// (trapezoid on 0.01 nm steps of both linear interpolants). The rays'
/// lumens read within 0.05 % of it (a 5 nm V(λ) and the spectrum's
/// samples summed read such files 0.46 % high); and the header is not
/// contradicted, so no warning.
#[test]
fn a_radiometric_files_lumens_agree_with_its_header() {
    let wavelengths: Vec<f32> = (0..=80).map(|k| 380.0 + 5.0 * k as f32).collect();
    let spd = |l: f64| {
        let blue = (-0.5 * ((l - 450.0) / 10.0).powi(2)).exp();
        let phosphor = 0.8 * (-0.5 * ((l - 570.0) / 55.0).powi(2)).exp();
        blue + phosphor
    };
    let weights: Vec<f32> = wavelengths
        .iter()
        .map(|&l| spd(f64::from(l)) as f32)
        .collect();
    // The maker's lumens per watt, independently.
    let v_lin = |l: f64| {
        let x = l - 360.0;
        let i = x.floor() as usize;
        let t = x - i as f64;
        let v: Vec<f64> = include_str!("../../data/cie_photopic_v_1nm.csv")
            .lines()
            .filter(|l| !l.starts_with('#') && !l.starts_with("wavelength"))
            .filter_map(|l| l.split_once(',').and_then(|(_, v)| v.parse().ok()))
            .collect();
        v[i] * (1.0 - t) + v[i + 1] * t
    };
    let s_lin = |l: f64| {
        let x = (l - 380.0) / 5.0;
        let i = (x.floor() as usize).min(79);
        let t = x - i as f64;
        f64::from(weights[i]) * (1.0 - t) + f64::from(weights[i + 1]) * t
    };
    let (mut luminous, mut power) = (0.0, 0.0);
    let n = 40_000;
    for k in 0..n {
        let (a, b) = (380.0 + 0.01 * k as f64, 380.0 + 0.01 * (k + 1) as f64);
        luminous += 0.005 * (s_lin(a) * v_lin(a) + s_lin(b) * v_lin(b));
        power += 0.005 * (s_lin(a) + s_lin(b));
    }
    let efficacy = 683.0 * luminous / power;
    let mut header = RayFileHeader::luminous(3, 0.0);
    header.known = KnownData {
        radiant_flux: true,
        ..KnownData::default()
    };
    header.spectrum = SpectrumType::Table;
    header.spectral_tables = vec![SpectralTable {
        wavelengths_nm: wavelengths,
        weights,
    }];
    header.radiant_flux_w = Some(0.6);
    header.luminous_flux_lm = Some((0.6 * efficacy) as f32);
    let records = vec![
        0.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.1, //
        0.0, 0.0, 0.0, 0.6, 0.0, 0.8, 0.2, //
        0.0, 0.0, 0.0, 0.0, 0.6, 0.8, 0.3,
    ];
    let back = read(&bytes_of(&set(header, records))).unwrap();
    let lumens = back.total_luminous_flux_lm();
    let stated = f64::from(back.header.luminous_flux_lm.unwrap());
    assert!(
        (lumens / stated - 1.0).abs() < 5e-4,
        "{lumens} lm against the header's {stated} lm"
    );
    assert!(
        back.flux_warnings().is_empty(),
        "{:?}",
        back.flux_warnings()
    );
}

#[test]
fn a_header_that_disagrees_with_its_rays_is_warned_about() {
    // The header says 2 W where the rays sum to 1.68 W (an edited file),
    // and 6 lm where the rays carry 6 lm: the watts are warned about,
    // naming both numbers.
    let mut s = luminous_set();
    s.header.known.radiant_flux = true;
    s.header.radiant_flux_w = Some(2.0);
    s.records = vec![
        0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.5, 1.0, //
        0.5, -0.25, 0.0, 0.6, 0.0, -0.8, 0.58, 2.0, //
        -1.0, 1.0, 0.1, 0.0, -3.0, -4.0, 0.6, 3.0,
    ];
    let back = read(&bytes_of(&s)).unwrap();
    let w = back.flux_warnings();
    assert_eq!(w.len(), 1, "{w:?}");
    assert!(w[0].contains("2 W") && w[0].contains("1.68"), "{w:?}");
    // Lumens off by 10⁴: warned as well.
    let mut far = luminous_set();
    far.header.luminous_flux_lm = Some(60_000.0);
    let back = read(&bytes_of(&far)).unwrap();
    assert!(
        back.flux_warnings()[0].contains("60000 lm"),
        "{:?}",
        back.flux_warnings()
    );
    // Within 1 %: nothing.
    let mut near = luminous_set();
    near.header.luminous_flux_lm = Some(6.05);
    assert!(read(&bytes_of(&near)).unwrap().flux_warnings().is_empty());
}

/// Rays from a point in a beam of Gaussian angular spread σ about −z (or
/// about +z, as LED files emit), flux equal, over the R2 sequence.
fn gaussian_beam(n: usize, sigma_deg: f64, up: bool) -> RaySet {
    let mut records = Vec::with_capacity(7 * n);
    let (a1, a2) = (0.754_877_666_246_692_7, 0.569_840_290_998_053_3);
    for i in 0..n {
        let u = (0.5 + a1 * i as f64).fract().max(1e-12);
        let v = (0.5 + a2 * i as f64).fract();
        let gamma = sigma_deg.to_radians() * (-2.0 * u.ln()).sqrt();
        let phi = std::f64::consts::TAU * v;
        let z = if up { gamma.cos() } else { -gamma.cos() };
        records.extend([0.0, 0.0, 0.0]);
        records.extend([
            (gamma.sin() * phi.cos()) as f32,
            (gamma.sin() * phi.sin()) as f32,
            z as f32,
        ]);
        records.push(1000.0 / n as f32);
    }
    set(RayFileHeader::luminous(n as u64, 1000.0), records)
}

/// The rays' own flux within `cone_deg` of the beam's axis.
fn rays_within(rays: &RaySet, cone_deg: f64, up: bool) -> f64 {
    (0..rays.len())
        .filter(|&i| {
            let d = rays.direction(i).map(f64::from);
            let z = if up { d[2] } else { -d[2] };
            let norm = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            (z / norm).acos().to_degrees() < cone_deg
        })
        .map(|i| f64::from(rays.luminous_flux_lm[i]))
        .sum()
}

#[test]
fn a_narrow_sets_far_field_keeps_its_flux_and_its_cone() {
    // 100 k rays in a beam of σ 3° (a 7° beam): binned by the ray count
    // alone its texels were 7° and its 10° cone read 11 % low.
    for up in [false, true] {
        let rays = read(&bytes_of(&gaussian_beam(100_000, 3.0, up))).unwrap();
        let layout = rays.far_field_layout();
        assert!(layout.resolution >= 128, "{}", layout.resolution);
        let table = rays.far_field_table();
        let total = rays.total_luminous_flux_lm();
        let flux = table.flux_lm();
        assert!(
            (flux / total - 1.0).abs() < 0.003,
            "{flux} lm against {total}"
        );
        let (lo, hi) = if up { (170.0, 180.0) } else { (0.0, 10.0) };
        let cone = table.flux_between_lm(lo, hi);
        let want = rays_within(&rays, 10.0, up);
        assert!(
            (cone / want - 1.0).abs() < 0.01,
            "10° cone {cone} lm against {want}"
        );
        // The beam angle, whichever pole it is about, within 1° of the
        // Gaussian's: 2σ√(2 ln 2) = 7.06°.
        let f = crate::figures::figures(&table, None);
        let b = f.beam_angle_deg[0].expect("a beam angle");
        assert!((b - 7.06).abs() < 1.0, "beam {b}°");
    }
}

#[test]
fn texts_that_fill_their_fields_and_long_dates_round_trip() {
    let mut original = luminous_set();
    original.header.description.name = "n".repeat(TEXT_FIELD_CHARS);
    original.header.additional_columns.clear();
    // 27 bytes of ASCII then a 2-byte character: the date keeps 27.
    original.header.date_time = format!("{}é", "2".repeat(27));
    let back = read(&bytes_of(&original)).unwrap();
    assert_eq!(
        back.header.description.name.chars().count(),
        TEXT_FIELD_CHARS
    );
    assert_eq!(back.header.date_time, "2".repeat(27));

    let mut header = RayFileHeader::luminous(1, 1.0);
    let name = "c".repeat(COLUMN_NAME_BYTES / 4);
    header.additional_columns = vec![name.clone()];
    let with_column = set(header, vec![0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 1.0, 5.0]);
    let back = read(&bytes_of(&with_column)).unwrap();
    assert_eq!(back.header.additional_columns, [name]);
}

/// A one-ray file with every column flagged: radiant, wavelength,
/// luminous, Stokes, tristimulus; `value` sets one of them.
fn every_column(column: usize, value: f32) -> Vec<u8> {
    let mut header = RayFileHeader::luminous(1, 1.0);
    header.radiant_flux_w = Some(0.01);
    header.known = KnownData {
        radiant_flux: true,
        wavelength: true,
        luminous_flux: true,
        stokes: true,
        tristimulus: true,
        spectrum_index: false,
    };
    header.spectrum = SpectrumType::PerRayWavelength;
    let mut record = vec![
        0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.01, 555.0, 1.0, 1.0, 0.0, 0.0, 0.3, 0.3,
    ];
    record[column] = value;
    bytes_of(&set(header, record))
}

#[test]
fn every_flagged_column_is_checked_not_only_the_one_the_flux_comes_from() {
    // The file as written reads: the luminous column gives the flux.
    let good = read(&every_column(8, 1.0)).unwrap();
    assert_eq!(good.luminous_flux_lm, [1.0]);
    for (column, value, says) in [
        (6, f32::NAN, "radiant flux must be finite"),
        (6, -5.0, "radiant flux must be finite and not negative"),
        (7, f32::NAN, "wavelength must be finite"),
        (7, -1.0, "wavelength must be finite and positive"),
        (9, f32::NAN, "Stokes values must be finite"),
        (11, f32::INFINITY, "Stokes values must be finite"),
        (13, f32::NAN, "tristimulus values must be finite"),
    ] {
        let m = message(&every_column(column, value));
        assert!(m.contains(says), "column {column} = {value}: {m}");
        assert!(m.contains("ray 0"), "{m}");
    }
}

#[test]
fn a_radiant_flux_whose_lumens_overflow_is_refused() {
    // 1e36 W at 555 nm is 6.8e38 lm: past f32's range.
    let mut header = RayFileHeader::luminous(1, 0.0);
    header.luminous_flux_lm = None;
    header.radiant_flux_w = Some(1.0);
    header.known = KnownData {
        radiant_flux: true,
        ..KnownData::default()
    };
    header.spectrum = SpectrumType::SingleWavelength;
    header.wavelength_nm = Some(555.0);
    let bytes = bytes_of(&set(header, vec![0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 1e36]));
    let m = message(&bytes);
    assert!(m.contains("luminous flux must be finite"), "{m}");
}

#[test]
fn a_bad_ray_past_the_first_blocks_is_named_by_its_index() {
    // 400 000 rays of 7 values: three blocks of reading; the checks of
    // each block run beside the reading of the next.
    let n = 400_000usize;
    let mut records = Vec::with_capacity(7 * n);
    for i in 0..n {
        records.extend([i as f32 * 1e-6, 0.0, 0.0, 0.0, 0.0, -1.0, 1.0]);
    }
    records[7 * 300_001 + 6] = -2.0;
    records[7 * 350_000 + 3] = f32::NAN;
    let bytes = bytes_of(&set(RayFileHeader::luminous(n as u64, n as f32), records));
    let m = message(&bytes);
    assert!(
        m.contains("ray 300001:") && m.contains("not negative"),
        "{m}"
    );
}
