#!/usr/bin/env bash
# The quick-start commands (see README.md). Each installs the missing Debian packages, then builds
# in build/ only what it needs (targets of one configuration, so the modes follow each other there):
#   ./build.sh run [SCENE]        the executable and the Python module; runs `rubcont run`
#                                 (extra arguments go to it, e.g. a scene file)
#   ./build.sh test               everything the tests need; runs the whole suite through ctest (CI)
#   ./build.sh quick              the same build; runs the quick tier (ctest -L quick: every folder,
#                                 a few minutes; tests/test_costs.txt)
#   ./build.sh bench [NAME ARGS]  the benchmarks (build/bench/); with NAME, runs that one with ARGS
set -euo pipefail
cd "$(dirname "$0")"

mode=${1:-}
shift || true
case "$mode" in
  run) target=rubcont_for_run; options=() ;;
  test|quick) target=rubcont_for_test; options=(-DRUBCONT_BUILD_TESTS=ON) ;;
  bench) target=rubcont_for_bench; options=(-DRUBCONT_BUILD_BENCH=ON) ;;
  *) echo "usage: ./build.sh run [SCENE] | ./build.sh test | ./build.sh quick | ./build.sh bench [NAME ARGS]" >&2
     exit 2 ;;
esac

scripts/install-deps.sh
jobs=$(nproc)
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release "${options[@]}" >/dev/null
cmake --build build --parallel "$jobs" --target "$target"

case "$mode" in
  run) exec build/rubcont run "$@" ;;
  test) exec ctest --test-dir build --output-on-failure --parallel "$jobs" ;;
  quick) exec ctest --test-dir build --output-on-failure --parallel "$jobs" -L quick ;;
  bench)
    if [ $# -gt 0 ]; then
      name=$1
      shift
      exec "build/bench/$name" "$@"
    fi
    echo "benchmarks built in build/bench/: $(cd build/bench && find . -maxdepth 1 -type f -executable -printf '%f ')" ;;
esac
