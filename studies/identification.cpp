#include "studies/identification.h"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <limits>
#include <numeric>
#include <optional>
#include <random>
#include <stdexcept>

#include <Eigen/SVD>
#include <fmt/core.h>
#include <nlopt.hpp>

#include "models/rub_model.h"
#include "models/units.h"
#include "solvers/parallel.h"
#include "solvers/stopwatch.h"

namespace rubcont {

namespace {

TwoPointParams Apply(TwoPointParams params, const std::vector<FitParameter>& parameters,
                     const std::vector<double>& theta) {
  for (std::size_t k = 0; k < parameters.size(); ++k) {
    params = WithDesignParameter(params, parameters[k].parameter, theta[k]);
  }
  return params;
}

struct Evaluation {
  std::vector<double> predicted;
  std::vector<double> residuals;
  std::vector<bool> missing;
  double objective = 0.0;
};

Evaluation EvaluateTargets(const TwoPointParams& params, const std::vector<IdentificationTarget>& targets,
                           const std::vector<FitParameter>& parameters, const std::vector<double>& theta,
                           const RotatingWaveBranchOptions& options) {
  Evaluation e;
  e.predicted = PredictTargets(Apply(params, parameters, theta), targets, options);
  for (std::size_t i = 0; i < targets.size(); ++i) {
    const bool missing = !std::isfinite(e.predicted[i]);
    const double r = missing ? kMissingResidual : (e.predicted[i] - targets[i].value) / targets[i].scale;
    e.missing.push_back(missing);
    e.residuals.push_back(r);
    e.objective += r * r;
  }
  return e;
}

// The objective on the normalized box x ∈ [0, 1]ᵈ, counting evaluations.
struct ObjectiveData {
  const TwoPointParams* params;
  const std::vector<IdentificationTarget>* targets;
  const std::vector<FitParameter>* parameters;
  const RotatingWaveBranchOptions* options;
  int evaluations = 0;
};

std::vector<double> Denormalize(const std::vector<FitParameter>& parameters, const std::vector<double>& x) {
  std::vector<double> theta(x.size());
  for (std::size_t k = 0; k < x.size(); ++k) {
    const double xk = std::clamp(x[k], 0.0, 1.0);
    theta[k] = parameters[k].lower + xk * (parameters[k].upper - parameters[k].lower);
  }
  return theta;
}

double NormalizedObjective(const std::vector<double>& x, std::vector<double>& /*grad*/, void* data) {
  auto* d = static_cast<ObjectiveData*>(data);
  ++d->evaluations;
  return EvaluateTargets(*d->params, *d->targets, *d->parameters, Denormalize(*d->parameters, x), *d->options)
      .objective;
}

// Runs one NLopt stage; returns the result code (negative: failure, with `why`).
int RunStage(nlopt::opt& opt, std::vector<double>& x, double& f, std::string& why) {
  try {
    return static_cast<int>(opt.optimize(x, f));
  } catch (const nlopt::roundoff_limited&) {
    f = opt.last_optimum_value();
    return static_cast<int>(nlopt::ROUNDOFF_LIMITED);
  } catch (const std::exception& e) {
    why = e.what();
    return static_cast<int>(nlopt::FAILURE);
  }
}

// A local refinement (LN_BOBYQA; Nelder–Mead in one dimension) from x on the normalized box.
struct LocalRun {
  std::vector<double> x;
  double f = 0.0;
  int evaluations = 0;
  int code = 0;      // nlopt::result
  std::string why;   // the exception's text where NLopt failed
};

LocalRun Refine(ObjectiveData data, std::vector<double> x, const IdentificationOptions& options) {
  const unsigned d = static_cast<unsigned>(x.size());
  data.evaluations = 0;
  nlopt::opt local(d >= 2 ? nlopt::LN_BOBYQA : nlopt::LN_NELDERMEAD, d);
  local.set_lower_bounds(std::vector<double>(d, 0.0));
  local.set_upper_bounds(std::vector<double>(d, 1.0));
  local.set_min_objective(NormalizedObjective, &data);
  local.set_maxeval(options.local_evaluations);
  local.set_xtol_rel(options.local_xtol);
  local.set_initial_step(std::vector<double>(d, 0.02));
  LocalRun run;
  run.code = RunStage(local, x, run.f, run.why);
  run.x = std::move(x);
  run.evaluations = data.evaluations;
  return run;
}

// A LocalRun through a batch: {f, evaluations, code, x...}.
std::vector<double> Encode(const LocalRun& run) {
  std::vector<double> v{run.f, static_cast<double>(run.evaluations), static_cast<double>(run.code)};
  v.insert(v.end(), run.x.begin(), run.x.end());
  return v;
}
LocalRun DecodeLocalRun(const std::vector<double>& v) {
  LocalRun run;
  run.f = v.at(0);
  run.evaluations = static_cast<int>(v.at(1));
  run.code = static_cast<int>(v.at(2));
  run.x.assign(v.begin() + 3, v.end());
  return run;
}

bool StageFailed(int code) { return code < 0 && code != nlopt::ROUNDOFF_LIMITED; }

std::vector<std::vector<double>> RunBatch(const BatchRunner& batches, int n,
                                          const std::function<std::vector<double>(int)>& job) {
  return (batches ? batches : ThreadBatchRunner(1))(n, job);
}

// The radical inverse of i in base b: coordinate b of the Halton sequence.
double RadicalInverse(unsigned i, unsigned base) {
  double digit = 1.0, value = 0.0;
  for (; i > 0; i /= base) {
    digit /= base;
    value += digit * (i % base);
  }
  return value;
}

// n points of the Halton sequence in [0, 1)ᵈ from index 1, every coordinate shifted by one random
// amount modulo 1 (Cranley–Patterson rotation, from `seed`): still evenly spread, but different
// designs for different seeds.
std::vector<std::vector<double>> HaltonPopulation(int n, unsigned d, unsigned seed) {
  static constexpr unsigned kPrimes[] = {2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37};
  if (d > std::size(kPrimes)) {  // more than the design parameters there are, each fitted once
    throw std::logic_error(fmt::format("HaltonPopulation: {} dimensions, at most {}", d, std::size(kPrimes)));
  }
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<double> shift(d);
  for (double& s : shift) s = uniform(random);
  std::vector<std::vector<double>> points(static_cast<size_t>(n), std::vector<double>(d));
  for (int i = 0; i < n; ++i) {
    for (unsigned k = 0; k < d; ++k) {
      const double u = RadicalInverse(static_cast<unsigned>(i + 1), kPrimes[k]) + shift[k];
      points[static_cast<size_t>(i)][k] = u - std::floor(u);
    }
  }
  return points;
}

// The indices of the `count` best points (lowest objective, ties by index) that lie at least
// `apart` from each other in the maximum norm.
std::vector<size_t> BestApart(const std::vector<std::vector<double>>& points,
                              const std::vector<double>& objective, int count, double apart) {
  std::vector<size_t> order(points.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return objective[a] < objective[b]; });
  std::vector<size_t> chosen;
  for (size_t i : order) {
    if (static_cast<int>(chosen.size()) == count) break;
    const bool far = std::all_of(chosen.begin(), chosen.end(), [&](size_t j) {
      double distance = 0.0;
      for (size_t k = 0; k < points[i].size(); ++k) {
        distance = std::max(distance, std::abs(points[i][k] - points[j][k]));
      }
      return distance >= apart;
    });
    if (far) chosen.push_back(i);
  }
  return chosen;
}

}  // namespace

const char* ToString(TargetQuantity quantity) {
  return quantity == TargetQuantity::kSpeedRpm ? "speed_rpm" : "precession_hz";
}

const char* ToString(GlobalMethod method) {
  switch (method) {
    case GlobalMethod::kDirectL: return "direct_l";
    case GlobalMethod::kCrs2: return "crs2";
    case GlobalMethod::kMultiStart: return "multistart";
  }
  return "?";
}

BatchRunner ThreadBatchRunner(int threads) {
  return [threads](int n, const std::function<std::vector<double>(int)>& job) {
    std::vector<std::vector<double>> results(static_cast<size_t>(n));
    ParallelFor(n, threads, [&](int i) { results[static_cast<size_t>(i)] = job(i); });
    return results;
  };
}

std::string IdentificationTarget::Name() const {
  return pattern + " " + event_label + " " + ToString(quantity);
}

const char* ToString(IdentificationStatus status) {
  switch (status) {
    case IdentificationStatus::kFitted: return "fitted";
    case IdentificationStatus::kTargetsNotReproduced: return "targets not reproduced";
    case IdentificationStatus::kFeatureMissing: return "feature missing";
    case IdentificationStatus::kFailed: return "failed";
  }
  return "?";
}

void Validate(const std::vector<IdentificationTarget>& targets,
              const std::vector<FitParameter>& parameters, const IdentificationOptions& options) {
  if (targets.empty()) throw std::invalid_argument("Identify: targets is empty: give at least one");
  if (parameters.empty()) {
    throw std::invalid_argument("Identify: parameters is empty: give at least one to fit");
  }
  const std::vector<std::string> patterns{"mode1", "mode2", "left_only", "right_only", "single"};
  for (std::size_t i = 0; i < targets.size(); ++i) {
    const IdentificationTarget& t = targets[i];
    if (std::find(patterns.begin(), patterns.end(), t.pattern) == patterns.end()) {
      throw std::invalid_argument(fmt::format(
          "targets[{}].pattern = \"{}\": must be mode1, mode2, left_only, right_only or single", i,
          t.pattern));
    }
    if (t.event_label.empty()) {
      throw std::invalid_argument(fmt::format("targets[{}].event_label is empty: name the event", i));
    }
    if (!std::isfinite(t.value) || (t.quantity == TargetQuantity::kSpeedRpm && t.value <= 0.0)) {
      throw std::invalid_argument(
          fmt::format("targets[{}].value = {}: must be finite and positive", i, t.value));
    }
    if (!(t.scale > 0.0 && std::isfinite(t.scale))) {
      throw std::invalid_argument(
          fmt::format("targets[{}].scale = {}: must be finite and positive", i, t.scale));
    }
  }
  for (std::size_t k = 0; k < parameters.size(); ++k) {
    const FitParameter& p = parameters[k];
    const char* name = ToString(p.parameter);
    if (!InPhysicalRange(p.parameter, p.lower)) {
      throw std::invalid_argument(fmt::format(
          "parameters[{}] ({}).lower = {}: must lie in the physical range ({} {} {})", k, name,
          p.lower, LowerLimitIncluded(p.parameter) ? "≥" : ">", LowerLimit(p.parameter),
          UnitOf(p.parameter)));
    }
    if (!(std::isfinite(p.upper) && p.upper > p.lower)) {
      throw std::invalid_argument(fmt::format(
          "parameters[{}] ({}).upper = {}: must be finite and exceed lower = {}", k, name, p.upper,
          p.lower));
    }
    for (std::size_t j = 0; j < k; ++j) {
      if (parameters[j].parameter == p.parameter) {
        throw std::invalid_argument(
            fmt::format("parameters[{}] = {}: already fitted as parameters[{}]", k, name, j));
      }
    }
  }
  if (options.global_evaluations < 1) {
    throw std::invalid_argument(fmt::format(
        "IdentificationOptions.global_evaluations = {}: must be at least 1", options.global_evaluations));
  }
  if (options.local_evaluations < 1) {
    throw std::invalid_argument(fmt::format(
        "IdentificationOptions.local_evaluations = {}: must be at least 1", options.local_evaluations));
  }
  if (options.local_starts < 1) {
    throw std::invalid_argument(fmt::format(
        "IdentificationOptions.local_starts = {}: must be at least 1", options.local_starts));
  }
  if (!(options.local_xtol > 0.0)) {
    throw std::invalid_argument(
        fmt::format("IdentificationOptions.local_xtol = {}: must be positive", options.local_xtol));
  }
  if (!(options.residual_tolerance > 0.0)) {
    throw std::invalid_argument(fmt::format(
        "IdentificationOptions.residual_tolerance = {}: must be positive", options.residual_tolerance));
  }
  if (!(options.sensitivity_step > 0.0 && options.sensitivity_step < 0.5)) {
    throw std::invalid_argument(fmt::format(
        "IdentificationOptions.sensitivity_step = {}: must be in (0, 0.5)", options.sensitivity_step));
  }
  Validate(options.branches.search);
}

std::vector<double> PredictTargets(const TwoPointParams& params,
                                   const std::vector<IdentificationTarget>& targets,
                                   const RotatingWaveBranchOptions& options) {
  std::vector<double> predicted(targets.size(), kNaN);
  std::vector<RotatingWaveBranch> branches;
  try {
    branches = ComputeRotatingWaveBranches(TwoPointStructure(WithoutImbalance(params)),
                                           params.friction_law.kind, options);
  } catch (const std::invalid_argument&) {
    return predicted;  // e.g. parameters for which no start exists: every feature is missing
  }
  for (std::size_t i = 0; i < targets.size(); ++i) {
    const IdentificationTarget& t = targets[i];
    double best = kInfinity;
    for (const RotatingWaveBranch& b : branches) {
      if (PatternName(b.normals) != t.pattern) continue;
      for (std::size_t s = 0; s < b.branch.special_points.size(); ++s) {
        const SpecialPoint& p = b.branch.special_points[s];
        if (p.type != SpecialPointType::kEvent && p.type != SpecialPointType::kTestFunction) continue;
        if (!p.converged || p.label.find(t.event_label) == std::string::npos) continue;
        const double value = t.quantity == TargetQuantity::kSpeedRpm
                                 ? RadPerSecondToRpm(p.lambda)
                                 : b.SpecialPrecessionHz(s);
        if (std::abs(value - t.value) < best) {
          best = std::abs(value - t.value);
          predicted[i] = value;
        }
      }
    }
  }
  return predicted;
}

IdentificationResult Identify(const TwoPointParams& params,
                              const std::vector<IdentificationTarget>& targets,
                              const std::vector<FitParameter>& parameters,
                              const IdentificationOptions& options, const BatchRunner& batches,
                              const std::function<void(const std::string&)>& progress) {
  Validate(targets, parameters, options);
  Validate(params);
  const SteadyClock::time_point start = SteadyClock::now();
  const unsigned d = static_cast<unsigned>(parameters.size());
  IdentificationResult result;
  ObjectiveData data{&params, &targets, &parameters, &options.branches};
  auto report = [&](const std::string& line) {
    if (progress) progress(line);
  };

  // Global stage on the normalized box, then the local refinement(s).
  std::vector<LocalRun> runs;
  if (options.global == GlobalMethod::kMultiStart) {
    const std::vector<std::vector<double>> population =
        HaltonPopulation(options.global_evaluations, d, options.random_seed);
    const std::vector<std::vector<double>> values = RunBatch(
        batches, options.global_evaluations, [&](int i) {
          std::vector<double> grad;
          ObjectiveData mine = data;
          return std::vector<double>{NormalizedObjective(population[static_cast<size_t>(i)], grad, &mine)};
        });
    std::vector<double> objective;
    for (const std::vector<double>& v : values) objective.push_back(v.at(0));
    const std::vector<size_t> starts = BestApart(population, objective, options.local_starts, 0.1);
    result.global_evaluations = options.global_evaluations;
    result.global_parameters = Denormalize(parameters, population[starts.front()]);
    result.global_objective = objective[starts.front()];
    report(fmt::format("population of {} evaluated: best J = {:.4g}; {} local refinements",
                       options.global_evaluations, result.global_objective, starts.size()));
    for (const std::vector<double>& v :
         RunBatch(batches, static_cast<int>(starts.size()), [&](int j) {
           return Encode(Refine(data, population[starts[static_cast<size_t>(j)]], options));
         })) {
      runs.push_back(DecodeLocalRun(v));
    }
  } else {
    nlopt::srand(options.random_seed);
    nlopt::opt global(options.global == GlobalMethod::kDirectL ? nlopt::GN_DIRECT_L : nlopt::GN_CRS2_LM, d);
    global.set_lower_bounds(std::vector<double>(d, 0.0));
    global.set_upper_bounds(std::vector<double>(d, 1.0));
    global.set_min_objective(NormalizedObjective, &data);
    global.set_maxeval(options.global_evaluations);
    std::vector<double> x(d, 0.5);
    double f = 0.0;
    std::string why;
    result.global_nlopt_result = RunStage(global, x, f, why);
    result.global_evaluations = data.evaluations;
    result.global_parameters = Denormalize(parameters, x);
    result.global_objective = f;
    if (StageFailed(result.global_nlopt_result)) {
      result.status = IdentificationStatus::kFailed;
      result.message = fmt::format("global stage failed: NLopt result {} ({})", result.global_nlopt_result, why);
      return result;
    }
    report(fmt::format("global stage ({}): {} evaluations, best J = {:.4g}", ToString(options.global),
                       result.global_evaluations, f));
    runs.push_back(Refine(data, x, options));
  }
  const LocalRun* best_run = nullptr;
  for (const LocalRun& run : runs) {
    result.local_evaluations += run.evaluations;
    if (!StageFailed(run.code) && (!best_run || run.f < best_run->f)) best_run = &run;
  }
  result.local_runs = static_cast<int>(runs.size());
  if (!best_run) {
    result.local_nlopt_result = runs.front().code;
    result.status = IdentificationStatus::kFailed;
    result.message = fmt::format("local stage failed: NLopt result {} ({})", runs.front().code,
                                 runs.front().why.empty() ? "in every refinement" : runs.front().why);
    return result;
  }
  result.local_nlopt_result = best_run->code;
  result.parameters = Denormalize(parameters, best_run->x);
  const Evaluation best = EvaluateTargets(params, targets, parameters, result.parameters, options.branches);
  result.objective = best.objective;
  result.predicted = best.predicted;
  result.residuals = best.residuals;
  result.missing = best.missing;
  report(fmt::format("local stage: {} evaluations in {} refinement(s), J = {:.4g}",
                     result.local_evaluations, result.local_runs, result.objective));

  // Sensitivity: Jᵣ = ∂r/∂θ by central differences, clipped to the box, and the rise of J for
  // ±1 % of each parameter (skipped where that leaves the box): 4 evaluations per parameter, as
  // one batch. Job 4k + s: s = 0, 1 the difference points, s = 2, 3 the ±1 % points.
  auto shifted = [&](unsigned k, int s) -> std::optional<std::vector<double>> {
    std::vector<double> theta = result.parameters;
    const double h = options.sensitivity_step * (parameters[k].upper - parameters[k].lower);
    switch (s) {
      case 0: theta[k] = std::min(theta[k] + h, parameters[k].upper); return theta;
      case 1: theta[k] = std::max(theta[k] - h, parameters[k].lower); return theta;
      default: theta[k] *= s == 2 ? 1.01 : 0.99;
    }
    if (theta[k] < parameters[k].lower || theta[k] > parameters[k].upper ||
        !InPhysicalRange(parameters[k].parameter, theta[k])) {
      return std::nullopt;
    }
    return theta;
  };
  const std::vector<std::vector<double>> around =
      RunBatch(batches, static_cast<int>(4 * d), [&](int job) {
        const std::optional<std::vector<double>> theta = shifted(static_cast<unsigned>(job / 4), job % 4);
        if (!theta) return std::vector<double>{};
        const Evaluation e = EvaluateTargets(params, targets, parameters, *theta, options.branches);
        std::vector<double> v = e.residuals;
        v.push_back(e.objective);
        return v;
      });
  const Index m = static_cast<Index>(targets.size());
  Matrix Jr(m, d);
  result.objective_rise.assign(d, 0.0);
  for (unsigned k = 0; k < d; ++k) {
    const std::vector<double>& ep = around[4 * k];
    const std::vector<double>& em = around[4 * k + 1];
    const double width = (*shifted(k, 0))[k] - (*shifted(k, 1))[k];
    for (Index i = 0; i < m; ++i) Jr(i, k) = (ep[static_cast<size_t>(i)] - em[static_cast<size_t>(i)]) / width;
    for (int s : {2, 3}) {
      const std::vector<double>& e = around[4 * k + static_cast<unsigned>(s)];
      if (!e.empty()) result.objective_rise[k] = std::max(result.objective_rise[k], e.back() - result.objective);
    }
  }
  const Eigen::JacobiSVD<Matrix> svd(Jr, Eigen::ComputeFullV);
  const Vector sigma = svd.singularValues();
  const bool singular = sigma.size() < d || sigma(sigma.size() - 1) <= 1e-12 * std::max(sigma(0), 1e-300);
  result.standard_deviation.assign(d, kInfinity);
  result.correlation.assign(d, std::vector<double>(d, kNaN));
  if (!singular) {
    const Matrix& V = svd.matrixV();
    const Matrix covariance = V * sigma.array().square().inverse().matrix().asDiagonal() * V.transpose();
    for (unsigned k = 0; k < d; ++k) result.standard_deviation[k] = std::sqrt(covariance(k, k));
    for (unsigned k = 0; k < d; ++k) {
      for (unsigned j = 0; j < d; ++j) {
        result.correlation[k][j] = covariance(k, j) / std::sqrt(covariance(k, k) * covariance(j, j));
      }
    }
  }
  result.seconds = SecondsSince(start);

  double worst = 0.0;
  std::size_t worst_index = 0;
  std::vector<std::string> missing_names;
  for (std::size_t i = 0; i < targets.size(); ++i) {
    if (result.missing[i]) missing_names.push_back(targets[i].Name());
    if (std::abs(result.residuals[i]) > worst) {
      worst = std::abs(result.residuals[i]);
      worst_index = i;
    }
  }
  if (!missing_names.empty()) {
    result.status = IdentificationStatus::kFeatureMissing;
    result.message = fmt::format(
        "at the best parameters found the model has no event for {} target(s) (first: {}): the "
        "feature does not exist in the box", missing_names.size(), missing_names.front());
  } else if (worst > options.residual_tolerance) {
    result.status = IdentificationStatus::kTargetsNotReproduced;
    result.message = fmt::format(
        "no parameters in the box reproduce the targets: the best fit (J = {:.4g}) leaves {} at "
        "{:.4g} against the target {:.4g} (residual {:.3g} scales > {:g})",
        result.objective, targets[worst_index].Name(), result.predicted[worst_index],
        targets[worst_index].value, result.residuals[worst_index], options.residual_tolerance);
  } else {
    result.status = IdentificationStatus::kFitted;
    result.message = fmt::format(
        "fitted in {} + {} evaluations ({:.1f} s): J = {:.3g}, largest |residual| {:.3g} scales",
        result.global_evaluations, result.local_evaluations, result.seconds, result.objective, worst);
  }
  return result;
}

}  // namespace rubcont
