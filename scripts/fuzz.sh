#!/usr/bin/env bash
# Fuzzes the scene loader with libFuzzer (tests/fuzz/scene_fuzz.cpp): builds build-fuzz/ with clang,
# AddressSanitizer and UndefinedBehaviorSanitizer, then mutates the committed corpus
# (tests/fuzz/corpus/ and scenes/) for SECONDS (default 600), guided by a dictionary of the schema's
# section and key names. Any crash, sanitizer report, escaping exception or failed round trip stops
# it and leaves the input in build-fuzz/ (crash-*). With --merge, the inputs that reached new code
# are minimized into tests/fuzz/corpus/ (commit them: every build replays them under ctest).
# Not part of CI: a separate clang build (41 min measured on the 2 cores beside two other long runs).
#   scripts/fuzz.sh [SECONDS] [--merge]
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-600}
scripts/install-deps.sh
if ! dpkg -s clang libclang-rt-14-dev >/dev/null 2>&1; then
  apt-get install -y --no-install-recommends clang libclang-rt-14-dev
fi
flags="-fsanitize=address,undefined,fuzzer-no-link -fno-omit-frame-pointer -fno-sanitize-recover=undefined"
CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=Debug -DRUBCONT_FUZZ=ON \
  -DRUBCONT_BUILD_BENCH=OFF -DCMAKE_CXX_FLAGS="-O1 -g $flags" -DCMAKE_C_FLAGS="-O1 -g $flags" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
cmake --build build-fuzz --target scene_fuzz rubcont --parallel "$(nproc)"
# The dictionary: every section header and key the schema documents, and the choice values.
build-fuzz/rubcont scene keys | awk -F'|' '
  /^### \[/ { s = $0; sub(/^### /, "", s); printf "\"%s\"\n", s }
  /^\| `/ { k = $2; gsub(/[ `]/, "", k); printf "\"%s = \"\n", k
            n = split($5, v, "\""); for (i = 2; i <= n; i += 2) printf "\"\\\"%s\\\"\"\n", v[i] }
' | sort -u > build-fuzz/scene.dict
mkdir -p build-fuzz/corpus
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
build-fuzz/tests/scene_fuzz -max_total_time="$seconds" -max_len=8192 -timeout=10 \
  -dict=build-fuzz/scene.dict -artifact_prefix=build-fuzz/ -print_final_stats=1 \
  build-fuzz/corpus tests/fuzz/corpus scenes
if [[ "${2:-}" == "--merge" ]]; then
  build-fuzz/tests/scene_fuzz -merge=1 -max_len=8192 tests/fuzz/corpus build-fuzz/corpus
fi
