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
# shellcheck source=tests/slurm/slurm_test_support.sh
source "$here/slurm_test_support.sh"
timeout_s="${SLURM_SMOKE_TIMEOUT:-120}"

require_slurm "install: scripts/slurm_local.sh install"

t0=$SECONDS
dir="$(mktemp -d /tmp/slurm_smoke.XXXXXX)"
ok=0
cleanup() {
  local rc=$?
  stop_cluster "$ok" "$dir" "$dir"/log/*.log "$dir"/work/*.out || rc=1
  if [ "$ok" -eq 1 ] && [ "${SLURM_SMOKE_KEEP:-0}" != 1 ]; then
    rm -rf "$dir"
  else
    echo "folder $dir kept" >&2
  fi
  exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

# 1. Cluster.
t_start=$SECONDS
start_cluster "$dir"
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

# 3. Wait until neither job is pending/running any more.
wait_for_jobs "$timeout_s" "$array_id" "$dep_id"

# 4. Checks: every job completed with exit code 0, and the result has the three lines.
expect_completed "$array_id" 3 "$dep_id"

[ -f "$work/result.txt" ] || fail "dependent job wrote no $work/result.txt"
expected=$'0\n1\n2'
actual="$(cat "$work/result.txt")"
[ "$actual" = "$expected" ] || fail "result.txt is '$actual', expected '$expected'"

ok=1
echo "PASS: array $array_id (3 tasks) then afterok job $dep_id; total $((SECONDS - t0)) s before stop"
