#include "studies/identification.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/SVD>
#include <fmt/core.h>
#include <nlopt.hpp>

#include "models/rub_model.h"
#include "models/units.h"
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

Evaluation Evaluate(const TwoPointParams& params, const std::vector<IdentificationTarget>& targets,
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
  return Evaluate(*d->params, *d->targets, *d->parameters, Denormalize(*d->parameters, x), *d->options)
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

}  // namespace

const char* ToString(TargetQuantity quantity) {
  return quantity == TargetQuantity::kSpeedRpm ? "speed_rpm" : "precession_hz";
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
  std::vector<double> predicted(targets.size(), std::numeric_limits<double>::quiet_NaN());
  std::vector<RotatingWaveBranch> branches;
  try {
    branches = ComputeRotatingWaveBranches(TwoPointStructure(WithoutImbalance(params)),
                                           params.friction_law.kind, options);
  } catch (const std::invalid_argument&) {
    return predicted;  // e.g. parameters for which no start exists: every feature is missing
  }
  for (std::size_t i = 0; i < targets.size(); ++i) {
    const IdentificationTarget& t = targets[i];
    double best = std::numeric_limits<double>::infinity();
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
                              const IdentificationOptions& options) {
  Validate(targets, parameters, options);
  Validate(params);
  const SteadyClock::time_point start = SteadyClock::now();
  const unsigned d = static_cast<unsigned>(parameters.size());
  IdentificationResult result;
  ObjectiveData data{&params, &targets, &parameters, &options.branches};
  nlopt::srand(options.random_seed);

  // Global stage on the normalized box.
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
  if (result.global_nlopt_result < 0 && result.global_nlopt_result != nlopt::ROUNDOFF_LIMITED) {
    result.status = IdentificationStatus::kFailed;
    result.message = fmt::format("global stage failed: NLopt result {} ({})", result.global_nlopt_result, why);
    return result;
  }

  // Local stage from the global best.
  data.evaluations = 0;
  nlopt::opt local(d >= 2 ? nlopt::LN_BOBYQA : nlopt::LN_NELDERMEAD, d);
  local.set_lower_bounds(std::vector<double>(d, 0.0));
  local.set_upper_bounds(std::vector<double>(d, 1.0));
  local.set_min_objective(NormalizedObjective, &data);
  local.set_maxeval(options.local_evaluations);
  local.set_xtol_rel(options.local_xtol);
  local.set_initial_step(std::vector<double>(d, 0.02));
  result.local_nlopt_result = RunStage(local, x, f, why);
  result.local_evaluations = data.evaluations;
  if (result.local_nlopt_result < 0 && result.local_nlopt_result != nlopt::ROUNDOFF_LIMITED) {
    result.status = IdentificationStatus::kFailed;
    result.message = fmt::format("local stage failed: NLopt result {} ({})", result.local_nlopt_result, why);
    return result;
  }
  result.parameters = Denormalize(parameters, x);
  const Evaluation best = Evaluate(params, targets, parameters, result.parameters, options.branches);
  result.objective = best.objective;
  result.predicted = best.predicted;
  result.residuals = best.residuals;
  result.missing = best.missing;

  // Sensitivity: Jᵣ = ∂r/∂θ by central differences, clipped to the box.
  const Index m = static_cast<Index>(targets.size());
  Matrix Jr(m, d);
  result.objective_rise.assign(d, 0.0);
  for (unsigned k = 0; k < d; ++k) {
    const double h = options.sensitivity_step * (parameters[k].upper - parameters[k].lower);
    std::vector<double> plus = result.parameters, minus = result.parameters;
    plus[k] = std::min(plus[k] + h, parameters[k].upper);
    minus[k] = std::max(minus[k] - h, parameters[k].lower);
    const Evaluation ep = Evaluate(params, targets, parameters, plus, options.branches);
    const Evaluation em = Evaluate(params, targets, parameters, minus, options.branches);
    for (Index i = 0; i < m; ++i) Jr(i, k) = (ep.residuals[i] - em.residuals[i]) / (plus[k] - minus[k]);
    std::vector<double> up = result.parameters, down = result.parameters;
    up[k] *= 1.01;
    down[k] *= 0.99;
    double rise = 0.0;
    for (const auto& theta : {up, down}) {
      if (theta[k] < parameters[k].lower || theta[k] > parameters[k].upper ||
          !InPhysicalRange(parameters[k].parameter, theta[k])) {
        continue;
      }
      rise = std::max(rise, Evaluate(params, targets, parameters, theta, options.branches).objective -
                                result.objective);
    }
    result.objective_rise[k] = rise;
  }
  const Eigen::JacobiSVD<Matrix> svd(Jr, Eigen::ComputeFullV);
  const Vector sigma = svd.singularValues();
  const bool singular = sigma.size() < d || sigma(sigma.size() - 1) <= 1e-12 * std::max(sigma(0), 1e-300);
  result.standard_deviation.assign(d, std::numeric_limits<double>::infinity());
  result.correlation.assign(d, std::vector<double>(d, std::numeric_limits<double>::quiet_NaN()));
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
