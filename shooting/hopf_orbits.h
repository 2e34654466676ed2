// Periodic orbits born at a Hopf point of an equilibrium: the equilibria of an OdeSystem as a
// continuation problem (Hopf points detected and located by the engine), and the switch from a
// located Hopf point onto the family of periodic orbits born there.
//
// The switch (Seydel §7.6; AUTO's and BifurcationKit's Hopf-to-orbit start, without the normal
// form): at the Hopf point (x_H, λ_H) with critical eigenvalue iω and eigenvector v, the small
// orbits are x(t) ≈ x_H + a Re(v e^{iωt}), T ≈ 2π/ω, and the family leaves the Hopf point
// along the amplitude a with dλ/da = 0. The engine is started (StartWithTangent) at a = amplitude
// along that direction: its corrector fixes the projection on the direction (the amplitude) and
// solves for λ, whichever side of λ_H the orbits lie on (supercritical or subcritical).
//
// Use:
//     EquilibriumProblem equilibria(system);
//     Branch eq = Continue(equilibria, x0, lambda0, options_with_stability);
//     for (const SpecialPoint& p : eq.special_points)
//       if (p.type == SpecialPointType::kHopf)
//         Branch orbits = ContinueOrbitsFromHopf(system, p, hopf_options);
#pragma once

#include "continuation/branch.h"
#include "continuation/continuation.h"
#include "continuation/equilibrium_problem.h"
#include "continuation/problem.h"
#include "shooting/orbit_branches.h"

namespace rubcont {

struct HopfOrbitOptions {
  // kAutonomous, or kRelative for a Hopf point of a relative equilibrium (a rotating wave, an
  // equilibrium of the co-rotating frame): the orbits born there drift with the symmetry and are
  // shot as relative periodic orbits, x(T) = R_φ x(0), starting from φ = 0.
  OrbitKind kind = OrbitKind::kAutonomous;
  // Amplitude a of the first orbit, in units of the scaled state (‖Re v ./ StateScale‖ = 1).
  double amplitude = 1e-2;
  // Range, shooting and engine options as for ContinuePeriodicOrbits (direction is ignored: the
  // branch leaves the Hopf point towards growing amplitude).
  PeriodicOrbitBranchOptions orbits;
  // Called after every continuation step (progress of long runs); returning false stops the branch.
  StepCallback on_step;
};

// The periodic orbits born at `hopf` (a kHopf special point of an EquilibriumProblem branch of
// `system`, or one built from a rotating wave's: u = x_H, lambda = λ_H, frequency = ω). Throws std::invalid_argument when the point is
// not a Hopf point or the system has no complex pair near iω there.
PeriodicOrbitBranch ContinueOrbitsFromHopf(OdeSystem& system, const SpecialPoint& hopf,
                                           const HopfOrbitOptions& options);

}  // namespace rubcont
