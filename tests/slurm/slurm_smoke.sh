#!/usr/bin/env bash
# Smoke test for scripts/slurm_local.sh: starts a private single-node Slurm cluster in a
# temporary folder, submits a 3-task job array whose tasks each write their
# SLURM_ARRAY_TASK_ID to a file, then a job that depends on the array (afterok) and
# concatenates those files; waits for both, checks the result and stops the cluster.
#
# Exit status: 0 on success; 77 ("SKIPPED: ...", the CTest/automake skip code) only when
# the Slurm/MUNGE packages are not installed; 1 on any other failure, with logs printed.
#
# Knobs: SLURM_SMOKE_TIMEOUT (seconds to wait for the jobs, default 120),
#        SLURM_SMOKE_KEEP=1 keeps the temporary folder even on success.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
slurm_local="$here/../../scripts/slurm_local.sh"
timeout_s="${SLURM_SMOKE_TIMEOUT:-120}"

for cmd in munged slurmctld slurmd sbatch squeue scontrol sinfo; do
  if ! command -v "$cmd" >/dev/null 2>&1; then
    echo "SKIPPED: $cmd not found (install: scripts/slurm_local.sh install)"
    exit 77
  fi
done

fail() {
  echo "FAIL: $*" >&2
  exit 1
}

t0=$SECONDS
# Short path: unix sockets (munge, slurmstepd) live below it and are limited to 108 bytes.
dir="$(mktemp -d /tmp/slurm_smoke.XXXXXX)"
ok=0
cleanup() {
  local rc=$?
  if [ "$ok" -ne 1 ]; then
    echo "---- diagnostics (folder $dir kept) ----" >&2
    if [ -n "${SLURM_CONF:-}" ]; then
      timeout 10 squeue >&2 2>&1 || true
      timeout 10 scontrol show job >&2 2>&1 || true
    fi
    for f in "$dir"/log/*.log "$dir"/work/*.out; do
      if [ -f "$f" ]; then
        echo "---- $f ----" >&2
        tail -n 30 "$f" >&2
      fi
    done
  fi
  "$slurm_local" stop "$dir" || rc=1
  if [ "$ok" -eq 1 ] && [ "${SLURM_SMOKE_KEEP:-0}" != 1 ]; then rm -rf "$dir"; fi
  exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# 1. Cluster.
t_start=$SECONDS
env_lines="$("$slurm_local" start "$dir")" || fail "could not start the cluster"
eval "$env_lines"
echo "cluster started in $((SECONDS - t_start)) s: SLURM_CONF=$SLURM_CONF"

# 2. Jobs. Single quotes: $SLURM_ARRAY_TASK_ID is expanded by each task, not here.
work="$dir/work"
mkdir -p "$work"
# shellcheck disable=SC2016 # expanded by the job, intentionally
array_id="$(sbatch --parsable --array=0-2 --job-name=smoke_array --chdir="$work" \
  --output="$work/array_%A_%a.out" \
  --wrap 'echo "$SLURM_ARRAY_TASK_ID" > "task_${SLURM_ARRAY_TASK_ID}.txt"')"
array_id="${array_id%%;*}" # --parsable prints "jobid[;cluster]"
[[ "$array_id" =~ ^[0-9]+$ ]] || fail "unexpected sbatch output for the array: '$array_id'"

dep_id="$(sbatch --parsable --dependency="afterok:$array_id" --job-name=smoke_cat \
  --chdir="$work" --output="$work/cat_%j.out" \
  --wrap 'cat task_0.txt task_1.txt task_2.txt > result.txt')"
dep_id="${dep_id%%;*}"
[[ "$dep_id" =~ ^[0-9]+$ ]] || fail "unexpected sbatch output for the dependent job: '$dep_id'"
echo "submitted array job $array_id and dependent job $dep_id"

# 3. Wait until neither job is pending/running any more (squeue lists array tasks and the
#    dependent job while they are pending, running or completing).
deadline=$((SECONDS + timeout_s))
while :; do
  active="$(squeue -h -j "$array_id,$dep_id" -t PD,R,CG,CF -o '%i %T %r' 2>/dev/null || true)"
  if [ -z "$active" ]; then break; fi
  if [ "$SECONDS" -ge "$deadline" ]; then
    fail "jobs still active after ${timeout_s}s: $(echo "$active" | tr '\n' ';')"
  fi
  sleep 0.5
done

# 4. Checks: every job completed with exit code 0, and the result has the three lines.
job_state() { scontrol show job -o "$1" | grep -o 'JobState=[A-Z_]*' | sort -u | tr '\n' ' '; }
for id in "$array_id" "$dep_id"; do
  state="$(job_state "$id")"
  [ "$state" = "JobState=COMPLETED " ] || fail "job $id ended as: ${state:-<unknown>}"
done
n_tasks="$(scontrol show job -o "$array_id" | grep -c 'JobState=COMPLETED')"
[ "$n_tasks" -eq 3 ] || fail "expected 3 completed array tasks, found $n_tasks"

[ -f "$work/result.txt" ] || fail "dependent job wrote no $work/result.txt"
expected=$'0\n1\n2'
actual="$(cat "$work/result.txt")"
[ "$actual" = "$expected" ] || fail "result.txt is '$actual', expected '$expected'"

ok=1
echo "PASS: array $array_id (3 tasks) then afterok job $dep_id; total $((SECONDS - t0)) s before stop"
