#!/bin/bash
# `lucerna design` against targets of known shape (issue "Design from the
# light you want"), on this machine, in one run:
#   1. single parameter: the parabolic spot's bake at f = 30 mm as the
#      target, the design started at f = 25 mm, varying the focal length
#      (60 s);
#   2. profile: the revolved reflector's bake (a 5-point Catmull-Rom
#      mirror around a 3 mm LED, 80 mm aperture, 60 mm deep) as the
#      target, the design started from a straight cone between the same
#      ends, varying the profile (120 s);
#   3. the same with a second hidden profile (interior points (18, -12),
#      (27, -27), (34, -43) mm: a 4.2 degree beam), 120 s;
#   4. the same with a third, bulging inward (interior points (11, -12),
#      (18, -28), (28, -44) mm: a wide beam, the start only 0.26 away),
#      120 s.
# Each target is baked with 30 M photons (seed 99); the Monte Carlo floor
# is the hidden scene itself baked with another seed and measured alike.
# Prints the remaining difference (relative L2 on the sphere) and the
# best merit of each stage against time (design.csv).
#
#   deploy/bench-design.sh        (LUCERNA=… TARGET_PHOTONS=30000000 DESIGN_SEED=1)
set -euo pipefail
REPO=$(cd "$(dirname "$0")/.." && pwd)
LUCERNA=${LUCERNA:-$REPO/target/debug/lucerna}
TARGET_PHOTONS=${TARGET_PHOTONS:-30000000}
WORK=$(mktemp -d -t lucerna-bench-design.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
DESIGNS=$REPO/assets/designs
sed 's/focal_length = 0.025/focal_length = 0.03/' "$REPO/assets/luminaires/parabolic_spot.toml" > "$WORK/spot_f30.toml"
sed 's/\[0.014, -0.008\], \[0.024, -0.021\], \[0.033, -0.039\]/[0.018, -0.012], [0.027, -0.027], [0.034, -0.043]/' \
  "$DESIGNS/revolved_reflector.toml" > "$WORK/revolved_reflector_2.toml"
grep -q '0.018, -0.012' "$WORK/revolved_reflector_2.toml"
sed 's/\[0.014, -0.008\], \[0.024, -0.021\], \[0.033, -0.039\]/[0.011, -0.012], [0.018, -0.028], [0.028, -0.044]/' \
  "$DESIGNS/revolved_reflector.toml" > "$WORK/revolved_reflector_3.toml"
grep -q '0.011, -0.012' "$WORK/revolved_reflector_3.toml"

run_case() { # name hidden start vary time
  local name=$1 hidden=$2 start=$3 vary=$4 time=$5
  "$LUCERNA" bake "$hidden" --photons "$TARGET_PHOTONS" --seed 99 --formats ies --date 2026-12-04 \
    --name target --out "$WORK/$name/target" > /dev/null 2>&1
  local target=$WORK/$name/target/target.ies
  echo "== $name: $(basename "$start") toward $(basename "$hidden")'s bake, --vary $vary, --time $time, $(nproc) cores"
  "$LUCERNA" design "$hidden" --target "$target" --vary "$vary" --evaluations 1 --no-direct --seed 7 \
    --date 2026-12-04 --out "$WORK/$name/floor" 2>/dev/null | grep "remaining" | sed 's/^/floor (the hidden scene, another seed): /'
  "$LUCERNA" design "$start" --target "$target" --vary "$vary" --time "$time" --seed "${DESIGN_SEED:-1}" --date 2026-12-04 \
    --out "$WORK/$name/design" 2>/dev/null | grep -v "^wrote"
  echo "best merit per stage (measure, photons): seconds"
  awk -F, 'NR > 1 && $4 != "" {
      key = $5 " " $3
      if (!(key in best) || $4 < best[key]) { best[key] = $4; at[key] = $2 }
      if (!(key in order)) { order[key] = ++n; keys[n] = key }
    }
    END { for (i = 1; i <= n; i++) printf "  %-28s %.5f at %6.1f s\n", keys[i], best[keys[i]], at[keys[i]] }' \
    "$WORK/$name/design/design.csv"
  cp "$WORK/$name/design/design.csv" "${OUT_DIR:-$WORK}/design-$name.csv" 2>/dev/null || true
}

run_case focal "$WORK/spot_f30.toml" "$REPO/assets/luminaires/parabolic_spot.toml" reflector.focal_length 60s
run_case profile "$DESIGNS/revolved_reflector.toml" "$DESIGNS/revolved_cone_start.toml" reflector.profile 120s
run_case profile2 "$WORK/revolved_reflector_2.toml" "$DESIGNS/revolved_cone_start.toml" reflector.profile 120s
run_case profile3 "$WORK/revolved_reflector_3.toml" "$DESIGNS/revolved_cone_start.toml" reflector.profile 120s
