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
timeout_s="${STUDY_SLURM_TIMEOUT:-300}"
# shellcheck source=tests/slurm/slurm_test_support.sh
source "$(dirname "${BASH_SOURCE[0]}")/slurm_test_support.sh"

require_slurm "scripts/setup.sh installs Slurm"

rm -rf "$work"
mkdir -p "$work"
cluster="$(mktemp -d /tmp/cs_slurm.XXXXXX)"
ok=0
cleanup() {
  local rc=$?
  stop_cluster "$ok" "$cluster" "$cluster"/log/*.log "$work"/slurm_study/slurm/*.log || rc=1
  rm -rf "$cluster"
  exit "$rc"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

start_cluster "$cluster"

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

wait_for_jobs "$timeout_s" "$array_id" "$merge_id"
expect_completed "$array_id" 3 "$merge_id"

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
