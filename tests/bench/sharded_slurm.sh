#!/usr/bin/env bash
# Sharded bake under Slurm (issue 23): starts a single-node Slurm on this
# machine from Debian's packages (`scripts/setup --slurm`: slurm-wlm, munge),
# configured entirely under a temporary directory (its own slurm.conf through
# SLURM_CONF, state, spool, log and pid directories, a munge key made for the
# run and munged on its own socket), then submits the three steps of
# docs/sharded-bakes-runners.md:
#   plan   one job, all CPUs           svit-bake plan LEVEL -o WORK --shards N ...
#   shards an array job 0..N-1, one CPU each, --dependency=afterok:<plan>
#                                      svit-bake shard WORK $SLURM_ARRAY_TASK_ID --threads 1
#   merge  one job, all CPUs, --dependency=afterok:<array>
#                                      svit-bake merge WORK -o OUT_DIR/merged
# waits for them, bakes the level whole (svit-bake LEVEL -o OUT_DIR/whole, same
# options) and checks that bake.svit and every lightmap-*.exr of the two are
# byte-identical. Every daemon it started is stopped on exit (trap), whatever
# happened; the temporary directory is removed (SVIT_SLURM_KEEP=1 keeps it).
#
# usage: tests/bench/sharded_slurm.sh BUILD_DIR LEVEL OUT_DIR [SHARDS] [bake options]
#   BUILD_DIR     holds baker/svit-bake (e.g. build/release)
#   SHARDS        number of shards (default 4)
#   bake options  given to `plan` and to the whole bake alike: --seed, --passes,
#                 --quality, --texels-per-m (not --threads, which the script sets)
# env:   SVIT_SLURM_TIMEOUT  seconds to wait for the jobs (default 7200)
#        SVIT_SLURM_KEEP=1   keep the temporary directory (its path is printed)
# Writes, replacing what was there, OUT_DIR/work (plan and shards),
# OUT_DIR/merged, OUT_DIR/whole, OUT_DIR/slurm/ (slurm.conf, job outputs,
# scontrol/squeue records, daemon logs) and OUT_DIR/slurm_summary.md. Exit 0 when every job completed and the
# outputs are identical, 1 when not, 2 on bad usage or missing packages.
set -euo pipefail

usage() {
  echo "usage: $0 BUILD_DIR LEVEL OUT_DIR [SHARDS] [bake options]" >&2
  exit 2
}
[[ $# -ge 3 ]] || usage
abs() { [[ "$1" = /* ]] && echo "$1" || echo "$PWD/$1"; }
build="$(abs "$1")"
level="$(abs "$2")"
out="$(abs "$3")"
shift 3
shards=4
if [[ $# -gt 0 && "$1" =~ ^[0-9]+$ ]]; then
  shards="$1"
  shift
fi
bake_options=("$@")
for option in "${bake_options[@]}"; do
  case "$option" in
    --threads | --threads=* | -o) echo "$0: '$option' is set by the script" >&2; exit 2 ;;
  esac
done
bake="$build/baker/svit-bake"
[[ -x "$bake" ]] || { echo "$0: no svit-bake at $bake" >&2; exit 2; }
[[ -f "$level" ]] || { echo "$0: no level at $level" >&2; exit 2; }
[[ "$shards" -ge 1 ]] || { echo "$0: SHARDS must be at least 1, not '$shards'" >&2; exit 2; }
# slurmd launches jobs and must run as root; SlurmUser is root as well.
[[ $EUID -eq 0 ]] || { echo "$0: needs root (slurmd and slurmctld run as root here)" >&2; exit 2; }
for tool in munged mungekey slurmctld slurmd sbatch scontrol squeue sinfo scancel; do
  command -v "$tool" >/dev/null || {
    echo "$0: '$tool' is missing; run scripts/setup --slurm (Debian's slurm-wlm and munge)" >&2
    exit 2
  }
done
timeout_s="${SVIT_SLURM_TIMEOUT:-7200}"
# A caller's own Slurm environment (run from inside a job) must not leak
# into this cluster's jobs.
for variable in $(compgen -e | grep '^SLURM_' || true); do unset "$variable"; done
ncpu="$(nproc)"
node="$(hostname -s)"

mkdir -p "$out"
work="$out/work"
merged="$out/merged"
whole="$out/whole"
logs="$out/slurm"
rm -rf "$work" "$merged" "$whole" "$logs"
mkdir -p "$logs"

# Everything Slurm and munge write lives here: nothing in /etc, /var or /run.
tmp="$(mktemp -d /tmp/svit-slurm.XXXXXX)"
# munged wants its socket's directory, and those above it, executable by all,
# and its key readable by nobody else.
chmod 0711 "$tmp"
mkdir -p "$tmp/munge" "$tmp/socket" "$tmp/state" "$tmp/spool" "$tmp/log" "$tmp/run"
chmod 0700 "$tmp/munge"
chmod 0755 "$tmp/socket"
conf="$tmp/slurm.conf"
socket="$tmp/socket/munge.socket"
munged_pid=""
slurmctld_pid=""
slurmd_pid=""
job_ids=()

log() { echo "[sharded_slurm $(date -u +%H:%M:%S)] $*"; }

# Stops one daemon we started: SIGTERM, up to 20 s, then SIGKILL.
stop_daemon() {
  local name="$1" pid="$2"
  [[ -n "$pid" ]] || return 0
  kill -0 "$pid" 2>/dev/null || return 0
  kill -TERM "$pid" 2>/dev/null || true
  for _ in $(seq 200); do
    kill -0 "$pid" 2>/dev/null || break
    sleep 0.1
  done
  if kill -0 "$pid" 2>/dev/null; then
    echo "sharded_slurm: $name ($pid) ignored SIGTERM; killing it" >&2
    kill -KILL "$pid" 2>/dev/null || true
  fi
  wait "$pid" 2>/dev/null || true
}

# What our daemons left behind (a slurmstepd still tearing a job down, a job
# process): every process but this script and munged that holds a file open
# in the temporary directory (slurmstepd logs to slurmd.log) or in
# OUT_DIR/slurm (a job's output). Found by that, ended by its id.
leftover_pids() {
  find /proc/[0-9]*/fd -maxdepth 1 \( -lname "$tmp/*" -o -lname "$logs/*" \) 2>/dev/null |
    cut -d/ -f3 | sort -u | grep -vxF -e "$$" -e "${munged_pid:-none}" || true
}

cleanup() {
  local rc=$?
  set +e
  trap - EXIT INT TERM
  if [[ -n "$slurmctld_pid" ]] && kill -0 "$slurmctld_pid" 2>/dev/null && [[ ${#job_ids[@]} -gt 0 ]]; then
    # Unfinished jobs are cancelled first, so that no slurmstepd outlives slurmd.
    local active_ids
    active_ids="$(IFS=,; echo "${job_ids[*]}")"
    if [[ -n "$(squeue -h -t PD,R,CG,CF,S,RQ -j "$active_ids" -o %i 2>/dev/null)" ]]; then
      log "stopping: cancelling jobs ${job_ids[*]}"
      scancel "${job_ids[@]}" 2>/dev/null
      for _ in $(seq 100); do
        [[ -z "$(squeue -h -t PD,R,CG,CF,S,RQ -j "$active_ids" -o %i 2>/dev/null)" ]] && break
        sleep 0.2
      done
    fi
  fi
  log "stopping: slurmd, slurmctld, munged"
  stop_daemon slurmd "$slurmd_pid"
  stop_daemon slurmctld "$slurmctld_pid"
  for _ in $(seq 75); do
    [[ -z "$(leftover_pids)" ]] && break
    sleep 0.2
  done
  for pid in $(leftover_pids); do
    echo "sharded_slurm: ending leftover process $pid ($(cat "/proc/$pid/comm" 2>/dev/null))" >&2
    kill -KILL "$pid" 2>/dev/null
  done
  stop_daemon munged "$munged_pid"
  log "stopped"
  # The daemons' logs are worth keeping; the rest (key, state) is not.
  cp "$tmp"/log/*.log "$logs/" 2>/dev/null
  if [[ "${SVIT_SLURM_KEEP:-0}" = 1 ]]; then
    echo "sharded_slurm: kept $tmp" >&2
  else
    rm -rf "$tmp"
  fi
  exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

# Two free TCP ports for slurmctld and slurmd, so that a second run or a
# system Slurm on the default 6817/6818 does not collide with this one.
port_free() { ! (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null; }
base=$((20000 + ($$ % 20000)))
while ! port_free "$base" || ! port_free $((base + 1)); do
  base=$((base + 2))
done
ctld_port=$base
slurmd_port=$((base + 1))

# --- munge ------------------------------------------------------------------
mungekey --create --keyfile="$tmp/munge/munge.key" --bits=1024
chmod 0600 "$tmp/munge/munge.key"
munged --foreground --socket="$socket" --key-file="$tmp/munge/munge.key" \
  --pid-file="$tmp/run/munged.pid" --log-file="$tmp/log/munged.log" \
  --seed-file="$tmp/munge/munged.seed" >"$tmp/log/munged.stdout" 2>&1 &
munged_pid=$!
for _ in $(seq 100); do
  [[ -S "$socket" ]] && break
  kill -0 "$munged_pid" 2>/dev/null || break
  sleep 0.1
done
[[ -S "$socket" ]] || { echo "$0: munged did not start:" >&2; cat "$tmp"/log/munged.* >&2; exit 1; }
munge --socket="$socket" -n | unmunge --socket="$socket" >/dev/null \
  || { echo "$0: munge credentials do not round-trip" >&2; exit 1; }
log "munged $munged_pid on $socket"

# --- slurm.conf ---------------------------------------------------------------
# The node line is what slurmd -C measures (CPUs, sockets, cores, threads,
# memory), so slurmd registers without a mismatch and the node never drains.
node_line="$(slurmd -C | head -n 1)"
node_line="${node_line/NodeName=* CPUs=/NodeName=$node NodeAddr=127.0.0.1 CPUs=}"
cat >"$conf" <<EOF
# Single-node Slurm for tests/bench/sharded_slurm.sh; made for one run.
ClusterName=svit
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$socket
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/run/slurmctld.pid
SlurmdPidFile=$tmp/run/slurmd.pid
SlurmctldLogFile=$tmp/log/slurmctld.log
SlurmdLogFile=$tmp/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
# No cgroups needed: processes tracked through /proc, no CPU binding.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
MailProg=/bin/true
SwitchType=switch/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
# A job that ends starts the next at once (the defaults wait up to 3 s for
# more submissions and backfill every 30 s: seconds per wave of shards).
SchedulerParameters=batch_sched_delay=0,bf_interval=1
ReturnToService=2
# No slurmdbd, so no sacct (each shard measures its own peak memory).
# Finished jobs stay in slurmctld (scontrol show job) for a day, and each one
# is written to a text file as it ends. The first start logs that it found
# no state files and that mpi/pmix cannot load: both harmless here.
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/filetxt
JobCompLoc=$logs/jobcomp.txt
MinJobAge=86400
# A failed plan or shard cancels what depends on it instead of leaving it
# pending forever (DependencyNeverSatisfied).
DependencyParameters=kill_invalid_depend
$node_line State=UNKNOWN
PartitionName=svit Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF="$conf"
cp "$conf" "$logs/slurm.conf"

# --- slurmctld, slurmd --------------------------------------------------------
slurmctld -D -c >"$tmp/log/slurmctld.stdout" 2>&1 &
slurmctld_pid=$!
for _ in $(seq 150); do
  scontrol ping 2>/dev/null | grep -q 'is UP' && break
  kill -0 "$slurmctld_pid" 2>/dev/null || break
  sleep 0.2
done
scontrol ping 2>/dev/null | grep -q 'is UP' \
  || { echo "$0: slurmctld did not come up:" >&2; tail -n 20 "$tmp"/log/slurmctld.* >&2; exit 1; }
slurmd -D -N "$node" >"$tmp/log/slurmd.stdout" 2>&1 &
slurmd_pid=$!
state=""
for _ in $(seq 150); do
  state="$(sinfo -h -n "$node" -o %T 2>/dev/null || true)"
  [[ "$state" = idle ]] && break
  kill -0 "$slurmd_pid" 2>/dev/null || break
  sleep 0.2
done
[[ "$state" = idle ]] \
  || { echo "$0: node $node is '$state', not idle:" >&2; tail -n 20 "$tmp"/log/slurmd.* >&2; exit 1; }
slurm_version="$(sinfo --version)"
log "$slurm_version up: slurmctld $slurmctld_pid (port $ctld_port), slurmd $slurmd_pid (port $slurmd_port), node $node"
sinfo -N -l >"$logs/sinfo.txt"
scontrol show node "$node" >"$logs/node.txt"

# --- the three steps ----------------------------------------------------------
# Shell-quotes its arguments readably: plain words as they are, others in
# single quotes (the form copied into the docs).
q() {
  local arg words=()
  for arg in "$@"; do
    if [[ "$arg" =~ ^[A-Za-z0-9_./=:,%@+-]+$ ]]; then
      words+=("$arg")
    else
      words+=("'${arg//\'/\'\\\'\'}'")
    fi
  done
  echo "${words[*]}"
}
jobid() { cut -d';' -f1; }
plan_cmd="exec $(q "$bake" plan "$level" -o "$work" --shards "$shards" --threads "$ncpu" "${bake_options[@]}")"
shard_cmd="exec $(q "$bake" shard "$work") \$SLURM_ARRAY_TASK_ID --threads 1"
merge_cmd="exec $(q "$bake" merge "$work" -o "$merged" --threads "$ncpu")"
plan_sbatch=(sbatch --parsable -J svit-plan -N 1 -n 1 -c "$ncpu" --chdir "$out"
  -o "$logs/plan-%j.out" --wrap "$plan_cmd")
# Each sbatch line, as run, goes to submitted.txt (and into the summary).
submit() {
  q "$@" >>"$logs/submitted.txt"
  "$@" | jobid
}
load_before="$(cut -d' ' -f1-3 /proc/loadavg)"
started=$(date +%s.%N)
plan_job=$(submit "${plan_sbatch[@]}")
job_ids+=("$plan_job")
array_job=$(submit sbatch --parsable -J svit-shard --array="0-$((shards - 1))" -N 1 -n 1 -c 1 \
  --chdir "$out" --dependency="afterok:$plan_job" -o "$logs/shard-%A_%a.out" --wrap "$shard_cmd")
job_ids+=("$array_job")
merge_job=$(submit sbatch --parsable -J svit-merge -N 1 -n 1 -c "$ncpu" --chdir "$out" \
  --dependency="afterok:$array_job" -o "$logs/merge-%j.out" --wrap "$merge_cmd")
job_ids+=("$merge_job")
log "submitted plan $plan_job, shards $array_job (array 0-$((shards - 1))), merge $merge_job"
squeue -l >"$logs/squeue-submitted.txt"

# Until none of our jobs is pending, running or completing; a queue snapshot
# every 10 s goes to squeue-progress.txt.
ids="$plan_job,$array_job,$merge_job"
deadline=$(($(date +%s) + timeout_s))
tick=0
while [[ -n "$(squeue -h -t PD,R,CG,CF,S,RQ -j "$ids" -o %i 2>/dev/null)" ]]; do
  if ! kill -0 "$slurmctld_pid" 2>/dev/null || ! kill -0 "$slurmd_pid" 2>/dev/null; then
    echo "$0: a Slurm daemon died while the jobs ran; see $logs/slurm*.log" >&2
    exit 1
  fi
  if [[ $(date +%s) -ge $deadline ]]; then
    echo "$0: jobs still running after $timeout_s s; cancelling" >&2
    squeue -l -j "$ids" >&2
    exit 1
  fi
  if ((tick % 50 == 0)); then
    { date -u +%T; squeue -h -j "$ids" -o '%.14i %.11j %.9T %.10M %R'; } >>"$logs/squeue-progress.txt"
  fi
  tick=$((tick + 1))
  sleep 0.2
done
finished=$(date +%s.%N)
slurm_wall=$(awk -v a="$started" -v b="$finished" 'BEGIN { printf "%.1f", b - a }')

{
  squeue -t all -j "$ids" -o '%.14i %.11j %.10T %.10M %.4C %N %r' | head -n 1
  squeue -h -t all -j "$ids" -o '%.14i %.11j %.10T %.10M %.4C %N %r' |
    awk '{ print $1 "\t" $0 }' | sort -t$'\t' -k1,1V | cut -f2-
} >"$logs/squeue-final.txt"
for id in "$plan_job" "$array_job" "$merge_job"; do
  scontrol show job "$id"
done >"$logs/scontrol-show-job.txt"
# One line per job (array tasks one each): id, name, state, exit code, times.
job_table="$(for id in "$plan_job" "$array_job" "$merge_job"; do scontrol -o show job "$id"; done |
  awk '{
    delete f
    for (i = 1; i <= NF; i++) { split($i, kv, "="); f[kv[1]] = substr($i, length(kv[1]) + 2) }
    id = f["JobId"]; if (f["ArrayTaskId"] != "") id = f["ArrayJobId"] "_" f["ArrayTaskId"]
    printf "| %s | %s | %s | %s | %s | %s | %s |\n", id, f["JobName"], f["JobState"], f["ExitCode"],
      f["StartTime"], f["EndTime"], f["RunTime"]
  }' | sort -t'|' -k2,2V)"
log "Slurm jobs finished in $slurm_wall s:"
cat "$logs/squeue-final.txt"

all_completed=1
grep -q . <<<"$job_table" || all_completed=0
while IFS='|' read -r _ _ _ job_state _; do
  [[ "${job_state// /}" = COMPLETED ]] || all_completed=0
done <<<"$job_table"

# --- the whole bake, the same options ----------------------------------------
log "whole bake: svit-bake $(basename "$level") -o $whole --threads $ncpu ${bake_options[*]}"
whole_started=$(date +%s.%N)
whole_rc=0
if [[ $all_completed = 1 ]]; then
  "$bake" "$level" -o "$whole" --threads "$ncpu" "${bake_options[@]}" --quiet || whole_rc=$?
else
  log "skipped: not every Slurm job completed"
  whole_rc=skipped
fi
whole_wall=$(awk -v a="$whole_started" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')

# --- byte identity ------------------------------------------------------------
identical=1
identity=""
if [[ $all_completed = 1 && $whole_rc = 0 ]]; then
  merged_files="$(cd "$merged" && ls bake.svit lightmap-*.exr 2>/dev/null | sort)"
  whole_files="$(cd "$whole" && ls bake.svit lightmap-*.exr 2>/dev/null | sort)"
  if [[ "$merged_files" != "$whole_files" ]]; then
    identical=0
    identity+="file sets differ: merged [$(tr '\n' ' ' <<<"$merged_files")] whole [$(tr '\n' ' ' <<<"$whole_files")]"$'\n'
  fi
  for file in $whole_files; do
    if cmp -s "$merged/$file" "$whole/$file"; then
      identity+="$file: identical ($(stat -c %s "$whole/$file") bytes, sha256 $(sha256sum <"$whole/$file" | cut -c1-16))"$'\n'
    else
      identical=0
      identity+="$file: DIFFERS ($(cmp "$merged/$file" "$whole/$file" 2>&1 | head -n 1))"$'\n'
    fi
  done
else
  identical=0
  identity="not compared: jobs completed=$all_completed, whole bake exit $whole_rc"$'\n'
fi
log "byte identity:"
printf '%s' "$identity"

# --- per-shard figures from WORK/shard-I.json ---------------------------------
shard_table="$(/usr/bin/python3 - "$work" "$shards" <<'EOF'
import json, os, sys
work, shards = sys.argv[1], int(sys.argv[2])
for i in range(shards):
    path = os.path.join(work, f"shard-{i}.json")
    try:
        with open(path) as f:
            s = json.load(f)
        size = os.path.getsize(os.path.join(work, f"shard-{i}.bin"))
    except (OSError, ValueError) as e:
        print(f"| {i} | - | - | - | - | - | {e} |")
        continue
    rss_mib = s.get("peak_rss_bytes", 0) / 2**20
    print(f"| {i} | {s.get('texels', '?')} | {s.get('seconds', 0):.2f} | {s.get('lighting_seconds', 0):.2f} "
          f"| {rss_mib:.1f} | {size} | {s.get('host', '?')} |")
EOF
)"
# Seconds each program measured itself (plan.json, the two report.json).
stage_line="$(/usr/bin/python3 - "$work" "$merged" "$whole" <<'EOF'
import json, os, sys
def seconds(path, key):
    try:
        with open(path) as f:
            return f"{json.load(f)[key]:.2f} s"
    except (OSError, ValueError, KeyError, TypeError):
        return "-"
work, merged, whole = sys.argv[1:]
try:
    with open(os.path.join(merged, "report.json")) as f:
        lighting = f"{json.load(f)['sharded']['shard_lighting_seconds_total']:.2f} s"
except (OSError, ValueError, KeyError, TypeError):
    lighting = "-"
print(f"plan {seconds(os.path.join(work, 'plan.json'), 'plan_seconds')}, "
      f"shards' lighting {lighting} in all, "
      f"merge {seconds(os.path.join(merged, 'report.json'), 'total_seconds')}; "
      f"whole bake {seconds(os.path.join(whole, 'report.json'), 'total_seconds')}")
EOF
)"

# --- summary ------------------------------------------------------------------
{
  echo "# Sharded bake under Slurm"
  echo
  echo "- date: $(date -u '+%Y-%m-%d %H:%M UTC'), host \`$node\`, $ncpu CPUs ($(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | sed 's/^ //'))"
  echo "- Slurm: \`$slurm_version\` (Debian), single node, own slurm.conf, munged on its own socket"
  echo "- level: \`$level\`, $shards shards, options \`${bake_options[*]:-(none)}\`"
  echo "- jobs: plan $plan_job, shard array $array_job (0-$((shards - 1)), one CPU each), merge $merge_job"
  echo "- Slurm pipeline wall time (first submit to last job done): $slurm_wall s; whole bake ($ncpu threads): $whole_wall s"
  echo "- as measured by svit-bake itself: $stage_line"
  echo "- load average before / after: $load_before / $(cut -d' ' -f1-3 /proc/loadavg)"
  echo "- result: $([[ $identical = 1 ]] && echo "merged output byte-identical to the whole bake" || echo "**FAILED**")"
  echo
  echo "## Submitted"
  echo
  echo '```'
  cat "$logs/submitted.txt"
  echo '```'
  echo
  echo "## Jobs (scontrol show job)"
  echo
  echo "| job | name | state | exit | start | end | run time |"
  echo "|---|---|---|---|---|---|---|"
  echo "$job_table"
  echo
  echo '```'
  cat "$logs/squeue-final.txt"
  echo '```'
  echo
  echo "## Shards (WORK/shard-I.json)"
  echo
  echo "| shard | texels | seconds | lighting s | peak RSS MiB | shard-I.bin bytes | host |"
  echo "|---|---|---|---|---|---|---|"
  echo "$shard_table"
  echo
  echo "## Byte identity (merged vs whole; report.json not compared)"
  echo
  echo '```'
  printf '%s' "$identity"
  echo '```'
  echo
  echo "## Job outputs (last lines; whole files in slurm/)"
  for f in "$logs"/plan-*.out "$logs"/shard-*.out "$logs"/merge-*.out; do
    [[ -f "$f" ]] || continue
    echo
    echo "\`$(basename "$f")\`:"
    echo '```'
    tail -n 2 "$f"
    echo '```'
  done
} >"$out/slurm_summary.md"
sed -n '/^## Jobs/,/^## Job outputs/p' "$out/slurm_summary.md" | sed '$d'
log "summary: $out/slurm_summary.md"
[[ $identical = 1 ]]
