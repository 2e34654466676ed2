// `rubcont loop SCENE`: the hysteresis loop of the scene's rotor, explained — every jump of a run-up
// and a run-down, its cause, how sure, and the level that decided it (studies/loop.h; file layout
// in apps/loop_output.h).
#pragma once

#include <iosfwd>
#include <optional>
#include <string>

namespace rubcont {

struct LoopRequest {
  std::string scene_file;
  // The run's schedule: speed step [rpm] and time per speed [s]; none: the scene's [analysis.sweep]
  // speed_step_rpm and dwell.
  std::optional<double> step_rpm;
  std::optional<double> dwell;
  std::optional<double> budget;         // [G work units]; none: the scene's
  std::optional<std::string> out_file;  // none: results/<scene>/loop.h5
  int threads = 0;                      // 0: one per core
  bool quiet = false;
  bool force = false;  // run a plan the plan check refuses (apps/plan_check.h), with a warning
  bool figures = true;                  // draw the figure after the HDF5 file (--no-figures)
  std::string figure_format = "png";    // its file format: png, pdf or svg (--format)
};

int LoopCommand(const LoopRequest& request, std::ostream& out, std::ostream& err);

}  // namespace rubcont
