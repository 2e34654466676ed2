#!/usr/bin/env bash
# `rubcont map` with its grid shared out over 2 MPI ranks, and over 2 threads, writes the same
# map as one process (scripts/compare_results.py: numbers to 1e-9, text exactly).
# Usage: check_mpi_map.sh MPIEXEC RUBCONT (from the repository root).
set -euo pipefail
mpiexec=$1
rubcont=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
map=(map scenes/default.toml --parameter friction --range 0.3 0.7 --eta-points 9 --speed-points 121 --quiet)
"$rubcont" "${map[@]}" --out "$work/one.h5" > /dev/null
"$rubcont" "${map[@]}" --threads 2 --out "$work/threads.h5" > /dev/null
"$mpiexec" -n 2 --oversubscribe "$rubcont" "${map[@]}" --out "$work/ranks.h5" > /dev/null
/usr/bin/python3 scripts/compare_results.py "$work/threads.h5" "$work/one.h5" --rtol 1e-9 --atol 1e-12
/usr/bin/python3 scripts/compare_results.py "$work/ranks.h5" "$work/one.h5" --rtol 1e-9 --atol 1e-12
