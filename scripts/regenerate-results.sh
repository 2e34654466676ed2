#!/usr/bin/env bash
# Regenerates everything in results/: the result file (analytic L0, rotating-wave branches L1),
# figures and summary of the
# eight thesis scenes (Kumar 2010, Table 1) and of the truly overhung contrast scene, and the
# thesis-vs-rubcont tables in results/README.md. Run from anywhere; takes a few seconds after the
# build (most of it is matplotlib). With --sweeps it also re-runs the time-marching sweeps (L3) of
# the scenes that have them: about 8 min per scene on 2 cores (results/README.md).
set -euo pipefail
cd "$(dirname "$0")/.."

scripts/install-deps.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build --parallel "$(nproc)"

scenes=(thesis_A_a thesis_A_b thesis_B_a thesis_B_b thesis_B_c thesis_C_a thesis_C_b thesis_C_c
        overhung_beyond_right jeffcott)
for scene in "${scenes[@]}"; do
  summary=$(build/rubcont run "scenes/$scene.toml" --out results --quiet)
  # The summary names files by path; keep it relative so results/ reads the same anywhere.
  printf '%s\n' "$summary" > "results/$scene/summary.txt"
  echo "results/$scene: $(ls "results/$scene" | tr '\n' ' ')"
done
# ε → 0 convergence of the regularized whirl → whip transition (case A(a)), and branch-set timings.
build/bench/branches_bench scenes 5 results/regularization/thesis_A_a.csv \
  > results/regularization/branches_bench.txt
/usr/bin/python3 plots/regularization.py results/regularization/thesis_A_a.csv \
  results/regularization/convergence.png
/usr/bin/python3 scripts/thesis_comparison.py results --update results/README.md
echo "results/README.md: tables updated"
if [[ "${1:-}" == "--sweeps" ]]; then
  for scene in thesis_A_a thesis_C_a thesis_A_a_imbalance; do
    build/rubcont sweep "scenes/$scene.toml" --quiet > "results/$scene/sweep_summary.txt"
    echo "results/$scene: sweeps"
  done
fi
