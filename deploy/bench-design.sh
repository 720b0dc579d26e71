#!/bin/bash
# `lucerna design` against targets of known shape, on this machine, in one
# run (issues "Design from the light you want" and "Design that works on
# what it has not seen"):
#   focal      the parabolic spot's bake at f = 30 mm as the target, the
#              design started at f = 25 mm, varying the focal length;
#   profile    the revolved reflector's bake (a 5-point Catmull-Rom mirror
#              around a 3 mm LED, 80 mm aperture, 60 mm deep), the design
#              started from the straight cone between the same ends;
#   profile2   the same with interior points (18, -12), (27, -27),
#              (34, -43) mm (a 4.2 degree beam);
#   profile3   the same bulging inward: (11, -12), (18, -28), (28, -44) mm;
#   heldout-K  the held-out set: HELD_OUT_COUNT profiles of the same kind
#              drawn by deploy/design-profiles.py from HELD_OUT_SEED, a
#              seed no development or tuning ever looked at;
#   real-*     makers' measured files of rotationally symmetric reflector
#              spots (REAL_FILES: shared/photometry-samples/reflector-lamps,
#              their sources and licences beside them), designed from the
#              cone with --free-ends and compared on each file's own grid.
# Each profile target is baked with TARGET_PHOTONS photons (seed 99); its
# floor is the hidden scene itself baked with another seed and measured
# alike (a measured file has none: its reachability bound is given
# instead). Each case is designed for each of TIMES seconds; a line per
# case gives the start, the floor, the remaining difference (relative L2
# on the sphere) at each time, the point count the design chose and the
# bound it stated; then the held-out set's median and worst of the
# remaining difference over the floor.
#
#   deploy/bench-design.sh      (LUCERNA=… TARGET_PHOTONS=30000000 DESIGN_SEED=1
#                                TIMES="30 60 120" CASES="focal heldout-1 …")
set -euo pipefail
REPO=$(cd "$(dirname "$0")/.." && pwd)
LUCERNA=${LUCERNA:-$REPO/target/release/lucerna}
TARGET_PHOTONS=${TARGET_PHOTONS:-30000000}
TIMES=${TIMES:-30 60 120}
HELD_OUT_SEED=${HELD_OUT_SEED:-20261207}
HELD_OUT_COUNT=${HELD_OUT_COUNT:-8}
REAL_FILES=${REAL_FILES:-$REPO/../shared/photometry-samples/reflector-lamps}
WORK=$(mktemp -d -t lucerna-bench-design.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
DESIGNS=$REPO/assets/designs
CONE=$DESIGNS/revolved_cone_start.toml

# A hidden scene: the revolved reflector with another profile.
with_profile() { # profile-array out
  python3 - "$1" "$DESIGNS/revolved_reflector.toml" > "$2" <<'PY'
import re, sys
text = open(sys.argv[2]).read()
new = re.sub(r"profile = \[\[.*?\]\]", "profile = " + sys.argv[1], text, count=1)
assert new != text
print(new, end="")
PY
}

remaining() { grep "^remaining" "$1" | sed -E 's/.*: ([0-9.]+) \(the start: ([0-9.]+)\)/\1 \2/'; }

# name hidden-scene-or-file start-scene vary [extra design args…]
run_case() {
  local name=$1 hidden=$2 scene=$3 vary=$4
  shift 4
  if [ -n "${CASES:-}" ] && ! [[ " $CASES " == *" $name "* ]]; then
    return
  fi
  mkdir -p "$WORK/$name"
  local target floor="-"
  if [[ $hidden == *.toml ]]; then
    "$LUCERNA" bake "$hidden" --photons "$TARGET_PHOTONS" --seed 99 --formats ies --date 2026-12-04 \
      --name target --out "$WORK/$name/target" > /dev/null 2>&1
    target=$WORK/$name/target/target.ies
    "$LUCERNA" design "$hidden" --target "$target" --vary "$vary" --evaluations 1 --no-direct --seed 7 \
      --date 2026-12-04 --out "$WORK/$name/floor" > "$WORK/$name/floor.txt" 2>/dev/null
    floor=$(remaining "$WORK/$name/floor.txt" | cut -d' ' -f1)
  else
    target=$hidden
  fi
  local start="-" points="-" bound="-" results="" result start_merit
  for t in $TIMES; do
    local out=$WORK/$name/design-$t.txt
    "$LUCERNA" design "$scene" --target "$target" --vary "$vary" --time "${t}s" --seed "${DESIGN_SEED:-1}" \
      --date 2026-12-04 --out "$WORK/$name/design-$t" "$@" > "$out" 2> "$WORK/$name/log-$t.txt" || true
    read -r result start_merit < <(remaining "$out" || echo "- -")
    start=${start_merit:-$start}
    results="$results ${t}s ${result:--}"
    points=$(grep -oE "[0-9]+ control points" "$out" | grep -oE "^[0-9]+" || echo "-")
    bound=$(grep -oE "cone can come closer than [0-9.]+" "$out" | grep -oE "[0-9.]+$" || echo "-")
    cp "$WORK/$name/design-$t/design.csv" "${OUT_DIR:-$WORK}/design-$name-$t.csv" 2>/dev/null || true
    grep -E "^(warning|what would help)" "$WORK/$name/log-$t.txt" "$out" 2>/dev/null | sed "s/^/  $name ${t}s: /" || true
  done
  printf '%-12s start %-7s floor %-7s %s   points %s  bound %s\n' "$name" "$start" "$floor" "$results" "$points" "$bound"
  echo "$name $floor$results" >> "$WORK/summary"
}

echo "== lucerna design benchmark: $(nproc) cores, times: $TIMES s, targets $TARGET_PHOTONS photons, held-out seed $HELD_OUT_SEED"
sed 's/focal_length = 0.025/focal_length = 0.03/' "$REPO/assets/luminaires/parabolic_spot.toml" > "$WORK/spot_f30.toml"
run_case focal "$WORK/spot_f30.toml" "$REPO/assets/luminaires/parabolic_spot.toml" reflector.focal_length
run_case profile "$DESIGNS/revolved_reflector.toml" "$CONE" reflector.profile
with_profile "[[0.006, 0.0], [0.018, -0.012], [0.027, -0.027], [0.034, -0.043], [0.04, -0.06]]" "$WORK/profile2.toml"
run_case profile2 "$WORK/profile2.toml" "$CONE" reflector.profile
with_profile "[[0.006, 0.0], [0.011, -0.012], [0.018, -0.028], [0.028, -0.044], [0.04, -0.06]]" "$WORK/profile3.toml"
run_case profile3 "$WORK/profile3.toml" "$CONE" reflector.profile
k=0
while read -r profile; do
  k=$((k + 1))
  with_profile "$profile" "$WORK/heldout-$k.toml"
  echo "   heldout-$k: $profile"
  run_case "heldout-$k" "$WORK/heldout-$k.toml" "$CONE" reflector.profile
done < <(python3 "$REPO/deploy/design-profiles.py" "$HELD_OUT_SEED" "$HELD_OUT_COUNT")
if [ -d "$REAL_FILES" ]; then
  for f in "$REAL_FILES"/*.ies "$REAL_FILES"/*.ldt; do
    [ -f "$f" ] || continue
    run_case "real-$(basename "${f%.*}" | cut -c1-12)" "$f" "$CONE" reflector.profile --free-ends
  done
fi
# The held-out set's remaining difference over its floor, at the longest time.
awk '$1 ~ /^heldout/ && $2 != "-" { r = $NF / $2; print r }' "$WORK/summary" | sort -g | awk '
  { v[NR] = $1 } END { if (NR) printf "held-out set: %d profiles, remaining / floor median %.2f, worst %.2f\n", NR, (NR % 2 ? v[(NR + 1) / 2] : 0.5 * (v[NR / 2] + v[NR / 2 + 1])), v[NR] }'
