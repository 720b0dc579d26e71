#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! Drawn photon paths are the photons the run counted: the same fates,
//! bounces and escape texels, photon for photon.

use std::path::Path;

use lucerna_photometry::CubeMapLayout;
use lucerna_scene::{load_scene, parse_scene, tessellate};
use lucerna_tracer::cpu::{Fate, TraceSettings, trace_batch};
use lucerna_tracer::{PreparedScene, sample_photon_paths};

fn prepare_file(name: &str) -> PreparedScene {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../assets/luminaires");
    let scene = load_scene(&dir.join(name)).unwrap();
    let t = tessellate(&scene, &dir).unwrap();
    PreparedScene::new(&scene, &t, &dir).unwrap()
}

#[test]
fn sampled_paths_are_the_photons_of_the_runs_first_iteration() {
    for name in ["parabolic_spot.toml", "opal_bell.toml"] {
        let scene = prepare_file(name);
        let settings = TraceSettings {
            seed: 11,
            max_bounces: 8,
            layout: CubeMapLayout::new(16),
        };
        let count = 3000;
        let tally = trace_batch(&scene, &settings, 0, 0, count);
        let paths = sample_photon_paths(&scene, settings.seed, settings.max_bounces, count);
        assert_eq!(paths.len(), count as usize);
        let mut counts = vec![0u32; settings.layout.texel_count()];
        let (mut absorbed, mut cut_off, mut bounces) = (0, 0, 0);
        for p in &paths {
            bounces += u64::from(p.bounces);
            // Start, then one point per surface reached: the surfaces it
            // left (its bounces), plus the one it ended on if it did not
            // escape.
            let ended_on_surface = !matches!(p.fate, Fate::Escaped(_));
            assert_eq!(
                p.points.len() as u32,
                1 + p.bounces + u32::from(ended_on_surface),
                "{name}: {p:?}"
            );
            assert!(p.points.iter().all(|q| q.is_finite()));
            match p.fate {
                Fate::Escaped(d) => {
                    let texel = settings.layout.texel_of_direction([
                        f64::from(d.x),
                        f64::from(d.y),
                        f64::from(d.z),
                    ]);
                    counts[texel] += 1;
                }
                Fate::Absorbed => absorbed += 1,
                Fate::CutOff => cut_off += 1,
            }
        }
        assert_eq!(counts, tally.counts, "{name}: escape texels");
        assert_eq!(absorbed, tally.absorbed, "{name}");
        assert_eq!(cut_off, tally.cut_off, "{name}");
        assert_eq!(bounces, tally.bounces, "{name}");
        // The example reflects light: some paths bounce.
        assert!(paths.iter().any(|p| p.bounces > 0), "{name}");
    }
}

#[test]
fn a_bare_disk_emits_straight_out_into_its_hemisphere() {
    let toml = r#"
format_version = 1
name = "bare disk"
[[emitter]]
name = "LED"
flux_lm = 1000.0
shape = { type = "disk", radius = 0.002 }
"#;
    let scene = parse_scene(toml, Path::new("test.toml")).unwrap();
    let t = tessellate(&scene, Path::new(".")).unwrap();
    let prepared = PreparedScene::new(&scene, &t, Path::new(".")).unwrap();
    let paths = sample_photon_paths(&prepared, 3, 4, 500);
    assert_eq!(paths.len(), 500);
    for p in &paths {
        assert_eq!(p.points.len(), 1);
        assert!(p.points[0].length() <= 0.002 + 1e-4, "{:?}", p.points[0]);
        let d = p.escape_direction().expect("nothing to hit");
        assert!((d.length() - 1.0).abs() < 1e-4);
    }
    // Emitted into one hemisphere: every direction on the same side.
    let side = paths[0].escape_direction().unwrap().z.signum();
    assert!(
        paths
            .iter()
            .all(|p| p.escape_direction().unwrap().z * side >= 0.0)
    );
}
