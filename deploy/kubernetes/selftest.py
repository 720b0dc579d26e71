#!/usr/bin/env python3
"""Runs the Kubernetes manifests' own container commands on this machine.

Without a cluster: the Indexed Job's command (bake-indexed-job.yaml) is run
once per index with JOB_COMPLETION_INDEX set, as the Job controller would,
with its $(VAR) references expanded from the container's env the way the
kubelet does; then the merge Job's command (merge-job.yaml). The volume's
/data is a temporary folder, the run is scaled down (4 parts, 2 000 000
photons, 64² texels) and the merged files are compared byte for byte with
one `lucerna bake` of the same photons; the same for a split `lucerna
tolerance` run (tolerance-indexed-job.yaml, tolerance-merge-job.yaml)
against one process's. With kubernetes-validate installed
(pip install kubernetes-validate) the manifests are first checked against
the Kubernetes API schema, strictly.

    LUCERNA=target/debug/lucerna deploy/kubernetes/selftest.py
"""

import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import yaml

def say(*a):
    print(*a, flush=True)

HERE = Path(__file__).resolve().parent
REPO = HERE.parent.parent
PARTS, PHOTONS, RESOLUTION = 4, 2_000_000, "64"


def container(manifest):
    job = yaml.safe_load((HERE / manifest).read_text())
    return job, job["spec"]["template"]["spec"]["containers"][0]


def expand(value, env):
    # The kubelet's $(VAR) expansion; $$ escapes a dollar.
    return re.sub(r"\$\$|\$\(([A-Za-z_][A-Za-z0-9_]*)\)",
                  lambda m: "$" if m.group(0) == "$$" else env.get(m.group(1), m.group(0)), value)


def command(spec, data, overrides):
    env = {e["name"]: e["value"] for e in spec.get("env", []) if "value" in e}
    env.update(overrides)
    env = {k: v.replace("/data", str(data)) for k, v in env.items()}
    args = [expand(a.replace("/data", str(data)), env) for a in spec["args"]]
    # Scaled down: a small map.
    if "--resolution" in args:
        args[args.index("--resolution") + 1] = RESOLUTION
    return args, env


def run(lucerna, args, env):
    full_env = {**os.environ, **env, "RAYON_NUM_THREADS": "1"}
    done = subprocess.run([lucerna, *args], env=full_env, capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"k8s selftest: `lucerna {' '.join(args)}` failed:\n{done.stderr}")
    return done


def main():
    lucerna = os.environ.get("LUCERNA") or str(REPO / "target/debug/lucerna")
    if shutil.which("kubernetes-validate"):
        subprocess.run(["kubernetes-validate", "--strict", "--quiet",
                        *map(str, sorted(HERE.glob("*.yaml")))], check=True)
        say("k8s selftest: the manifests validate strictly against the Kubernetes API schema")
    else:
        say("k8s selftest: kubernetes-validate not installed: schema check skipped")
    job, bake = container("bake-indexed-job.yaml")
    assert job["spec"]["completionMode"] == "Indexed"
    _, merge = container("merge-job.yaml")
    with tempfile.TemporaryDirectory(prefix="lucerna-k8s-selftest.") as tmp:
        data = Path(tmp) / "data"
        scene = data / "scenes" / "parabolic_spot.toml"
        scene.parent.mkdir(parents=True)
        shutil.copy(REPO / "assets/luminaires/parabolic_spot.toml", scene)
        overrides = {"PARTS": str(PARTS), "PHOTONS": str(PHOTONS)}
        for index in range(PARTS):
            args, env = command(bake, data, overrides)
            done = run(lucerna, args, dict(env, JOB_COMPLETION_INDEX=str(index)))
            say(f"k8s selftest: index {index}: " + done.stderr.strip().splitlines()[-1])
        args, env = command(merge, data, {})
        done = run(lucerna, args, env)
        say("k8s selftest: merge: " + done.stdout.strip().splitlines()[0])
        results = Path(args[args.index("--out") + 1])
        single = Path(tmp) / "single"
        run(lucerna, ["bake", str(scene), "--photons", str(PHOTONS), "--resolution", RESOLUTION,
                      "--backend", "cpu", "--out", str(single)], {})
        for name in ["parabolic_spot.exr", "parabolic_spot.ies", "parabolic_spot.ldt"]:
            a, b = (single / name).read_bytes(), (results / name).read_bytes()
            if a != b:
                sys.exit(f"k8s selftest: {name} of the merged parts differs from one process's")
            say(f"k8s selftest: {name} of the merged {PARTS} parts = the single run's ({len(a)} bytes)")
    tolerance_selftest(lucerna)
    say("k8s selftest: passed")


def tolerance_selftest(lucerna):
    """The tolerance Indexed Job's command once per index, then its merge
    Job's, against one process's run of the same samples (scaled down:
    8 samples of 20 000 photons at 64² texels)."""
    _, part = container("tolerance-indexed-job.yaml")
    _, merge = container("tolerance-merge-job.yaml")
    small = ["--photons", "20000", "--resolution", RESOLUTION, "--noise-runs", "2"]
    with tempfile.TemporaryDirectory(prefix="lucerna-k8s-tolerance.") as tmp:
        data = Path(tmp) / "data"
        folder = data / "tolerance"
        folder.mkdir(parents=True)
        shutil.copy(REPO / "assets/luminaires/parabolic_spot.toml", folder)
        for name in ["parabolic_spot_spec.toml", "parabolic_spot_tolerances.toml"]:
            shutil.copy(REPO / "assets/tolerances" / name, folder)
        overrides = {"PARTS": str(PARTS), "SAMPLES": "8"}
        for index in range(PARTS):
            args, env = command(part, data, overrides)
            run(lucerna, args + small, dict(env, JOB_COMPLETION_INDEX=str(index)))
        args, env = command(merge, data, {"SAMPLES": "8"})
        run(lucerna, args + small, env)
        results = Path(args[args.index("--out") + 1])
        single = Path(tmp) / "single"
        i = args.index("--merge")
        one = args[:i] + args[i + 2:]
        one[one.index("--out") + 1] = str(single)
        run(lucerna, one + small, env)
        for name in ["samples.csv", "yield.csv", "figures.csv", "sensitivities.csv"]:
            a, b = (single / name).read_bytes(), (results / name).read_bytes()
            if a != b:
                sys.exit(f"k8s selftest: tolerance {name} of the merged parts differs from one process's")
            say(f"k8s selftest: tolerance {name} of the merged {PARTS} parts = the single run's ({len(a)} bytes)")


if __name__ == "__main__":
    main()
