// Continuation branches in a result file (docs/result_files.md):
//
//   /branches                     attrs level, friction_law, speed_range_rpm (2)
//   /branches/<name>              attrs kind ("rotating_wave"), mode ("mode1", "mode2",
//                                 "left_only", "right_only", "single": the closed-form pattern of
//                                 its start), level ("L1"), family, status, message (how each
//                                 half of the two-way run ended), summary (Branch::BriefReport())
//       speed_rpm, precession_hz, stable (1 / 0; −1 not computed), unstable_count,
//       leading_growth_rate [1/s] (largest Re of the spectrum), arclength, piece (contact modes),
//       and every measure of the problem by name: normal_phase_deg, normal_force_<c> [N],
//       friction_force_<c> [N], slip_velocity_<c> [m/s], penetration_<c> [m], mu_ratio_<c>,
//       mode_<c> (0 free, 1 stick, 2 slip+, 3 slip−) for each contact <c> (left/right or contact)
//       special_points/{type (SpecialPointType name), label (event name), speed_rpm,
//                       precession_hz, converged, residual_norm and last_correction (the
//                       achieved precision, scaled), frequency_hz (Hopf: Im λ/2π), nonsmooth_fold
//                       (1 where the branch turns back at a switch), point_index, note, and
//                       every measure at the point (events: on the piece that ends there)}
#pragma once

#include <array>
#include <string>
#include <vector>

#include "apps/hdf5_file.h"
#include "waves/rotating_wave_branches.h"

namespace rubcont {

// The continuation parameter as written: dataset name and factor from the problem's λ (e.g.
// "speed_rpm" with 60/2π for a running speed in rad/s).
struct ParameterColumn {
  std::string name = "parameter";
  double factor = 1.0;
};

// The columns every branch group has, whatever its kind (rotating waves here, periodic orbits in
// apps/orbit_output.h): in <group>, the parameter, stable, unstable_count, arclength and every
// measure of the problem by name; in <group>/special_points, type, label, the parameter,
// converged, residual_norm, last_correction, note, point_index and every measure at the point.
void WriteBranchPointColumns(ResultWriter& writer, const std::string& group, const Branch& branch,
                             const ParameterColumn& parameter);
void WriteSpecialPointColumns(ResultWriter& writer, const std::string& group, const Branch& branch,
                              const ParameterColumn& parameter);

// "  l1 <value>: supercritical|subcritical" for a Hopf point with a first Lyapunov coefficient,
// "" otherwise: the summaries' one wording of it.
std::string LyapunovText(const SpecialPoint& point);

// `root`: the group to write ("/branches"; the sweeps keep the branches of their own friction law
// in "/sweeps/branches").
void WriteRotatingWaveBranches(ResultWriter& writer, const std::vector<RotatingWaveBranch>& branches,
                               FrictionLawKind law, const std::array<double, 2>& speed_range_rpm,
                               const std::string& root = "/branches");

}  // namespace rubcont
