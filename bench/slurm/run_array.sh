#!/usr/bin/env bash
# Runs a shearsph sweep as a Slurm job array on a one-node Slurm configured
# here, in a temporary folder, on localhost (munged, slurmctld, slurmd), then
# merges the shards in a dependent job and compares the merged rows with a
# single-machine sweep of the same grid. Optional; not part of cargo test.
#
# Needs: Debian's munge, slurmctld, slurmd and slurm-client
# (apt-get install slurm-wlm munge), root (the daemons run as root here),
# and a release build (cargo build --release).
#
#   bench/slurm/run_array.sh            # keeps its folder, prints its path
#   FAIL_TASK=1 bench/slurm/run_array.sh   # task 1 killed once, named, resubmitted alone
set -euo pipefail
HERE=$(cd "$(dirname "$0")" && pwd)
REPO=$(cd "$HERE/../.." && pwd)
export SHEARSPH=${SHEARSPH:-$REPO/target/release/shearsph}
export GRID=$HERE/grid.toml
TASKS=${TASKS:-4}
[ -x "$SHEARSPH" ] || { echo "no $SHEARSPH: run cargo build --release" >&2; exit 1; }
for c in munged slurmctld slurmd sbatch squeue scontrol sinfo; do
    command -v "$c" >/dev/null || { echo "missing $c: apt-get install slurm-wlm munge" >&2; exit 1; }
done

W=$(mktemp -d /tmp/shearsph-slurm.XXXXXX)
export OUT=$W/out
mkdir -p "$W/munge" "$W/spool/ctld" "$W/spool/d" "$W/log" "$OUT"
echo "working folder: $W"

# --- munge, with a key of its own
dd if=/dev/urandom of="$W/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$W/munge/munge.key"
MUNGE_SOCKET=$W/munge/munge.socket
munged --force --key-file="$W/munge/munge.key" --socket="$MUNGE_SOCKET" \
    --pid-file="$W/munge/munged.pid" --log-file="$W/log/munged.log" \
    --seed-file="$W/munge/munged.seed"

stop() {
    for p in "$W/slurmd.pid" "$W/slurmctld.pid" "$W/munge/munged.pid"; do
        [ -s "$p" ] && kill "$(cat "$p")" 2>/dev/null || true
    done
}
trap stop EXIT

# --- a one-node cluster on localhost
CPUS=$(nproc)
cat > "$W/slurm.conf" <<CONF
ClusterName=shearsph
SlurmctldHost=localhost
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$MUNGE_SOCKET
SlurmctldPort=16817
SlurmdPort=16818
StateSaveLocation=$W/spool/ctld
SlurmdSpoolDir=$W/spool/d
SlurmctldPidFile=$W/slurmctld.pid
SlurmdPidFile=$W/slurmd.pid
SlurmctldLogFile=$W/log/slurmctld.log
SlurmdLogFile=$W/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SwitchType=switch/none
MpiDefault=none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
ReturnToService=2
JobCompType=jobcomp/filetxt
JobCompLoc=$W/log/jobcomp.log
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
NodeName=localhost NodeAddr=127.0.0.1 CPUs=$CPUS State=UNKNOWN
PartitionName=local Nodes=localhost Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$W/slurm.conf
slurmctld -f "$SLURM_CONF"
slurmd -f "$SLURM_CONF" -N localhost
for _ in $(seq 60); do
    sinfo -h -o %t 2>/dev/null | grep -q idle && break
    sleep 1
done
echo "+ sinfo"; sinfo

# --- the array and the dependent merge
cd "$W"
# FAIL_TASK=K: task K's first attempt is killed (SIGKILL, as a node failure
# or the OOM killer would) once its folder records its shard; the script
# then names it, cancels the merge waiting on it, and resubmits that task
# alone (--array=K), which keeps its shard (shard.toml) and resumes.
REAL=$SHEARSPH
if [ -n "${FAIL_TASK:-}" ]; then
    cat > "$W/flaky-shearsph" <<FLAKY
#!/bin/bash
if [ "\${SLURM_ARRAY_TASK_ID:-}" = "$FAIL_TASK" ] && [ ! -e "$W/failed-once" ]; then
    touch "$W/failed-once"
    "$REAL" "\$@" & pid=\$!
    for _ in \$(seq 300); do [ -e "$OUT/s$FAIL_TASK/shard.toml" ] && break; sleep 0.1; done
    kill -9 \$pid; echo "injected failure: task $FAIL_TASK killed" >&2; exit 137
fi
exec "$REAL" "\$@"
FLAKY
    chmod +x "$W/flaky-shearsph"
    export SHEARSPH=$W/flaky-shearsph
fi
echo "+ sbatch --array=0-$((TASKS - 1)) $HERE/sweep_array.sbatch"
ARRAY=$(sbatch --parsable --array=0-$((TASKS - 1)) "$HERE/sweep_array.sbatch")
echo "Submitted batch job $ARRAY"
echo "+ sbatch --dependency=afterok:$ARRAY $HERE/merge.sbatch"
MERGE=$(sbatch --parsable --dependency=afterok:"$ARRAY" "$HERE/merge.sbatch")
echo "Submitted batch job $MERGE"

# The array tasks of job $1 that ended other than COMPLETED, one a line
# ("1_2 FAILED 1:0"), from the job records.
failed_tasks() {
    [ -f "$W/log/jobcomp.log" ] || return 0
    python3 - "$W/log/jobcomp.log" "$1" <<'PY'
import sys
for line in open(sys.argv[1]):
    f = dict(kv.split("=", 1) for kv in line.split() if "=" in kv)
    if f.get("ArrayJobId") == sys.argv[2] and f.get("ArrayTaskId") and f.get("JobState") != "COMPLETED":
        print(f"{f['ArrayJobId']}_{f['ArrayTaskId']} {f['JobState']} {f.get('ExitCode', '?')}")
PY
}

# Wait for the queue to empty, printing it every 2 s; a failed array task
# of job $1 is named at once (with its output) and the merge $2 that waits
# on it (afterok: it never runs) is cancelled. Status 1 then.
wait_queue() {
    local array=$1 merge=$2 start bad
    start=$(date +%s)
    echo "+ squeue (every 2 s until the queue is empty)"
    while [ -n "$(squeue -h)" ]; do
        echo "--- $(($(date +%s) - start)) s"
        squeue -o "%.10i %.16j %.8T %.10M %.6D %R"
        bad=$(failed_tasks "$array")
        if [ -n "$bad" ]; then
            echo "array task(s) of job $array ended badly (task, state, exit):"
            echo "$bad" | sed 's/^/  /'
            for t in $(echo "$bad" | cut -d' ' -f1); do
                echo "+ shearsph-sweep-$t.out"; cat "shearsph-sweep-$t.out" 2>/dev/null || true
            done
            echo "+ scancel $merge (it waits on job $array with afterok: it would never run)"
            scancel "$merge"
            while [ -n "$(squeue -h -j "$merge" 2>/dev/null)" ]; do sleep 1; done
            return 1
        fi
        sleep 2
        [ $(($(date +%s) - start)) -lt 900 ] || { echo "timed out after 900 s" >&2; exit 1; }
    done
}

if ! wait_queue "$ARRAY" "$MERGE"; then
    [ -n "${FAIL_TASK:-}" ] || exit 1
    ids=$(failed_tasks "$ARRAY" | cut -d' ' -f1 | cut -d_ -f2 | paste -sd,)
    echo "+ sbatch --array=$ids $HERE/sweep_array.sbatch (the failed task(s) alone: each keeps its shard)"
    ARRAY=$(sbatch --parsable --array="$ids" "$HERE/sweep_array.sbatch")
    echo "Submitted batch job $ARRAY"
    echo "+ sbatch --dependency=afterok:$ARRAY $HERE/merge.sbatch"
    MERGE=$(sbatch --parsable --dependency=afterok:"$ARRAY" "$HERE/merge.sbatch")
    echo "Submitted batch job $MERGE"
    wait_queue "$ARRAY" "$MERGE" || exit 1
fi
echo "+ the jobs as Slurm recorded them (jobcomp/filetxt; sacct needs slurmdbd, not set up here)"
python3 - "$W/log/jobcomp.log" <<'PY'
import sys
print(f"{'JobId':>6} {'Array':>8} {'Name':>15} {'State':>10} {'Start':>20} {'End':>20} {'Exit':>5}")
for line in open(sys.argv[1]):
    f = dict(kv.split("=", 1) for kv in line.split() if "=" in kv)
    arr = f"{f['ArrayJobId']}_{f['ArrayTaskId']}" if f.get("ArrayTaskId") else ""
    print(f"{f['JobId']:>6} {arr:>8} {f['Name']:>15} {f['JobState']:>10} {f['StartTime']:>20} {f['EndTime']:>20} {f['ExitCode']:>5}")
PY
echo "+ scontrol show job $ARRAY (array summary)"
scontrol show job "$ARRAY" 2>/dev/null | grep -E "JobId|JobState" || echo "(purged from slurmctld's memory)"
for f in shearsph-sweep-*.out shearsph-merge-"$MERGE".out; do
    echo "+ $f"; cat "$f"
done
[ -s "$OUT/merged/results.jsonl" ] || { echo "the merge job wrote no rows" >&2; exit 1; }

# --- the same grid on this machine alone
echo "+ shearsph sweep --sweep grid.toml --out single (one machine)"
"$REAL" sweep --sweep "$GRID" --out "$W/single" --jobs 1 --quiet --no-charts

# The wall-clock fields differ between any two runs of a point: left out,
# the same list as the rows' own (Row::TIMING_FIELDS in src/studies/sweep/row.rs).
echo "+ compare merged/results.jsonl with single/results.jsonl"
python3 - "$OUT/merged/results.jsonl" "$W/single/results.jsonl" <<'PY'
import json, sys
TIMING = {"wall_s", "particle_steps_per_s"}
def rows(p):
    return {r["index"]: r for r in map(json.loads, open(p))}
a, b = rows(sys.argv[1]), rows(sys.argv[2])
print(f"merged: {len(a)} rows, single machine: {len(b)} rows, same points: {sorted(a) == sorted(b)}")
differ = {}
for i in sorted(set(a) & set(b)):
    for k in sorted(set(a[i]) | set(b[i])):
        if a[i].get(k) != b[i].get(k):
            differ.setdefault(k, []).append(i)
for k, idx in differ.items():
    print(f"  field {k!r} differs in {len(idx)} of {len(a)} rows{' (wall clock)' if k in TIMING else ''}")
other = set(differ) - TIMING
print("identical except wall-clock fields" if not other and sorted(a) == sorted(b) else f"DIFFERENT: {sorted(other)}")
sys.exit(1 if other or sorted(a) != sorted(b) else 0)
PY
