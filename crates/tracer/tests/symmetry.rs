#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! Symmetry found from a luminaire's geometry: the examples get the groups
//! their construction gives them, small asymmetries lose them, and a
//! traced map of a luminaire found symmetric is symmetric within noise.

use std::path::Path;

use lucerna_photometry::{AxialSymmetry, CubeMapLayout, TexelSymmetry};
use lucerna_scene::{Scene, load_scene, parse_scene, tessellate};
use lucerna_tracer::cpu::{TraceSettings, trace_batch};
use lucerna_tracer::{PreparedScene, luminaire_symmetry};

fn examples() -> std::path::PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires")
}

fn symmetry_of(scene: &Scene, dir: &Path) -> AxialSymmetry {
    let t = tessellate(scene, dir).unwrap();
    luminaire_symmetry(scene, &t).symmetry
}

fn example(name: &str) -> Scene {
    load_scene(&examples().join(name)).unwrap()
}

#[test]
fn the_examples_have_the_symmetry_they_are_built_with() {
    let dir = examples();
    // Spun reflectors round a square LED or a sphere: all eight.
    for name in [
        "faceted_downlight.toml",
        "opal_bell.toml",
        "parabolic_spot.toml",
    ] {
        assert_eq!(
            symmetry_of(&example(name), &dir),
            AxialSymmetry::Square,
            "{name}"
        );
    }
    // A linear luminaire: mirror in both planes, no quarter turns.
    assert_eq!(
        symmetry_of(&example("linear_louvre.toml"), &dir),
        AxialSymmetry::Quadrant
    );
}

const SQUARE_BOX: &str = r#"
format_version = 1
name = "square box"
[materials.white]
type = "lambertian"
albedo = 0.8
[[emitter]]
name = "LED"
flux_lm = 100.0
shape = { type = "disk", radius = 0.005 }
[[part]]
name = "box"
material = "white"
shape = { type = "box", size = [0.04, 0.04, 0.02] }
transform = { translate = [0.0, 0.0, 0.011] }
"#;

fn parsed(toml: &str) -> Scene {
    parse_scene(toml, Path::new("test.toml")).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn small_changes_break_the_symmetry_they_should() {
    let dir = examples();
    assert_eq!(
        symmetry_of(&parsed(SQUARE_BOX), &dir),
        AxialSymmetry::Square
    );
    // A box longer in x: the two plane mirrors remain.
    let long = SQUARE_BOX.replace("size = [0.04,", "size = [0.05,");
    assert_eq!(symmetry_of(&parsed(&long), &dir), AxialSymmetry::Quadrant);
    // The LED 1 mm off axis along x: only the mirror in the C0-C180 plane.
    let off = SQUARE_BOX.replace(
        "shape = { type = \"disk\", radius = 0.005 }",
        "shape = { type = \"disk\", radius = 0.005 }\ntransform = { translate = [0.001, 0.0, 0.0] }",
    );
    assert_eq!(symmetry_of(&parsed(&off), &dir), AxialSymmetry::AboutC0C180);
    // 0.1 mm off is still far beyond the tolerance (a millionth of the size).
    let slightly = off.replace("0.001, 0.0, 0.0", "0.0001, 0.0, 0.0");
    assert_eq!(
        symmetry_of(&parsed(&slightly), &dir),
        AxialSymmetry::AboutC0C180
    );
    // Turned by 10° about z: the box keeps its quarter turns (about the
    // axis) but its mirror planes no longer line up with the cube map's.
    let turned = SQUARE_BOX.replace(
        "translate = [0.0, 0.0, 0.011] }",
        "translate = [0.0, 0.0, 0.011], rotate_deg = [0.0, 0.0, 10.0] }",
    );
    assert_eq!(
        symmetry_of(&parsed(&turned), &dir),
        AxialSymmetry::QuarterTurns
    );
}

#[test]
fn materials_and_emitters_count_as_well_as_geometry() {
    let dir = examples();
    // Two LEDs at ±x, one brighter: no mirror in the C90-C270 plane.
    let two = |flux_b: f64| {
        format!(
            r#"
format_version = 1
name = "two LEDs"
[[emitter]]
name = "a"
flux_lm = 100.0
shape = {{ type = "disk", radius = 0.003 }}
transform = {{ translate = [0.01, 0.0, 0.0] }}
[[emitter]]
name = "b"
flux_lm = {flux_b}
shape = {{ type = "disk", radius = 0.003 }}
transform = {{ translate = [-0.01, 0.0, 0.0] }}
"#
        )
    };
    assert_eq!(
        symmetry_of(&parsed(&two(100.0)), &dir),
        AxialSymmetry::Quadrant
    );
    assert_eq!(
        symmetry_of(&parsed(&two(120.0)), &dir),
        AxialSymmetry::AboutC0C180
    );
    // Brushing at 30° to the circumferential direction keeps the turns
    // only, and says why.
    let mut spot = example("faceted_downlight.toml");
    if let Some(lucerna_scene::Material::RoughConductor {
        orientation_deg, ..
    }) = spot.materials.get_mut("anodised_alu")
    {
        *orientation_deg = 30.0;
    }
    let t = tessellate(&spot, &dir).unwrap();
    let found = luminaire_symmetry(&spot, &t);
    assert_eq!(found.symmetry, AxialSymmetry::QuarterTurns);
    assert!(found.limited_by.unwrap().contains("anodised_alu"));
}

#[test]
fn a_luminaire_found_symmetric_traces_a_symmetric_map() {
    // The linear louvre (quadrant): each texel's mirror images hold the same
    // intensity within Poisson noise, checked as a χ² over bright texels.
    let dir = examples();
    let scene = example("linear_louvre.toml");
    let t = tessellate(&scene, &dir).unwrap();
    assert_eq!(
        luminaire_symmetry(&scene, &t).symmetry,
        AxialSymmetry::Quadrant
    );
    let prepared = PreparedScene::new(&scene, &t, &dir).unwrap();
    let layout = CubeMapLayout::new(8);
    let settings = TraceSettings {
        seed: 3,
        max_bounces: 32,
        layout,
    };
    let tally = trace_batch(&prepared, &settings, 0, 0, 400_000);
    let counts: Vec<u64> = tally.counts.iter().map(|&c| u64::from(c)).collect();
    let sym = TexelSymmetry::new(layout, AxialSymmetry::Quadrant);
    let (mut chi2, mut dof) = (0.0, 0usize);
    for t in 0..layout.texel_count() {
        let images: Vec<usize> = (0..sym.order()).map(|g| sym.image(g, t)).collect();
        if images.iter().any(|&i| i < t) || sym.multiplicity(t) > 1 {
            continue; // each orbit once, generic orbits only
        }
        let c: Vec<f64> = images.iter().map(|&i| counts[i] as f64).collect();
        let mean = c.iter().sum::<f64>() / c.len() as f64;
        if mean < 50.0 {
            continue;
        }
        chi2 += c.iter().map(|x| (x - mean).powi(2) / mean).sum::<f64>();
        dof += c.len() - 1;
    }
    assert!(dof > 30, "too few bright orbits ({dof})");
    let z = (chi2 - dof as f64) / (2.0 * dof as f64).sqrt();
    assert!(
        z.abs() < 4.0,
        "χ² {chi2:.1} on {dof} degrees of freedom (z = {z:.2})"
    );
}
