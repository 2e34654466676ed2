#!/usr/bin/env bash
# `mpirun -n 2 rubcont batch`: the ranks share the jobs out (each runs some), rank 0 writes the
# summary, and a re-run under MPI does nothing. Usage: check_mpi_batch.sh MPIEXEC RUBCONT
# (run from the repository root; as root, Open MPI needs the two OMPI_ALLOW_RUN_AS_ROOT variables).
set -euo pipefail
mpiexec=$1
rubcont=$2
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
cat > "$work/jobs.toml" <<JOBS
out = "$work/out"
[[job]]
command = "branches"
vary = { scene = ["scenes/thesis_A_a.toml", "scenes/thesis_A_b.toml", "scenes/thesis_B_a.toml",
                  "scenes/thesis_B_b.toml", "scenes/thesis_C_a.toml", "scenes/thesis_C_b.toml"] }
JOBS
"$mpiexec" -n 2 --oversubscribe "$rubcont" batch "$work/jobs.toml" --quiet > "$work/first.txt"
cat "$work/first.txt"
grep -q "MPI, rank 0 of 2; 6 run now" "$work/first.txt"
grep -q " rank 0 " "$work/first.txt"
grep -q " rank 1 " "$work/first.txt"
grep -q "6 done, 0 failed" "$work/first.txt"
"$mpiexec" -n 2 --oversubscribe "$rubcont" batch "$work/jobs.toml" --quiet > "$work/again.txt"
grep -q "0 run now" "$work/again.txt"
echo "both ranks ran jobs; the re-run ran none"
