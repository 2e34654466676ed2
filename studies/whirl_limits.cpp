#include "studies/whirl_limits.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "sweeps/rub_sweep.h"

namespace rubcont {
namespace {

// Every contact touches (N > 0) at point measures m: the measures normal_force_<contact>.
bool AllTouching(const Branch& branch, const Vector& measures) {
  bool any = false;
  for (std::size_t i = 0; i < branch.measure_names.size(); ++i) {
    if (branch.measure_names[i].rfind("normal_force_", 0) != 0) continue;
    any = true;
    if (!(measures(static_cast<Index>(i)) > 0.0)) return false;
  }
  return any;
}

bool Stable(const BranchPoint& p) { return p.num_unstable == 0; }

// The special point (not a test function) nearest in speed to `lambda` among those located
// between points lo − 1 and hi + 1; −1 when there is none.
int SpecialPointBetween(const Branch& branch, Index lo, Index hi, double lambda) {
  int best = -1;
  double best_distance = 0.0;
  for (std::size_t k = 0; k < branch.special_points.size(); ++k) {
    const SpecialPoint& p = branch.special_points[k];
    if (p.type == SpecialPointType::kTestFunction) continue;
    if (p.index < lo - 1 || p.index > hi + 1) continue;
    const double distance = std::abs(p.lambda - lambda);
    if (best < 0 || distance < best_distance) {
      best = static_cast<int>(k);
      best_distance = distance;
    }
  }
  return best;
}

// The walk of the header from point `start`, direction `direction`, on branch b.
WhirlLimit Walk(const RotatingWaveBranch& b, int branch_index, Index start, int direction) {
  WhirlLimit limit;
  limit.direction = direction;
  limit.branch = branch_index;
  limit.start = static_cast<int>(start);
  const auto& p = b.branch.points;
  const Index n = b.branch.Size();
  auto moves = [&](Index from, Index to) { return (p[to].lambda - p[from].lambda) * direction; };
  int step = 0;
  if (start + 1 < n && moves(start, start + 1) > 0.0) step = +1;
  else if (start > 0 && moves(start, start - 1) > 0.0) step = -1;
  if (step == 0) {
    limit.reason = fmt::format("{} ends at {:.3f} rpm", b.name, RadPerSecondToRpm(p[start].lambda));
    return limit;
  }
  limit.step = step;
  Index last = start;
  while (true) {
    const Index next = last + step;
    if (next < 0 || next >= n) {
      limit.last = static_cast<int>(last);
      limit.reason = fmt::format("{} stays stable up to its end at {:.3f} rpm ({})", b.name,
                                 RadPerSecondToRpm(p[last].lambda), b.branch.message);
      return limit;
    }
    if (!Stable(p[next]) || moves(last, next) < 0.0) break;
    last = next;
  }
  limit.last = static_cast<int>(last);
  const Index next = last + step;
  const int k = SpecialPointBetween(b.branch, std::min(last, next), std::max(last, next),
                                    p[last].lambda);
  if (k < 0) {
    limit.reason = fmt::format(
        "{} stops being stable between {:.3f} and {:.3f} rpm, but no special point was located "
        "there", b.name, RadPerSecondToRpm(p[last].lambda), RadPerSecondToRpm(p[next].lambda));
    return limit;
  }
  const SpecialPoint& s = b.branch.special_points[static_cast<std::size_t>(k)];
  limit.found = true;
  limit.special = k;
  limit.speed = s.lambda;
  limit.precession_hz = b.SpecialPrecessionHz(static_cast<std::size_t>(k));
  limit.point = s.Name();
  limit.converged = s.converged;
  return limit;
}

double Interpolate(double x0, double y0, double x1, double y1, double x) {
  return x1 == x0 ? y0 : y0 + (y1 - y0) * (x - x0) / (x1 - x0);
}

void CheckDirection(int direction) {
  if (direction != 1 && direction != -1) {
    throw std::invalid_argument(
        fmt::format("whirl limit: direction = {}: must be +1 (speed-up) or −1 (speed-down)", direction));
  }
}

void CheckBiasArguments(double epsilon, double tolerance) {
  if (!(tolerance > 0.0) || !(epsilon > 0.0)) {
    throw std::invalid_argument(fmt::format(
        "regularization bias: tolerance = {} rad/s, velocity_scale ε = {} m/s: both must be positive",
        tolerance, epsilon));
  }
}

}  // namespace

WhirlLimit StableLimitFrom(const std::vector<RotatingWaveBranch>& branches, int branch, Index point,
                           int direction) {
  CheckDirection(direction);
  if (branch < 0 || branch >= static_cast<int>(branches.size()) || point < 0 ||
      point >= branches[static_cast<std::size_t>(branch)].branch.Size()) {
    throw std::invalid_argument(fmt::format("stable limit: branch {}, point {}: not a point of the branch set",
                                            branch, point));
  }
  return Walk(branches[static_cast<std::size_t>(branch)], branch, point, direction);
}

WhirlLimit FindWhirlLimit(const std::vector<RotatingWaveBranch>& branches, int direction,
                          double range_end, const std::vector<std::string>& patterns) {
  CheckDirection(direction);
  if (patterns.empty()) throw std::invalid_argument("whirl limit: patterns: must not be empty");
  // The engine puts a branch's last point on its λ bound to its location tolerance.
  const double tolerance = 1e-2 * std::abs(range_end);
  WhirlLimit first_unfound;
  for (const std::string& pattern : patterns) {
    for (std::size_t i = 0; i < branches.size(); ++i) {
      const RotatingWaveBranch& b = branches[i];
      if (PatternName(b.normals) != pattern) continue;
      for (Index j = 0; j < b.branch.Size(); ++j) {
        const BranchPoint& p = b.branch.points[static_cast<std::size_t>(j)];
        if (std::abs(p.lambda - range_end) > tolerance || !Stable(p) ||
            !AllTouching(b.branch, p.measures)) {
          continue;
        }
        // Only an end of the branch: no neighbour further out.
        auto inward = [&](Index k) {
          return k < 0 || k >= b.branch.Size() ||
                 (b.branch.points[static_cast<std::size_t>(k)].lambda - p.lambda) * direction > 0.0;
        };
        if (!inward(j - 1) || !inward(j + 1)) continue;
        WhirlLimit limit = Walk(b, static_cast<int>(i), j, direction);
        if (limit.found) return limit;
        if (first_unfound.reason.empty()) first_unfound = limit;
      }
    }
  }
  if (first_unfound.reason.empty()) {
    first_unfound.direction = direction;
    first_unfound.reason = fmt::format(
        "no branch of the families {} is stable with every contact touching at {:.3f} rpm",
        fmt::join(patterns, ", "), RadPerSecondToRpm(range_end));
  }
  return first_unfound;
}

BranchReading PrecessionBeyond(const std::vector<RotatingWaveBranch>& branches,
                               const WhirlLimit& limit, double omega) {
  BranchReading reading;
  if (!limit.found) {
    reading.reason = "no limit: " + limit.reason;
    return reading;
  }
  if ((omega - limit.speed) * limit.direction < 0.0) {
    reading.reason = fmt::format("{:.3f} rpm lies before the limit at {:.3f} rpm: the whirl is still "
                                 "stable there", RadPerSecondToRpm(omega), RadPerSecondToRpm(limit.speed));
    return reading;
  }
  const RotatingWaveBranch& b = branches.at(static_cast<std::size_t>(limit.branch));
  const Index precession = b.branch.MeasureIndex("precession_hz");
  const auto& p = b.branch.points;
  double lambda = limit.speed;
  double hz = limit.precession_hz;
  for (Index k = limit.last + limit.step; k >= 0 && k < b.branch.Size(); k += limit.step) {
    const double next_lambda = p[k].lambda;
    const double next_hz = p[k].measures(precession);
    if ((next_lambda - lambda) * limit.direction < 0.0) {
      reading.reason = fmt::format("{} turns back at {:.3f} rpm before {:.3f} rpm", b.name,
                                   RadPerSecondToRpm(lambda), RadPerSecondToRpm(omega));
      return reading;
    }
    if ((omega - lambda) * limit.direction >= 0.0 && (next_lambda - omega) * limit.direction >= 0.0) {
      reading.found = true;
      reading.value = Interpolate(lambda, hz, next_lambda, next_hz, omega);
      return reading;
    }
    lambda = next_lambda;
    hz = next_hz;
  }
  reading.reason = fmt::format("{} ends at {:.3f} rpm before {:.3f} rpm", b.name,
                               RadPerSecondToRpm(lambda), RadPerSecondToRpm(omega));
  return reading;
}

Vector WhirlStateAt(const std::vector<RotatingWaveBranch>& branches, const WhirlLimit& limit,
                    double omega) {
  if (limit.branch < 0 || limit.step == 0) return {};
  const auto& p = branches.at(static_cast<std::size_t>(limit.branch)).branch.points;
  for (int k = limit.start; k != limit.last; k += limit.step) {
    const BranchPoint& a = p[static_cast<std::size_t>(k)];
    const BranchPoint& b = p[static_cast<std::size_t>(k + limit.step)];
    if (a.piece != b.piece || a.u.size() != b.u.size()) continue;
    if ((omega - a.lambda) * (omega - b.lambda) > 0.0) continue;
    const double s = b.lambda == a.lambda ? 0.0 : (omega - a.lambda) / (b.lambda - a.lambda);
    return (1.0 - s) * a.u + s * b.u;
  }
  return {};
}

RegularizationBias CompareRegularization(const WhirlLimit& at_epsilon, const WhirlLimit& at_tenth,
                                         double epsilon, double tolerance) {
  CheckBiasArguments(epsilon, tolerance);
  RegularizationBias bias;
  bias.epsilon = epsilon;
  bias.tolerance = tolerance;
  bias.at_epsilon = at_epsilon;
  bias.at_tenth = at_tenth;
  const char* which = at_epsilon.direction > 0 ? "speed-up" : "speed-down";
  if (!at_epsilon.found || !at_tenth.found) {
    bias.flagged = true;
    bias.message = fmt::format("{} limit missing at ε = {:g} m/s or ε/10: {}", which, epsilon,
                               !at_epsilon.found ? at_epsilon.reason : at_tenth.reason);
    return bias;
  }
  bias.shift = at_epsilon.speed - at_tenth.speed;
  bias.flagged = std::abs(bias.shift) > tolerance;
  bias.message = fmt::format(
      "{} limit {:.4f} rpm at ε = {:g} m/s, {:.4f} rpm at ε/10: estimated regularization bias "
      "{:+.4f} rpm, {} the tolerance {:.4f} rpm",
      which, RadPerSecondToRpm(at_epsilon.speed), epsilon, RadPerSecondToRpm(at_tenth.speed),
      RadPerSecondToRpm(bias.shift), bias.flagged ? "above" : "within", RadPerSecondToRpm(tolerance));
  return bias;
}

RegularizationBias EstimateRegularizationBias(const RubStructure& structure, int direction,
                                              const RotatingWaveBranchOptions& options,
                                              double tolerance,
                                              const std::vector<std::string>& patterns) {
  CheckDirection(direction);
  const double epsilon = structure.law.velocity_scale;
  CheckBiasArguments(epsilon, tolerance);
  const double range_end = direction > 0 ? options.search.speed_min : options.search.speed_max;
  RubStructure tenth = structure;
  tenth.law.velocity_scale = epsilon / 10.0;
  return CompareRegularization(
      FindWhirlLimit(ComputeRotatingWaveBranches(structure, FrictionLawKind::kTanh, options),
                     direction, range_end, patterns),
      FindWhirlLimit(ComputeRotatingWaveBranches(tenth, FrictionLawKind::kTanh, options),
                     direction, range_end, patterns),
      epsilon, tolerance);
}

}  // namespace rubcont
