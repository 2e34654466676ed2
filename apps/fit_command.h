// `rubcont fit SCENE --targets TARGETS.toml`: identification of design parameters from target
// jump speeds and whip frequencies (studies/identification.h), written atomically to HDF5 under
// /fit/.
//
// Targets file (TOML; every key checked, unknown keys rejected, errors name key, value and rule):
//   [[parameter]]                 one per fitted parameter
//   name = "friction"             a design parameter (rubcont map --help lists them)
//   range = [0.2, 0.8]            search box, inside the physical range
//   [[target]]                    one per target
//   family = "mode1"              mode1 | mode2 | left_only | right_only | single
//   event = "stick to slip+"      substring of the event's label
//   quantity = "speed_rpm"        speed_rpm | precession_hz
//   value = 50.08                 the target
//   uncertainty = 0.01            its 1-σ uncertainty (> 0), same unit
//   [fit]                         optional
//   global = "direct_l"           direct_l | crs2 | multistart (the one shared over threads/ranks)
//   global_evaluations = 120      ≥ 1 (multistart: the population)
//   local_evaluations = 200       ≥ 1, per local refinement
//   local_starts = 4              multistart: refinements from the best points, ≥ 1
//   residual_tolerance = 3        |residual| / uncertainty that counts as reproduced (> 0)
//
// Under mpirun every rank runs the fit, the batches of independent evaluations (multistart's
// population and refinements, the sensitivities) shared out over the ranks and gathered at each;
// rank 0 writes and prints. The answer is the same with any number of ranks and threads.
//
// HDF5 layout, /fit (attributes status, message, objective, global_objective, evaluations,
// global_method, local_runs, seconds): parameter_names, values, global_values, lower, upper, standard_deviation,
// objective_rise, correlation (d × d); target_names, target_values, predicted, residuals,
// uncertainties, missing.
// Kept free of Eigen so that main.cpp stays light.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>

namespace rubcont {

struct FitRequest {
  std::string scene_file;
  std::string targets_file;
  std::optional<std::string> out_file;  // default results/<scene name>/fit.h5
  bool quiet = false;
  int threads = 1;  // threads for the batches within this process (0: one per core)
  // Under mpirun, share the batches over the ranks (every rank must call FitCommand); false: this
  // rank fits alone (a job of `rubcont batch`).
  bool over_ranks = true;
};

// Exit codes: 0 fitted; 1 numerical failure or targets not reproduced / feature missing (the
// HDF5 file is still written, with the status); 2 bad scene, targets file or arguments.
int FitCommand(const FitRequest& request, std::ostream& out, std::ostream& err);

}  // namespace rubcont
