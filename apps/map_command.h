// `rubcont map SCENE --parameter NAME`: the hysteresis map of a two-point scene in (running speed,
// design parameter) (studies/hysteresis_map.h), written atomically to HDF5 under
// /maps/<parameter>/ with a figure (rubcont.plots.map).
//
// Kept free of Eigen so that main.cpp stays light; the writer is in apps/map_output.h.
//
// HDF5 layout, /maps/<parameter>/ (attributes: parameter, unit, base_value, level "L1",
// friction_law, summary, note, grid_seconds, curve_seconds, region_codes):
//   eta (m), speed_rpm (k), stable_count (m × k: stable circular states, −1 where the branch set
//   failed), region (m × k: 0 none, 1 one, 2 two or more coexisting),
//   by_pattern/<pattern>/stable_count (the count within one closed-form family: mode1, mode2,
//   left_only, right_only);
//   points/{eta, speed_rpm, precession_hz, type, label, nonsmooth_fold, branch, stable_before,
//           stable_after}: special points of the branch set at every grid value;
//   curves/<curveN>/{eta, speed_rpm, precession_hz} (attributes kind "event" | "fold" | "hopf",
//           label, piece, pattern, status, message, start_eta, start_speed_rpm,
//           start_nonsmooth_fold, fold_sense, partner_margins); Hopf curves also {hopf_hz (NaN on
//           neutral saddles), stable (1 where the rest of the spectrum is stable: the state loses
//           its stability there; 0; −1 not computed)}; curves/<curveN>/special_points/{type, label,
//           eta, speed_rpm} and
//           curves/<curveN>/extrema/{eta, speed_rpm, ipopt_eta, ipopt_speed_rpm, ipopt_status}
//           (turning points of the curve in the parameter, by the engine and by Ipopt);
//   failures: one sentence per failed grid value or curve.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>

namespace rubcont {

struct MapRequest {
  std::string scene_file;
  std::string parameter;                // a DesignParameter name
  std::optional<double> eta_min;        // default: DefaultMapRange
  std::optional<double> eta_max;
  int eta_points = 31;
  int speed_points = 481;
  std::optional<std::string> out_file;  // default results/<scene name>/map_<parameter>.h5
  bool quiet = false;
  bool force = false;  // run a plan the plan check refuses (apps/plan_check.h), with a warning
  bool figures = true;  // draw the figure after the HDF5 file
  std::string figure_format = "png";  // its file format: png, pdf or svg (--format)
  // Under mpirun, share the grid out over the ranks (every rank must call MapCommand); false: this
  // rank computes the whole map alone (a job of `rubcont batch`).
  bool over_ranks = true;
  int threads = 1;  // threads for the grid within this process (0: one per core)
};

int MapCommand(const MapRequest& request, std::ostream& out, std::ostream& err);

}  // namespace rubcont
