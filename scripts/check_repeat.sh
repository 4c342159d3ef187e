#!/usr/bin/env bash
# The saved scenario repeats the run: every shipped scenario (scenarios/*.yaml) and every include
# chain of tests/data/repeat/*.yaml is run (shortened: a wrapper includes it and sets duration_s),
# then run again from the scenario.yaml its run folder saved. The two folders must hold the same
# bytes, every file but timing.json, maps/*_frame_times.csv and viewer.html (wall clock) and provenance.json's
# `scenario.file` (the path given); the second scenario.yaml is the first one's bytes (the echo is a fixed point).
#
#   scripts/check_repeat.sh [--bin build/bin/corridorsim] [--duration S] [SCENARIO.yaml ...]
#
# Exit 0: every rerun identical; 1: a difference (printed) or a run failed.
set -euo pipefail
cd "$(dirname "$0")/.."

bin=build/bin/corridorsim
duration=20
scenarios=()
while [ $# -gt 0 ]; do
  case "$1" in
    --bin) bin="$2"; shift ;;
    --duration) duration="$2"; shift ;;
    -h|--help) sed -n '2,10p' "$0"; exit 0 ;;
    *) scenarios+=("$1") ;;
  esac
  shift
done
[ ${#scenarios[@]} -gt 0 ] || scenarios=(scenarios/*.yaml tests/data/repeat/*.yaml)
[ -x "$bin" ] || { echo "check_repeat: $bin not found (build first)" >&2; exit 1; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failed=0
# Runs `$1` into folder `$2`; exit 3 (an expectation failed) still leaves a run to compare.
run_into() {
  local rc=0
  "$bin" run "$1" --out "$2" --no-plots --no-viewer > "$2.log" 2>&1 || rc=$?
  if [ "$rc" -ne 0 ] && [ "$rc" -ne 3 ]; then
    echo "FAIL $name: corridorsim run $1 exited $rc"; tail -5 "$2.log"; return 1
  fi
}
for scenario in "${scenarios[@]}"; do
  name=$(basename "$(dirname "$scenario")")_$(basename "$scenario" .yaml)
  mkdir -p "$work/$name"
  wrapper="$work/$name/short.yaml"
  printf 'include: %s\nduration_s: %s\n' "$(realpath "$scenario")" "$duration" > "$wrapper"
  first="$work/$name/first" second="$work/$name/second"
  run_into "$wrapper" "$first" || { failed=1; continue; }
  cp "$first/scenario.yaml" "$work/$name/saved.yaml"
  run_into "$work/$name/saved.yaml" "$second" || { failed=1; continue; }
  same=1
  while IFS= read -r -d '' file; do
    rel=${file#"$first/"}
    case "$rel" in
      timing.json | maps/*_frame_times.csv | viewer.html) continue ;;  # wall clock (the page shows the frame times)
      provenance.json)
        if ! diff <(grep -v '"file":' "$file") <(grep -v '"file":' "$second/$rel") > /dev/null; then
          echo "DIFF $name: $rel"; diff <(grep -v '"file":' "$file") \
            <(grep -v '"file":' "$second/$rel") | head -10; same=0
        fi ;;
      *)
        if [ ! -f "$second/$rel" ]; then
          echo "DIFF $name: $rel missing in the rerun"; same=0
        elif ! cmp -s "$file" "$second/$rel"; then
          echo "DIFF $name: $rel"; diff "$file" "$second/$rel" | head -10; same=0
        fi ;;
    esac
  done < <(find "$first" -type f -print0 | sort -z)
  if [ "$(find "$first" -type f | wc -l)" -ne "$(find "$second" -type f | wc -l)" ]; then
    echo "DIFF $name: the rerun wrote other files"; same=0
  fi
  if [ "$same" -eq 1 ]; then echo "same $name"; else failed=1; fi
done
exit $failed
