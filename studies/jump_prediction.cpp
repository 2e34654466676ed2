#include "studies/jump_prediction.h"
#include "models/units.h"
#include "solvers/constants.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rubcont {
namespace {

struct BranchMatch {
  const RotatingWaveBranch* branch = nullptr;
  double score = kInfinity;
  int stable = -1;
  int index = -1;   // of the branch in the set
  Index point = -1;  // the branch's point nearest in speed
};

// What the sweep saw at one speed, per contact.
struct SweepState {
  double speed_rpm = kNaN;
  std::vector<char> touching;        // in contact for at least half the analysed time
  std::vector<double> precession_hz;
  std::vector<double> normal_force;  // mean over the time in contact [N]
};

// The branch whose state at the sweep state's speed matches it: the same contacts touching, each
// touching contact's precession within the tolerance; among those the stable ones first (a sweep
// settles on attractors), then the smallest relative normal-force mismatch (which tells, e.g., the
// Mode 1 whirl from the Mode 2 and single-contact whirls that roll at the same precession).
BranchMatch MatchState(const SweepState& state, const RubStructure& structure,
                       const std::vector<RotatingWaveBranch>& branches, const JumpMatchOptions& o) {
  BranchMatch best;
  bool best_stable = false;
  if (!std::isfinite(state.speed_rpm)) return best;
  const std::size_t m = structure.contacts.size();
  bool any_touching = false;
  for (std::size_t k = 0; k < m; ++k) {
    if (!state.touching[k]) continue;
    if (!std::isfinite(state.precession_hz[k])) return best;
    any_touching = true;
  }
  if (!any_touching) return best;
  for (std::size_t bi = 0; bi < branches.size(); ++bi) {
    const RotatingWaveBranch& b = branches[bi];
    const auto& names = b.branch.measure_names;
    auto index = [&](const std::string& name) -> Index {
      const auto it = std::find(names.begin(), names.end(), name);
      return it == names.end() ? -1 : static_cast<Index>(it - names.begin());
    };
    const Index precession = index("precession_hz");
    std::vector<Index> normal(m);
    bool complete = precession >= 0;
    for (std::size_t k = 0; k < m; ++k) {
      normal[k] = index("normal_force_" + structure.contacts[k].name);
      complete = complete && normal[k] >= 0;
    }
    if (!complete) continue;
    const auto& points = b.branch.points;
    for (std::size_t i = 0; i + 1 < points.size(); ++i) {
      const double r0 = RadPerSecondToRpm(points[i].lambda);
      const double r1 = RadPerSecondToRpm(points[i + 1].lambda);
      if (state.speed_rpm < std::min(r0, r1) || state.speed_rpm > std::max(r0, r1)) continue;
      if (points[i].piece != points[i + 1].piece) continue;  // no interpolation across a switch
      const double s = r1 == r0 ? 0.0 : (state.speed_rpm - r0) / (r1 - r0);
      auto at = [&](Index j) { return (1.0 - s) * points[i].measures(j) + s * points[i + 1].measures(j); };
      const double hz = at(precession);
      bool matches = true;
      double score = 0.0;
      for (std::size_t k = 0; k < m && matches; ++k) {
        const double n = at(normal[k]);
        const bool touching = n > 0.0;
        if (touching != static_cast<bool>(state.touching[k])) {
          matches = false;
        } else if (touching) {
          const double tolerance = std::max(o.match_hz, o.match_relative * std::abs(hz));
          matches = std::abs(hz - state.precession_hz[k]) <= tolerance;
          const double ns = state.normal_force[k];
          score += std::abs(ns - n) / std::max({std::abs(ns), std::abs(n), 1e-12});
        }
      }
      if (!matches) continue;
      const std::size_t near = s < 0.5 ? i : i + 1;
      const BranchPoint& nearer = points[near];
      const bool stable = nearer.num_unstable == 0;
      if ((stable && !best_stable) || (stable == best_stable && score < best.score)) {
        best.branch = &b;
        best.score = score;
        best.stable = nearer.num_unstable < 0 ? -1 : stable ? 1 : 0;
        best.index = static_cast<int>(bi);
        best.point = static_cast<Index>(near);
        best_stable = stable;
      }
    }
  }
  return best;
}

SweepState StateOf(std::size_t i, const RubStructure& structure, const std::vector<SweepPoint>& points,
                   const RubSweepRegimes& regimes) {
  SweepState state;
  const std::size_t m = structure.contacts.size();
  if (points[i].channels.size() != m) return state;
  state.speed_rpm = RadPerSecondToRpm(points[i].parameter);
  for (std::size_t k = 0; k < m; ++k) {
    const ChannelSummary& c = points[i].channels[k];
    state.touching.push_back(c.active_fraction >= 0.5 ? 1 : 0);
    state.precession_hz.push_back(regimes.precession_hz[k][i]);
    state.normal_force.push_back(c.measures.size() > kNormalForceMeasure
                                     ? c.measures[kNormalForceMeasure].mean : kNaN);
  }
  return state;
}

SweepState StateAt(double speed_rpm, const RubStructure& structure,
                   const std::vector<SweepPoint>& points, const RubSweepRegimes& regimes) {
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (std::abs(RadPerSecondToRpm(points[i].parameter) - speed_rpm) > 1e-9) continue;
    return StateOf(i, structure, points, regimes);
  }
  return SweepState{};
}

// The special point of `b` nearest the speed interval [lo, hi] (distance 0 inside it; the first
// one of the branch among equals), if within `max_distance`; −1 otherwise. A test function marks
// a corner of a smooth branch, not a change of existence or stability, and does not count, with
// one exception: `knee` (the tanh law's "<contact> knee", where rolling rounds into slipping;
// empty for none) for a whirl ↔ whip change at that contact, since the regime rule reads the slip
// (sweeps/rub_sweep.h) and the knee is where the slip sets in. It wins among equals: a Hopf point
// in the same interval is where the circular whip then gives way to the modulated one.
int NearestSpecialPoint(const RotatingWaveBranch& b, double lo, double hi, double max_distance,
                        const std::string& knee) {
  int best = -1;
  double best_distance = kInfinity;
  bool best_knee = false;
  for (std::size_t i = 0; i < b.branch.special_points.size(); ++i) {
    const SpecialPoint& p = b.branch.special_points[i];
    const bool is_knee = p.type == SpecialPointType::kTestFunction && !knee.empty() && p.label == knee;
    if (p.type == SpecialPointType::kTestFunction && !is_knee) continue;
    const double rpm = RadPerSecondToRpm(p.lambda);
    const double distance = rpm < lo ? lo - rpm : rpm > hi ? rpm - hi : 0.0;
    if (distance > max_distance) continue;
    if (distance < best_distance || (distance == best_distance && is_knee && !best_knee)) {
      best_distance = distance;
      best_knee = is_knee;
      best = static_cast<int>(i);
    }
  }
  return best;
}

}  // namespace

WaveMatch MatchWave(const RubStructure& structure, const std::vector<SweepPoint>& points,
                    const RubSweepRegimes& regimes, std::size_t index,
                    const std::vector<RotatingWaveBranch>& branches, const JumpMatchOptions& options) {
  WaveMatch match;
  if (index >= points.size() || points[index].status == SweepPointStatus::kIntegrationFailure) return match;
  const BranchMatch m = MatchState(StateOf(index, structure, points, regimes), structure, branches, options);
  match.branch = m.index;
  match.point = m.point;
  match.stable = m.stable;
  return match;
}

std::vector<PredictedJump> PredictJumps(const std::string& direction, const RubStructure& structure,
                                        const std::vector<SweepPoint>& points,
                                        const RubSweepRegimes& regimes,
                                        const std::vector<RotatingWaveBranch>& branches,
                                        const JumpMatchOptions& options) {
  std::vector<PredictedJump> rows;
  for (const RubSweepJump& j : regimes.jumps) {
    PredictedJump row;
    row.direction = direction;
    row.contact = structure.contacts.at(static_cast<std::size_t>(j.contact)).name;
    row.jump = j;
    row.bifurcation_speed_rpm = kNaN;
    row.bifurcation_precession_hz = kNaN;
    row.difference_rpm = kNaN;
    const double lo = std::min(j.speed_from_rpm, j.speed_to_rpm);
    const double hi = std::max(j.speed_from_rpm, j.speed_to_rpm);
    const bool regime_change = j.kind == RubJumpKind::kWhirlToWhip || j.kind == RubJumpKind::kWhipToWhirl;
    const std::string knee = regime_change ? row.contact + " knee" : std::string();
    bool first_match = true;
    for (const char* side : {"departure", "landing"}) {
      const double speed = side[0] == 'd' ? j.speed_from_rpm : j.speed_to_rpm;
      const BranchMatch match =
          MatchState(StateAt(speed, structure, points, regimes), structure, branches, options);
      if (match.branch == nullptr) continue;
      const int k = NearestSpecialPoint(*match.branch, lo, hi, options.max_distance_rpm, knee);
      if (first_match || k >= 0) {
        row.matched_side = side;
        row.branch = match.branch->name;
        row.branch_stable = match.stable;
        first_match = false;
      }
      if (k < 0) continue;
      const SpecialPoint& p = match.branch->branch.special_points[static_cast<std::size_t>(k)];
      row.bifurcation = p.Name();
      row.bifurcation_speed_rpm = RadPerSecondToRpm(p.lambda);
      row.bifurcation_precession_hz = match.branch->SpecialPrecessionHz(static_cast<std::size_t>(k));
      row.difference_rpm = 0.5 * (lo + hi) - row.bifurcation_speed_rpm;
      break;
    }
    rows.push_back(row);
  }
  return rows;
}

}  // namespace rubcont
