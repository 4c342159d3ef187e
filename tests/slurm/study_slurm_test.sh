#!/usr/bin/env bash
# `corridorsim study --slurm --submit` on a real single-node Slurm (scripts/slurm_local.sh: munge,
# slurmctld and slurmd from Debian's packages, all in a temporary folder, no systemd): a small
# camera-less study runs as a 3-task job array and a merge job that depends on it (afterok); the
# merged summary must be the same bytes as the same study run here in one process.
#
# Usage: study_slurm_test.sh CORRIDORSIM SOURCE_DIR WORK_DIR
# Exit status: 0 passed; 77 ("SKIPPED: <reason>") only when the Slurm packages are not installed
# (scripts/setup.sh installs them); 1 on any failure, with the logs printed.
set -euo pipefail

corridorsim="$1"
source_dir="$2"
work="$3"
slurm_local="$source_dir/scripts/slurm_local.sh"
timeout_s="${STUDY_SLURM_TIMEOUT:-300}"

for cmd in munged slurmctld slurmd sbatch squeue scontrol sinfo; do
  if ! command -v "$cmd" >/dev/null 2>&1; then
    echo "SKIPPED: $cmd not found (scripts/setup.sh installs Slurm)"
    exit 77
  fi
done

fail() {
  echo "FAIL: $*" >&2
  exit 1
}

rm -rf "$work"
mkdir -p "$work"
# Short path: unix sockets (munge, slurmstepd) live below it and are limited to 108 bytes.
cluster="$(mktemp -d /tmp/cs_slurm.XXXXXX)"
ok=0
cleanup() {
  local rc=$?
  if [ "$ok" -ne 1 ]; then
    echo "---- diagnostics ----" >&2
    for f in "$cluster"/log/*.log "$work"/slurm_study/slurm/*.log; do
      if [ -f "$f" ]; then
        echo "---- $f ----" >&2
        tail -n 30 "$f" >&2
      fi
    done
  fi
  "$slurm_local" stop "$cluster" || rc=1
  rm -rf "$cluster"
  exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

env_lines="$("$slurm_local" start "$cluster")" || fail "could not start the cluster"
eval "$env_lines"

cat > "$work/study.yaml" <<YAML
include: $source_dir/scenarios/umbmark_cw.yaml
duration_s: 8
study:
  runs: 3
  first_seed: 4
  vary:
    robot.odometry.random_k_m: [1.0e-5, 1.0e-3]
  expectations:
    - odometry.ate_rmse_m.mean < 5
    - runs.failed < 1
YAML

cd "$work"
out="$("$corridorsim" study study.yaml --slurm --submit --slurm-tasks 3 --no-plots --no-viewer \
  --out slurm_study)" || fail "study --slurm --submit exited $?: $out"
echo "$out"
if [ ! -f slurm_study/slurm/study.sbatch ] || [ ! -f slurm_study/slurm/merge.sbatch ]; then
  fail "no job scripts"
fi
grep -q '^#SBATCH --array=1-3$' slurm_study/slurm/study.sbatch || fail "not a 3-task array"
array_id="$(sed -n 's/.*"array_job": "\([0-9]*\)".*/\1/p' slurm_study/slurm/jobs.json)"
merge_id="$(sed -n 's/.*"merge_job": "\([0-9]*\)".*/\1/p' slurm_study/slurm/jobs.json)"
if [ -z "$array_id" ] || [ -z "$merge_id" ]; then fail "no job ids in slurm/jobs.json"; fi
scontrol show job -o "$merge_id" | grep -q "Dependency=afterok:${array_id}" ||
  scontrol show job -o "$merge_id" | grep -q "JobState=COMPLETED" ||
  fail "the merge job does not depend on the array: $(scontrol show job -o "$merge_id")"

deadline=$((SECONDS + timeout_s))
while [ -n "$(squeue -h -j "$array_id,$merge_id" -t PD,R,CG,CF 2>/dev/null || true)" ]; do
  [ "$SECONDS" -lt "$deadline" ] || fail "jobs still active after ${timeout_s} s"
  sleep 0.5
done
for id in "$array_id" "$merge_id"; do
  states="$(scontrol show job -o "$id" | grep -o 'JobState=[A-Z_]*' | sort -u | tr '\n' ' ')"
  [ "$states" = "JobState=COMPLETED " ] || fail "job $id ended as: $states"
done
tasks="$(scontrol show job -o "$array_id" | grep -c 'JobState=COMPLETED')"
[ "$tasks" -eq 3 ] || fail "$tasks array tasks completed, expected 3"

# The run measured here before submitting is given to its shard (task 1), not run again.
grep -q "1 already finished, 1 to run" slurm_study/slurm/task_1.log ||
  fail "task 1 ran the measured run again: $(head -n 3 slurm_study/slurm/task_1.log)"

# The same study here, in one process: the same summary, byte for byte.
"$corridorsim" study study.yaml --no-plots --no-viewer --out local > local.log ||
  fail "local study failed"
for f in summary.json summary.csv paired.csv; do
  cmp "local/$f" "slurm_study/$f" || fail "$f differs between the local and the Slurm study"
done
ok=1
echo "PASS: array job $array_id (3 tasks) and merge job $merge_id; merged summary = local summary"
