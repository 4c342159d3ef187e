#!/usr/bin/env bash
# Issue 37's stress test of llvmpipe's rasterizer threads (docs/rendering.md, "llvmpipe's
# rasterizer threads"). Runs a scenario again and again with every condition-variable broadcast of
# an llvmpipe thread delayed by 2 ms (tests/render/stress/slow_broadcast.c, LD_PRELOAD) and
# glibc's malloc checking on (libc_malloc_debug, MALLOC_PERTURB_: freed memory holds 0xA5 bytes),
# each run under a time limit. A run that hangs past the limit or dies is the race: Mesa 22.3
# frees a fence that a rasterizer thread is still signalling. corridorsim's default (no
# rasterizer thread) must pass; `--threads 2` shows the race (here 1 hang in 2 runs).
#
#   scripts/stress_llvmpipe_threads.sh [--bin build/bin/corridorsim] [--runs 4] [--threads T]
#                                      [--limit 300] [--duration 60] [SCENARIO.yaml]
#
# --threads T runs with LP_NUM_THREADS=T (default: unset, corridorsim's default of 0).
# SCENARIO defaults to scenarios/p3_lamps.yaml (the upward camera: five passes a frame), cut to
# --duration seconds of simulated time. Needs a C compiler (cc) for the shim.
# Exit 0: every run finished; 1: a run hung or crashed (its log's end printed); 2: bad arguments.
set -euo pipefail
cd "$(dirname "$0")/.."

bin=build/bin/corridorsim
runs=4
threads=""
limit=300
duration=60
scenario=scenarios/p3_lamps.yaml
positive_int() { [[ "$2" =~ ^[0-9]+$ ]] && [ "$2" -ge "$3" ] && [ "$2" -le "$4" ] ||
  { echo "stress_llvmpipe_threads: $1 must be an integer in [$3, $4], got '$2'" >&2; exit 2; }; }
while [ $# -gt 0 ]; do
  case "$1" in
    --bin) bin="${2:?--bin needs a path}"; shift ;;
    --runs) positive_int --runs "${2:-}" 1 10000; runs="$2"; shift ;;
    --threads) positive_int --threads "${2:-}" 0 64; threads="$2"; shift ;;
    --limit) positive_int --limit "${2:-}" 10 86400; limit="$2"; shift ;;
    --duration) positive_int --duration "${2:-}" 1 3600; duration="$2"; shift ;;
    -h|--help) sed -n '2,17p' "$0"; exit 0 ;;
    -*) echo "stress_llvmpipe_threads: unknown flag $1 (--help)" >&2; exit 2 ;;
    *) scenario="$1" ;;
  esac
  shift
done
[ -x "$bin" ] || { echo "stress_llvmpipe_threads: $bin not found (build first)" >&2; exit 2; }
[ -f "$scenario" ] || { echo "stress_llvmpipe_threads: $scenario: no such file" >&2; exit 2; }
malloc_debug=/usr/lib/x86_64-linux-gnu/libc_malloc_debug.so.0
[ -f "$malloc_debug" ] || { echo "stress_llvmpipe_threads: $malloc_debug missing (glibc 2.34+)" >&2; exit 2; }

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cc -O2 -shared -fPIC tests/render/stress/slow_broadcast.c -o "$work/slow_broadcast.so" -ldl
printf 'include: %s\nduration_s: %s\n' "$(realpath "$scenario")" "$duration" > "$work/short.yaml"
if [ -n "$threads" ]; then thread_env=(LP_NUM_THREADS="$threads"); else thread_env=(-u LP_NUM_THREADS); fi

failed=0
for i in $(seq 1 "$runs"); do
  rc=0
  start=$(date +%s)
  timeout --kill-after=10 "$limit" env "${thread_env[@]}" \
    LD_PRELOAD="$work/slow_broadcast.so $malloc_debug" MALLOC_CHECK_=3 MALLOC_PERTURB_=165 \
    "$bin" run "$work/short.yaml" --out "$work/run" --force --no-plots --no-viewer \
    > "$work/log.txt" 2>&1 || rc=$?
  slowed=$(grep -o 'slow_broadcast: [0-9]*' "$work/log.txt" | tail -1 | grep -o '[0-9]*$' || echo 0)
  if [ "$rc" -eq 0 ] || [ "$rc" -eq 3 ]; then
    echo "run $i: finished (exit $rc) in $(( $(date +%s) - start )) s, $slowed llvmpipe broadcasts slowed"
  else
    what="exit $rc"; [ "$rc" -eq 124 ] || [ "$rc" -eq 137 ] && what="hung past ${limit} s"
    # The progress line is rewritten in place (\r): show where the run stopped.
    echo "run $i: FAILED, $what"; tr '\r' '\n' < "$work/log.txt" | grep -v '^ *$' | tail -3
    failed=1
  fi
done
exit "$failed"
