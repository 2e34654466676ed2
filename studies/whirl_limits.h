// What a branch set of rotating waves (level L1) says about a time-marching speed sweep (level
// L3): where the stable whirl the sweep follows ends going up (the speed-up jump) and going down
// (the speed-down jump), and at what precession the whip that the speed-up jump leads to turns at
// a given speed. bench/work_precision_bench.cpp sets these answers beside the sweeps' own.
//
// The whirl a sweep follows. A speed sweep starts with an impulse at one end of its range (the
// bottom for speed-up, the top for speed-down) that sets every contact rubbing, so its whirl is a
// branch that is stable at that end of the range with every contact touching (N > 0). When
// several are (case A(a) at 20 rpm: the Mode 1 and the Mode 2 whirl), the first of `patterns`
// (PatternName) wins: Mode 1 first, because a translation impulse puts the contact normals in
// phase (sweeps/rub_sweep.h, RubImpulseIncrement), then Mode 2 (the truly overhung disk's
// two-contact whirl belongs to that family).
//
// The limit. From that end the branch is walked in its own point order while its points stay
// stable and the speed keeps moving the sweep's way (an event point stored on both pieces counts
// once). Where the walk stops, the whirl stops existing (a fold, or a non-smooth fold at a
// stick ↔ slip event) or being stable (a Hopf point, a real eigenvalue crossing, an event onto an
// unstable piece): the special point between the last point of the walk and the next is the
// limit (test functions such as the tanh law's knee mark corners, not limits, and are skipped).
// A walk that reaches the other end of the range, or a stability change without a located
// special point, is reported as such, not as an answer.
#pragma once

#include <string>
#include <vector>

#include "solvers/constants.h"
#include "waves/rotating_wave_branches.h"

namespace rubcont {

struct WhirlLimit {
  bool found = false;
  double speed = kNaN;  // ω of the limit [rad/s]
  double precession_hz = kNaN;
  std::string point;            // SpecialPoint::Name() of the limit
  bool converged = false;       // the special point was located to the engine's tolerance
  std::string reason;           // why there is no answer, when !found
  int direction = 0;            // +1 speed-up, −1 speed-down
  // Where it lies: branches[branch].branch; the walk went from point `start` to point `last` in
  // steps of `step` (+1 / −1 in point order); the limit is special point `special` (−1: none).
  int branch = -1;
  int start = -1;
  int last = -1;
  int step = 0;
  int special = -1;
};

// The limit of the whirl a sweep in `direction` (+1 speed-up, −1 speed-down) follows from the end
// `range_end` [rad/s] of the branch set's speed range (its speed_min for speed-up, speed_max for
// speed-down). Throws std::invalid_argument for a direction other than ±1 or no patterns.
WhirlLimit FindWhirlLimit(const std::vector<RotatingWaveBranch>& branches, int direction,
                          double range_end,
                          const std::vector<std::string>& patterns = {"mode1", "mode2"});

// The same walk from any point of a branch: from point `point` of branches[branch] in `direction`
// while the points stay stable and the speed keeps moving that way (the point itself is taken as
// the start, stable or not). Where a sweep that stands on a stable wave stays until it must leave
// (studies/loop.h). Throws std::invalid_argument for a direction other than ±1 or a point that is
// not in the set.
WhirlLimit StableLimitFrom(const std::vector<RotatingWaveBranch>& branches, int branch, Index point,
                           int direction);

// A value read off a branch, or why there is none.
struct BranchReading {
  bool found = false;
  double value = kNaN;
  std::string reason;  // when !found
};

// The precession [Hz] at speed ω [rad/s] of the state the branch goes on to beyond a speed-up
// limit (the circular whip the speed-up jump leads to): the branch followed from the limit's
// special point on, in the same direction, interpolated linearly between points of one piece.
// Not found when the limit was not found, ω lies before it, or the branch turns back or ends
// before ω.
BranchReading PrecessionBeyond(const std::vector<RotatingWaveBranch>& branches,
                               const WhirlLimit& limit, double omega);

// The rotating wave's unknowns (RotatingWaveProblem: [p, Ω, …]) at speed ω on the stable stretch
// the limit's walk covered, interpolated linearly between points of one piece: the whirl a sweep
// is on at that speed. Empty when ω is not on the stretch.
Vector WhirlStateAt(const std::vector<RotatingWaveBranch>& branches, const WhirlLimit& limit,
                    double omega);

// The regularization bias of a tanh-law limit, estimated from the law itself: the limit at the
// structure's ε (structure.law.velocity_scale) and at ε/10. For a limit converging at first order
// in ε the shift between them is 0.9 times the bias at ε; the estimate reported is the shift.
struct RegularizationBias {
  double epsilon = 0.0;        // [m/s]
  WhirlLimit at_epsilon;       // the limit at ε
  WhirlLimit at_tenth;         // the limit at ε/10
  double shift = kNaN;  // ω(ε) − ω(ε/10) [rad/s]
  double tolerance = 0.0;      // [rad/s]
  bool flagged = false;        // |shift| > tolerance, or either limit missing
  std::string message;         // one sentence with the numbers (speeds in rpm)
};

// The comparison, for limits already found on the branch sets at ε and ε/10. tolerance [rad/s] > 0
// and ε > 0 (std::invalid_argument otherwise).
RegularizationBias CompareRegularization(const WhirlLimit& at_epsilon, const WhirlLimit& at_tenth,
                                         double epsilon, double tolerance);

// Computes both tanh-law branch sets (options as for ComputeRotatingWaveBranches) and compares
// the limits of `direction` from the end of options.search's speed range. Throws
// std::invalid_argument for a non-positive tolerance or ε, or invalid options.
RegularizationBias EstimateRegularizationBias(const RubStructure& structure, int direction,
                                              const RotatingWaveBranchOptions& options,
                                              double tolerance,
                                              const std::vector<std::string>& patterns = {"mode1", "mode2"});

}  // namespace rubcont
