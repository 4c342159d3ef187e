#!/usr/bin/env bash
# Runs every shipped scenario (scenarios/*.yaml, at its own seed) and compares the bytes of each
# run's metrics.json with the reference copy in tests/data/metrics/<scenario>.json. A refactoring
# must leave them all identical; a change that is meant to move a metric updates the references
# with --update in the same commit and says why. Each run folder is also given to
# scripts/check_analysis.py: corridorsim.Run must recompute every pipeline's trajectory metrics
# from the TUM files to the last digit (docs/analysis.md), and its viewer.html must keep within
# 10 MB (docs/viewer.md).
#
#   scripts/check_metrics.sh [--update] [--bin build/bin/corridorsim] [SCENARIO.yaml ...]
#
# Exit 0: all identical (or updated) and recomputed exactly; 1: a difference (the diff is
# printed), a mismatch of the Python recomputation (each is printed) or a run failed.
set -euo pipefail
cd "$(dirname "$0")/.."

update=0
bin=build/bin/corridorsim
scenarios=()
while [ $# -gt 0 ]; do
  case "$1" in
    --update) update=1 ;;
    --bin) bin="$2"; shift ;;
    -h|--help) sed -n '2,10p' "$0"; exit 0 ;;
    *) scenarios+=("$1") ;;
  esac
  shift
done
[ ${#scenarios[@]} -gt 0 ] || scenarios=(scenarios/*.yaml)
[ -x "$bin" ] || { echo "check_metrics: $bin not found (build first)" >&2; exit 1; }

reference_dir=tests/data/metrics
# Debian's python3 (numpy, pandas) as the plots use it, with the checkout's corridorsim package
# first on its path.
python=/usr/bin/python3
[ -x "$python" ] || python=python3
python_path="$PWD/python${PYTHONPATH:+:$PYTHONPATH}"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failed=0
for scenario in "${scenarios[@]}"; do
  name=$(basename "$scenario" .yaml)
  out="$work/$name"
  rc=0
  "$bin" run "$scenario" --out "$out" --no-plots > "$work/$name.log" 2>&1 || rc=$?
  # 3 = an expectation failed: the metrics are still a result to compare.
  if [ "$rc" -ne 0 ] && [ "$rc" -ne 3 ]; then
    echo "FAIL $name: corridorsim run exited $rc"; tail -5 "$work/$name.log"; failed=1; continue
  fi
  if [ "$update" -eq 1 ]; then
    cp "$out/metrics.json" "$reference_dir/$name.json"
    echo "updated $reference_dir/$name.json"
  elif [ ! -f "$reference_dir/$name.json" ]; then
    echo "FAIL $name: no reference $reference_dir/$name.json (run with --update)"; failed=1
  elif cmp -s "$out/metrics.json" "$reference_dir/$name.json"; then
    echo "same $name"
  else
    echo "DIFF $name"; diff "$reference_dir/$name.json" "$out/metrics.json" | head -20 || true
    failed=1
  fi
  # viewer.html (docs/viewer.md) within its budget of 10 MB without frames (exit 4 above when
  # the page failed).
  viewer_bytes=$(stat -c %s "$out/viewer.html" 2>/dev/null || echo missing)
  if [ "$viewer_bytes" = missing ] || [ "$viewer_bytes" -gt 10000000 ]; then
    echo "FAIL $name: viewer.html is $viewer_bytes bytes (budget 10000000)"; failed=1
  else
    echo "viewer $name: $viewer_bytes bytes"
  fi
  # corridorsim.Run's ATE, RPE and final error equal metrics.json's, float for float.
  if PYTHONPATH="$python_path" "$python" scripts/check_analysis.py "$out" \
      > "$work/$name.analysis" 2>&1; then
    echo "exact $(cat "$work/$name.analysis")"
  else
    echo "FAIL $name: corridorsim.Run does not recompute metrics.json exactly"
    head -20 "$work/$name.analysis"
    failed=1
  fi
done
exit $failed
