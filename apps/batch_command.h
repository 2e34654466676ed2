// `rubcont batch JOBS.toml`: many independent commands (sweeps, maps, fits, branch sets) from one
// jobs file, shared out over the ranks of an MPI run (`mpirun -n N rubcont batch JOBS.toml`) or
// run one after another in one process.
//
// Jobs file (TOML):
//   out = "results/batch"           optional; --out overrides; default results/batch/<file stem>
//   [[job]]                          one per job, or one per combination of its `vary` lists
//   command = "sweep"                run | analytic | branches | sweep | map | fit
//   scene = "scenes/thesis_A_a.toml" (run: optional, the built-in default scene); paths relative
//                                    to the working directory, as on the command line
//   name = "..."                     optional: <scene stem>_<command>[_<direction|parameter>]
//   direction = "up"                 sweep: up | down | both (default both)
//   parameter = "friction"           map (required); range = [lo, hi], eta_points, speed_points
//   targets = "fit_targets.toml"     fit (required)
//   figures = false                  draw the figures (default false)
//   vary = { scene = [...], direction = ["up", "down"] }   every combination: one job each
//
// Each job writes <out>/<name>.h5 (run: <out>/<name>/<scene>/<scene>.h5) atomically, its output in
// <out>/<name>.log and its outcome in <out>/<name>.outcome (exit code, status, rank, host, pid,
// Slurm allocation, wall and CPU seconds); rank 0 writes <out>/summary.txt when every rank has finished. A job is done when its
// outcome says exit code 0 or 1 (a numerical failure is a result) and its result file exists: a
// re-run does only what is missing. `out` must be on a file system every rank sees.
//
// Claims (apps/claims.h): a rank takes the next job that is not done by claiming it, so the longest
// jobs do not wait behind each other if they are listed first. A claim names its owner (host,
// pid, start, Slurm allocation, rank) and beats while the job runs; another run (a second
// allocation on the same `out`, a re-run after a kill) takes it over only when it is stale
// (--stale-after, default 300 s) or its owner is provably dead (this host, pid gone or reused).
// When only jobs claimed by others are left, a rank waits until each claim's heartbeat moves (its
// owner is live: the job is left to it) or goes stale (taken over and run here): a second
// allocation runs only the jobs nobody live runs, and its summary lists the others as running
// elsewhere. A job tried in this run (an outcome written since its start) is not tried again.
//
// Job arrays: --job-index N, or else the environment's SLURM_ARRAY_TASK_ID, runs the one job N,
// numbered from 1 in the order of the jobs file with its `vary` expanded (the order of the summary;
// `#SBATCH --array=1-<number of jobs>`; --list prints them numbered); its outcome and exit code
// are that job's, and summary.txt is left to a run without an index.
//
// Exit codes: 0 every job (or the indexed one) done with exit code 0; 1 a job failed, did not
// finish or runs elsewhere (the others' results are kept); 2 a bad jobs file (key, value and rule
// named) or bad arguments (an index out of range names its option, value and the number of jobs).
#pragma once

#include <iosfwd>
#include <optional>
#include <string>

#include "apps/claims.h"

namespace rubcont {

struct BatchRequest {
  std::string jobs_file;
  std::optional<std::string> out_dir;
  bool quiet = false;
  bool list = false;                   // --list: print the jobs, numbered, and run none
  std::optional<long long> job_index;  // --job-index: the one job to run, from 1; else SLURM_ARRAY_TASK_ID
  ClaimOptions claims;                 // --stale-after
};

int BatchCommand(const BatchRequest& request, std::ostream& out, std::ostream& err);

}  // namespace rubcont
