// Jump prediction: each jump a time-marching sweep makes (level L3) next to the bifurcation of the
// continuation branches (level L1) that predicts it — the rows of a scene's jump table
// (apps/sweep_output.h writes them to /sweeps/jump_table).
//
// The rule (PredictJumps): a state of the sweep lies on a branch when, at its speed, the same
// contacts touch (sweep: in contact ≥ half the analysed time; branch: N > 0) and each touching
// contact's BP is within max(match_hz, match_relative·BP) of the branch's precession (linear
// interpolation between points of one smooth piece); stable branch points are preferred (a sweep
// settles on attractors), then the smallest relative normal-force mismatch. The departure state (before the jump) is tried
// first: the jump happens where that state stops existing or being stable, which is one of its
// branch's special points (event: stick ↔ slip or contact loss, fold, Hopf, branch point; not
// test functions, which mark corners, not bifurcations, except for a whirl ↔ whip change the
// contact's tanh knee: the regime rule reads the slip, and the knee is where it sets in). The
// special point nearest to the speed interval of the jump is taken, if it lies within
// max_distance_rpm of it (a knee wins among equals). When the departure state is on no branch (a non-circular motion, or no
// contact) or its branch has no special point near the jump, the landing state is tried the same
// way. A jump neither side of which is predicted keeps the matched branch (if any) and no
// bifurcation: the branches do not explain it.
#pragma once

#include <string>
#include <vector>

#include "sweeps/rub_sweep.h"
#include "waves/rotating_wave_branches.h"

namespace rubcont {

struct JumpMatchOptions {
  double match_hz = 1.0;         // [Hz] > 0: absolute precession tolerance of a state on a branch
  double match_relative = 0.01;  // [-] ≥ 0: relative precession tolerance
  // [rpm] > 0: a special point further than this from the jump's speed interval does not predict
  // it (the thesis's sweeps overshoot a jump by about one 2 rpm step and a transient).
  double max_distance_rpm = 10.0;
};

struct PredictedJump {
  std::string direction;  // "up" or "down"
  std::string contact;    // contact name
  RubSweepJump jump;
  std::string matched_side = "none";  // "departure", "landing" or "none"
  std::string branch;                 // the branch the matched state lies on
  int branch_stable = -1;             // 1 / 0 at the matched speed; −1 unknown
  std::string bifurcation;            // SpecialPoint::Name() of the predicting point
  double bifurcation_speed_rpm;       // NaN when there is none
  double bifurcation_precession_hz;
  double difference_rpm;              // middle of the jump's interval − bifurcation speed
};

// The wave a state of a sweep lies on (the rule above: the same contacts touching, each touching
// contact's precession within the tolerance, stable branches first, then the smallest normal-force
// mismatch): the branch's index in `branches` and its point nearest in speed, and whether it is
// stable there (1 / 0 / −1 unknown); branch −1 when the state lies on none (or the point failed).
// `points` and `regimes` as for PredictJumps; `index` the point asked about.
struct WaveMatch {
  int branch = -1;
  Index point = -1;
  int stable = -1;
};
WaveMatch MatchWave(const RubStructure& structure, const std::vector<SweepPoint>& points,
                    const RubSweepRegimes& regimes, std::size_t index,
                    const std::vector<RotatingWaveBranch>& branches, const JumpMatchOptions& options = {});

// The prediction of every jump of one direction's classified sweep.
// `points` and `regimes` are one direction's sweep (SweepStepper::points(), ClassifySweep).
std::vector<PredictedJump> PredictJumps(const std::string& direction, const RubStructure& structure,
                                        const std::vector<SweepPoint>& points,
                                        const RubSweepRegimes& regimes,
                                        const std::vector<RotatingWaveBranch>& branches,
                                        const JumpMatchOptions& options = {});

}  // namespace rubcont
