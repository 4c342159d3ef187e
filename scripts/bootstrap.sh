#!/usr/bin/env bash
# One entry point for a fresh Debian 12 machine: installs what is missing, builds, then
#   run       runs the main job on the default scenario
#   test      runs the whole test suite (Release build)
#   sanitize  runs the unit tests under AddressSanitizer + UndefinedBehaviorSanitizer
#   build     only builds
set -euo pipefail
cd "$(dirname "$0")/.."

mode="${1:-run}"
jobs="${CORRIDORSIM_JOBS:-$(nproc)}"

scripts/setup.sh

configure_and_build() {  # build_dir, extra cmake args...
  local dir="$1"; shift
  if [ ! -f "$dir/build.ninja" ]; then
    cmake -S . -B "$dir" -G Ninja "$@" > /dev/null
  fi
  cmake --build "$dir" --parallel "$jobs"
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
    ctest --test-dir build --output-on-failure --parallel "$jobs"
    ;;
  sanitize)
    configure_and_build build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCORRIDORSIM_SANITIZE=ON \
      -DCORRIDORSIM_BUILD_BENCHMARKS=OFF
    ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
      ctest --test-dir build-asan --output-on-failure --parallel "$jobs" -L unit \
        -E "ten thousand frames"  # runs in the Release suite; 10,000 frames under ASan take minutes
    ;;
  *)
    echo "usage: scripts/bootstrap.sh [run|test|sanitize|build]" >&2
    exit 2
    ;;
esac
