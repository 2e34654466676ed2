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
// <out>/<name>.log and its outcome in <out>/<name>.outcome (exit code, status, rank, wall and CPU
// seconds); rank 0 writes <out>/summary.txt when every rank has finished. Ranks take the next job
// nobody has taken (a claim file <out>/<name>.claim, created exclusively), so the longest jobs do
// not wait behind each other if they are listed first. A job is done when its outcome says exit
// code 0 or 1 (a numerical failure is a result) and its result file exists: a re-run does only
// what is missing (rank 0 first removes the claims of jobs that are not done). `out` must be on a
// file system every rank sees.
//
// Exit codes: 0 every job done with exit code 0; 1 a job failed or did not finish (the others'
// results are kept); 2 a bad jobs file (key, value and rule named) or bad arguments.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>

namespace rubcont {

struct BatchRequest {
  std::string jobs_file;
  std::optional<std::string> out_dir;
  bool quiet = false;
};

int BatchCommand(const BatchRequest& request, std::ostream& out, std::ostream& err);

}  // namespace rubcont
