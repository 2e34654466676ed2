#!/usr/bin/env bash
# Scaling of the work that multiplies runs, on this machine, in one run: the default scene's
# friction map (41 grid values, as results/design/map_friction) in one process, with 2 threads,
# and over 1 and 2 MPI ranks; the hidden-parameter fit (scenes/fits/default_hidden.toml, with
# global = "multistart": 120 population points, 4 refinements) likewise, beside the same fit by
# DIRECT-L in one process; and a batch of sweeps (the nine thesis scenes, speed-up over
# 40–72 rpm, 4 rpm steps: short enough to repeat) over 1 and 2 ranks. Each configuration REPEATS
# times in turn, and every speed-up is the median of the per-repeat ratios: the configurations of
# one repeat run within a minute of each other, so the machine's drift (other tenants slowed the
# same configuration by up to 45 % between repeats on 2026-11-27) falls on both sides of a ratio. Usage: bench/mpi_scaling.sh BUILD_DIR [REPEATS] > results/bench/mpi_scaling.txt
# (from the repository root; as root, Open MPI needs OMPI_ALLOW_RUN_AS_ROOT, set here).
set -euo pipefail
build=${1:?usage: bench/mpi_scaling.sh BUILD_DIR [REPEATS]}
repeats=${2:-3}
rubcont="$build/rubcont"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

seconds() { /usr/bin/time -f "%e" "$@" 2>&1 >/dev/null | tail -1; }
# The map's own grid seconds (its summary line), then the command's wall seconds.
map_seconds() {
  local grid
  grid=$( { /usr/bin/time -f "wall %e" "$@" > "$work/map.txt"; } 2>&1 | awk '/^wall/ { print $2 }')
  echo "$(grep -o 'grid [0-9.]* s' "$work/map.txt" | awk '{ print $2 }'):$grid"
}
median() { sort -g | awk '{ v[NR] = $1 } END { print (NR % 2) ? v[(NR + 1) / 2] : (v[NR / 2] + v[NR / 2 + 1]) / 2 }'; }
# The median over the repeats of A's time over B's (field F of "a:b" entries; 1 for plain times).
ratio() {
  paste -d' ' <(tr ' ' '\n' <<< "${runs[$1]}" | grep . | cut -d: -f"$3") \
              <(tr ' ' '\n' <<< "${runs[$2]}" | grep . | cut -d: -f"$3") | awk '{ print $1 / $2 }' | median
}

map=(map scenes/default.toml --parameter friction --range 0.1 1.0 --eta-points 41 --quiet --no-figures)
declare -A runs
for ((r = 0; r < repeats; r++)); do
  runs[map_one]+="$(map_seconds "$rubcont" "${map[@]}" --out "$work/m.h5") "
  runs[map_threads2]+="$(map_seconds "$rubcont" "${map[@]}" --threads 2 --out "$work/m.h5") "
  runs[map_ranks1]+="$(map_seconds mpirun -n 1 "$rubcont" "${map[@]}" --out "$work/m.h5") "
  runs[map_ranks2]+="$(map_seconds mpirun -n 2 "$rubcont" "${map[@]}" --out "$work/m.h5") "
done

# The fit: its own seconds (its summary line), then the command's wall seconds.
fit_seconds() {
  local wall
  wall=$( { /usr/bin/time -f "wall %e" "$@" > "$work/fit.txt"; } 2>&1 | awk '/^wall/ { print $2 }')
  echo "$(grep -o 'evaluations ([0-9.]* s)' "$work/fit.txt" | tr -d '()' | awk '{ print $2 }'):$wall"
}
sed 's/^global = .*/global = "multistart"/' scenes/fits/default_hidden.toml > "$work/multistart.toml"
fit=(fit scenes/default.toml --targets "$work/multistart.toml" --quiet --out "$work/f.h5")
for ((r = 0; r < repeats; r++)); do
  runs[fit_direct]+="$(fit_seconds "$rubcont" fit scenes/default.toml --targets scenes/fits/default_hidden.toml --quiet --out "$work/f.h5") "
  runs[fit_one]+="$(fit_seconds "$rubcont" "${fit[@]}") "
  runs[fit_threads2]+="$(fit_seconds "$rubcont" "${fit[@]}" --threads 2) "
  runs[fit_ranks1]+="$(fit_seconds mpirun -n 1 "$rubcont" "${fit[@]}") "
  runs[fit_ranks2]+="$(fit_seconds mpirun -n 2 "$rubcont" "${fit[@]}") "
done
fit_evaluations=$(grep -o 'in [0-9]* + [0-9]* evaluations' "$work/fit.txt")

# The sweep batch: scene copies with a short speed-up range.
jobs="$work/sweeps.toml"
echo "out = \"$work/batch\"" > "$jobs"
scenes=()
for s in thesis_A_a thesis_A_b thesis_A_c thesis_B_a thesis_B_b thesis_B_c thesis_C_a thesis_C_b thesis_C_c; do
  [ -f "scenes/$s.toml" ] || continue
  sed 's/^up_range_rpm = .*/up_range_rpm = [40.0, 72.0]/' "scenes/$s.toml" > "$work/$s.toml"
  scenes+=("\"$work/$s.toml\"")
done
{
  echo "[[job]]"
  echo "command = \"sweep\""
  echo "direction = \"up\""
  echo "vary = { scene = [$(IFS=,; echo "${scenes[*]}")] }"
} >> "$jobs"
for ((r = 0; r < repeats; r++)); do
  rm -rf "$work/batch"
  runs[batch_ranks1]+="$(seconds mpirun -n 1 "$rubcont" batch "$jobs" --quiet) "
  rm -rf "$work/batch"
  runs[batch_ranks2]+="$(seconds mpirun -n 2 "$rubcont" batch "$jobs" --quiet) "
done
job_seconds=$(awk '/^  thesis/ { s += $6 } END { printf "%.1f", s }' "$work/batch/summary.txt")

echo "MPI and thread scaling, $(date -u +%Y-%m-%d) on $(nproc) cores ($(mpirun --version | head -1)); $repeats runs each, medians"
echo "  map: its grid (41 branch sets) / the whole command (with the 12 curves, rank 0 only), wall seconds"
for key in map_one map_threads2 map_ranks1 map_ranks2; do
  g=$(tr ' ' '\n' <<< "${runs[$key]}" | grep . | cut -d: -f1 | median)
  w=$(tr ' ' '\n' <<< "${runs[$key]}" | grep . | cut -d: -f2 | median)
  printf '  %-14s grid %6.2f s  command %6.2f s   (runs grid:command %s)\n' "$key" "$g" "$w" "${runs[$key]% }"
  declare "wall_$key=$w"
done
echo "  fit: the fit itself / the whole command, wall seconds (direct_l: one process, the fit as committed;"
echo "  the others multistart, $fit_evaluations)"
for key in fit_direct fit_one fit_threads2 fit_ranks1 fit_ranks2; do
  g=$(tr ' ' '\n' <<< "${runs[$key]}" | grep . | cut -d: -f1 | median)
  w=$(tr ' ' '\n' <<< "${runs[$key]}" | grep . | cut -d: -f2 | median)
  printf '  %-14s fit  %6.2f s  command %6.2f s   (runs fit:command %s)\n' "$key" "$g" "$w" "${runs[$key]% }"
done
for key in batch_ranks1 batch_ranks2; do
  m=$(tr ' ' '\n' <<< "${runs[$key]}" | grep . | median)
  printf '  %-14s %8.2f s   (runs: %s)\n' "$key" "$m" "${runs[$key]% }"
done
printf 'map grid: 2 threads %.2f×, 2 ranks %.2f× against one process\n' "$(ratio map_one map_threads2 1)" "$(ratio map_one map_ranks2 1)"
printf 'map command: 2 threads %.2f×, 2 ranks %.2f×, 1 rank %.2f× (MPI start-up %.2f s)\n' \
  "$(ratio map_one map_threads2 2)" "$(ratio map_one map_ranks2 2)" "$(ratio map_one map_ranks1 2)" \
  "$(awk -v a="$wall_map_ranks1" -v b="$wall_map_one" 'BEGIN { print a - b }')"
printf 'fit (multistart): 2 threads %.2f×, 2 ranks %.2f× against one process; whole command on 2 ranks %.2f× against 1 rank; against direct_l in one process: %.2f× alone, %.2f× on 2 threads\n' \
  "$(ratio fit_one fit_threads2 1)" "$(ratio fit_one fit_ranks2 1)" "$(ratio fit_ranks1 fit_ranks2 2)" \
  "$(ratio fit_direct fit_one 1)" "$(ratio fit_direct fit_threads2 1)"
printf 'sweep batch (%d jobs, %.1f s of job wall time in the last 2-rank run): 2 ranks %.2f× against 1 rank\n' \
  "${#scenes[@]}" "$job_seconds" "$(ratio batch_ranks1 batch_ranks2 1)"
