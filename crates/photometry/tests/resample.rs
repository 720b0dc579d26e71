//! The fast cell integration against its definition: every texel cut into
//! up to 64 × 64 sub-texels with exact directions and solid angles, each binned
//! by its centre with the map's value there, reconstructed bilinearly
//! between texel centres from the histopolated texels.

use lucerna_photometry::cubemap::rectangle_solid_angle;
use lucerna_photometry::fidelity::{FidelityTargets, map_intensity_bilinear};
use lucerna_photometry::resample::{
    CellBinning, gamma_cell_edges, histopolated, table_from_cube_map,
};
use lucerna_photometry::table::{angles, uniform_c_planes, uniform_gammas};
use lucerna_photometry::tabulate::{CPooling, GammaGrid, TableResampler};
use lucerna_photometry::{CandelaTable, CubeMapLayout};

/// The cell integral by brute force (the definition).
fn reference_table(
    layout: CubeMapLayout,
    candela: &[f64],
    c_planes: &[f64],
    gammas: &[f64],
    split: usize,
) -> CandelaTable {
    let edges = gamma_cell_edges(gammas);
    let reconstructed = histopolated(layout, candela);
    let (nc, ng) = (c_planes.len(), gammas.len());
    let mut flux = vec![0.0; nc * ng];
    let mut omega = vec![0.0; nc * ng];
    let mut caps = [(0.0, 0.0); 2];
    for t in 0..layout.texel_count() {
        let (face, a0, b0, a1, b1) = layout.texel_bounds(t);
        let (da, db) = ((a1 - a0) / split as f64, (b1 - b0) / split as f64);
        for i in 0..split {
            for j in 0..split {
                let (sa, sb) = (a0 + i as f64 * da, b0 + j as f64 * db);
                let w = rectangle_solid_angle(sa, sb, sa + da, sb + db);
                let d = face.direction(sa + 0.5 * da, sb + 0.5 * db);
                let value = map_intensity_bilinear(layout, &reconstructed, d);
                let (c, g) = angles(d);
                let (c, g) = (c.to_degrees(), g.to_degrees());
                let k = (edges.partition_point(|&e| e <= g).max(1) - 1).min(ng - 1);
                if k == 0 || k == ng - 1 {
                    let cap = &mut caps[usize::from(k != 0)];
                    cap.0 += value * w;
                    cap.1 += w;
                    continue;
                }
                let plane = (0..nc)
                    .min_by(|&x, &y| {
                        let d = |p: usize| {
                            let d = (c_planes[p] - c).rem_euclid(360.0);
                            d.min(360.0 - d)
                        };
                        d(x).total_cmp(&d(y))
                    })
                    .unwrap_or(0);
                flux[plane * ng + k] += value * w;
                omega[plane * ng + k] += w;
            }
        }
    }
    let mut values = Vec::with_capacity(nc * ng);
    for i in 0..nc {
        for j in 0..ng {
            let (f, o) = if j == 0 || j == ng - 1 {
                caps[usize::from(j != 0)]
            } else {
                (flux[i * ng + j], omega[i * ng + j])
            };
            values.push(f / o);
        }
    }
    CandelaTable::new(c_planes.to_vec(), gammas.to_vec(), values).expect("a valid table")
}

/// A distribution with a narrow beam, a tilted lobe and C structure.
fn structured_map(layout: CubeMapLayout) -> Vec<f64> {
    (0..layout.texel_count())
        .map(|t| {
            let (c, g) = angles(layout.texel_centre_direction(t));
            let beam = 1000.0 * (-(g.to_degrees() / 6.0).powi(2)).exp();
            let lobe = 200.0 * (1.0 + (3.0 * c).cos()) * (g.sin()).powi(2);
            beam + lobe + 5.0
        })
        .collect()
}

fn worst_relative_difference(a: &CandelaTable, b: &CandelaTable) -> f64 {
    let peak = b.candela.iter().cloned().fold(0.0, f64::max);
    a.candela
        .iter()
        .zip(&b.candela)
        .map(|(x, y)| (x - y).abs() / peak)
        .fold(0.0, f64::max)
}

#[test]
fn cell_integration_matches_brute_force_subdivision() {
    // Texels of 5.6° to 1.4°: the affine model's error shrinks with the
    // texel (at 256², texels are 0.35°).
    for (resolution, c_step, gamma_step, split, tolerance) in [
        (16, 15.0, 5.0, 48, 0.015),
        (32, 22.5, 1.0, 32, 0.015),
        // The reference's own binning error is about 0.4 % here.
        (64, 5.0, 2.5, 32, 0.007),
    ] {
        let layout = CubeMapLayout::new(resolution);
        let candela = structured_map(layout);
        let c_planes = uniform_c_planes(c_step);
        let gammas = uniform_gammas(gamma_step, 180.0);
        let reference = reference_table(layout, &candela, &c_planes, &gammas, split);
        let fast = table_from_cube_map(layout, &candela, &c_planes, &gammas);
        let worst = worst_relative_difference(&fast, &reference);
        eprintln!(
            "{resolution}²: worst {worst:.5}, flux {:.6} vs {:.6}",
            fast.flux_lm(),
            reference.flux_lm()
        );
        assert!(
            worst < tolerance,
            "{resolution}², C {c_step}°, γ {gamma_step}°: worst difference {worst:.4} of the peak"
        );
        let (f, r) = (fast.flux_lm(), reference.flux_lm());
        assert!((f / r - 1.0).abs() < 1e-3, "flux {f} vs {r}");
        // The stored binning gives the streaming pass's table (f32 shares).
        let binning = CellBinning::new(layout, &c_planes, &gamma_cell_edges(&gammas))
            .expect("a small layout");
        let stored = binning.integrate(&candela).table(&gammas);
        assert!(worst_relative_difference(&stored, &fast) < 1e-5);
    }
}

#[test]
fn every_texel_is_shared_out_whole() {
    // The shares of a texel add up to its solid angle, so a constant map
    // gives a constant table and the cells hold the whole sphere.
    let layout = CubeMapLayout::new(40);
    let ones = vec![1.0; layout.texel_count()];
    for gammas in [uniform_gammas(2.5, 180.0), uniform_gammas(0.3125, 180.0)] {
        let t = table_from_cube_map(layout, &ones, &uniform_c_planes(5.0), &gammas);
        for v in &t.candela {
            assert!((v - 1.0).abs() < 1e-9, "{v}");
        }
    }
}

#[test]
fn the_automatic_grid_refines_until_the_beam_holds() {
    // A 1.5° beam: 2.5° cells smear it and the interpolated table's flux
    // misses; the resampler refines until its figures hold.
    let layout = CubeMapLayout::new(128);
    let candela: Vec<f64> = (0..layout.texel_count())
        .map(|t| {
            let (_, g) = angles(layout.texel_centre_direction(t));
            1e5 * (-(g.to_degrees() / 1.5).powi(2)).exp()
        })
        .collect();
    let flux: f64 = (0..layout.texel_count())
        .map(|t| candela[t] * layout.texel_solid_angle(t))
        .sum();
    let c_planes = uniform_c_planes(5.0);
    let coarse = table_from_cube_map(layout, &candela, &c_planes, &uniform_gammas(2.5, 180.0));
    assert!((coarse.flux_lm() / flux - 1.0).abs() > 0.005);
    let mut resampler = TableResampler::new();
    let grid = GammaGrid::Automatic(FidelityTargets::default());
    let table = resampler.table(layout, &candela, &c_planes, grid, None, CPooling::Separate);
    eprintln!("{}", table.fidelity.summary());
    // A beam 3.5 texels wide: its tent reconstruction near the pole keeps
    // the flux to 0.2 % (the targets hold from about 6 texels up).
    assert!((table.table.flux_lm() / flux - 1.0).abs() <= 0.003);
    // Listed angles: fine in the beam, the coarsest step where it is dark.
    let g = &table.table.gammas_deg;
    let shape = table.fidelity.gamma_grid;
    assert_eq!(shape.angles, g.len());
    assert!(shape.finest_step_deg < 2.5, "{shape:?}");
    assert_eq!(shape.coarsest_step_deg, 5.0);
    assert!(g.len() <= lucerna_photometry::tabulate::MAX_AUTOMATIC_GAMMAS);
    assert!(
        g.windows(2).all(|w| w[0] >= 4.0 || w[1] - w[0] <= 1.25),
        "{g:?}"
    );
    // A second map of the same layout reuses the binning: same answer.
    let again = resampler.table(layout, &candela, &c_planes, grid, None, CPooling::Separate);
    assert_eq!(again, table);
}

#[test]
fn a_round_beam_pooled_over_c_has_no_square_pattern() {
    // A 3.6° beam on 64² faces, whose texels near the pole span 1.4°: each
    // C-plane's own texels put its 10 % edge at a different γ, with the
    // square texels' 90° period; pooled over C every plane carries the
    // ring's mean, so the edge is the same all round, and the flux stays.
    let layout = CubeMapLayout::new(64);
    let sigma_deg = 3.6 / (2.0 * (2.0 * 2f64.ln()).sqrt());
    let candela: Vec<f64> = (0..layout.texel_count())
        .map(|t| {
            let (_, g) = angles(layout.texel_centre_direction(t));
            1.7e5 * (-0.5 * (g.to_degrees() / sigma_deg).powi(2)).exp()
        })
        .collect();
    let c_planes = uniform_c_planes(5.0);
    let grid = GammaGrid::Step(0.25, FidelityTargets::default());
    let mut resampler = TableResampler::new();
    let separate = resampler.table(layout, &candela, &c_planes, grid, None, CPooling::Separate);
    let pooled = resampler.table(
        layout,
        &candela,
        &c_planes,
        grid,
        None,
        CPooling::Rotational,
    );
    let field = |t: &CandelaTable| -> Vec<f64> {
        (0..36)
            .map(|k| {
                lucerna_photometry::figures::spread_angle(t, 5.0 * k as f64, 0.1).expect("edge")
            })
            .collect()
    };
    let swing = |v: &[f64]| {
        v.iter().copied().fold(f64::MIN, f64::max) - v.iter().copied().fold(f64::MAX, f64::min)
    };
    let (separate_field, pooled_field) = (field(&separate.table), field(&pooled.table));
    // The pattern pooling removes is there to remove.
    assert!(swing(&separate_field) > 0.2, "{separate_field:?}");
    assert!(swing(&pooled_field) < 1e-9, "{pooled_field:?}");
    // Among the planes' own edges, and as near the true field angle
    // (2 σ √(2 ln 10)) as the 1.4° texels resolve it.
    let lowest = separate_field.iter().copied().fold(f64::MAX, f64::min);
    let highest = separate_field.iter().copied().fold(f64::MIN, f64::max);
    assert!(
        (lowest..=highest).contains(&pooled_field[0]),
        "{pooled_field:?} {separate_field:?}"
    );
    let truth = 2.0 * sigma_deg * (2.0 * 10f64.ln()).sqrt();
    assert!(
        (pooled_field[0] - truth).abs() < 0.5,
        "{} vs {truth}",
        pooled_field[0]
    );
    // Each ring keeps its flux; the tables' own integrals (between their
    // angles) differ by how the planes' values were spread.
    let (a, b) = (separate.table.flux_lm(), pooled.table.flux_lm());
    assert!((a / b - 1.0).abs() < 1e-3, "{a} lm vs {b} lm");
}
