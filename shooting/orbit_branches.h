// Periodic orbits continued in the system's parameter: the "orbits" stage of the textbook scenes
// (and of any OdeSystem with a periodic orbit to follow).
//
//   1. a start: a point on (or near) the orbit and its period, from a transient that has settled
//      onto an attracting orbit (SettleOnCycle for autonomous systems, SettleForced for forced
//      ones), or from anything else close enough for Newton;
//   2. ContinuePeriodicOrbits: a ShootingProblem (single or multiple shooting) started there and
//      continued with the engine both ways to the ends of [lambda_min, lambda_max] (one way when
//      the start is at an end), the two runs joined (JoinAtStart; a closed curve followed round
//      by the first run is not followed again the other way), Floquet stability at every
//      point, folds, period doubling and Neimark–Sacker points located (continuation.h).
//
// Use:
//     VanDerPolOscillator vdp({0.5});
//     const OrbitStart start = SettleOnCycle(vdp, Vector2(2, 0), 200.0, 1, {});
//     PeriodicOrbitBranchOptions options;
//     options.lambda_min = 0.5;  options.lambda_max = 10;  options.shooting.segments = 4;
//     const PeriodicOrbitBranch b = ContinuePeriodicOrbits(vdp, OrbitKind::kAutonomous, start,
//                                                          options);
//     // b.branch.Measure("period"), b.branch.points[i].spectrum, b.branch.special_points
#pragma once

#include <string>
#include <vector>

#include "continuation/branch.h"
#include "continuation/options.h"
#include "shooting/shooting.h"

namespace rubcont {

// A point near a periodic orbit.
struct OrbitStart {
  Vector x0;            // state at t = 0 (kForced: at the forcing phase 0)
  double period = 0.0;  // period guess (kForced: ignored, the forcing period applies)
  double lambda = 0.0;  // the system's parameter there
  bool valid = false;
  std::string message;  // why not, when !valid
};

// Integrates the autonomous system from x0 over `duration` at its current parameter, recording the
// falling zeros of state `section_state` (a Poincaré section); the start is the state at the last
// crossing and the period the time between the last two. Invalid when fewer than two crossings are
// found, the integration fails, or the last two periods differ by more than 1e-6 relative (the
// transient has not settled).
OrbitStart SettleOnCycle(OdeSystem& system, const Vector& x0, double duration, Index section_state,
                         const IntegratorOptions& integrator);

// Integrates the forced system from x0 over `periods` forcing periods at its current parameter (so
// that the forcing phase is 0 again): the start of an attracting forced orbit.
OrbitStart SettleForced(OdeSystem& system, const Vector& x0, int periods,
                        const IntegratorOptions& integrator);

struct PeriodicOrbitBranchOptions {
  double lambda_min = 0.0;  // parameter range (system units), lambda_min ≤ start ≤ lambda_max
  double lambda_max = 1.0;
  // The shooting problem; refresh_phase_reference is set for autonomous and relative orbits.
  ShootingOptions shooting;
  // The engine; bounds.lambda_min / lambda_max are overwritten by the range above,
  // detect.stability is switched on, and direction is set per run.
  ContinuationOptions continuation;
  // Replaces the default measures (max and min of every state) when not empty.
  std::vector<OrbitMeasure> measures;
};

// Throws std::invalid_argument naming the field (an empty or non-finite range).
void Validate(const PeriodicOrbitBranchOptions& options);

struct PeriodicOrbitBranch {
  OrbitKind kind = OrbitKind::kForced;
  Branch branch;             // both runs joined at the start (or the one run)
  Index state_dimension = 0;
  int segments = 1;
  double start_lambda = 0.0;
  ShootingStatistics work;   // integrations of both runs
};

// Throws std::invalid_argument for an invalid start (start.valid false: its message), a start
// outside the range, or invalid options. Numerical failures end the branch with a status
// (Branch::status, message).
PeriodicOrbitBranch ContinuePeriodicOrbits(OdeSystem& system, OrbitKind kind,
                                           const OrbitStart& start,
                                           const PeriodicOrbitBranchOptions& options);

}  // namespace rubcont
