#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! End-to-end: a bake split with `lucerna bake --part`, merged with
//! `lucerna merge`, writes the one-machine bake's files to the byte; a
//! part killed with SIGKILL or stopped with SIGTERM resumes to the counts
//! it would have had; bad parts and bad flags are refused naming the file,
//! and nothing is written.

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

mod common;
use common::{assets, bake_on_cpu, lucerna, text};

const DATE: &str = "2026-01-31";

fn spot() -> PathBuf {
    assets().join("luminaires/parabolic_spot.toml")
}

fn s(p: &Path) -> &str {
    p.to_str().unwrap()
}

/// `lucerna bake SCENE --part PART` of `photons` at 32² into `out`.
fn part(
    scene: &Path,
    part: &str,
    photons: u64,
    out: &Path,
    extra: &[&str],
) -> std::process::Output {
    let mut args = vec!["--part", part, "--date", DATE];
    args.extend_from_slice(extra);
    bake_on_cpu(scene, photons, 32, out, &args)
}

fn ok(o: &std::process::Output) {
    assert!(
        o.status.success(),
        "failed: {}\n{}",
        text(&o.stdout),
        text(&o.stderr)
    );
}

fn refused(o: &std::process::Output) -> String {
    assert!(
        !o.status.success(),
        "should have failed: {}",
        text(&o.stdout)
    );
    text(&o.stderr)
}

#[test]
fn merged_parts_are_the_bake_on_one_machine_to_the_byte() {
    let dir = tempfile::tempdir().unwrap();
    let (parts, merged, single, whole) = (
        dir.path().join("parts"),
        dir.path().join("merged"),
        dir.path().join("single"),
        dir.path().join("whole"),
    );
    let photons = 150_000;
    for k in [3, 1, 2] {
        ok(&part(&spot(), &format!("{k}/3"), photons, &parts, &[]));
    }
    let o = lucerna(&["merge", s(&parts), "--out", s(&merged)]);
    ok(&o);
    assert!(
        text(&o.stdout).contains("3 parts merged: 150000 photons"),
        "{}",
        text(&o.stdout)
    );
    ok(&bake_on_cpu(
        &spot(),
        photons,
        32,
        &single,
        &["--date", DATE],
    ));
    // A whole bake with checkpoints writes the same files and leaves no
    // checkpoint behind.
    ok(&bake_on_cpu(
        &spot(),
        photons,
        32,
        &whole,
        &["--date", DATE, "--checkpoint", "1s"],
    ));
    for file in [
        "parabolic_spot.ies",
        "parabolic_spot.ldt",
        "parabolic_spot.exr",
        "parabolic_spot_polar.png",
        "parabolic_spot_cube.png",
    ] {
        let reference = std::fs::read(single.join(file)).unwrap();
        assert!(
            std::fs::read(merged.join(file)).unwrap() == reference,
            "merged {file} differs"
        );
        assert!(
            std::fs::read(whole.join(file)).unwrap() == reference,
            "checkpointed {file} differs"
        );
    }
    let left: Vec<_> = std::fs::read_dir(&whole)
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(left.len(), 5, "only the bake's files remain: {left:?}");
    // Parts named one by one merge the same.
    let manifests: Vec<String> = (1..=3)
        .map(|k| s(&parts.join(format!("parabolic_spot.part-{k}-of-3.json"))).to_owned())
        .collect();
    let again = dir.path().join("again");
    let mut args = vec!["merge", "--out", s(&again)];
    args.extend(manifests.iter().map(String::as_str));
    ok(&lucerna(&args));
    assert!(
        std::fs::read(again.join("parabolic_spot.ies")).unwrap()
            == std::fs::read(single.join("parabolic_spot.ies")).unwrap()
    );
}

fn manifest(dir: &Path, part: &str) -> Option<serde_json::Value> {
    let path = dir.join(format!(
        "parabolic_spot.part-{}.json",
        part.replace('/', "-of-")
    ));
    let text = std::fs::read_to_string(path).ok()?;
    serde_json::from_str(&text).ok()
}

fn counts(dir: &Path, part: &str) -> Vec<u8> {
    let m = manifest(dir, part).expect("a manifest");
    std::fs::read(dir.join(m["counts"]["file"].as_str().unwrap())).unwrap()
}

/// Starts a checkpointing part bake and returns it once its first
/// checkpoint is on disk.
fn started_part(out: &Path, photons: u64) -> std::process::Child {
    let child = Command::new(env!("CARGO_BIN_EXE_lucerna"))
        .args([
            "bake",
            s(&spot()),
            "--part",
            "1/2",
            "--photons",
            &photons.to_string(),
        ])
        .args([
            "--resolution",
            "32",
            "--backend",
            "cpu",
            "--checkpoint",
            "300ms",
            "--out",
            s(out),
        ])
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let deadline = Instant::now() + Duration::from_secs(120);
    while manifest(out, "1/2").is_none() {
        assert!(Instant::now() < deadline, "no checkpoint within 2 minutes");
        std::thread::sleep(Duration::from_millis(20));
    }
    child
}

#[test]
fn a_part_killed_or_stopped_resumes_to_the_counts_of_an_uninterrupted_one() {
    let dir = tempfile::tempdir().unwrap();
    // Large enough that it is still tracing at its first checkpoint and
    // a while after (24 M once finished before the SIGTERM below, in a
    // full test run on this machine).
    let photons = 36_000_000;
    let reference = dir.path().join("reference");
    ok(&part(&spot(), "1/2", photons, &reference, &[]));

    // SIGKILL: the last checkpoint stands, whole.
    let killed = dir.path().join("killed");
    let mut child = started_part(&killed, photons);
    child.kill().unwrap();
    child.wait().unwrap();
    let m = manifest(&killed, "1/2").unwrap();
    assert_eq!(m["complete"], false, "killed before the end: {m}");
    let o = lucerna(&["bake", "--resume", s(&killed)]);
    ok(&o);
    assert!(
        text(&o.stderr).contains("resuming part 1/2"),
        "{}",
        text(&o.stderr)
    );
    assert!(
        counts(&killed, "1/2") == counts(&reference, "1/2"),
        "resumed after SIGKILL: other counts"
    );

    // SIGTERM: a final checkpoint, a failure exit that says how to go on.
    let stopped = dir.path().join("stopped");
    let child = started_part(&stopped, photons);
    let first = manifest(&stopped, "1/2").unwrap()["photons_traced"]
        .as_u64()
        .unwrap();
    std::thread::sleep(Duration::from_millis(300));
    let status = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(status.success());
    let out = child.wait_with_output().unwrap();
    let stderr = text(&out.stderr);
    assert_eq!(
        out.status.code(),
        Some(75),
        "a stopped part exits with EX_TEMPFAIL, for a scheduler's retry rules"
    );
    assert!(
        stderr.contains("stopped by a signal") && stderr.contains("--resume"),
        "{stderr}"
    );
    let m = manifest(&stopped, "1/2").unwrap();
    let last = m["photons_traced"].as_u64().unwrap();
    assert!(
        m["complete"] == false && last > first,
        "final checkpoint at {last}, first at {first}"
    );
    ok(&lucerna(&[
        "bake",
        "--resume",
        s(&stopped),
        "--part",
        "1/2",
    ]));
    assert!(
        counts(&stopped, "1/2") == counts(&reference, "1/2"),
        "resumed after SIGTERM: other counts"
    );
    // A complete part resumed again has nothing to do.
    let o = lucerna(&["bake", "--resume", s(&stopped)]);
    ok(&o);
    assert!(counts(&stopped, "1/2") == counts(&reference, "1/2"));
}

/// The obj_cone example (a scene that reads an OBJ) copied where it can
/// be changed.
fn cone_copy(root: &Path) -> PathBuf {
    std::fs::create_dir_all(root.join("luminaires")).unwrap();
    std::fs::create_dir_all(root.join("meshes")).unwrap();
    std::fs::copy(
        assets().join("luminaires/obj_cone.toml"),
        root.join("luminaires/obj_cone.toml"),
    )
    .unwrap();
    std::fs::copy(
        assets().join("meshes/cone_reflector.obj"),
        root.join("meshes/cone_reflector.obj"),
    )
    .unwrap();
    root.join("luminaires/obj_cone.toml")
}

#[test]
fn bad_parts_and_flags_are_refused_naming_the_file_and_nothing_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let nothing = dir.path().join("nothing");
    let photons = 40_000;

    for bad in ["0/4", "5/4", "two/4"] {
        let e = refused(&part(&spot(), bad, photons, &nothing, &[]));
        assert!(e.contains("--part") && e.contains(bad), "{bad}: {e}");
    }
    let e = refused(&bake_on_cpu(
        &spot(),
        photons,
        32,
        &nothing,
        &["--part", "1/2", "--time", "3s"],
    ));
    assert!(e.contains("--photons"), "{e}");
    let e = refused(&part(&spot(), "auto", photons, &nothing, &[]));
    assert!(
        e.contains("SLURM_ARRAY_TASK_ID") && e.contains("JOB_COMPLETION_INDEX"),
        "{e}"
    );
    assert!(!nothing.exists(), "a refused bake created its folder");

    // A folder without a checkpoint.
    let empty = dir.path().join("empty");
    std::fs::create_dir(&empty).unwrap();
    let e = refused(&lucerna(&["bake", "--resume", s(&empty)]));
    assert!(
        e.contains("holds no checkpoint") && e.contains(s(&empty)),
        "{e}"
    );
    let e = refused(&lucerna(&["merge", s(&empty), "--out", s(&nothing)]));
    assert!(e.contains(s(&empty)), "{e}");

    // Parts of different seeds, a part missing, a part twice.
    let parts = dir.path().join("parts");
    ok(&part(&spot(), "1/3", photons, &parts, &[]));
    ok(&part(&spot(), "2/3", photons, &parts, &[]));
    let seed = dir.path().join("seed");
    ok(&part(&spot(), "3/3", photons, &seed, &["--seed", "2"]));
    let p = |dir: &Path, k: u32| dir.join(format!("parabolic_spot.part-{k}-of-3.json"));
    let e = refused(&lucerna(&[
        "merge",
        s(&parts),
        s(&p(&seed, 3)),
        "--out",
        s(&nothing),
    ]));
    assert!(
        e.contains("the seed differs (1 and 2)") && e.contains(s(&p(&seed, 3))),
        "{e}"
    );
    let e = refused(&lucerna(&["merge", s(&parts), "--out", s(&nothing)]));
    assert!(
        e.contains("photons are missing: photons 26666..40000 (part 3/3, not given)"),
        "{e}"
    );
    let e = refused(&lucerna(&[
        "merge",
        s(&parts),
        s(&p(&parts, 2)),
        "--out",
        s(&nothing),
    ]));
    assert!(e.contains("both part 2/3"), "{e}");
    // Parts of another output setting (a filter) do not make one bake.
    let filtered = dir.path().join("filtered");
    ok(&part(
        &spot(),
        "3/3",
        photons,
        &filtered,
        &["--filter", "auto"],
    ));
    let e = refused(&lucerna(&[
        "merge",
        s(&parts),
        s(&p(&filtered, 3)),
        "--out",
        s(&nothing),
    ]));
    assert!(e.contains("the output settings differ"), "{e}");
    // The same part again goes on from its checkpoint (a requeued job);
    // another bake's over it is refused, as it would lose its photons.
    let o = part(&spot(), "2/3", photons, &parts, &[]);
    ok(&o);
    assert!(
        text(&o.stderr).contains("holds this bake's part 2/3: going on from it"),
        "{}",
        text(&o.stderr)
    );
    let e = refused(&part(&spot(), "2/3", photons, &parts, &["--seed", "2"]));
    assert!(
        e.contains("holds part 2/3 of another bake: the photons asked for"),
        "{e}"
    );
    let e = refused(&part(&spot(), "2/3", photons, &parts, &["--c-step", "10"]));
    assert!(
        e.contains("the output settings (c_step_deg 5.0 then, 10.0 now)"),
        "{e}"
    );

    // A truncated part and a newer one.
    ok(&part(&spot(), "3/3", photons, &parts, &[]));
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(p(&parts, 2)).unwrap()).unwrap();
    let counts = parts.join(m["counts"]["file"].as_str().unwrap());
    let good = std::fs::read(&counts).unwrap();
    std::fs::write(&counts, &good[..good.len() - 10]).unwrap();
    let e = refused(&lucerna(&["merge", s(&parts), "--out", s(&nothing)]));
    assert!(e.contains("truncated") && e.contains(s(&counts)), "{e}");
    std::fs::write(&counts, &good).unwrap();
    let json = std::fs::read_to_string(p(&parts, 1)).unwrap();
    std::fs::write(
        p(&parts, 1),
        json.replace("\"version\": 2", "\"version\": 3"),
    )
    .unwrap();
    let e = refused(&lucerna(&["merge", s(&parts), "--out", s(&nothing)]));
    assert!(
        e.contains("format version 3") && e.contains(s(&p(&parts, 1))),
        "{e}"
    );
    std::fs::write(p(&parts, 1), json).unwrap();
    assert!(!nothing.exists(), "a refused merge wrote something");
    ok(&lucerna(&["merge", s(&parts), "--out", s(&nothing)]));

    // A scene whose mesh changed since its part was traced.
    let cone = cone_copy(&dir.path().join("cone"));
    let cone_parts = dir.path().join("cone_parts");
    ok(&bake_on_cpu(
        &cone,
        photons,
        32,
        &cone_parts,
        &["--part", "1/1"],
    ));
    let obj = cone.parent().unwrap().join("../meshes/cone_reflector.obj");
    let mut mesh = std::fs::read(&obj).unwrap();
    mesh.extend_from_slice(b"\n# edited\n");
    std::fs::write(&obj, mesh).unwrap();
    let cone_out = dir.path().join("cone_out");
    let e = refused(&lucerna(&["merge", s(&cone_parts), "--out", s(&cone_out)]));
    assert!(
        e.contains("the scene changed since") && e.contains("cone_reflector.obj changed"),
        "{e}"
    );
    let e = refused(&lucerna(&["bake", "--resume", s(&cone_parts)]));
    assert!(
        e.contains("the scene changed since") && e.contains("obj_cone.part-1-of-1.json"),
        "{e}"
    );
    assert!(!cone_out.exists());
}

#[test]
fn part_auto_takes_the_schedulers_task() {
    let dir = tempfile::tempdir().unwrap();
    let out = dir.path().join("k8s");
    for index in 0..2 {
        let o = Command::new(env!("CARGO_BIN_EXE_lucerna"))
            .args([
                "bake",
                s(&spot()),
                "--part",
                "auto",
                "--parts",
                "2",
                "--photons",
                "30000",
            ])
            .args(["--resolution", "32", "--backend", "cpu", "--out", s(&out)])
            .env("JOB_COMPLETION_INDEX", index.to_string())
            .output()
            .unwrap();
        ok(&o);
    }
    let slurm = dir.path().join("slurm");
    for id in [5, 6] {
        let o = Command::new(env!("CARGO_BIN_EXE_lucerna"))
            .args(["bake", s(&spot()), "--part", "auto", "--photons", "30000"])
            .args(["--resolution", "32", "--backend", "cpu", "--out", s(&slurm)])
            .env("SLURM_ARRAY_TASK_ID", id.to_string())
            .env("SLURM_ARRAY_TASK_MIN", "5")
            .env("SLURM_ARRAY_TASK_MAX", "6")
            .output()
            .unwrap();
        ok(&o);
    }
    for k in ["1/2", "2/2"] {
        assert!(
            counts(&out, k) == counts(&slurm, k),
            "part {k}: Kubernetes and Slurm numbering differ"
        );
    }
}
