// Which rotating waves (circular whirl and whip) a rub structure admits in a speed range, and
// starting solutions for each family, found from the rigid-contact closed form.
//
// The closed form (SolveRigidContactOrbit) gives the contact forces P_k = N_k + jF_k of a circular
// orbit at precession Ω for a chosen pattern of contact normals: Mode 1 (in phase), Mode 2 (in
// antiphase), or one contact alone. A family is started wherever the closed form says it exists:
//  - whirl: contact r rolls (stick, Ω = RCI_r·ω) where N > 0 at every touching contact and
//    |μ_req,r| ≤ μ; another contact of equal RCI rolls too when its own |μ_req| ≤ μ, otherwise it
//    slips in the direction of its slip velocity (with unequal RCI it cannot roll as well);
//  - whip: every touching contact slips, at each Ω where some contact's μ_req crosses ±μ, at a
//    speed where the slip velocities ωR_k − ΩC_k have that sign.
// Each guess is solved by RotatingWaveProblem::SolveConsistent, whose active-set iteration
// corrects the contact modes; the compliant solution may have a phase between the contact normals
// other than 0 or π. Starts that converge to the same solution are reported once.
#pragma once

#include <string>
#include <vector>

#include "waves/rotating_wave.h"

namespace rubcont {

struct FamilySearchOptions {
  double speed_min = 0.0;      // ω range [rad/s], 0 < speed_min < speed_max
  double speed_max = 0.0;
  // Ω [rad/s] of a grid that does not depend on the speed range: the closed form is sampled at
  // `samples` points over (0, precession_max] and at `samples` points up to the range's highest
  // whirl Ω (when that is higher), so that a wider speed range finds every family a narrower one
  // finds below precession_max. ≤ 0: the range's grid alone.
  double precession_max = 0.0;
  int samples = 800;           // grid points of the closed form on each grid
  NewtonOptions newton;
};

// Throws std::invalid_argument naming the field, value and rule.
void Validate(const FamilySearchOptions& options);

struct RotatingWaveStart {
  Vector u;                        // converged unknowns of RotatingWaveProblem
  double speed = 0.0;              // ω [rad/s]
  std::vector<ContactMode> modes;  // contact modes of the converged solution
  std::vector<double> normals;     // the closed-form pattern it came from (+1, −1, 0 per contact)
  std::string family;              // how it was found, e.g. "whirl, left rolls, Mode 1"
};

// Every start that converged to a consistent solution (all contact modes valid), in the order:
// patterns (Mode 1, Mode 2, single contacts), then increasing Ω. `problem` must be built on the
// same structure; its modes and phase reference are left at the last start's.
std::vector<RotatingWaveStart> FindRotatingWaveStarts(RotatingWaveProblem& problem,
                                                      const FamilySearchOptions& options);

}  // namespace rubcont
