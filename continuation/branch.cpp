#include "continuation/branch.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include <fmt/core.h>

#include "solvers/constants.h"

namespace rubcont {

const char* ToString(BranchStatus status) {
  switch (status) {
    case BranchStatus::kRunning: return "running";
    case BranchStatus::kReachedLambdaBound: return "reached a λ bound";
    case BranchStatus::kReachedStateBound: return "reached a state bound";
    case BranchStatus::kMaxSteps: return "reached the maximum number of steps";
    case BranchStatus::kClosed: return "closed";
    case BranchStatus::kStoppedByCaller: return "stopped by the caller";
    case BranchStatus::kSwitchRefused: return "switch refused";
    case BranchStatus::kNoValidDirection: return "no valid direction after a switch";
    case BranchStatus::kStepTooSmall: return "step below its minimum";
    case BranchStatus::kStartFailed: return "start failed";
    case BranchStatus::kGrazing: return "ended at a grazing";
  }
  return "unknown";
}

bool IsFailure(BranchStatus status) {
  return status == BranchStatus::kStepTooSmall || status == BranchStatus::kStartFailed;
}

namespace {

// "fold" → "folds", "branch point" → "branch points", "Hopf" stays (as in "2 Hopf").
std::string Plural(const std::string& name) {
  if (name == "Hopf" || name == "Neimark-Sacker" || name == "multiplier +1") return name;
  if (name == "grazing") return "grazing points";
  if (name.back() == 's' || name.back() == 'h') return name + "es";
  return name + "s";
}

}  // namespace

std::string SpecialPoint::Name() const {
  const std::string type_name = ToString(type);
  if (label.empty() || label == type_name) return type_name;
  return type_name + ": " + label;
}

int Branch::Count(SpecialPointType type) const {
  return static_cast<int>(std::count_if(special_points.begin(), special_points.end(),
                                        [type](const SpecialPoint& p) { return p.type == type; }));
}

const SpecialPoint* Branch::FirstLocated(SpecialPointType type) const {
  for (const SpecialPoint& p : special_points) {
    if (p.type == type && p.converged) return &p;
  }
  return nullptr;
}

std::string Branch::BriefReport() const {
  std::string report = fmt::format("branch: {} point{}", points.size(),
                                   points.size() == 1 ? "" : "s");
  if (!points.empty()) {
    double lo = points.front().lambda;
    double hi = lo;
    for (const BranchPoint& p : points) {
      lo = std::min(lo, p.lambda);
      hi = std::max(hi, p.lambda);
    }
    report += fmt::format(", λ ∈ [{:.6g}, {:.6g}]", lo, hi);
  }
  // Special points counted by name, in the order of first appearance.
  std::vector<std::string> names;
  std::map<std::string, int> counts;
  for (const SpecialPoint& p : special_points) {
    std::string name = p.type == SpecialPointType::kEvent ? "event"
                       : p.type == SpecialPointType::kTestFunction ? p.label
                                                                   : ToString(p.type);
    if (counts[name]++ == 0) names.push_back(name);
  }
  for (const std::string& name : names) {
    const int count = counts[name];
    report += fmt::format(", {} {}", count, count == 1 ? name : Plural(name));
  }
  if (statistics.stray_rejections > 0) {  // Problem::StrayPoint
    report += fmt::format(", {} stray point{} refused", statistics.stray_rejections,
                          statistics.stray_rejections == 1 ? "" : "s");
  }
  if (!start_note.empty()) report += ", " + start_note;
  report += fmt::format(", ended: {}", message.empty() ? ToString(status) : message);
  return report;
}

Vector Branch::Lambda() const {
  Vector column(points.size());
  for (size_t i = 0; i < points.size(); ++i) column(i) = points[i].lambda;
  return column;
}

Index Branch::MeasureIndex(const std::string& name) const {
  const auto it = std::find(measure_names.begin(), measure_names.end(), name);
  if (it == measure_names.end()) {
    std::string known;
    for (const std::string& m : measure_names) known += (known.empty() ? "" : ", ") + m;
    throw std::invalid_argument(fmt::format(
        "Branch::Measure: no measure named '{}' (the branch has: {})", name, known));
  }
  return it - measure_names.begin();
}

Vector Branch::Measure(const std::string& name) const {
  const Index k = MeasureIndex(name);
  Vector column(points.size());
  for (size_t i = 0; i < points.size(); ++i) {
    column(i) = k < points[i].measures.size() ? points[i].measures(k) : kNaN;
  }
  return column;
}

Vector Branch::StateComponent(Index i) const {
  Vector column(points.size());
  for (size_t k = 0; k < points.size(); ++k) {
    column(k) = i >= 0 && i < points[k].u.size() ? points[k].u(i) : kNaN;
  }
  return column;
}

Vector Branch::Arclength() const {
  Vector column(points.size());
  for (size_t i = 0; i < points.size(); ++i) column(i) = points[i].arclength;
  return column;
}

Vector Branch::Step() const {
  Vector column(points.size());
  for (size_t i = 0; i < points.size(); ++i) column(i) = points[i].step;
  return column;
}

Vector Branch::ResidualNorm() const {
  Vector column(points.size());
  for (size_t i = 0; i < points.size(); ++i) column(i) = points[i].residual_norm;
  return column;
}

Eigen::VectorXi Branch::NewtonIterations() const {
  Eigen::VectorXi column(points.size());
  for (size_t i = 0; i < points.size(); ++i) column(i) = points[i].newton_iterations;
  return column;
}

Eigen::VectorXi Branch::NumUnstable() const {
  Eigen::VectorXi column(points.size());
  for (size_t i = 0; i < points.size(); ++i) column(i) = points[i].num_unstable;
  return column;
}

std::vector<std::string> Branch::PieceLabels() const {
  std::vector<std::string> column;
  column.reserve(points.size());
  for (const BranchPoint& p : points) column.push_back(p.piece);
  return column;
}

}  // namespace rubcont

namespace rubcont {

Branch JoinAtStart(const Branch& backward, const Branch& forward) {
  if (backward.points.empty() || forward.points.empty()) {
    throw std::invalid_argument("JoinAtStart: a run has no points (its start failed)");
  }
  if (backward.points.front().lambda != forward.points.front().lambda) {
    throw std::invalid_argument(fmt::format(
        "JoinAtStart: the runs start at different λ ({} and {})", backward.points.front().lambda,
        forward.points.front().lambda));
  }
  Branch joined;
  joined.measure_names = forward.measure_names;
  joined.options = forward.options;
  joined.start_note = forward.start_note.empty() ? backward.start_note : forward.start_note;
  const Index nb = backward.Size();
  for (Index i = nb - 1; i >= 0; --i) {
    BranchPoint p = backward.points[i];
    p.tangent = -p.tangent;
    p.arclength = -p.arclength;
    // The step to a point is from its predecessor, which is now the next point of `backward`.
    p.step = i + 1 < nb ? backward.points[i + 1].step : 0.0;
    joined.points.push_back(std::move(p));
  }
  for (Index i = 1; i < forward.Size(); ++i) joined.points.push_back(forward.points[i]);
  // A point between backward's i and i + 1 lies between the joined nb − 2 − i and nb − 1 − i.
  for (auto it = backward.special_points.rbegin(); it != backward.special_points.rend(); ++it) {
    SpecialPoint p = *it;
    p.tangent = -p.tangent;
    p.index = std::max<Index>(0, nb - 2 - p.index);
    joined.special_points.push_back(std::move(p));
  }
  for (SpecialPoint p : forward.special_points) {
    p.index += nb - 1;
    joined.special_points.push_back(std::move(p));
  }
  joined.status = IsFailure(forward.status) || !IsFailure(backward.status) ? forward.status
                                                                          : backward.status;
  const auto ended = [](const Branch& b) {
    return b.message.empty() ? std::string(ToString(b.status)) : b.message;
  };
  joined.message = fmt::format("backward: {}; forward: {}", ended(backward), ended(forward));
  joined.statistics = backward.statistics;
  joined.statistics += forward.statistics;
  return joined;
}

BranchStatistics& operator+=(BranchStatistics& into, const BranchStatistics& other) {
  into.steps += other.steps;
  into.corrector_failures += other.corrector_failures;
  into.angle_rejections += other.angle_rejections;
  into.residual_evaluations += other.residual_evaluations;
  into.jacobian_evaluations += other.jacobian_evaluations;
  into.stability_evaluations += other.stability_evaluations;
  into.switches += other.switches;
  into.jump_rejections += other.jump_rejections;
  into.stray_rejections += other.stray_rejections;
  return into;
}

}  // namespace rubcont
