#!/usr/bin/env bash
# One entry point for a fresh Debian 12 machine: installs what is missing, builds, then
#   run       runs the main job on the default scenario
#   test      runs the whole test suite (Release build)
#   sanitize [all|inputs]  builds the tree with clang, AddressSanitizer + UndefinedBehaviorSanitizer
#             (build-fuzz/) and runs the unit tests in it: all of them (default), or `inputs`, the
#             tests of the code that reads what comes from outside (common_tests, harness_tests,
#             slam_plate_tests and the command-line tests registered there), as CI does (docs/ci.md)
#   fuzz [SECONDS]  builds the libFuzzer targets in that same tree and runs each for SECONDS
#             (default 60 per target), as many at a time as build jobs, on a copy of its seed corpus
#             (docs/fuzzing.md); fails on a crash, a leak, an input slower than its timeout (1 s
#             unless fuzz/CMakeLists.txt says otherwise) or over 2 GiB
#   build     only builds
# sanitize and fuzz share build-fuzz/ (one compile of the libraries serves both; docs/ci.md).
set -euo pipefail
cd "$(dirname "$0")/.."

mode="${1:-run}"
jobs="${CORRIDORSIM_JOBS:-$(nproc)}"

scripts/setup.sh

configure_and_build() {  # build_dir, extra cmake args...
  local dir="$1"; shift
  local start=$SECONDS
  # Configured every time (a no-op when nothing changed): a tree configured before with other
  # options (a fuzz tree without tests) gets this mode's.
  cmake -S . -B "$dir" -G Ninja "$@" > /dev/null
  cmake --build "$dir" --parallel "$jobs" ${CORRIDORSIM_BUILD_TARGET:+--target "$CORRIDORSIM_BUILD_TARGET"}
  echo "bootstrap: $dir built in $((SECONDS - start)) s"
}

# timed NAME COMMAND...: runs it and says how long it took (docs/ci.md reads these lines).
timed() {
  local name="$1"; shift
  local start=$SECONDS rc=0
  "$@" || rc=$?
  echo "bootstrap: $name took $((SECONDS - start)) s (exit $rc)"
  return "$rc"
}

# Runs every fuzz target of build-fuzz/fuzz/fuzzers.tsv for $1 seconds each, $jobs at a time
# (each is one process); the corpus each run grows and any crash input stay under
# build-fuzz/fuzz-runs/<target>/.
run_one_fuzzer() {  # seconds name binary corpus dict timeout
  local seconds="$1" name="$2" binary="$3" corpus="$4" dict="$5" timeout="$6"
  local work="build-fuzz/fuzz-runs/$name"
  rm -rf "$work"
  mkdir -p "$work/corpus" "$work/artifacts"
  cp -R "$corpus/." "$work/corpus/"
  local args=(-max_total_time="$seconds" -timeout="$timeout" -rss_limit_mb=2048 -detect_leaks=1
              -print_final_stats=1 -artifact_prefix="$work/artifacts/")
  if [ "$dict" != "-" ]; then args+=(-dict="$dict"); fi
  ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 \
  UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
    "$binary" "${args[@]}" "$work/corpus" > "$work/log.txt" 2>&1
}

run_fuzzers() {
  local seconds="$1" failed=0 name binary corpus dict timeout
  local names=() pids=()
  while IFS=$'\t' read -r name binary corpus dict timeout; do
    while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n || true; done
    echo "fuzz: $name for ${seconds} s (corpus build-fuzz/fuzz-runs/$name/corpus, crashes build-fuzz/fuzz-runs/$name/artifacts)"
    run_one_fuzzer "$seconds" "$name" "$binary" "$corpus" "$dict" "$timeout" &
    names+=("$name")
    pids+=("$!")
  done < build-fuzz/fuzz/fuzzers.tsv
  local i
  for i in "${!pids[@]}"; do
    name="${names[$i]}"
    if ! wait "${pids[$i]}"; then
      failed=1
      echo "fuzz: $name FAILED (log build-fuzz/fuzz-runs/$name/log.txt, inputs build-fuzz/fuzz-runs/$name/artifacts):" >&2
      tail -n 40 "build-fuzz/fuzz-runs/$name/log.txt" >&2
    else
      echo "fuzz: $name:"
      grep -E '^stat::|^Done' "build-fuzz/fuzz-runs/$name/log.txt" || true
    fi
  done
  return "$failed"
}

# The sanitized tree: clang, every library, program and test compiled with ASan + UBSan (and
# libFuzzer's coverage, fuzz/CMakeLists.txt), the fuzz targets beside them; no benchmarks.
install_clang() {  # clang and its libFuzzer runtime (Debian 12: clang-14), as scripts/setup.sh does
  local p
  for p in clang libclang-rt-14-dev; do
    if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
      echo "bootstrap: installing $p"
      SUDO=""; if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
      $SUDO apt-get update -qq
      DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "$p"
    fi
  done
}
build_sanitized() {  # [target [cmake args...]]: builds it (default: everything) in build-fuzz/
  install_clang
  local target="${1:-}"
  shift || true
  CORRIDORSIM_BUILD_TARGET="$target" configure_and_build build-fuzz \
    -DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_C_COMPILER=clang \
    -DCORRIDORSIM_FUZZ=ON -DCORRIDORSIM_BUILD_BENCHMARKS=OFF "$@"
}

case "$mode" in
  build)
    configure_and_build build -DCMAKE_BUILD_TYPE=Release
    ;;
  run)
    configure_and_build build -DCMAKE_BUILD_TYPE=Release
    build/bin/corridorsim run scenarios/default.yaml --out out/run --force
    ;;
  test)
    configure_and_build build -DCMAKE_BUILD_TYPE=Release
    timed "the Release suite (ctest)" ctest --test-dir build --output-on-failure --parallel "$jobs"
    ;;
  sanitize)
    scope="${2:-all}"
    if [ "$scope" != all ] && [ "$scope" != inputs ]; then
      echo "usage: scripts/bootstrap.sh sanitize [all|inputs]" >&2
      exit 2
    fi
    build_sanitized "" -DCORRIDORSIM_SANITIZED_TESTS="$scope"
    ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
      timed "the sanitized unit tests (ctest -L unit)" ctest --test-dir build-fuzz --output-on-failure --parallel "$jobs" -L unit \
        -E "scripts.plot_run"
    # The plot script's test is Python only (no instrumented code, 4 minutes); it and the test
    # cases tagged [heavy] (tests/CMakeLists.txt: not registered in this tree) run in the Release
    # suite.
    ;;
  fuzz)
    seconds="${2:-60}"
    if ! [[ "$seconds" =~ ^[0-9]+$ ]] || [ "$seconds" -lt 1 ] || [ "$seconds" -gt 604800 ]; then
      echo "usage: scripts/bootstrap.sh fuzz [SECONDS per target, 1..604800]" >&2
      exit 2
    fi
    # Only the fuzz targets and what they link (after `sanitize`, only the targets' own files).
    build_sanitized corridorsim_fuzzers
    timed "the fuzz runs" run_fuzzers "$seconds"
    ;;
  *)
    echo "usage: scripts/bootstrap.sh [run|test|sanitize [all|inputs]|fuzz [SECONDS]|build]" >&2
    exit 2
    ;;
esac
