#!/bin/bash
# `lucerna tolerance` on the parabolic spot, on this machine, in one run
# (issue "Tolerance analysis"): the LED placed with σ 0.1 mm in x, y and
# z and the reflector's form error σ 0.05 mm over a 10 mm correlation
# length (assets/tolerances/parabolic_spot_tolerances.toml) against the
# spec assets/tolerances/parabolic_spot_spec.toml.
#   photons    for each of PHOTON_STEPS: STUDY_SAMPLES samples; each
#              figure's photon noise σ beside its spread, and samples/s;
#   precision  --yield-precision 5 at PHOTONS photons: the time until the
#              yield's 95 % interval is within ± 5 points, samples/s;
#   reference  the same samples at REFERENCE_PHOTONS photons: the yield
#              and the pass/fail of each sample compared;
#   bake       the worst sample's scene baked by `lucerna bake` with
#              BAKE_PHOTONS photons (another pipeline, another seed): its
#              beam and field against the analysis's.
#
#   deploy/bench-tolerance.sh   (LUCERNA=… PHOTONS=200000 …)
set -euo pipefail
REPO=$(cd "$(dirname "$0")/.." && pwd)
LUCERNA=${LUCERNA:-$REPO/target/release/lucerna}
PHOTONS=${PHOTONS:-200000}
PHOTON_STEPS=${PHOTON_STEPS:-50000 100000 200000 500000 1000000}
STUDY_SAMPLES=${STUDY_SAMPLES:-60}
REFERENCE_PHOTONS=${REFERENCE_PHOTONS:-1000000}
BAKE_PHOTONS=${BAKE_PHOTONS:-5000000}
SCENE=$REPO/assets/luminaires/parabolic_spot.toml
SPEC=$REPO/assets/tolerances/parabolic_spot_spec.toml
TOL=$REPO/assets/tolerances/parabolic_spot_tolerances.toml
WORK=$(mktemp -d -t lucerna-bench-tolerance.XXXXXX)
trap 'rm -rf "$WORK"' EXIT

run() { # out photons [args…]
  local out=$1 photons=$2
  shift 2
  "$LUCERNA" tolerance "$SCENE" --spec "$SPEC" --tolerances "$TOL" \
    --photons "$photons" --out "$out" "$@" > "$out.txt" 2> "$out.err"
}

column() { # figures.csv figure field
  python3 - "$@" <<'PY'
import csv, sys
rows = {r["figure"]: r for r in csv.DictReader(open(sys.argv[1]))}
print(rows[sys.argv[2]][sys.argv[3]])
PY
}

echo "== photons per sample ($STUDY_SAMPLES samples each)"
printf "%9s %10s %22s %22s %22s\n" photons samples/s "beam σ / noise σ (°)" "field σ / noise σ (°)" "cut-off σ / noise σ (%)"
for p in $PHOTON_STEPS; do
  out=$WORK/study-$p
  run "$out" "$p" --samples "$STUDY_SAMPLES"
  rate=$(grep -oE '\(([0-9.]+) samples/s\)' "$out.txt" | tr -d '()' | cut -d' ' -f1)
  line=""
  for f in beam_deg field_deg cutoff_percent_of_peak; do
    line+=$(printf "%22s" "$(printf "%.4f / %.4f" "$(column "$out/figures.csv" $f sd)" "$(column "$out/figures.csv" $f photon_noise_sd)")")
    line+=" "
  done
  printf "%9s %10s %s\n" "$p" "$rate" "$line"
done

echo "== yield within ± 5 points at $PHOTONS photons per sample"
out=$WORK/precision
start=$(date +%s.%N)
run "$out" "$PHOTONS" --yield-precision 5
end=$(date +%s.%N)
grep -E "^yield|samples in" "$out.txt"
echo "wall time including the nominal and its noise: $(python3 -c "print(f'{$end - $start:.1f}')") s"
n=$(python3 -c "import json; print(json.load(open('$out/tolerance.json'))['samples'])")

echo "== the same $n samples at $REFERENCE_PHOTONS photons"
ref=$WORK/reference
run "$ref" "$REFERENCE_PHOTONS" --samples "$n"
grep -E "^yield" "$ref.txt"
python3 - "$out/samples.csv" "$ref/samples.csv" <<'PY'
import csv, sys
a = list(csv.DictReader(open(sys.argv[1])))
b = list(csv.DictReader(open(sys.argv[2])))
same = sum(1 for x, y in zip(a, b) if x["status"] == y["status"])
print(f"samples judged alike at both photon counts: {same} of {len(a)}")
PY

echo "== the worst sample baked by lucerna bake ($BAKE_PHOTONS photons, seed 7)"
bake=$WORK/bake
"$LUCERNA" bake "$out/worst.toml" --photons "$BAKE_PHOTONS" --seed 7 --formats ies \
  --symmetry none --out "$bake" > /dev/null 2>&1
ies=$(ls "$bake"/*.ies)
python3 - "$out/samples.csv" "$out/tolerance.json" <<'PY'
import csv, json, sys
worst = json.load(open(sys.argv[2]))["worst"]["index"]
row = next(r for r in csv.DictReader(open(sys.argv[1])) if int(r["sample"]) == worst)
print(f"analysis: sample {worst}: beam {float(row['beam_deg']):.3f}°, field {float(row['field_deg']):.3f}°, "
      f"above γ 3°: {float(row['cutoff_percent_of_peak']):.2f} % of the peak")
PY
"$LUCERNA" info "$ies" | grep -iE "beam|field" | head -4
