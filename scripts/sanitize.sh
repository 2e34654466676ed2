#!/usr/bin/env bash
# Builds rubcont with AddressSanitizer and UndefinedBehaviorSanitizer (build-asan/, Debug with -O1)
# and runs the whole test suite under them: any memory error, leak or undefined behaviour fails
# the run. Not part of CI (a full extra build: about 15 min on 2 cores); run before a release.
#   scripts/sanitize.sh [CTEST_ARGS...]     e.g. scripts/sanitize.sh -R continuation
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
flags="-fsanitize=address,undefined -fno-omit-frame-pointer -fno-sanitize-recover=undefined"
launcher=()
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache -DCMAKE_C_COMPILER_LAUNCHER=ccache)
fi
cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=Debug "${launcher[@]}" \
  -DCMAKE_CXX_FLAGS="-O1 $flags" -DCMAKE_C_FLAGS="-O1 $flags" \
  -DCMAKE_EXE_LINKER_FLAGS="$flags" -DCMAKE_SHARED_LINKER_FLAGS="$flags" \
  -DRUBCONT_BUILD_BENCH=OFF -DRUBCONT_PYTHON=OFF >/dev/null
cmake --build build-asan --parallel "$(nproc)"
# The installed-package tests build a separate project or import a module into Debian's python3,
# neither with the sanitizer runtime: skipped; the Python module is not built here (a module built
# with ASan loads only into an interpreter that preloads the runtime). Its C++ side is the
# commands, which the other tests run.
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
ctest --test-dir build-asan --output-on-failure --parallel "$(nproc)" \
  -E "installed package|over MPI ranks" "$@"
# Under mpirun, LeakSanitizer reports Open MPI's own allocations at exit (121 kB in about 3350
# blocks per process, 2026-11-27, most in its plugins, unloaded by MPI_Finalize so that their
# frames have no symbols to suppress by): leaks are not checked there, memory errors are.
ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 ctest --test-dir build-asan --output-on-failure \
  -R "over MPI ranks" "$@"
