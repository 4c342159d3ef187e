# shellcheck shell=bash
# What the Slurm tests (tests/slurm/*.sh, on scripts/slurm_local.sh's cluster) share. Source it
# after `set -euo pipefail`:
#   # shellcheck source=tests/slurm/slurm_test_support.sh
#   source "$(dirname "${BASH_SOURCE[0]}")/slurm_test_support.sh"

slurm_local="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)/scripts/slurm_local.sh"

# require_slurm <how to install>: exits 77 ("SKIPPED: ...", the CTest/automake skip code) unless
# every Slurm and MUNGE command the cluster needs is installed.
require_slurm() {
  for cmd in munged slurmctld slurmd sbatch squeue scontrol sinfo; do
    if ! command -v "$cmd" >/dev/null 2>&1; then
      echo "SKIPPED: $cmd not found ($1)"
      exit 77
    fi
  done
}

fail() {
  echo "FAIL: $*" >&2
  exit 1
}

# print_logs <file>...: the last 30 lines of each file that exists, on stderr.
print_logs() {
  local f
  for f in "$@"; do
    if [ -f "$f" ]; then
      echo "---- $f ----" >&2
      tail -n 30 "$f" >&2
    fi
  done
}

# start_cluster <folder>: scripts/slurm_local.sh's cluster in <folder> (a short path: the unix
# sockets below it are limited to 108 bytes), its environment (SLURM_CONF, ...) exported here.
start_cluster() {
  local env_lines
  env_lines="$("$slurm_local" start "$1")" || fail "could not start the cluster"
  eval "$env_lines"
}

# stop_cluster <passed> <folder> <log file>...: the end of a test's cluster, in its EXIT trap:
# unless <passed> is 1, the diagnostics on stderr first (the queue and the jobs while the cluster
# is up, the logs' tails). Fails if the cluster does not stop.
stop_cluster() {
  local passed=$1 folder=$2
  shift 2
  if [ "$passed" -ne 1 ]; then
    echo "---- diagnostics ----" >&2
    if [ -n "${SLURM_CONF:-}" ]; then
      timeout 10 squeue >&2 2>&1 || true
      timeout 10 scontrol show job >&2 2>&1 || true
    fi
    print_logs "$@"
  fi
  "$slurm_local" stop "$folder"
}

# wait_for_jobs <timeout_s> <job id>...: until none of the jobs is pending or running any more
# (squeue lists array tasks and dependent jobs while they are pending, running or completing).
wait_for_jobs() {
  local timeout_s=$1 ids deadline active
  shift
  ids="$(IFS=,; echo "$*")"
  deadline=$((SECONDS + timeout_s))
  while :; do
    active="$(squeue -h -j "$ids" -t PD,R,CG,CF -o '%i %T %r' 2>/dev/null || true)"
    if [ -z "$active" ]; then break; fi
    if [ "$SECONDS" -ge "$deadline" ]; then
      fail "jobs still active after ${timeout_s}s: $(echo "$active" | tr '\n' ';')"
    fi
    sleep 0.5
  done
}

# expect_completed <array job id> <tasks> <job id>...: every job completed with exit code 0, the
# array with <tasks> tasks.
expect_completed() {
  local array_id=$1 tasks=$2 id state completed
  shift 2
  for id in "$array_id" "$@"; do
    state="$(scontrol show job -o "$id" | grep -o 'JobState=[A-Z_]*' | sort -u | tr '\n' ' ')"
    [ "$state" = "JobState=COMPLETED " ] || fail "job $id ended as: ${state:-<unknown>}"
  done
  completed="$(scontrol show job -o "$array_id" | grep -c 'JobState=COMPLETED')"
  [ "$completed" -eq "$tasks" ] || fail "expected $tasks completed array tasks, found $completed"
}
