#include "studies/hysteresis_map.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <mutex>
#include <numeric>
#include <stdexcept>

#include <fmt/core.h>
#include <fmt/format.h>

#include "continuation/event_curve.h"
#include "continuation/fold.h"
#include "continuation/hopf.h"
#include "models/rub_model.h"
#include "models/units.h"
#include "solvers/parallel.h"
#include "solvers/stopwatch.h"

namespace rubcont {

namespace {

// Why a Hopf point of the base branch set starts no curve, or "" when it does: one that is not
// located (the critical value jumps: "not a zero"), and one that the engine located where a marginal
// pair's growth rate crosses the stability tolerance rather than 0 (its special point's note says
// so): the Hopf point of that pair lies outside the step, and Newton from there diverged (A(a),
// exact law, the one-contact whirls at 47.123 rpm: the pair's Re = 0 is 0.36–0.75 rpm away).
std::string NoHopfCurve(const SpecialPoint& sp, double stability_tolerance) {
  if (!sp.converged) return "not located";
  if (!(sp.critical_value.imag() > 0.0)) return "no frequency";
  if (!(std::abs(sp.critical_value.real()) < 0.5 * stability_tolerance)) {
    return fmt::format("located at the stability tolerance (Re = {:.3g})", sp.critical_value.real());
  }
  return "";
}

// Puts `problem` on the piece and phase of a special point of `branch`.
void PlaceAt(RotatingWaveDesignProblem& problem, const Branch& branch, const SpecialPoint& point) {
  problem.SetModes(ModesAt(branch, point, problem.Contacts()));
  problem.SetPhaseReference(point.u);
}

// Ipopt on every located turning point of an event curve (see CurveExtremum).
std::vector<CurveExtremum> LocateExtrema(RotatingWaveDesignProblem& problem, const Branch& branch,
                                         const SpecialPoint& event, const Branch& curve,
                                         double eta_min, double eta_max) {
  std::vector<CurveExtremum> extrema;
  const double base = problem.SecondParameter();
  const Index n = problem.Dimension();
  for (const SpecialPoint& turn : curve.special_points) {
    if (turn.type != SpecialPointType::kFold || !turn.converged) continue;
    const BranchPoint& before = curve.points[turn.index];
    CurveExtremum e;
    e.engine_eta = turn.lambda;
    e.engine_speed = turn.u(n);
    e.sense = before.lambda < turn.lambda ? +1 : -1;
    PlaceAt(problem, branch, event);
    problem.SetSecondParameter(before.lambda);
    problem.SetPhaseReference(before.u.head(n));
    const std::vector<std::string> names = problem.EventNames();
    const int k = static_cast<int>(std::find(names.begin(), names.end(), event.label) - names.begin());
    EventCurveProblem manifold(problem, k, before.u.head(n), before.u(n));
    FoldOptimizationOptions options;
    options.sense = e.sense;
    options.lambda_min = eta_min;  // the map's range: Ipopt's iterates stay physical
    options.lambda_max = eta_max;
    e.ipopt = LocateFoldByOptimization(manifold, before.u, before.lambda, options);
    if (!e.ipopt.Solved()) {
      // The finite-difference Hessian of the event manifold differences a Jacobian whose margin
      // row is itself a difference; where that is too noisy for Ipopt's first steps, the
      // limited-memory approximation needs no second derivatives.
      options.hessian = FoldHessian::kLimitedMemory;
      problem.SetSecondParameter(before.lambda);
      e.ipopt = LocateFoldByOptimization(manifold, before.u, before.lambda, options);
    }
    e.ipopt_speed = e.ipopt.u.size() > n ? e.ipopt.u(n) : 0.0;
    extrema.push_back(e);
  }
  problem.SetSecondParameter(base);
  return extrema;
}

}  // namespace

void Validate(const HysteresisMapOptions& o) {
  auto fail = [](const std::string& field, double value, const std::string& rule) {
    throw std::invalid_argument(fmt::format("HysteresisMapOptions.{} = {}: {}", field, value, rule));
  };
  const char* name = ToString(o.parameter);
  if (!InPhysicalRange(o.parameter, o.eta_min)) {
    fail("eta_min", o.eta_min,
         fmt::format("must lie in the physical range of {} ({} {})", name,
                     LowerLimitIncluded(o.parameter) ? "≥" : ">", LowerLimit(o.parameter)));
  }
  if (!(std::isfinite(o.eta_max) && o.eta_max > o.eta_min)) {
    fail("eta_max", o.eta_max, fmt::format("must be finite and exceed eta_min = {}", o.eta_min));
  }
  if (o.threads < 1 || o.threads > 1024) fail("threads", o.threads, "must be in 1 … 1024");
  if (o.eta_points < 2) fail("eta_points", o.eta_points, "must be at least 2");
  if (o.speed_points < 2) fail("speed_points", o.speed_points, "must be at least 2");
  if (o.curve_max_steps < 1) fail("curve_max_steps", o.curve_max_steps, "must be at least 1");
  if (!(o.curve_max_step > 0.0)) fail("curve_max_step", o.curve_max_step, "must be positive");
  Validate(o.branches.search);
}

const char* ToString(MapRegion region) {
  switch (region) {
    case MapRegion::kNone: return "no stable circular state";
    case MapRegion::kOne: return "one stable circular state";
    case MapRegion::kCoexisting: return "two or more coexisting stable circular states";
  }
  return "?";
}

MapRegion HysteresisMap::Region(Index i, Index j) const {
  const int c = stable_count(i, j);
  return c <= 0 ? MapRegion::kNone : c == 1 ? MapRegion::kOne : MapRegion::kCoexisting;
}

std::string HysteresisMap::BriefReport() const {
  int coexisting = 0, none = 0, cells = 0;
  for (Index i = 0; i < stable_count.rows(); ++i) {
    for (Index j = 0; j < stable_count.cols(); ++j) {
      if (stable_count(i, j) < 0) continue;
      ++cells;
      if (stable_count(i, j) >= 2) ++coexisting;
      if (stable_count(i, j) == 0) ++none;
    }
  }
  int cusps = 0, hopf_curves = 0, codimension_two = 0;
  for (const MapCurve& c : curves) {
    cusps += c.curve.Count(SpecialPointType::kCusp);
    if (c.kind != "hopf") continue;
    ++hopf_curves;
    codimension_two += c.curve.Count(SpecialPointType::kBogdanovTakens) +
                       c.curve.Count(SpecialPointType::kZeroHopf) +
                       c.curve.Count(SpecialPointType::kDoubleHopf) +
                       c.curve.Count(SpecialPointType::kGeneralizedHopf);
  }
  return fmt::format(
      "map of {} over [{:g}, {:g}] ({} values, {} branches) × {} speeds: {:.1f} % of the cells "
      "with coexisting stable states, {:.1f} % with none; {} curves ({} Hopf), {} cusps, {} "
      "Bogdanov-Takens / zero-Hopf / double-Hopf / generalized Hopf points; grid {:.2f} s, curves {:.2f} s{}",
      ToString(parameter), eta.size() ? eta(0) : 0.0, eta.size() ? eta(eta.size() - 1) : 0.0,
      eta.size(), grid_branches, speed.size(), cells ? 100.0 * coexisting / cells : 0.0,
      cells ? 100.0 * none / cells : 0.0, curves.size(), hopf_curves, cusps, codimension_two,
      grid_seconds, curve_seconds,
      failures.empty() ? "" : fmt::format(", {} failures", failures.size()));
}

std::vector<std::pair<double, double>> StableIntervals(const Branch& branch) {
  std::vector<std::pair<double, double>> intervals;
  const auto& p = branch.points;
  std::size_t i = 0;
  while (i < p.size()) {
    if (p[i].num_unstable != 0) {
      ++i;
      continue;
    }
    // A run of stable points on one piece; a piece change (a switch point stored twice) or an
    // unstable point ends it.
    double lo = p[i].lambda, hi = p[i].lambda;
    std::size_t j = i + 1;
    while (j < p.size() && p[j].num_unstable == 0 && p[j].piece == p[i].piece) {
      lo = std::min(lo, p[j].lambda);
      hi = std::max(hi, p[j].lambda);
      // A turning point inside a run starts a new state at the same speeds: split there.
      if (j + 1 < p.size() && p[j + 1].num_unstable == 0 && p[j + 1].piece == p[i].piece &&
          (p[j].lambda - p[j - 1].lambda) * (p[j + 1].lambda - p[j].lambda) < 0.0) {
        break;
      }
      ++j;
    }
    if (hi > lo) intervals.emplace_back(lo, hi);
    i = j;  // j > i: the first point after the run, or the turning point that starts the next
  }
  return intervals;
}

namespace {

// The friction law and the branch options the grid and the curves use. The regularized law's knee
// test functions sit at the branches' turning points and would be recorded there instead of the
// folds: switch them off, so the folds are located and continued.
RotatingWaveBranchOptions MapBranchOptions(const TwoPointParams& params,
                                           const HysteresisMapOptions& options) {
  RotatingWaveBranchOptions branch_options = options.branches;
  if (params.friction_law.kind == FrictionLawKind::kTanh) {
    branch_options.continuation.detect.test_functions = false;
  }
  return branch_options;
}

Vector GridEtas(const HysteresisMapOptions& options) {
  return Vector::LinSpaced(options.eta_points, options.eta_min, options.eta_max);
}

Vector GridSpeeds(const HysteresisMapOptions& options) {
  return Vector::LinSpaced(options.speed_points, options.branches.search.speed_min,
                           options.branches.search.speed_max);
}

MapGridRow ComputeGridRow(const TwoPointParams& params, const HysteresisMapOptions& options,
                          const RotatingWaveBranchOptions& branch_options, const Vector& etas,
                          const Vector& speeds, Index i) {
  const Index k = speeds.size();
  MapGridRow row;
  row.index = i;
  row.stable_count.assign(static_cast<size_t>(k), 0);
  const double eta = etas(i);
  try {
    const TwoPointParams p = WithoutImbalance(WithDesignParameter(params, options.parameter, eta));
    const std::vector<RotatingWaveBranch> branches =
        ComputeRotatingWaveBranches(TwoPointStructure(p), params.friction_law.kind, branch_options);
    row.branches = static_cast<int>(branches.size());
    for (std::size_t b = 0; b < branches.size(); ++b) {
      const Branch& branch = branches[b].branch;
      if (IsFailure(branch.status)) {
        row.failures.push_back(fmt::format("{} = {:g}: {} ended: {}", ToString(options.parameter),
                                           eta, branches[b].name, branch.message));
      }
      const std::string pattern = PatternName(branches[b].normals);
      auto where = std::find_if(row.pattern_counts.begin(), row.pattern_counts.end(),
                                [&](const auto& entry) { return entry.first == pattern; });
      if (where == row.pattern_counts.end()) {
        row.pattern_counts.emplace_back(pattern, std::vector<int>(static_cast<size_t>(k), 0));
        where = row.pattern_counts.end() - 1;
      }
      std::vector<int>& pattern_count = where->second;
      for (const auto& [lo, hi] : StableIntervals(branch)) {
        for (Index j = 0; j < k; ++j) {
          if (speeds(j) >= lo && speeds(j) < hi) {
            ++row.stable_count[static_cast<size_t>(j)];
            ++pattern_count[static_cast<size_t>(j)];
          }
        }
      }
      for (std::size_t s = 0; s < branch.special_points.size(); ++s) {
        const SpecialPoint& sp = branch.special_points[s];
        if (sp.type != SpecialPointType::kEvent && sp.type != SpecialPointType::kFold &&
            sp.type != SpecialPointType::kHopf && sp.type != SpecialPointType::kRealEigenvalueCrossing) {
          continue;
        }
        MapPoint point;
        point.eta = eta;
        point.speed = sp.lambda;
        point.precession_hz = branches[b].SpecialPrecessionHz(s);
        point.type = sp.type;
        point.label = sp.label;
        point.nonsmooth_fold = sp.nonsmooth_fold;
        point.branch = static_cast<int>(b);
        const std::size_t at = static_cast<std::size_t>(sp.index);
        if (at < branch.points.size()) point.stable_before = branch.points[at].StableFlag();
        if (at + 1 < branch.points.size()) point.stable_after = branch.points[at + 1].StableFlag();
        row.points.push_back(point);
      }
    }
  } catch (const std::invalid_argument& e) {
    row.failed = true;
    row.failures.push_back(fmt::format("{} = {:g}: {}", ToString(options.parameter), eta, e.what()));
  }
  return row;
}

}  // namespace

std::vector<MapGridRow> ComputeMapGrid(const TwoPointParams& params,
                                       const HysteresisMapOptions& options,
                                       const std::vector<Index>& indices,
                                       const MapProgress& progress) {
  Validate(options);
  Validate(params);
  for (Index i : indices) {
    if (i < 0 || i >= options.eta_points) {
      throw std::invalid_argument(
          fmt::format("ComputeMapGrid: index {} outside the grid of {}", i, options.eta_points));
    }
  }
  const RotatingWaveBranchOptions branch_options = MapBranchOptions(params, options);
  const Vector etas = GridEtas(options), speeds = GridSpeeds(options);
  std::vector<MapGridRow> rows(indices.size());
  std::mutex mutex;  // guards `done` and the progress callback
  int done = 0;
  ParallelFor(static_cast<int>(indices.size()), options.threads, [&](int j) {
    rows[static_cast<size_t>(j)] = ComputeGridRow(params, options, branch_options, etas, speeds, indices[static_cast<size_t>(j)]);
    std::lock_guard<std::mutex> lock(mutex);
    if (progress) progress("grid", ++done, static_cast<int>(indices.size()));
  });
  return rows;
}

HysteresisMap ComputeHysteresisMap(const TwoPointParams& params, const HysteresisMapOptions& options,
                                   const MapProgress& progress) {
  const SteadyClock::time_point grid_start = SteadyClock::now();
  std::vector<Index> all(static_cast<size_t>(std::max(options.eta_points, 0)));
  std::iota(all.begin(), all.end(), Index{0});
  std::vector<MapGridRow> rows = ComputeMapGrid(params, options, all, progress);
  return AssembleHysteresisMap(params, options, std::move(rows), SecondsSince(grid_start), progress);
}

HysteresisMap AssembleHysteresisMap(const TwoPointParams& params,
                                    const HysteresisMapOptions& options,
                                    std::vector<MapGridRow> rows, double grid_seconds,
                                    const MapProgress& progress) {
  Validate(options);
  Validate(params);
  HysteresisMap map;
  map.parameter = options.parameter;
  map.base_value = GetDesignParameter(params, options.parameter);
  if (!InPhysicalRange(options.parameter, map.base_value)) {
    throw std::invalid_argument(fmt::format("{} = {} in the scene: outside its physical range",
                                            ToString(options.parameter), map.base_value));
  }
  const FrictionLawKind law = params.friction_law.kind;
  const RotatingWaveBranchOptions branch_options = MapBranchOptions(params, options);
  const Index m = options.eta_points, k = options.speed_points;
  map.eta = GridEtas(options);
  map.speed = GridSpeeds(options);
  map.stable_count = Eigen::MatrixXi::Zero(m, k);

  // 1. The grid, row by row in η order (patterns, points and failures in the order met).
  std::sort(rows.begin(), rows.end(),
            [](const MapGridRow& a, const MapGridRow& b) { return a.index < b.index; });
  std::vector<bool> seen(static_cast<size_t>(m), false);
  for (const MapGridRow& row : rows) {
    if (row.index < 0 || row.index >= m || seen[static_cast<size_t>(row.index)] ||
        static_cast<Index>(row.stable_count.size()) != k) {
      throw std::invalid_argument(fmt::format(
          "AssembleHysteresisMap: row {} is outside the grid, repeated or not of {} speeds",
          row.index, k));
    }
    seen[static_cast<size_t>(row.index)] = true;
  }
  if (static_cast<Index>(rows.size()) != m) {
    throw std::invalid_argument(fmt::format("AssembleHysteresisMap: {} rows for a grid of {}",
                                            rows.size(), m));
  }
  for (const MapGridRow& row : rows) {
    const Index i = row.index;
    map.grid_branches += row.branches;
    for (const auto& [pattern, counts] : row.pattern_counts) {
      auto where = std::find(map.patterns.begin(), map.patterns.end(), pattern);
      if (where == map.patterns.end()) {
        map.patterns.push_back(pattern);
        map.pattern_counts.push_back(Eigen::MatrixXi::Zero(m, k));
        where = map.patterns.end() - 1;
      }
      Eigen::MatrixXi& count = map.pattern_counts[where - map.patterns.begin()];
      for (Index j = 0; j < k; ++j) count(i, j) = counts[static_cast<size_t>(j)];
    }
    for (Index j = 0; j < k; ++j) map.stable_count(i, j) = row.stable_count[static_cast<size_t>(j)];
    map.points.insert(map.points.end(), row.points.begin(), row.points.end());
    map.failures.insert(map.failures.end(), row.failures.begin(), row.failures.end());
  }
  for (const MapGridRow& row : rows) {
    if (!row.failed) continue;
    map.stable_count.row(row.index).setConstant(-1);
    for (Eigen::MatrixXi& c : map.pattern_counts) c.row(row.index).setConstant(-1);
  }
  map.grid_seconds = grid_seconds;
  if (!options.continue_curves) return map;
  if (map.base_value < options.eta_min || map.base_value > options.eta_max) {
    // The curves start from the branch set at the scene's own value.
    map.note = fmt::format(
        "no curves: the scene's {} = {:g} lies outside the range [{:g}, {:g}] they start from",
        ToString(options.parameter), map.base_value, options.eta_min, options.eta_max);
    return map;
  }

  // 2. Curves through the events and folds of the branch set at the base η.
  const SteadyClock::time_point curve_start = SteadyClock::now();
  const std::vector<RotatingWaveBranch> base = ComputeRotatingWaveBranches(
      TwoPointStructure(WithoutImbalance(params)), law, branch_options);
  RotatingWaveDesignProblem problem(params, options.parameter);
  ContinuationOptions curve_options;
  curve_options.bounds.lambda_min = options.eta_min;
  curve_options.bounds.lambda_max = options.eta_max;
  curve_options.bounds.max_steps = options.curve_max_steps;
  curve_options.step.max = options.curve_max_step;
  curve_options.step.initial = std::min(curve_options.step.initial, options.curve_max_step);
  curve_options.detect.branch_points = false;
  curve_options.detect.closed_branches = false;
  // Keep the inner speed ω inside the scene's range: the last state component of U = (u, ω).
  auto speed_box = [&](Index dimension) {
    curve_options.bounds.state_lower = Vector::Constant(dimension, -kInfinity);
    curve_options.bounds.state_upper = Vector::Constant(dimension, kInfinity);
    curve_options.bounds.state_lower(dimension - 1) = options.branches.search.speed_min;
    curve_options.bounds.state_upper(dimension - 1) = options.branches.search.speed_max;
  };
  // Events, folds and Hopf points start curves (see NoHopfCurve for the Hopf points that do not).
  const double tolerance = problem.StabilityTolerance();
  auto starts_curve = [&](const SpecialPoint& sp) {
    return sp.type == SpecialPointType::kEvent || sp.type == SpecialPointType::kFold ||
           (sp.type == SpecialPointType::kHopf && NoHopfCurve(sp, tolerance).empty());
  };
  int total = 0;
  std::vector<std::string> no_curve;
  for (std::size_t b = 0; b < base.size(); ++b) {
    for (const SpecialPoint& sp : base[b].branch.special_points) {
      if (starts_curve(sp)) ++total;
      if (sp.type != SpecialPointType::kHopf || starts_curve(sp)) continue;
      no_curve.push_back(fmt::format("{:.3f} rpm on branch{} ({})", RadPerSecondToRpm(sp.lambda),
                                     b + 1, NoHopfCurve(sp, tolerance)));
    }
  }
  if (!no_curve.empty()) {
    map.note = fmt::format("Hopf points without a curve: {}", fmt::join(no_curve, "; "));
  }
  int done = 0;
  for (std::size_t b = 0; b < base.size(); ++b) {
    const Branch& branch = base[b].branch;
    for (const SpecialPoint& sp : branch.special_points) {
      if (!starts_curve(sp)) continue;
      MapCurve curve;
      curve.name = "curve" + std::to_string(map.curves.size() + 1);
      curve.kind = sp.type == SpecialPointType::kEvent ? "event"
                   : sp.type == SpecialPointType::kFold ? "fold"
                                                        : "hopf";
      curve.label = sp.type == SpecialPointType::kEvent ? sp.label
                    : sp.type == SpecialPointType::kFold ? "fold"
                                                         : "Hopf";
      curve.piece = sp.piece;
      curve.branch = static_cast<int>(b);
      curve.pattern = PatternName(base[b].normals);
      curve.start_eta = map.base_value;
      curve.start_speed = sp.lambda;
      curve.start_nonsmooth_fold = sp.nonsmooth_fold;
      if (sp.type == SpecialPointType::kFold) {
        curve.fold_sense = branch.points[sp.index].lambda < sp.lambda ? +1 : -1;
      }
      try {
        problem.SetSecondParameter(map.base_value);
        PlaceAt(problem, branch, sp);
        speed_box(problem.Dimension() + 1);
        if (sp.type == SpecialPointType::kEvent) {
          const std::vector<std::string> names = problem.EventNames();
          const auto it = std::find(names.begin(), names.end(), sp.label);
          if (it != names.end()) {
            EventCurveProblem probe(problem, static_cast<int>(it - names.begin()), sp.u, sp.lambda);
            curve.partner_margins = probe.PartnerMargins();
          }
          curve.curve = ContinueEventCurve(problem, sp, curve_options);
          curve.extrema =
              LocateExtrema(problem, branch, sp, curve.curve, options.eta_min, options.eta_max);
        } else {
          // Folds and Hopf points: both ways from the base η, joined at the start.
          auto run_half = [&](int direction) {
            problem.SetSecondParameter(map.base_value);
            PlaceAt(problem, branch, sp);
            ContinuationOptions run = curve_options;
            run.direction = direction;
            return sp.type == SpecialPointType::kFold ? ContinueFoldCurve(problem, sp, run)
                                                      : ContinueHopfCurve(problem, sp, run);
          };
          const Branch backward = run_half(-1);
          const Branch forward = run_half(+1);
          curve.curve = backward.points.empty() ? forward
                        : forward.points.empty() ? backward
                                                 : JoinAtStart(backward, forward);
        }
        if (IsFailure(curve.curve.status)) {
          map.failures.push_back(fmt::format("{} ({} \"{}\" at {:.4f} rad/s): {}", curve.name,
                                             curve.kind, curve.label, sp.lambda, curve.curve.message));
        }
      } catch (const std::invalid_argument& e) {
        curve.curve.status = BranchStatus::kStartFailed;
        curve.curve.message = e.what();
        map.failures.push_back(fmt::format("{} ({} \"{}\"): {}", curve.name, curve.kind, curve.label,
                                           e.what()));
      }
      map.curves.push_back(std::move(curve));
      if (progress) progress("curves", ++done, total);
    }
  }
  map.curve_seconds = SecondsSince(curve_start);
  return map;
}

}  // namespace rubcont
