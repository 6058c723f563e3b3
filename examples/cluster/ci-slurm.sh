#!/usr/bin/env bash
# Runs examples/cluster/sweep-array.slurm (the very file users submit) on a real single-node Slurm
# started on this machine, and checks it:
#
#   1. the array runs, its shard stores merge into a store equal to a single-process sweep of the
#      same plan (`mrbrake export --json`, metrics within the merge tolerance 1e-9);
#   2. an interrupted array: one task is cancelled (`scancel`) mid-run, the array is resubmitted,
#      and nothing is lost (same merged store) or recomputed (the resumed task reuses every design
#      stored before the cancel and computes only the rest).
#
# Needs Debian's slurm-wlm and munge (apt-get install slurm-wlm munge), python3 and root (slurmd
# runs jobs as the submitting user; as root no user set-up is needed). No cgroups are used
# (proctrack/linuxproc, task/none), so it runs in containers. Everything lives in a temporary folder;
# the daemons are stopped on exit.
#
#   examples/cluster/ci-slurm.sh                   # uses target/release/mrbrake
#   MRBRAKE=/path/to/mrbrake MRBRAKE_SAMPLE=sobol:64 examples/cluster/ci-slurm.sh
#
# Environment: MRBRAKE (binary), MRBRAKE_SAMPLE (plan, default sobol:24), MRBRAKE_SHARDS (array
# size, default 2), MRBRAKE_EXTRA (more sweep flags, e.g. "--mesh coarse"), SLURM_TEST_DIR (work
# folder, default a new one under /tmp), KEEP=1 keeps it.
set -euo pipefail

ROOT=$(cd "$(dirname "$0")/../.." && pwd)
SCRIPT="$ROOT/examples/cluster/sweep-array.slurm"
export MRBRAKE=${MRBRAKE:-$ROOT/target/release/mrbrake}
export MRBRAKE_SAMPLE=${MRBRAKE_SAMPLE:-sobol:24}
export MRBRAKE_SHARDS=${MRBRAKE_SHARDS:-2}
export MRBRAKE_EXTRA=${MRBRAKE_EXTRA:-}
export MRBRAKE_SPEC="$ROOT/examples/specs/thesis-bidirectional.toml"
WORK=${SLURM_TEST_DIR:-$(mktemp -d /tmp/mrbrake-slurm.XXXXXX)}
mkdir -p "$WORK"
WORK=$(cd "$WORK" && pwd)
LAST=$((MRBRAKE_SHARDS - 1))

now() { date +%s.%N; }
elapsed() { python3 -c "import sys; print(f'{float(sys.argv[2]) - float(sys.argv[1]):.1f}')" "$1" "$2"; }
say() { echo "== slurm: $*"; }
fail() { echo "FAILED: $*" >&2; exit 1; }

for tool in slurmctld slurmd munged sbatch squeue scancel python3; do
  command -v "$tool" >/dev/null || fail "$tool not found (apt-get install slurm-wlm munge python3)"
done
[ -x "$MRBRAKE" ] || fail "no mrbrake binary at $MRBRAKE (cargo build --release -p mrbrake-cli)"

# --- a single-node Slurm on localhost -------------------------------------------------------------
start_slurm() {
  mkdir -p "$WORK/munge" "$WORK/state" "$WORK/spool" "$WORK/log"
  chmod 700 "$WORK/munge"
  dd if=/dev/urandom of="$WORK/munge/munge.key" bs=1024 count=1 status=none
  chmod 400 "$WORK/munge/munge.key"
  munged --force --key-file="$WORK/munge/munge.key" --socket="$WORK/munge/munge.socket" \
    --pid-file="$WORK/munge/munged.pid" --log-file="$WORK/log/munged.log" \
    --seed-file="$WORK/munge/munged.seed"
  local cpus mem_mb
  cpus=$(nproc)
  mem_mb=$(awk '/MemTotal/ { printf "%d", $2 / 1024 * 0.8 }' /proc/meminfo)
  cat >"$WORK/slurm.conf" <<CONF
ClusterName=mrbrake-ci
SlurmctldHost=localhost
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$WORK/munge/munge.socket
SlurmctldPort=${SLURMCTLD_PORT:-16817}
SlurmdPort=${SLURMD_PORT:-16818}
StateSaveLocation=$WORK/state
SlurmdSpoolDir=$WORK/spool
SlurmctldPidFile=$WORK/slurmctld.pid
SlurmdPidFile=$WORK/slurmd.pid
SlurmctldLogFile=$WORK/log/slurmctld.log
SlurmdLogFile=$WORK/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
ReturnToService=2
KillWait=5
NodeName=localhost CPUs=$cpus RealMemory=$mem_mb State=UNKNOWN
PartitionName=ci Nodes=localhost Default=YES MaxTime=INFINITE State=UP
CONF
  export SLURM_CONF="$WORK/slurm.conf"
  slurmctld -f "$SLURM_CONF"
  slurmd -f "$SLURM_CONF" -N localhost
  local deadline=$((SECONDS + 60))
  until sinfo -h -o %t 2>/dev/null | grep -qE '^(idle|mix|alloc)'; do
    [ $SECONDS -lt $deadline ] || { tail -20 "$WORK"/log/*.log >&2; fail "the node never became idle"; }
    sleep 0.5
  done
}

stop_slurm() {
  local pid_file pid
  for pid_file in "$WORK/slurmd.pid" "$WORK/slurmctld.pid" "$WORK/munge/munged.pid"; do
    [ -f "$pid_file" ] || continue
    pid=$(cat "$pid_file")
    kill "$pid" 2>/dev/null || continue
    # Wait (up to 10 s) for it to exit: slurmctld saves its state on the way out.
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.2; done
  done
  if [ "${KEEP:-0}" = 1 ]; then echo "kept $WORK"; else rm -rf "$WORK"; fi
}
trap stop_slurm EXIT

# --- helpers --------------------------------------------------------------------------------------
# sbatch RESULTS_DIR [more sbatch flags]: submits the example array, prints the job id.
submit() {
  local results=$1
  shift
  mkdir -p "$results"
  MRBRAKE_RESULTS="$results" sbatch --parsable --array="0-$LAST" --cpus-per-task=1 --mem=500M \
    --output="$results/slurm-%A_%a.out" --chdir="$WORK" "$@" "$SCRIPT"
}

# Number of records in a store (0 while it does not exist yet).
records_in() {
  [ -f "$1" ] || { echo 0; return; }
  "$MRBRAKE" export "$1" --json 2>/dev/null | python3 -c 'import json, sys; print(len(json.load(sys.stdin)))' \
    || echo 0
}

# Keys of a store, one a line, sorted.
keys_of() {
  "$MRBRAKE" export "$1" --json | python3 -c 'import json, sys; print("\n".join(sorted(r["key"] for r in json.load(sys.stdin))))'
}

# Fails unless two stores hold the same keys with the same status and metrics (relative 1e-9).
same_results() {
  python3 - "$1" "$2" <<'PY'
import json, math, subprocess, sys, os
def load(path):
    out = subprocess.run([os.environ["MRBRAKE"], "export", path, "--json"], check=True,
                         capture_output=True, text=True).stdout
    return {r["key"]: r for r in json.loads(out)}
a, b = load(sys.argv[1]), load(sys.argv[2])
if a.keys() != b.keys():
    sys.exit(f"different designs: {len(a)} against {len(b)}, {len(a.keys() ^ b.keys())} differ")
def close(x, y):
    if isinstance(x, str) or isinstance(y, str):
        return x == y
    return x == y or abs(x - y) <= 1e-9 * max(abs(x), abs(y))
for key, ra in a.items():
    rb = b[key]
    if ra["status"] != rb["status"]:
        sys.exit(f"{key}: status {ra['status']} against {rb['status']}")
    ma, mb = ra["metrics"], rb["metrics"]
    if ma.keys() != mb.keys() or not all(close(ma[k], mb[k]) for k in ma):
        sys.exit(f"{key}: metrics differ")
print(f"{len(a)} designs agree")
PY
}

wait_for_job() {
  while [ -n "$(squeue -h -j "$1" 2>/dev/null)" ]; do sleep 0.5; done
}

# --- the test -------------------------------------------------------------------------------------
say "plan: ${MRBRAKE_SAMPLE}, ${MRBRAKE_SHARDS} shards, ${MRBRAKE_EXTRA}; work folder $WORK"
t0=$(now)
start_slurm
t_started=$(now)
say "Slurm up in $(elapsed "$t0" "$t_started") s ($(sinfo -h -o '%N %c CPUs %t'))"

# Reference: one process, the same plan.
# shellcheck disable=SC2086
"$MRBRAKE" sweep "$MRBRAKE_SPEC" --vary R0=15mm..30mm --vary h=4mm..14mm --vary n=1..3 \
  --sample "$MRBRAKE_SAMPLE" $MRBRAKE_EXTRA --store "$WORK/single.sqlite" >/dev/null
t_single=$(now)
total=$(records_in "$WORK/single.sqlite")
say "single process: $total designs in $(elapsed "$t_started" "$t_single") s"

# 1. The whole array.
submit "$WORK/run1" --wait >/dev/null || { cat "$WORK"/run1/slurm-*.out >&2; fail "the array failed"; }
t_array=$(now)
"$MRBRAKE" merge "$WORK/run1/merged.sqlite" "$WORK"/run1/shard-*.sqlite >/dev/null
same_results "$WORK/single.sqlite" "$WORK/run1/merged.sqlite"
t_merged=$(now)
say "array of $MRBRAKE_SHARDS tasks: $(elapsed "$t_single" "$t_array") s, merge and check $(elapsed "$t_array" "$t_merged") s"

# 2. Cancel task $LAST once it has stored a design, let the others finish, resubmit the array.
job=$(submit "$WORK/run2")
victim="$WORK/run2/shard-$LAST.sqlite"
deadline=$((SECONDS + 300))
until [ "$(records_in "$victim")" -ge 1 ]; do
  [ $SECONDS -lt $deadline ] || fail "task $LAST stored nothing in 300 s"
  sleep 0.2
done
scancel "${job}_$LAST"
wait_for_job "$job"
t_cancelled=$(now)
before=$(records_in "$victim")
share=$(records_in "$WORK/run1/shard-$LAST.sqlite")
[ "$before" -lt "$share" ] || fail "task $LAST finished ($before of $share designs) before the cancel; use a larger MRBRAKE_SAMPLE"
keys_of "$victim" >"$WORK/keys-before"
ls -a "$WORK/run2" | grep -q '\.tmp-' && fail "the cancelled task left temporary files: $(ls -a "$WORK/run2")"
say "cancelled task $LAST after $before of its $share designs ($(elapsed "$t_merged" "$t_cancelled") s)"

submit "$WORK/run2" --wait >/dev/null || { cat "$WORK"/run2/slurm-*.out >&2; fail "the resubmitted array failed"; }
t_resumed=$(now)
keys_of "$victim" >"$WORK/keys-after"
missing=$(comm -23 "$WORK/keys-before" "$WORK/keys-after" | wc -l)
[ "$missing" -eq 0 ] || fail "$missing designs stored before the cancel are gone"
[ "$(records_in "$victim")" -eq "$share" ] || fail "task $LAST has $(records_in "$victim") designs, expected $share"
# The resumed task's log: every design stored before the cancel reused, only the rest computed.
resumed_log=$(ls -t "$WORK"/run2/slurm-*_"$LAST".out | head -1)
grep -q "computed $((share - before)) .*reused $before from the store" "$resumed_log" \
  || { cat "$resumed_log" >&2; fail "the resumed task did not report $before reused, $((share - before)) computed"; }
"$MRBRAKE" merge "$WORK/run2/merged.sqlite" "$WORK"/run2/shard-*.sqlite >/dev/null
same_results "$WORK/single.sqlite" "$WORK/run2/merged.sqlite"
t_end=$(now)
say "resubmitted array: $(elapsed "$t_cancelled" "$t_resumed") s; nothing lost, $before reused, $((share - before)) computed"
say "timings (s): slurm start $(elapsed "$t0" "$t_started"), single process $(elapsed "$t_started" "$t_single"), array $(elapsed "$t_single" "$t_array"), interrupted + resubmitted $(elapsed "$t_merged" "$t_resumed"), total $(elapsed "$t0" "$t_end")"
say "passed"
