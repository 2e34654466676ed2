#!/usr/bin/env bash
# Regenerates the work-precision charts (issue 7, docs/studies/work_precision.md): builds
# bench/work_precision_bench if needed, runs it for the default scene (case A(a) physics) and for
# the overhung thesis case C(a), and plots each. Writes results/bench/<scene>/work_precision.csv,
# summary.txt, log.txt (the harness's progress: every answer with its note) and work_precision.png.
# 8–12 min on this shared 2-core machine (measured 464 s and 696 s of wall time; docs/studies/work_precision.md).
set -euo pipefail
cd "$(dirname "$0")/.."

start=$(date +%s)
build=${BUILD:-build}  # another build directory (bench/against_peers.py passes its own)
if [[ ! -f $build/build.ninja ]]; then
  cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
fi
cmake --build "$build" --target work_precision_bench --parallel "$(nproc)"

for scene in default thesis_C_a; do
  out="results/bench/$scene"
  mkdir -p "$out"
  "$build/bench/work_precision_bench" "scenes/$scene.toml" "$out" 2> "$out/log.txt"
  PYTHONPATH=python /usr/bin/python3 -m rubcont.plots.work_precision "$out"
  echo "$out: $(ls "$out" | tr '\n' ' ')"
done
echo "work-precision: $(( $(date +%s) - start )) s wall"
