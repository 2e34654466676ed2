#!/usr/bin/env bash
# A command whose work is shared out over 2 MPI ranks, and over 2 threads (`rubcont map`'s grid,
# `rubcont fit`'s batches of evaluations), writes the same file as one process
# (scripts/compare_results.py: numbers to 1e-9, text exactly).
# Usage: check_mpi_same.sh MPIEXEC RUBCONT COMMAND ARGS... (from the repository root; --out added).
set -euo pipefail
mpiexec=$1
rubcont=$2
shift 2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
"$rubcont" "$@" --out "$work/one.h5" > /dev/null
"$rubcont" "$@" --threads 2 --out "$work/threads.h5" > /dev/null
"$mpiexec" -n 2 --oversubscribe "$rubcont" "$@" --out "$work/ranks.h5" > /dev/null
/usr/bin/python3 scripts/compare_results.py "$work/threads.h5" "$work/one.h5" --rtol 1e-9 --atol 1e-12
/usr/bin/python3 scripts/compare_results.py "$work/ranks.h5" "$work/one.h5" --rtol 1e-9 --atol 1e-12
