// Periodic-orbit branches in a result file, in the layout of the rotating-wave branches
// (docs/result_files.md, apps/branch_output.h):
//
//   /branches (or /orbits)        attrs level ("L2": periodic orbits by shooting), parameter_name
//   /branches/<name>              attrs kind ("periodic_orbit"), orbit_kind ("forced",
//                                 "autonomous", "relative"), level, parameter_name, segments,
//                                 status, message, summary (Branch::BriefReport())
//       <parameter_name>          the continuation parameter (e.g. frequency, lambda, mu, speed_rpm)
//       period, stable (1 / 0; −1 not computed), unstable_count, max_multiplier_modulus,
//       multipliers_real, multipliers_imag (points × nontrivial multipliers, sorted by decreasing
//       modulus; NaN where a point has fewer), arclength, newton_iterations, and every measure of
//       the problem by name (max_<state>, min_<state>, ...)
//       special_points/{type, label, <parameter_name>, period, converged, residual_norm,
//                       last_correction, critical_real, critical_imag (the critical multiplier),
//                       angle (Neimark–Sacker: arg μ, rad), point_index, note, and every measure}
#pragma once

#include <string>

#include "apps/branch_output.h"
#include "apps/hdf5_file.h"
#include "shooting/orbit_branches.h"

namespace rubcont {

// Writes <root>/<name>; creates <root> with its attributes if needed. `root`: "/branches" (the
// textbook scenes) or "/orbits" (the modulated orbits of the rotor, apps/orbits_stage.h).
void WritePeriodicOrbitBranch(ResultWriter& writer, const std::string& name,
                              const PeriodicOrbitBranch& orbits, const ParameterColumn& parameter,
                              const std::string& root = "/branches");

}  // namespace rubcont
