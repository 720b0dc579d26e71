#!/bin/bash
# Throughput of a split bake on this machine, in one run (the machine is
# shared: compare the ratios): one `lucerna bake` process; the same photons
# as one part (`--part 1/1`, the batch path with checkpoints every 5 min,
# and every 1 s for the overhead's upper bound); and as two parts traced
# by two processes at once, then merged.
#
#   deploy/bench-split.sh [SCENE]     (PHOTONS=60000000 RESOLUTION=256 LUCERNA=…)
set -euo pipefail
REPO=$(cd "$(dirname "$0")/.." && pwd)
LUCERNA=${LUCERNA:-$REPO/target/debug/lucerna}
SCENE=${1:-$REPO/assets/luminaires/parabolic_spot.toml}
PHOTONS=${PHOTONS:-60000000}
RESOLUTION=${RESOLUTION:-256}
WORK=$(mktemp -d -t lucerna-bench-split.XXXXXX)
trap 'rm -rf "$WORK"' EXIT
COMMON=(--photons "$PHOTONS" --resolution "$RESOLUTION" --backend cpu --date 2026-01-31)
now() { date +%s.%N; }
rate() { echo "scale=2; $PHOTONS / ($2 - $1) / 1000000" | bc; }

echo "$(basename "$SCENE"), $PHOTONS photons at ${RESOLUTION}², $(nproc) cores"
t0=$(now); "$LUCERNA" bake "$SCENE" "${COMMON[@]}" --out "$WORK/one" > /dev/null 2>&1; t1=$(now)
ONE=$(rate "$t0" "$t1")
printf '%-44s %6.1f s  %6s M photons/s\n' "one process (lucerna bake)" "$(echo "$t1 - $t0" | bc)" "$ONE"

t0=$(now); "$LUCERNA" bake "$SCENE" "${COMMON[@]}" --part 1/1 --out "$WORK/part" > /dev/null 2>&1; t1=$(now)
PART=$(rate "$t0" "$t1")
printf '%-44s %6.1f s  %6s M photons/s  (%.3f of one process)\n' "one process, --part 1/1 (checkpoint 5 min)" "$(echo "$t1 - $t0" | bc)" "$PART" "$(echo "$PART / $ONE" | bc -l)"

t0=$(now); "$LUCERNA" bake "$SCENE" "${COMMON[@]}" --part 1/1 --checkpoint 1s --out "$WORK/often" > /dev/null 2>&1; t1=$(now)
OFTEN=$(rate "$t0" "$t1")
printf '%-44s %6.1f s  %6s M photons/s  (%.3f of one process)\n' "one process, --part 1/1 (checkpoint 1 s)" "$(echo "$t1 - $t0" | bc)" "$OFTEN" "$(echo "$OFTEN / $ONE" | bc -l)"

t0=$(now)
"$LUCERNA" bake "$SCENE" "${COMMON[@]}" --part 1/2 --out "$WORK/two" > /dev/null 2>&1 &
A=$!
"$LUCERNA" bake "$SCENE" "${COMMON[@]}" --part 2/2 --out "$WORK/two" > /dev/null 2>&1 &
B=$!
wait $A $B
t1=$(now)
"$LUCERNA" merge "$WORK/two" --out "$WORK/merged" > /dev/null 2>&1
t2=$(now)
TWO=$(rate "$t0" "$t1")
printf '%-44s %6.1f s  %6s M photons/s  (%.3f of one process)\n' "two processes at once, --part 1/2 and 2/2" "$(echo "$t1 - $t0" | bc)" "$TWO" "$(echo "$TWO / $ONE" | bc -l)"
printf '%-44s %6.1f s\n' "  then lucerna merge of the two" "$(echo "$t2 - $t1" | bc)"
cmp -s "$WORK/one/$(basename "${SCENE%.*}").exr" "$WORK/merged/$(basename "${SCENE%.*}").exr" \
    && echo "merged EXR = one process's EXR (same counts)" || { echo "merged EXR DIFFERS" >&2; exit 1; }
