#!/bin/bash
# Submits a split Lucerna bake to Slurm: the job array of its parts and
# the merge as a job that starts only once every part succeeded
# (--dependency=afterok).
#
#   deploy/slurm/submit.sh SCENE PHOTONS PARTS OUT RESULT [sbatch options...]
#
# e.g. deploy/slurm/submit.sh /shared/spot.toml 100000000000 64 /shared/spot-parts /shared/spot \
#          --partition=cpu --cpus-per-task=16 --time=2:00:00
# LUCERNA, CHECKPOINT and BAKE_ARGS are passed on from the environment
# (see bake-array.sbatch). Prints the two job ids.
set -euo pipefail
if (($# < 5)); then
    sed -n '2,12p' "$0" >&2
    exit 2
fi
[[ -f $1 ]] || { echo "submit.sh: no scene file $1" >&2; exit 2; }
SCENE=$(realpath "$1")
PHOTONS=$2
PARTS=$3
OUT=$(realpath -m "$4")
RESULT=$(realpath -m "$5")
shift 5
HERE=$(cd "$(dirname "$0")" && pwd)
mkdir -p "$OUT"
export SCENE PHOTONS OUT RESULT
ARRAY=$(sbatch --parsable --array="1-$PARTS" --export=ALL "$@" "$HERE/bake-array.sbatch")
ARRAY=${ARRAY%%;*}
# The same options (partition, account, …) for the merge.
MERGE=$(sbatch --parsable --dependency="afterok:$ARRAY" --kill-on-invalid-dep=yes --export=ALL \
    "$@" "$HERE/merge.sbatch")
MERGE=${MERGE%%;*}
echo "parts: job array $ARRAY (tasks 1-$PARTS); merge: job $MERGE after all of them"
