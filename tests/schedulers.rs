#![allow(clippy::unwrap_used, clippy::expect_used)] // reason: test helpers may panic
//! The split bake under the schedulers it ships for. On a real Slurm:
//! `deploy/slurm/selftest.sh` starts munged, slurmctld and slurmd on this
//! machine, runs the job array of an example in 4 parts (one task requeued
//! while it traces) and the dependent merge, compares the merged files
//! with one process's to the byte, and stops its daemons. For Kubernetes:
//! `deploy/kubernetes/selftest.py` checks the manifests against the API
//! schema and runs their container commands with JOB_COMPLETION_INDEX set.
//! `.ci/run` installs what they need; without it the tests are skipped
//! locally and fail under CI.

use std::path::Path;
use std::process::Command;

#[test]
fn a_job_array_and_its_merge_on_a_real_slurm_give_the_single_run() {
    let missing: Vec<&str> = ["munged", "slurmctld", "slurmd", "sbatch"]
        .into_iter()
        .filter(|tool| {
            !Command::new("sh")
                .args(["-c", &format!("command -v {tool}")])
                .output()
                .is_ok_and(|o| o.status.success())
        })
        .collect();
    let root = Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0");
    if !missing.is_empty() || !root {
        assert!(
            std::env::var_os("CI").is_none(),
            "CI must run the Slurm selftest, but {missing:?} are missing or this is not root"
        );
        println!("skipped: Slurm not installed ({missing:?} missing) or not root");
        return;
    }
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../deploy/slurm/selftest.sh");
    let out = Command::new("bash")
        .arg(script)
        .env("LUCERNA", env!("CARGO_BIN_EXE_lucerna"))
        .output()
        .unwrap();
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    println!("{stdout}");
    assert!(
        out.status.success(),
        "the selftest failed:\n{stdout}\n{stderr}"
    );
    assert!(stdout.contains("selftest: passed"), "{stdout}");
    assert!(
        stdout.contains("went on from it"),
        "no task was requeued: {stdout}"
    );
    // Nothing it started is left running.
    let left = Command::new("sh")
        .args(["-c", "pgrep -af 'lucerna-slurm-selftes[t]' || true"])
        .output()
        .unwrap();
    assert!(
        String::from_utf8_lossy(&left.stdout).trim().is_empty(),
        "daemons left running: {}",
        String::from_utf8_lossy(&left.stdout)
    );
}

#[test]
fn the_kubernetes_jobs_commands_run_here_give_the_single_run() {
    let python = Command::new("python3")
        .args(["-c", "import yaml"])
        .output()
        .is_ok_and(|o| o.status.success());
    if !python {
        assert!(
            std::env::var_os("CI").is_none(),
            "CI must run the Kubernetes selftest, but python3 with PyYAML is missing"
        );
        println!("skipped: python3 with PyYAML is missing");
        return;
    }
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../deploy/kubernetes/selftest.py");
    let out = Command::new("python3")
        .arg(script)
        .env("LUCERNA", env!("CARGO_BIN_EXE_lucerna"))
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    println!("{stdout}");
    assert!(
        out.status.success(),
        "the selftest failed:\n{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(stdout.contains("k8s selftest: passed"), "{stdout}");
}
