#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! Split bakes against truth: the parts of a run, traced apart, written
//! as partial maps and merged, are the one-machine run's counts bit for
//! bit (CPU for 1, 3 and 8 parts; the GPU kernel too where an adapter
//! opens), and every file a merge is given is checked before it counts.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use lucerna_photometry::IntensityMap;
use lucerna_simulation::part::{
    self, PartManifest, SceneIdentity, TraceIdentity, manifest_file_name, merge_parts,
    new_manifest, write_part,
};
use lucerna_simulation::{
    BackendRequest, Luminaire, PartSpec, Run, SimulationSettings, StoppingRule,
};

const PHOTONS: u64 = 200_000;

fn example(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../assets/luminaires")
        .join(name)
}

fn settings(photons: u64) -> SimulationSettings {
    SimulationSettings {
        resolution: 32,
        seed: 7,
        backend: BackendRequest::Cpu,
        stop: StoppingRule {
            photons: Some(photons),
            ..Default::default()
        },
        ..Default::default()
    }
}

/// Traces `spec`'s range of a `total`-photon run in `run`, small
/// iterations so that a part is many of them.
fn trace_part(mut run: Run, spec: PartSpec, total: u64) -> IntensityMap {
    let range = spec.range(total);
    run.set_first_iteration_photons(5_000);
    run.set_iteration_time(std::time::Duration::from_millis(5));
    run.set_stopping_rule(StoppingRule {
        photons: Some(range.len()),
        ..Default::default()
    });
    let empty = run.session().map().clone();
    run.continue_from(range.first, empty).unwrap();
    while run.stop_reason().is_none() {
        run.step().unwrap();
    }
    run.session().map().clone()
}

/// Writes part `spec` of a run as a partial map in `dir`.
fn write(
    dir: &Path,
    scene: &Path,
    luminaire: &Luminaire,
    spec: PartSpec,
    map: &IntensityMap,
) -> PathBuf {
    let identity = SceneIdentity::of(scene, &luminaire.scene).unwrap();
    let trace = TraceIdentity {
        resolution: 32,
        seed: 7,
        max_bounces: 64,
        photons_total: PHOTONS,
        parts: spec.count,
        emitter_flux_lm: luminaire.prepared.total_flux_lm,
    };
    let job = lucerna_simulation::BakeJob::new(scene, dir);
    let mut manifest = new_manifest(identity, trace, job, spec, "cpu", false);
    let path = dir.join(manifest_file_name("spot", spec));
    write_part(&path, &mut manifest, map).unwrap();
    path
}

fn assert_same_counts(a: &IntensityMap, b: &IntensityMap, what: &str) {
    assert_eq!(a.photons_emitted, b.photons_emitted, "{what}: emitted");
    assert_eq!(a.photons_absorbed, b.photons_absorbed, "{what}: absorbed");
    assert_eq!(a.photons_cut_off, b.photons_cut_off, "{what}: cut off");
    assert!(a.counts == b.counts, "{what}: the texels' counts differ");
}

#[test]
fn merged_parts_are_the_one_machine_run_bit_for_bit_on_the_cpu() {
    let scene = example("parabolic_spot.toml");
    let luminaire = Arc::new(Luminaire::load(&scene).unwrap());
    let whole = lucerna_simulation::bake(luminaire.clone(), settings(PHOTONS)).unwrap();
    assert!(
        whole.map.photons_escaped() > PHOTONS / 2,
        "the spot lets light out"
    );
    for n in [1, 3, 8] {
        let dir = tempfile::tempdir().unwrap();
        let mut paths = Vec::new();
        // Out of order, as a scheduler finishes them.
        for k in (1..=n).rev() {
            let spec = PartSpec::new(k, n).unwrap();
            let run = Run::new(luminaire.clone(), settings(PHOTONS)).unwrap();
            let map = trace_part(run, spec, PHOTONS);
            assert_eq!(map.photons_emitted, spec.range(PHOTONS).len());
            paths.push(write(dir.path(), &scene, &luminaire, spec, &map));
        }
        let merged = merge_parts(&paths).unwrap();
        assert_same_counts(&merged.map, &whole.map, &format!("{n} parts"));
    }
}

#[test]
fn merged_gpu_parts_are_the_gpu_run_bit_for_bit() {
    let Some(context) = lucerna_gpu::open_for_tests() else {
        return;
    };
    let scene = example("parabolic_spot.toml");
    let luminaire = Arc::new(Luminaire::load(&scene).unwrap());
    let photons = 60_000;
    let gpu_run = || {
        let s = SimulationSettings {
            backend: BackendRequest::Gpu,
            ..settings(photons)
        };
        Run::on_gpu(luminaire.clone(), s, context.clone(), "test".into()).unwrap()
    };
    let whole = trace_part(gpu_run(), PartSpec::WHOLE, photons);
    let mut merged = IntensityMap::new(whole.layout, whole.emitter_flux_lm);
    for k in 1..=3 {
        let part = trace_part(gpu_run(), PartSpec::new(k, 3).unwrap(), photons);
        merged.merge(&part).unwrap();
    }
    assert_same_counts(&merged, &whole, "3 GPU parts");
}

#[test]
fn a_part_continued_from_its_checkpoint_traces_no_photon_twice() {
    let scene = example("parabolic_spot.toml");
    let luminaire = Arc::new(Luminaire::load(&scene).unwrap());
    let spec = PartSpec::new(2, 3).unwrap();
    let uninterrupted = trace_part(
        Run::new(luminaire.clone(), settings(PHOTONS)).unwrap(),
        spec,
        PHOTONS,
    );
    // Stopped after a few iterations, written, read back and continued.
    let range = spec.range(PHOTONS);
    let mut run = Run::new(luminaire.clone(), settings(range.len())).unwrap();
    run.set_first_iteration_photons(7_000);
    run.set_iteration_time(std::time::Duration::from_millis(5));
    let empty = run.session().map().clone();
    run.continue_from(range.first, empty).unwrap();
    for _ in 0..3 {
        run.step().unwrap();
    }
    let dir = tempfile::tempdir().unwrap();
    let path = write(dir.path(), &scene, &luminaire, spec, run.session().map());
    let manifest = part::read_manifest(&path).unwrap();
    assert!(!manifest.complete && manifest.photons_traced < range.len());
    let restored = part::read_part_counts(&path, &manifest).unwrap();
    let resumed = trace_part_from(
        Run::new(luminaire, settings(range.len())).unwrap(),
        range.first,
        restored,
    );
    assert_same_counts(&resumed, &uninterrupted, "resumed part");
}

fn trace_part_from(mut run: Run, first: u64, traced: IntensityMap) -> IntensityMap {
    run.set_first_iteration_photons(3_000);
    run.continue_from(first, traced).unwrap();
    while run.stop_reason().is_none() {
        run.step().unwrap();
    }
    run.session().map().clone()
}

/// Three parts of a run, written in `dir`.
fn three_parts(dir: &Path) -> Vec<PathBuf> {
    let scene = example("parabolic_spot.toml");
    let luminaire = Arc::new(Luminaire::load(&scene).unwrap());
    (1..=3)
        .map(|k| {
            let spec = PartSpec::new(k, 3).unwrap();
            let map = trace_part(
                Run::new(luminaire.clone(), settings(PHOTONS)).unwrap(),
                spec,
                PHOTONS,
            );
            write(dir, &scene, &luminaire, spec, &map)
        })
        .collect()
}

fn edit_manifest(path: &Path, edit: impl Fn(&mut serde_json::Value)) {
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    edit(&mut v);
    std::fs::write(path, serde_json::to_string_pretty(&v).unwrap()).unwrap();
}

fn counts_of(path: &Path) -> PathBuf {
    let m: PartManifest = part::read_manifest(path).unwrap();
    path.with_file_name(m.counts.file)
}

#[test]
fn parts_that_do_not_make_one_run_are_refused_naming_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let parts = three_parts(dir.path());
    let name = |p: &Path| p.file_name().unwrap().to_string_lossy().into_owned();
    let refused = |paths: &[PathBuf]| merge_parts(paths).expect_err("refused").to_string();

    // A part missing: its photons, by number.
    let e = refused(&parts[..2]);
    let range = PartSpec::new(3, 3).unwrap().range(PHOTONS);
    assert!(
        e.contains(&format!("photons {}..{}", range.first, range.end)) && e.contains("part 3/3"),
        "{e}"
    );
    // A part twice.
    let e = refused(&[
        parts[0].clone(),
        parts[1].clone(),
        parts[1].clone(),
        parts[2].clone(),
    ]);
    assert!(e.contains("both part 2/3"), "{e}");
    // Another seed.
    let other = tempfile::tempdir().unwrap();
    let copy = other.path().join(name(&parts[1]));
    std::fs::copy(&parts[1], &copy).unwrap();
    std::fs::copy(
        counts_of(&parts[1]),
        other.path().join(counts_of(&parts[1]).file_name().unwrap()),
    )
    .unwrap();
    edit_manifest(&copy, |v| v["trace"]["seed"] = 8.into());
    let e = refused(&[parts[0].clone(), copy.clone(), parts[2].clone()]);
    assert!(
        e.contains("the seed differs (7 and 8)") && e.contains(&copy.display().to_string()),
        "{e}"
    );
    // Another scene.
    edit_manifest(&copy, |v| {
        v["trace"]["seed"] = 7.into();
        v["scene"]["sha256"] = "00".repeat(32).into();
    });
    let e = refused(&[parts[0].clone(), copy.clone(), parts[2].clone()]);
    assert!(e.contains("the scene differs"), "{e}");
    // A range claimed that overlaps another's.
    edit_manifest(&copy, |v| {
        v["scene"]["sha256"] =
            serde_json::from_str::<serde_json::Value>(&std::fs::read_to_string(&parts[0]).unwrap())
                .unwrap()["scene"]["sha256"]
                .clone();
        v["part"] = 3.into();
        let r = PartSpec::new(3, 3).unwrap().range(PHOTONS);
        v["range"]["first"] = r.first.into();
        v["range"]["end"] = r.end.into();
    });
    let e = refused(&[parts[0].clone(), copy.clone(), parts[2].clone()]);
    assert!(e.contains("both part 3/3"), "{e}");
    // A newer format, and an older one (version 1 stored command-line
    // flags where version 2 stores the typed bake).
    edit_manifest(&copy, |v| v["version"] = 3.into());
    let e = refused(&[parts[0].clone(), copy.clone()]);
    assert!(
        e.contains("format version 3")
            && e.contains("newer")
            && e.contains(&copy.display().to_string()),
        "{e}"
    );
    edit_manifest(&copy, |v| v["version"] = 1.into());
    let e = refused(&[parts[0].clone(), copy.clone()]);
    assert!(
        e.contains("format version 1")
            && e.contains("older")
            && e.contains("trace that part again"),
        "{e}"
    );
}

#[test]
fn a_truncated_or_corrupt_counts_file_is_refused_naming_it() {
    let dir = tempfile::tempdir().unwrap();
    let parts = three_parts(dir.path());
    let counts = counts_of(&parts[1]);
    let good = std::fs::read(&counts).unwrap();
    std::fs::write(&counts, &good[..good.len() / 2]).unwrap();
    let e = merge_parts(&parts).expect_err("truncated").to_string();
    assert!(
        e.contains("truncated") && e.contains(&counts.display().to_string()),
        "{e}"
    );
    let mut flipped = good.clone();
    flipped[100] ^= 0x10;
    std::fs::write(&counts, &flipped).unwrap();
    let e = merge_parts(&parts).expect_err("corrupt").to_string();
    assert!(
        e.contains("corrupt") && e.contains(&counts.display().to_string()),
        "{e}"
    );
    std::fs::write(&counts, &good).unwrap();
    assert!(merge_parts(&parts).is_ok());
}

#[test]
fn a_checkpoint_killed_between_its_two_writes_still_has_its_counts() {
    // write_part writes the counts to the slot the manifest does not name,
    // then the manifest: a kill in between leaves the old pair intact.
    let dir = tempfile::tempdir().unwrap();
    let parts = three_parts(dir.path());
    let before = part::read_manifest(&parts[0]).unwrap();
    let slot = counts_of(&parts[0]);
    let other_slot = if slot.to_string_lossy().ends_with(".a.counts") {
        slot.with_file_name(
            slot.file_name()
                .unwrap()
                .to_string_lossy()
                .replace(".a.counts", ".b.counts"),
        )
    } else {
        slot.with_file_name(
            slot.file_name()
                .unwrap()
                .to_string_lossy()
                .replace(".b.counts", ".a.counts"),
        )
    };
    std::fs::write(&other_slot, b"half of a new checkpoint").unwrap();
    let map = part::read_part_counts(&parts[0], &before).unwrap();
    assert_eq!(map.photons_emitted, before.photons_traced);
    // The next write goes to the other slot and removes the stale one.
    let mut manifest = before.clone();
    write_part(&parts[0], &mut manifest, &map).unwrap();
    assert_eq!(counts_of(&parts[0]), other_slot);
    assert!(!slot.exists(), "the stale slot is removed");
    assert!(merge_parts(&parts).is_ok());
}

#[test]
fn part_numbers_come_from_the_user_or_the_scheduler_and_cover_the_run_once() {
    for bad in ["0/4", "5/4", "1/0", "x/4", "3", "-1/4"] {
        let e = bad.parse::<PartSpec>().expect_err(bad).to_string();
        assert!(!e.is_empty(), "{bad}");
    }
    assert_eq!(
        "3/8".parse::<PartSpec>().unwrap(),
        PartSpec::new(3, 8).unwrap()
    );
    for (total, n) in [(10u64, 3u32), (1 << 40, 7), (5, 5), (u64::MAX / 3, 1000)] {
        let mut at = 0;
        for k in 1..=n {
            let r = PartSpec::new(k, n).unwrap().range(total);
            assert_eq!(r.first, at);
            assert!(r.len().abs_diff(total / u64::from(n)) <= 1);
            at = r.end;
        }
        assert_eq!(at, total);
    }
    let env = |vars: &'static [(&'static str, &'static str)]| {
        move |name: &str| {
            vars.iter()
                .find(|(k, _)| *k == name)
                .map(|(_, v)| (*v).to_owned())
        }
    };
    let slurm = env(&[
        ("SLURM_ARRAY_TASK_ID", "6"),
        ("SLURM_ARRAY_TASK_MIN", "4"),
        ("SLURM_ARRAY_TASK_MAX", "11"),
    ]);
    assert_eq!(
        PartSpec::from_scheduler(&slurm, None).unwrap(),
        PartSpec::new(3, 8).unwrap()
    );
    let slurm = env(&[
        ("SLURM_ARRAY_TASK_ID", "0"),
        ("SLURM_ARRAY_TASK_COUNT", "4"),
    ]);
    assert_eq!(
        PartSpec::from_scheduler(&slurm, None).unwrap(),
        PartSpec::new(1, 4).unwrap()
    );
    assert!(
        PartSpec::from_scheduler(&slurm, Some(5)).is_err(),
        "--parts disagrees"
    );
    let k8s = env(&[("JOB_COMPLETION_INDEX", "3")]);
    assert_eq!(
        PartSpec::from_scheduler(&k8s, Some(4)).unwrap(),
        PartSpec::new(4, 4).unwrap()
    );
    assert!(
        PartSpec::from_scheduler(&k8s, Some(3)).is_err(),
        "index 3 of 3 parts"
    );
    assert!(
        PartSpec::from_scheduler(&k8s, None).is_err(),
        "needs --parts"
    );
    assert!(
        PartSpec::from_scheduler(&env(&[]), None).is_err(),
        "no scheduler"
    );
    assert!(PartSpec::from_scheduler(&env(&[("JOB_COMPLETION_INDEX", "two")]), Some(3)).is_err());
}

#[test]
fn a_counts_file_round_trips_exactly_even_with_counts_beyond_u32() {
    let layout = lucerna_photometry::CubeMapLayout::new(4);
    let mut map = IntensityMap::new(layout, 1234.5);
    for (i, c) in map.counts.iter_mut().enumerate() {
        *c = match i % 4 {
            0 => 0,
            1 => 127,
            2 => 1 << 40,
            _ => u64::MAX / 1000,
        };
    }
    let escaped: u64 = map.counts.iter().sum();
    map.photons_emitted = escaped + 17;
    map.photons_absorbed = 10;
    map.photons_cut_off = 7;
    let bytes = part::encode_counts(&map);
    let back = part::decode_counts(&bytes, Path::new("x.counts")).unwrap();
    assert_same_counts(&back, &map, "round trip");
    assert_eq!(back.emitter_flux_lm, 1234.5);
    // Unbalanced counts are refused even with a right CRC.
    map.photons_absorbed = 11;
    let e = part::decode_counts(&part::encode_counts(&map), Path::new("x.counts"))
        .expect_err("unbalanced");
    assert!(matches!(e, part::ReadPartError::Corrupt { .. }), "{e}");
}

#[test]
fn a_flux_of_seventeen_digits_and_hostile_manifests_read_back_exactly_or_are_refused() {
    let dir = tempfile::tempdir().unwrap();
    let scene = example("parabolic_spot.toml");
    let luminaire = Luminaire::load(&scene).unwrap();
    // A flux whose shortest decimal has 17 digits must come back to the bit.
    let flux = 130.653_316_326_530_61_f64;
    let mut map = IntensityMap::new(lucerna_photometry::CubeMapLayout::new(8), flux);
    map.counts[3] = 5;
    map.photons_emitted = 7;
    map.photons_absorbed = 2;
    let spec = PartSpec::WHOLE;
    let trace = TraceIdentity {
        resolution: 8,
        seed: 1,
        max_bounces: 64,
        photons_total: 7,
        parts: 1,
        emitter_flux_lm: flux,
    };
    let identity = SceneIdentity::of(&scene, &luminaire.scene).unwrap();
    let job = lucerna_simulation::BakeJob::new(&scene, dir.path());
    let mut manifest = new_manifest(identity, trace, job, spec, "cpu", false);
    let path = dir.path().join(manifest_file_name("flux", spec));
    write_part(&path, &mut manifest, &map).unwrap();
    let back = part::read_manifest(&path).unwrap();
    assert_eq!(back.trace.emitter_flux_lm.to_bits(), flux.to_bits());
    let counts = part::read_part_counts(&path, &back).unwrap();
    assert_same_counts(&counts, &map, "17-digit flux");

    // Hostile values are refused as corrupt, never a panic.
    type ManifestEdit = fn(&mut serde_json::Value);
    let edits: [(&str, ManifestEdit); 4] = [
        ("a short non-ASCII digest", |v| {
            v["scene"]["sha256"] = "ééééééé".into()
        }),
        ("a huge resolution", |v| {
            v["trace"]["resolution"] = 100_000.into()
        }),
        ("photons past 2^62", |v| {
            v["trace"]["photons_total"] = u64::MAX.into()
        }),
        ("a file digest of the wrong length", |v| {
            v["scene"]["files"][0]["sha256"] = "ab".into()
        }),
    ];
    let good = std::fs::read_to_string(&path).unwrap();
    for (what, edit) in edits {
        edit_manifest(&path, edit);
        let e = part::read_manifest(&path).expect_err(what);
        assert!(
            e.to_string().contains(&path.display().to_string()),
            "{what}: {e}"
        );
        std::fs::write(&path, &good).unwrap();
    }
}

#[test]
fn a_stepped_slurm_array_is_refused_rather_than_misnumbered() {
    let env = |name: &str| match name {
        "SLURM_ARRAY_TASK_ID" => Some("3".to_owned()),
        "SLURM_ARRAY_TASK_MIN" => Some("1".to_owned()),
        "SLURM_ARRAY_TASK_MAX" => Some("63".to_owned()),
        "SLURM_ARRAY_TASK_COUNT" => Some("32".to_owned()),
        _ => None,
    };
    let e = PartSpec::from_scheduler(&env, None)
        .expect_err("1-63:2")
        .to_string();
    assert!(e.contains("contiguously"), "{e}");
}
