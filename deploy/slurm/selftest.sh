#!/bin/bash
# A real Slurm on this machine, for the split bake: starts munged, a
# single-node slurmctld and slurmd (this host the only node, everything
# under a temporary folder, ports of its own), submits the job array of an
# example luminaire in 4 parts and the dependent merge (submit.sh), waits,
# and compares the merged files with a bake of the same photons in one
# process: the counts (EXR), IES and LDT must be the same bytes. Stops
# every daemon it started, whatever happens. On the way it requeues the
# second task while it traces (`scontrol requeue`: SIGTERM, then a new
# start), which must go on from its final checkpoint.
#
#   deploy/slurm/selftest.sh            # uses target/{release,debug}/lucerna
#   LUCERNA=/path/to/lucerna deploy/slurm/selftest.sh
#
# Needs Debian's slurm-wlm and munge (apt-get install slurm-wlm munge) and
# root (slurmd runs jobs as their user). KEEP=1 keeps the work folder.
set -euo pipefail
START=$(date +%s.%N)
REPO=$(cd "$(dirname "$0")/../.." && pwd)
if [[ -z ${LUCERNA:-} ]]; then
    for b in "$REPO/target/release/lucerna" "$REPO/target/debug/lucerna"; do
        if [[ -x $b ]]; then LUCERNA=$b; break; fi
    done
fi
: "${LUCERNA:?build lucerna first (cargo build -p lucerna-cli) or set LUCERNA}"
for tool in munged slurmctld slurmd sbatch squeue scontrol sinfo; do
    command -v "$tool" > /dev/null || { echo "selftest: $tool is missing (apt-get install slurm-wlm munge)" >&2; exit 2; }
done
SCENE=${SCENE:-$REPO/assets/luminaires/parabolic_spot.toml}
PHOTONS=${PHOTONS:-24000000}
PARTS=4
BAKE_ARGS="--resolution 64 --backend cpu --date 2026-01-31"

WORK=$(mktemp -d -t lucerna-slurm-selftest.XXXXXX)
PIDS=()
cleanup() {
    local rc=$?
    # The jobs first: their processes outlive slurmd.
    if [[ -n ${SLURM_CONF:-} ]]; then
        scancel --full --quiet --user=root 2> /dev/null || true
        for _ in $(seq 100); do [[ -z $(squeue -h 2> /dev/null) ]] && break; sleep 0.1; done
    fi
    for pid in "${PIDS[@]}"; do kill "$pid" 2> /dev/null || true; done
    for pid in "${PIDS[@]}"; do
        for _ in $(seq 50); do kill -0 "$pid" 2> /dev/null || break; sleep 0.1; done
        kill -9 "$pid" 2> /dev/null || true
    done
    if ((rc != 0)); then
        echo "selftest: FAILED; the daemons' logs:" >&2
        tail -n 20 "$WORK"/*.log >&2 2> /dev/null || true
    fi
    if [[ -z ${KEEP:-} ]]; then rm -rf "$WORK"; else echo "selftest: kept $WORK"; fi
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# A free TCP port on the loopback.
free_port() { python3 -c 'import socket; s=socket.socket(); s.bind(("127.0.0.1",0)); print(s.getsockname()[1])'; }
HOST=$(hostname -s)
CPUS=$(nproc)
MEMORY=$(($(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 * 9 / 10))
mkdir -p "$WORK"/{munge,state,spool,jobs}
chmod 700 "$WORK/munge"

# munge with its own key and socket, so it touches nothing of the system's.
dd if=/dev/urandom of="$WORK/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$WORK/munge/munge.key"
SOCKET="$WORK/munge/munge.socket"
munged --force --foreground --socket="$SOCKET" --key-file="$WORK/munge/munge.key" \
    --pid-file="$WORK/munge/munged.pid" --seed-file="$WORK/munge/munge.seed" \
    --log-file="$WORK/munged.log" > "$WORK/munged.out" 2>&1 &
PIDS+=($!)

CONF="$WORK/slurm.conf"
cat > "$CONF" << CONF
ClusterName=lucerna-selftest
SlurmctldHost=$HOST
SlurmctldPort=$(free_port)
SlurmdPort=$(free_port)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$SOCKET
StateSaveLocation=$WORK/state
SlurmdSpoolDir=$WORK/spool
SlurmctldPidFile=$WORK/slurmctld.pid
SlurmdPidFile=$WORK/slurmd.pid
SlurmctldLogFile=$WORK/slurmctld.log
SlurmdLogFile=$WORK/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/builtin
MpiDefault=none
ReturnToService=2
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
PlugStackConfig=$WORK/plugstack.conf
MinJobAge=600
SlurmdTimeout=60
NodeName=$HOST CPUs=$CPUS RealMemory=$MEMORY State=UNKNOWN
PartitionName=selftest Nodes=$HOST Default=YES MaxTime=INFINITE State=UP
CONF
: > "$WORK/plugstack.conf"
export SLURM_CONF=$CONF

for _ in $(seq 100); do [[ -S $SOCKET ]] && break; sleep 0.1; done
slurmctld -D -i -f "$CONF" > "$WORK/slurmctld.out" 2>&1 &
PIDS+=($!)
slurmd -D -N "$HOST" -f "$CONF" > "$WORK/slurmd.out" 2>&1 &
PIDS+=($!)
UP=""
for _ in $(seq 120); do
    if [[ $(sinfo -h -N -o %t 2> /dev/null) == idle ]]; then UP=1; break; fi
    sleep 0.5
done
[[ -n $UP ]] || { echo "selftest: the node did not come up within 60 s" >&2; exit 1; }
printf 'selftest: Slurm up in %.1f s (node %s, %s CPUs)\n' "$(echo "$(date +%s.%N) - $START" | bc)" "$HOST" "$CPUS"

cd "$WORK/jobs"
export LUCERNA BAKE_ARGS CHECKPOINT=1s
SUBMITTED=$("$REPO/deploy/slurm/submit.sh" "$SCENE" "$PHOTONS" "$PARTS" "$WORK/parts" "$WORK/merged" --cpus-per-task=1)
echo "selftest: $SUBMITTED"
MERGE_JOB=$(echo "$SUBMITTED" | sed -n 's/.*merge: job \([0-9]*\).*/\1/p')
ARRAY_JOB=$(echo "$SUBMITTED" | sed -n 's/.*job array \([0-9]*\).*/\1/p')

# Task 2 requeued once it has written a checkpoint, as a preempting
# scheduler does.
STEM=$(basename "${SCENE%.*}")
for _ in $(seq 600); do
    [[ -f $WORK/parts/$STEM.part-2-of-$PARTS.json ]] && break
    sleep 0.1
done
if grep -q '"complete": false' "$WORK/parts/$STEM.part-2-of-$PARTS.json" \
    && scontrol requeue "${ARRAY_JOB}_2" 2> /dev/null; then
    # A requeued job is held back 2 minutes before it may start again.
    for _ in $(seq 100); do
        [[ $(scontrol show job "${ARRAY_JOB}_2" | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p' | head -n 1) == PENDING ]] && break
        sleep 0.1
    done
    scontrol update jobid="${ARRAY_JOB}_2" StartTime=now
    echo "selftest: requeued task 2 while it traced"
    REQUEUED=1
else
    echo "selftest: task 2 finished before it could be requeued (raise PHOTONS)" >&2
    exit 1
fi

# Meanwhile, the same photons in one process.
"$LUCERNA" bake "$SCENE" --photons "$PHOTONS" $BAKE_ARGS --out "$WORK/single" > "$WORK/single.log" 2>&1

state() { scontrol show job "$1" 2> /dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p' | head -n 1; }
for _ in $(seq 600); do
    case $(state "$MERGE_JOB") in
        COMPLETED) break ;;
        FAILED | CANCELLED | TIMEOUT | NODE_FAIL | OUT_OF_MEMORY)
            echo "selftest: the merge job ended $(state "$MERGE_JOB")" >&2
            tail -n 20 "$WORK"/jobs/*.out >&2
            exit 1 ;;
    esac
    sleep 0.5
done
[[ $(state "$MERGE_JOB") == COMPLETED ]] || { echo "selftest: the merge did not finish within 5 min" >&2; exit 1; }
echo "selftest: the tasks said:"
grep -h -e "^lucerna-bake: task" -e "complete" -e "parts merged" "$WORK"/jobs/*.out | sed 's/^/  /'

if [[ -n $REQUEUED ]]; then
    grep -q "stopped by a signal" "$WORK"/jobs/lucerna-bake-*_2.out \
        && grep -q "going on from it" "$WORK"/jobs/lucerna-bake-*_2.out \
        || { echo "selftest: the requeued task did not checkpoint and resume" >&2; exit 1; }
    echo "selftest: the requeued task wrote a checkpoint on SIGTERM and went on from it:"
    grep -h -e "stopped by a signal" -e "resuming part" "$WORK"/jobs/lucerna-bake-*_2.out | sed 's/^/  /'
fi
SAME=1
for f in "$STEM.exr" "$STEM.ies" "$STEM.ldt"; do
    if cmp -s "$WORK/single/$f" "$WORK/merged/$f"; then
        echo "selftest: $f of the merged $PARTS parts = the single run's ($(stat -c %s "$WORK/merged/$f") bytes)"
    else
        echo "selftest: $f of the merged parts DIFFERS from the single run's" >&2
        SAME=""
    fi
done
[[ -n $SAME ]] || exit 1
printf 'selftest: passed in %.1f s wall\n' "$(echo "$(date +%s.%N) - $START" | bc)"
