// Options of the continuation engine (continuation/continuation.h). Plain structs with in-class
// defaults; one Validate() names the offending field, its value and the rule.
//
// Units: every length below (steps, tolerances) is measured in the engine's scaled variables
// û = u ./ Scale(), λ̂ = λ / LambdaScale(), with residuals F ./ ResidualScale() (see
// continuation.h). With a problem whose scales are its unknowns' typical magnitudes, a scaled
// length of 0.01 is a 1 % change of the solution, whatever the units.
#pragma once

#include "solvers/constants.h"
#include "solvers/types.h"

namespace rubcont {

// Newton corrector on the bordered (pseudo-arclength) system [F̂; τ̂ᵀ(x̂ − x̂_k) − Δs] = 0.
struct CorrectorOptions {
  int max_iterations = 8;             // Newton iterations (LU factorizations) per attempt (≥ 1)
  double residual_tolerance = 1e-10;  // converged when ‖F ./ ResidualScale‖∞ ≤ this (> 0) ...
  double step_tolerance = 1e-8;       // ... and the last Newton correction ‖Δx̂‖∞ ≤ this (> 0);
                                      // the next correction is then O(this²), below round-off.
                                      // (Also converged at the round-off floor: residual below
                                      // tolerance and no longer halving.)
  double divergence_factor = 1e3;     // fail when ‖F̂‖∞ exceeds this × its value at the predictor
                                      // (> 1)
  double min_pivot_ratio = 1e-14;     // fail (singular) when min |U_ii| / max |U_ii| of the
                                      // bordered matrix's LU falls below this, in [0, 1). O(n),
                                      // where Eigen's rcond() estimate costs several solves: it
                                      // took a quarter of the run time of a rub-model branch
                                      // (bench/continuation_bench.cpp)
};

// Step-length control (Seydel, "Practical Bifurcation and Stability Analysis", §4.6; the angle
// criterion as in AUTO and BifurcationKit). After an accepted step with N Newton iterations and
// tangent turning angle α, Δs ← Δs · clamp(min(2^((N_target − N)/2), α_target/α), 1/2, max_growth).
struct StepOptions {
  double initial = 0.01;      // first arclength step Δs, scaled (min ≤ initial ≤ max)
  double min = 1e-7;          // smallest step; a corrector failing below it ends the branch (> 0)
  double max = 0.1;           // largest step (≥ min)
  int target_iterations = 3;  // Newton iterations per step the controller aims at (≥ 1)
  double max_growth = 2.0;    // largest factor by which Δs grows after one step (≥ 1)
  double target_angle = 0.1;  // tangent turning angle per step the controller aims at, rad (> 0)
  double max_angle = 0.35;    // a step whose tangent turns more than this is rejected and halved
                              // (guards against jumping between branches), rad, in
                              // [target_angle, π)
  // After a corrector failure, the steps to the next `failure_memory` points stay below 3/4 of the
  // step that failed instead of growing back to it at once (≥ 0; 0: off, the default). On A(a)'s
  // modulated whip the iteration target grows a step that converged in 4 iterations by √2 into
  // one that fails, every second step: 136 failures in 279 orbits (bench/whip_family_bench.cpp).
  int failure_memory = 0;
  // The corrector starts from the parabola through the previous point, tangent to the branch at the
  // current one, instead of the tangent line (continuation.cpp, Predictor): off by default.
  bool curved_predictor = false;
};

// Where the branch ends. λ bounds are met exactly (the last point is located on the bound).
struct BoundsOptions {
  double lambda_min = -kInfinity;  // λ, the problem's units
  double lambda_max = kInfinity;   // λ (> lambda_min)
  // Box on the state, problem units: empty, or Dimension() entries (±∞ allowed). Applies to the
  // pieces whose dimension matches (piecewise problems may change dimension at events). The branch
  // ends at the last point inside.
  Vector state_lower;
  Vector state_upper;
  double max_state_norm = kInfinity;  // bound on ‖û‖∞ (> 0)
  int max_steps = 1000;  // accepted continuation steps (≥ 1)
  // End at the first located zero of a test function of type kGrazing (Problem::TestFunctionType),
  // status kGrazing: the step that meets it is cut there, like at a λ bound, and only the part
  // before it is searched for other special points. Past a grazing the orbits cross a switching
  // surface, where the Jacobian's determinant and the multipliers jump as a contact opens at one
  // collocation point after another: on A(a)'s modulated whip (curved predictor, 400 uniform
  // intervals) locating those jumps, and taking the steps again shorter, made the last two orbits
  // (from 132.3822 rpm to the end) cost 25.7 s of the run's 43.8 s; 3.6 s with the cut
  // (bench/whip_family_bench.cpp, one run each).
  bool end_at_grazing = false;
};

// What to look for along the branch. Detection compares consecutive points of the same piece.
struct DetectionOptions {
  bool folds = true;          // sign change of the tangent's λ-component
  bool branch_points = true;  // sign change of det [F̂_û F̂_λ̂; τ̂ᵀ]
  // Compute Problem::Stability at every accepted point (costly for shooting problems) and detect
  // eigenvalue / multiplier crossings. Ignored when the problem has no stability operator.
  bool stability = false;
  bool events = true;          // event functions of piecewise-smooth problems (and switching)
  bool test_functions = true;  // Problem::TestFunctions (e.g. cusps on fold curves)
  bool closed_branches = true; // end with status kClosed when the branch returns to its start
  bool locate = true;          // locate what was detected (false: record the bracketing point)
  // A spectral value counts as real when |Im| ≤ this · max(1, |value|) (≥ 0).
  double imaginary_tolerance = 1e-8;
};

// Location of special points: Newton on the minimally augmented fold system, or Illinois regula
// falsi on arclength with the corrector at every trial point (everything else).
struct LocationOptions {
  int max_iterations = 40;            // Newton iterations or trial points per location (≥ 1)
  double residual_tolerance = 1e-11;  // fold Newton: ‖[F̂; g]‖∞ ≤ this (> 0) ...
  double step_tolerance = 1e-10;      // ... and last correction ‖Δx̂‖∞ ≤ this; Illinois: bracket
                                      // width in scaled arclength ≤ this (> 0)
  // Branch points are located by Newton on the branch-point system (continuation/branch_point.h)
  // when the problem has at most this many unknowns n + 1 (≥ 0): each iteration costs 2(n + 1)
  // Jacobians, which is cheap for rotating waves (n + 1 ≤ 20) and not for shooting problems whose
  // Jacobian is an integration with sensitivities (a 4-segment relative orbit of the rub: 67
  // unknowns, ~1 s per Jacobian); above it, Illinois on det [DF̂; τ̂ᵀ] along arclength.
  int branch_point_newton_max_unknowns = 64;
};

// Piecewise-smooth problems: what happens at a located event (Problem::SwitchAt).
struct SwitchOptions {
  // Arclength of the two probe points, one either way along the new piece's tangent, on which the
  // new piece's margins decide the direction (scaled, > 0). Larger than the location error, small
  // enough that no other event lies within it.
  double probe_step = 1e-5;
};

struct ContinuationOptions {
  int direction = +1;  // initial direction of λ: +1 increasing, −1 decreasing
  CorrectorOptions corrector;
  StepOptions step;
  BoundsOptions bounds;
  DetectionOptions detect;
  LocationOptions location;
  SwitchOptions events;
  // The branch is closed when it returns to its start point within this distance (scaled, relative
  // to max(1, ‖x̂₀‖)) with a tangent pointing the same way (> 0).
  double closure_tolerance = 1e-6;
};

// Throw std::invalid_argument naming the field (e.g. "ContinuationOptions.step.min"), the value and
// the rule.
void Validate(const CorrectorOptions& options);
void Validate(const StepOptions& options);
void Validate(const BoundsOptions& options);
void Validate(const DetectionOptions& options);
void Validate(const LocationOptions& options);
void Validate(const SwitchOptions& options);
void Validate(const ContinuationOptions& options);

}  // namespace rubcont
