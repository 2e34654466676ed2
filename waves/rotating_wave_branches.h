// The whole set of rotating-wave branches (circular whirl and whip) of a rub structure against
// running speed: every family FindRotatingWaveStarts admits, continued both ways in ω by the
// pseudo-arclength engine, with stability, stick ↔ slip switches and contact loss located as events,
// and folds / Hopf points located. Starts that fall on a branch already traced are skipped, so
// each branch appears once however many families lead to it.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "continuation/continuation.h"
#include "waves/rotating_wave_families.h"

namespace rubcont {

// The engine's defaults with two changes for rotating waves: stability on (the point of a branch
// set is which state is stable where), and 4 target Newton iterations. With the contact stiffness
// (condition ~6e7) the corrector's step test ‖Δx̂‖ ≤ 1e-8 takes 3 iterations from almost any
// predictor, so with the default target of 3 the step never grows again after a cut: case A(b)'s
// Mode 1 whirl stalled at Δs = 1.25e-3 and used up its 1000 steps; with 4 it takes 275 points.
inline ContinuationOptions RotatingWaveContinuationDefaults() {
  ContinuationOptions options;
  options.detect.stability = true;
  options.step.target_iterations = 4;
  return options;
}

struct RotatingWaveBranchOptions {
  FamilySearchOptions search;        // speed range [rad/s], whip search range, Newton options
  // λ bounds are set from search.speed_min/max.
  ContinuationOptions continuation = RotatingWaveContinuationDefaults();
  // A start lies on a traced branch when, at its speed, the branch's precession, normal forces
  // and phase between the contacts match it to this relative tolerance (linear interpolation
  // between neighbouring points of the same piece).
  double duplicate_tolerance = 5e-3;
};

struct RotatingWaveBranch {
  std::string name;            // "branch1", "branch2", ... in the order they were found
  std::string family;          // how its start was found (RotatingWaveStart::family)
  std::vector<double> normals;  // closed-form pattern of the start (+1, −1, 0 per contact)
  Branch branch;
  // Ω/2π of special point i [Hz] (its measure "precession_hz").
  double SpecialPrecessionHz(std::size_t i) const {
    return branch.special_points[i].measures(branch.MeasureIndex("precession_hz"));
  }
};

// "mode1", "mode2", "left_only", "right_only" (two contacts) or "single" (one contact): the
// closed-form pattern a branch was started from.
std::string PatternName(const std::vector<double>& normals);

// Progress: called after each branch with (branches done, starts tried, starts in all).
using BranchProgress = std::function<void(int branches, int tried, int starts)>;

// The branches are those of the balanced rotor: a rotating wave is stationary only in the frame
// precessing backward, where a forward-turning imbalance is not, so `structure.imbalance` is left
// out. Throws std::invalid_argument on invalid options. Numerical failures of single branches are in
// their Branch::status; a start whose continuation fails immediately is still reported.
std::vector<RotatingWaveBranch> ComputeRotatingWaveBranches(
    const RubStructure& structure, FrictionLawKind law, const RotatingWaveBranchOptions& options,
    const BranchProgress& progress = {});

// Contact-mode code of the measure mode_<contact> (RotatingWaveProblem::Measures): 0 free,
// 1 stick, 2 slip+, 3 slip−.
const char* ContactModeName(double code);

}  // namespace rubcont
