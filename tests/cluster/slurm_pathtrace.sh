#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# Sharded path tracing through a real Slurm cluster started for this test on this machine.
#
#   tests/cluster/slurm_pathtrace.sh TRANSLUCENT SCRIPTS_DIR [--cluster-only]
#
# TRANSLUCENT: the CLI binary; SCRIPTS_DIR: scripts/slurm. Starts munged, slurmctld and slurmd with
# their own configuration, key, sockets, ports, state and logs in a temporary folder (SLURM_CONF
# points the clients at them only), waits for the node, then
#   phase 1: a trivial 4-task array (`--wrap hostname`): the cluster runs jobs;
#   phase 2: `pathtrace slab` and `pathtrace sphere` as 4 shards + merge through scripts/slurm/submit,
#            compared with the same commands in one process: the JSON equal but for the keys
#            seconds, photons_per_second, threads; the slab's CSV and the sphere's PNG
#            byte-identical, its EXR too but for the header's capDate (the time of writing);
#   phase 3: failing shards make submit --wait fail with the merge never run; a merge job given a
#            missing part fails naming it;
#   phase 4: a shard stopped by SIGTERM (scancel) mid-run and submitted again with submit --only
#            resumes from its partial file; the merge equals the uninterrupted run bit for bit.
# --cluster-only runs phase 1 only (a diagnostic of the Slurm set-up). The test fails, printing the
# daemons' logs, when the cluster cannot start. It stops the daemons (by pid) and removes the
# folder on exit (TRANSLUCENT_TEST_KEEP=1: keeps the folder, with the logs).
set -euo pipefail

fail() {
  echo "slurm_pathtrace: FAIL: $*" >&2
  exit 1
}
[[ $# -ge 2 ]] || fail "usage: slurm_pathtrace.sh TRANSLUCENT SCRIPTS_DIR [--cluster-only]"
TRANSLUCENT=$(realpath "$1")
SCRIPTS=$(realpath "$2")
CLUSTER_ONLY=0
[[ ${3:-} == --cluster-only ]] && CLUSTER_ONLY=1
[[ -x $TRANSLUCENT && -s $TRANSLUCENT ]] || fail "TRANSLUCENT '$1' is not an executable (or is empty)"
for f in submit pathtrace.sbatch merge.sbatch; do
  [[ -x $SCRIPTS/$f ]] || fail "SCRIPTS_DIR '$2' has no executable $f"
done
for tool in munged slurmctld slurmd sbatch squeue sinfo scontrol scancel ss; do
  command -v "$tool" >/dev/null || fail "'$tool' not found: install slurm-wlm and munge (scripts/install-deps)"
done
export TRANSLUCENT

now() { date +%s.%N; }
seconds_since() { awk -v a="$1" -v b="$(now)" 'BEGIN { printf "%.1f", b - a }'; }

# Nothing of an enclosing Slurm job (or another cluster) may leak into the clients.
while read -r var; do unset "$var"; done < <(compgen -e | grep -E '^(SLURM|SBATCH|SALLOC|SRUN)_' || true)

TMP=$(mktemp -d "${TMPDIR:-/tmp}/translucent-slurm.XXXXXX")
chmod 755 "$TMP"  # munged wants its socket's folders searchable by all; the key itself is 0400
PIDS=()   # daemons, stopped in reverse order
JOBS=()   # jobs submitted, cancelled on exit if still there
SHOW_LOGS=1
LOG_LINES=40  # of each daemon log shown on failure; fewer once the cluster runs

show_logs() {
  local f
  for f in "$TMP"/log/*; do
    [[ -s $f ]] || continue
    echo "----- $(basename "$f") (last $LOG_LINES lines) -----" >&2
    tail -n "$LOG_LINES" "$f" >&2
  done
}

cleanup() {
  local rc=$? pid i
  set +e
  if [[ $rc -ne 0 && $SHOW_LOGS -eq 1 ]]; then show_logs; fi
  if [[ ${#JOBS[@]} -gt 0 ]] && [[ ${#PIDS[@]} -ge 2 ]]; then
    scancel "${JOBS[@]}" 2>/dev/null
    for ((i = 0; i < 20; i++)); do
      [[ -z $(squeue -h -o %i 2>/dev/null) ]] && break
      sleep 0.5
    done
  fi
  for ((i = ${#PIDS[@]} - 1; i >= 0; i--)); do
    pid=${PIDS[i]}
    kill "$pid" 2>/dev/null
  done
  for pid in "${PIDS[@]}"; do
    for ((i = 0; i < 50; i++)); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$pid" 2>/dev/null
    wait "$pid" 2>/dev/null
  done
  if [[ -n ${TRANSLUCENT_TEST_KEEP:-} ]]; then
    echo "slurm_pathtrace: kept $TMP (TRANSLUCENT_TEST_KEEP)" >&2
  else
    rm -rf "$TMP"
  fi
  exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

daemon_alive() { kill -0 "$1" 2>/dev/null; }

# Two free TCP ports (slurmctld, slurmd), so parallel runs and a system Slurm do not collide.
free_port() {
  local p
  for _ in $(seq 200); do
    p=$((20000 + RANDOM % 20000))
    [[ -z $(ss -Htan "sport = :$p") ]] && [[ " ${USED_PORTS:-} " != *" $p "* ]] && { echo "$p"; return; }
  done
  fail "no free TCP port found"
}
USED_PORTS=""
CTLD_PORT=$(free_port); USED_PORTS="$CTLD_PORT"
SLURMD_PORT=$(free_port)

mkdir -p "$TMP"/{log,munge,state,spool,wrap,run}
chmod 700 "$TMP/state" "$TMP/spool"

# --- munge: own key, socket, pid, seed and log --------------------------------------------------
dd if=/dev/urandom of="$TMP/munge/munge.key" bs=1 count=1024 status=none
chmod 400 "$TMP/munge/munge.key"
MUNGE_SOCKET=$TMP/munge/munge.socket
munge_args=(--foreground --socket="$MUNGE_SOCKET" --key-file="$TMP/munge/munge.key"
            --pid-file="$TMP/munge/munged.pid" --log-file="$TMP/log/munged.log"
            --seed-file="$TMP/munge/munged.seed")
[[ $(id -u) -eq 0 ]] && munge_args+=(--force)
munged "${munge_args[@]}" >"$TMP/log/munged.stderr" 2>&1 &
PIDS+=($!)
for ((i = 0; i < 100; i++)); do
  [[ -S $MUNGE_SOCKET ]] && break
  daemon_alive "${PIDS[0]}" || fail "munged exited (its log follows)"
  sleep 0.1
done
[[ -S $MUNGE_SOCKET ]] || fail "munged did not create its socket $MUNGE_SOCKET within 10 s"

# --- slurm.conf ---------------------------------------------------------------------------------
HOST=$(hostname -s)
# slurmd -C: this node's CPUs, sockets, cores, threads and memory, as a NodeName line.
NODE_LINE=$(slurmd -C 2>"$TMP/log/slurmd-C.stderr" | grep '^NodeName=') ||
  fail "slurmd -C printed no NodeName line: $(cat "$TMP/log/slurmd-C.stderr")"
NODE_NAME=$(sed -n 's/^NodeName=\([^ ]*\).*/\1/p' <<<"$NODE_LINE")
[[ $NODE_NAME == "$HOST" ]] || fail "slurmd -C names the node '$NODE_NAME', hostname -s is '$HOST'"
CPUS=$(sed -n 's/.* CPUs=\([0-9]*\).*/\1/p' <<<"$NODE_LINE")
USER_NAME=$(id -un)
export SLURM_CONF=$TMP/slurm.conf
: >"$TMP/plugstack.conf"
cat >"$SLURM_CONF" <<CONF
# Written by tests/cluster/slurm_pathtrace.sh: a one-node cluster for this test only.
ClusterName=translucent-test
SlurmctldHost=$HOST(127.0.0.1)
SlurmctldPort=$CTLD_PORT
SlurmdPort=$SLURMD_PORT
SlurmUser=$USER_NAME
SlurmdUser=$USER_NAME
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$MUNGE_SOCKET
StateSaveLocation=$TMP/state
SlurmdSpoolDir=$TMP/spool
SlurmctldPidFile=$TMP/run/slurmctld.pid
SlurmdPidFile=$TMP/run/slurmd.pid
SlurmctldLogFile=$TMP/log/slurmctld.log
SlurmdLogFile=$TMP/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
PlugStackConfig=$TMP/plugstack.conf
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SwitchType=switch/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
ReturnToService=2
MinJobAge=600
MailProg=/bin/true
# Start jobs as soon as they are submitted or resources free up (the defaults wait up to 3 s).
SchedulerParameters=batch_sched_delay=0,sched_min_interval=0
$NODE_LINE NodeAddr=127.0.0.1 NodeHostname=$HOST State=UNKNOWN
PartitionName=test Nodes=$HOST Default=YES MaxTime=INFINITE State=UP
CONF

# --- slurmctld, slurmd --------------------------------------------------------------------------
slurmctld -D -i -f "$SLURM_CONF" >"$TMP/log/slurmctld.stderr" 2>&1 &
PIDS+=($!)
CTLD_PID=$!
slurmd -D -f "$SLURM_CONF" >"$TMP/log/slurmd.stderr" 2>&1 &
PIDS+=($!)
SLURMD_PID=$!

echo "slurm_pathtrace: cluster in $TMP: node $HOST ($CPUS CPUs), slurmctld :$CTLD_PORT (pid $CTLD_PID), slurmd :$SLURMD_PORT (pid $SLURMD_PID)"
start=$(now)
state=""
for ((i = 0; i < 120; i++)); do
  daemon_alive "$CTLD_PID" || fail "slurmctld exited (its log follows)"
  daemon_alive "$SLURMD_PID" || fail "slurmd exited (its log follows)"
  state=$(sinfo -h -n "$HOST" -o %T 2>/dev/null || true)
  [[ $state == idle ]] && break
  sleep 0.5
done
[[ $state == idle ]] || fail "node $HOST not idle within 60 s (sinfo state: '${state:-no answer}')"
echo "slurm_pathtrace: node idle after $(seconds_since "$start") s"
LOG_LINES=10

# wait_job ID SECONDS [STATE]: waits until every record of the job (array tasks included) has
# ended; succeeds when all are COMPLETED with exit code 0:0 (or all in STATE), else prints them
# and fails.
wait_job() {
  local id=$1 limit=$2 expect=${3:-COMPLETED .*ExitCode=0:0} records states t0
  t0=$(now)
  while true; do
    records=$(scontrol -o show job "$id") || fail "scontrol show job $id failed"
    states=$(grep -o 'JobState=[A-Z_]*' <<<"$records" | sort -u | tr '\n' ' ')
    if ! grep -qE 'JobState=(PENDING|CONFIGURING|RUNNING|COMPLETING|SUSPENDED|REQUEUED|RESIZING)' <<<"$records"; then
      break
    fi
    if awk -v a="$t0" -v b="$(now)" -v l="$limit" 'BEGIN { exit !(b - a > l) }'; then
      fail "job $id not done within $limit s: $states"
    fi
    sleep 0.2
  done
  if grep -vqE "JobState=$expect" <<<"$records"; then
    grep -oE 'JobId=[0-9]+|ArrayTaskId=[0-9]+|JobState=[A-Z_]+|Reason=[^ ]+|ExitCode=[0-9:]+' <<<"$records" |
      paste -sd' ' >&2
    fail "job $id: expected every record in JobState=$expect, got $states"
  fi
}

# --- phase 1: a trivial array -------------------------------------------------------------------
start=$(now)
job=$(sbatch --parsable --array=0-3 --output="$TMP/wrap/hostname-%a.out" --wrap 'hostname -s') ||
  fail "sbatch of the trivial array failed"
JOBS+=("$job")
wait_job "$job" 60
for a in 0 1 2 3; do
  [[ $(cat "$TMP/wrap/hostname-$a.out" 2>/dev/null) == "$HOST" ]] ||
    fail "array task $a of job $job printed '$(cat "$TMP/wrap/hostname-$a.out" 2>/dev/null)', expected '$HOST'"
done
echo "slurm_pathtrace: phase 1: a 4-task 'hostname' array ran in $(seconds_since "$start") s"
[[ $CLUSTER_ONLY -eq 0 ]] || { echo "slurm_pathtrace: PASS (cluster only)"; exit 0; }

# --- phase 2: sharded path tracing, compared with one process -----------------------------------
# The JSON with the keys that may differ (seconds, photons_per_second, threads) deleted, and the
# separating commas dropped (json dump(2): one key per line), numbers compared as text.
normalized_json() {
  grep -vE '^[[:space:]]*"(seconds|photons_per_second|threads)":' "$1" | sed 's/,$//'
}
same_json() {
  [[ -s $1 ]] || fail "$1 missing or empty"
  [[ -s $2 ]] || fail "$2 missing or empty"
  if ! diff <(normalized_json "$1") <(normalized_json "$2") >"$TMP/json.diff"; then
    head -n 40 "$TMP/json.diff" >&2
    fail "$1 and $2 differ (beyond seconds, photons_per_second, threads)"
  fi
  grep -qE '^[[:space:]]*"seconds":' "$1" || fail "$1 has no \"seconds\" key: not the JSON expected"
}

# Byte-identical EXR files but for the value of the header attribute capDate (the time of writing,
# "YYYY:MM:DD HH:MM:SS", which the EXR writer adds): any other differing byte fails.
same_exr() {
  local a=$1 b=$2 off offb type len first last outside
  [[ -s $a ]] || fail "$a missing or empty"
  [[ -s $b ]] || fail "$b missing or empty"
  cmp -s "$a" "$b" && return 0
  [[ $(stat -c %s "$a") -eq $(stat -c %s "$b") ]] || fail "$a and $b differ in size"
  off=$(grep -obUa capDate "$a" | head -n 1 | cut -d: -f1)
  offb=$(grep -obUa capDate "$b" | head -n 1 | cut -d: -f1)
  [[ -n $off && $off == "$offb" ]] || { cmp "$a" "$b" >&2 || true; fail "$a and $b differ (no capDate attribute at one offset in both)"; }
  # An attribute: name NUL, type NUL, 4-byte little-endian size, value.
  type=$(dd if="$a" bs=1 skip=$((off + 8)) count=6 status=none)
  len=$(od -An -tu4 -j $((off + 15)) -N4 "$a" | tr -d ' ')
  [[ $type == string && $len -gt 0 ]] || fail "$a: capDate attribute of type '$type', size '$len': not a string"
  first=$((off + 19 + 1))  # cmp -l counts bytes from 1
  last=$((off + 19 + len))
  outside=$({ cmp -l "$a" "$b" || true; } | awk -v f="$first" -v l="$last" '$1 < f || $1 > l' | head -n 5)
  [[ -z $outside ]] || fail "$a and $b differ beyond the capDate attribute (byte, octal values): $outside"
  echo "slurm_pathtrace: $a and $b byte-identical but for capDate" \
       "('$(dd if="$a" bs=1 skip=$((off + 19)) count="$len" status=none)' vs '$(dd if="$b" bs=1 skip=$((off + 19)) count="$len" status=none)')"
}

# sharded NAME PATHTRACE_ARGS... -- OUTPUT_OPTIONS...: 4 shards + merge through submit --wait.
SHARDS=4
declare -A SHARDED_SECONDS
sharded() {
  local name=$1 out t0 rc=0
  shift
  t0=$(now)
  out=$(SUBMIT_POLL_SECONDS=0.2 "$SCRIPTS/submit" -n "$SHARDS" -d "$TMP/$name-parts" --wait -- "$@" 2>"$TMP/$name-submit.err") || rc=$?
  SHARDED_SECONDS[$name]=$(seconds_since "$t0")
  local ids
  ids=$(sed -n 's/^\(array\|merge\)_job=//p' <<<"$out" | paste -sd' ')
  # shellcheck disable=SC2206
  JOBS+=($ids)
  if [[ $rc -ne 0 ]]; then
    echo "$out" >&2
    cat "$TMP/$name-submit.err" >&2
    for f in "$TMP/$name-parts"/*.out; do
      [[ -f $f ]] && { echo "----- $(basename "$f") -----" >&2; tail -n 20 "$f" >&2; }
    done
    fail "$name: the sharded run through scripts/slurm/submit failed (exit $rc)"
  fi
  local n
  n=$(find "$TMP/$name-parts" -name 'part-*.tpart' | wc -l)
  [[ $n -eq $SHARDS ]] || fail "$name: $n part files in $TMP/$name-parts, expected $SHARDS"
  echo "slurm_pathtrace: $name: $SHARDS shards + merge through Slurm (jobs $ids) in ${SHARDED_SECONDS[$name]} s"
}
single() {
  local name=$1 t0
  shift
  t0=$(now)
  "$TRANSLUCENT" "$@" >"$TMP/$name-single.log" 2>&1 ||
    { cat "$TMP/$name-single.log" >&2; fail "$name: the single-process run failed"; }
  local s
  s=$(seconds_since "$t0")
  echo "slurm_pathtrace: $name: one process in $s s (sharded: ${SHARDED_SECONDS[$name]} s)"
}

# Each run writes the same relative file names in its own folder (the JSON records the paths).
mkdir -p "$TMP/sharded" "$TMP/single"
S=$TMP/sharded
P=$TMP/single
SLAB=(pathtrace slab --device cpu --material Skimmilk --channel r --photons 4e5 --radial-bins 50 --radial-max 5 --seed 7)
cd "$S"
sharded slab "${SLAB[@]}" -- --json slab.json --csv slab.csv
cd "$P"
single slab "${SLAB[@]}" --json slab.json --csv slab.csv
same_json "$S/slab.json" "$P/slab.json"
cmp "$S/slab.csv" "$P/slab.csv" || fail "slab: the CSV profiles differ"

SPHERE=(pathtrace sphere --device cpu --photons 2e5 --width 32 --height 32 --seed 3)
cd "$S"
sharded sphere "${SPHERE[@]}" -- --exr sphere.exr --png sphere.png --json sphere.json
cd "$P"
single sphere "${SPHERE[@]}" --exr sphere.exr --png sphere.png --json sphere.json
same_exr "$S/sphere.exr" "$P/sphere.exr"
cmp "$S/sphere.png" "$P/sphere.png" || fail "sphere: the PNG files differ"
same_json "$S/sphere.json" "$P/sphere.json"
cd "$TMP"

# --- phase 3: failures are failures ------------------------------------------------------------
# Shards that fail (no photons): submit --wait fails, the merge never runs, no output appears.
rc=0
SUBMIT_POLL_SECONDS=0.2 "$SCRIPTS/submit" -n 2 -d "$TMP/bad-parts" --wait \
  -- pathtrace slab --material Skimmilk --channel r --photons 0 -- --json "$TMP/bad.json" \
  >"$TMP/bad-submit.out" 2>"$TMP/bad-submit.err" || rc=$?
# shellcheck disable=SC2207
JOBS+=($(sed -n 's/^\(array\|merge\)_job=//p' "$TMP/bad-submit.out"))
[[ $rc -ne 0 ]] || fail "submit --wait exited 0 though every shard had --photons 0"
grep -q 'never ran' "$TMP/bad-submit.err" ||
  { cat "$TMP/bad-submit.err" >&2; fail "submit did not report the merge job as never run"; }
[[ ! -e $TMP/bad.json ]] || fail "the merge of failed shards wrote $TMP/bad.json"
# A merge job told of 5 parts where 4 exist fails naming the missing one.
job=$(sbatch --parsable --output="$TMP/merge5.out" "$SCRIPTS/merge.sbatch" "$TMP/slab-parts" 5 \
  --json "$TMP/five.json") || fail "sbatch of merge.sbatch failed"
JOBS+=("$job")
wait_job "$job" 60 FAILED
grep -q 'part-4.tpart' "$TMP/merge5.out" ||
  { cat "$TMP/merge5.out" >&2; fail "the merge of 4 of 5 parts did not name part-4.tpart"; }
echo "slurm_pathtrace: phase 3: failed shards cancel the merge (exit $rc); a missing part fails the merge: $(grep -m1 'part-4' "$TMP/merge5.out")"

# --- phase 4: a shard stopped mid-run, submitted again with --only, resumes ---------------------
# Shard 0 of 2 gets SIGTERM from scancel while it traces (as Slurm sends it 120 s before the time
# limit, pathtrace.sbatch's --signal): it writes its partial file, fails, and the merge never runs.
# `submit --only 0` runs it again into the same folder: it resumes from its partial file, and the
# merge of both parts equals the uninterrupted single-process run bit for bit.
start=$(now)
RESUME=(pathtrace slab --device cpu --material Skimmilk --channel r --photons 2e7 --radial-bins 50
        --radial-max 5 --seed 11)
RP=$TMP/resume-parts
cd "$S"  # the JSON records the output paths: relative, as the single run's
out=$("$SCRIPTS/submit" -n 2 -d "$RP" -- "${RESUME[@]}" --threads 1 -- --json resume.json --csv resume.csv) ||
  fail "submit of the run to stop failed: $out"
array=$(sed -n 's/^array_job=//p' <<<"$out")
merge=$(sed -n 's/^merge_job=//p' <<<"$out")
JOBS+=("$array" "$merge")
# Until shard 0 runs translucent (its log names the command), then a second of tracing.
for ((i = 0; i < 300; i++)); do
  grep -q 'pathtrace.sbatch: shard 0/2' "$RP/pathtrace-${array}_0.out" 2>/dev/null && break
  sleep 0.1
done
grep -q 'pathtrace.sbatch: shard 0/2' "$RP/pathtrace-${array}_0.out" 2>/dev/null ||
  fail "shard 0 of job $array did not start within 30 s"
sleep 1.5
scancel --signal=TERM --batch "${array}_0" || fail "scancel --signal=TERM --batch ${array}_0 failed"
wait_job "$array" 120 '(COMPLETED|FAILED)'
grep -q 'INCOMPLETE' "$RP/pathtrace-${array}_0.out" ||
  { cat "$RP/pathtrace-${array}_0.out" >&2; fail "shard 0 did not write an incomplete partial file after SIGTERM (it may have finished first)"; }
done0=$(sed -n 2p "$RP/part-0.tpart" | grep -o '"blocks_done":[0-9]*' | cut -d: -f2 || true)
[[ -n $done0 && $done0 -gt 0 ]] || fail "part-0.tpart records no finished blocks ('$done0')"
wait_job "$merge" 60 CANCELLED
[[ ! -e $S/resume.json ]] || fail "the merge ran although shard 0 was stopped"
rc=0
out=$(SUBMIT_POLL_SECONDS=0.2 "$SCRIPTS/submit" --shards 2 --only 0 -d "$RP" --wait -- "${RESUME[@]}" --threads 1 \
  -- --json resume.json --csv resume.csv 2>"$TMP/resume-submit.err") || rc=$?
# shellcheck disable=SC2207
JOBS+=($(sed -n 's/^\(array\|merge\)_job=//p' <<<"$out"))
again=$(sed -n 's/^array_job=//p' <<<"$out")
[[ $rc -eq 0 ]] || { cat "$TMP/resume-submit.err" "$RP"/pathtrace-"${again}"_*.out >&2; fail "submit --only 0 failed (exit $rc)"; }
grep -q "resuming shard 0/2 after its $done0 of" "$RP/pathtrace-${again}_0.out" ||
  { cat "$RP/pathtrace-${again}_0.out" >&2; fail "shard 0 submitted again did not resume from its $done0 blocks"; }
[[ ! -e $RP/pathtrace-${again}_1.out ]] || fail "submit --only 0 also ran shard 1"
cd "$P"
"$TRANSLUCENT" "${RESUME[@]}" --json resume.json --csv resume.csv >"$TMP/resume-single.log" 2>&1 ||
  { cat "$TMP/resume-single.log" >&2; fail "the uninterrupted single-process run failed"; }
cd "$TMP"
same_json "$S/resume.json" "$P/resume.json"
cmp "$S/resume.csv" "$P/resume.csv" || fail "resume: the CSV profiles differ"
echo "slurm_pathtrace: phase 4: shard 0 stopped by SIGTERM after $done0 blocks, submitted again with --only 0, resumed; merge identical to one process ($(seconds_since "$start") s)"

echo "slurm_pathtrace: PASS"
