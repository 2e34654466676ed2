#include "continuation/options.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <fmt/core.h>

#include "solvers/constants.h"

namespace rubcont {

namespace {

[[noreturn]] void RejectOption(const std::string& field, double value, const std::string& rule) {
  throw std::invalid_argument(
      fmt::format("ContinuationOptions.{} = {}: {}", field, value, rule));
}

void RequirePositive(const std::string& field, double value) {
  if (!(value > 0.0) || !std::isfinite(value)) RejectOption(field, value, "must be positive and finite");
}

}  // namespace

void Validate(const CorrectorOptions& options) {
  if (options.max_iterations < 1) {
    RejectOption("corrector.max_iterations", options.max_iterations, "must be at least 1");
  }
  RequirePositive("corrector.residual_tolerance", options.residual_tolerance);
  RequirePositive("corrector.step_tolerance", options.step_tolerance);
  if (!(options.divergence_factor > 1.0)) {
    RejectOption("corrector.divergence_factor", options.divergence_factor, "must be greater than 1");
  }
  if (!(options.min_pivot_ratio >= 0.0 && options.min_pivot_ratio < 1.0)) {
    RejectOption("corrector.min_pivot_ratio", options.min_pivot_ratio, "must lie in [0, 1)");
  }
}

void Validate(const StepOptions& options) {
  RequirePositive("step.min", options.min);
  RequirePositive("step.max", options.max);
  if (!(options.max >= options.min)) {
    RejectOption("step.max", options.max, fmt::format("must be at least step.min = {}", options.min));
  }
  if (!(options.initial >= options.min && options.initial <= options.max)) {
    RejectOption("step.initial", options.initial,
                 fmt::format("must lie in [step.min, step.max] = [{}, {}]", options.min, options.max));
  }
  if (options.target_iterations < 1) {
    RejectOption("step.target_iterations", options.target_iterations, "must be at least 1");
  }
  if (!(options.max_growth >= 1.0) || !std::isfinite(options.max_growth)) {
    RejectOption("step.max_growth", options.max_growth, "must be finite and at least 1");
  }
  RequirePositive("step.target_angle", options.target_angle);
  if (options.failure_memory < 0) {
    RejectOption("step.failure_memory", options.failure_memory, "must be at least 0");
  }
  if (!(options.max_angle >= options.target_angle && options.max_angle < kPi)) {
    RejectOption("step.max_angle", options.max_angle,
                 fmt::format("must lie in [step.target_angle, π) = [{}, {})", options.target_angle, kPi));
  }
}

void Validate(const BoundsOptions& options) {
  if (std::isnan(options.lambda_min)) RejectOption("bounds.lambda_min", options.lambda_min, "is NaN");
  if (std::isnan(options.lambda_max)) RejectOption("bounds.lambda_max", options.lambda_max, "is NaN");
  if (!(options.lambda_max > options.lambda_min)) {
    RejectOption("bounds.lambda_max", options.lambda_max,
                 fmt::format("must be greater than bounds.lambda_min = {}", options.lambda_min));
  }
  const bool lower = options.state_lower.size() > 0;
  const bool upper = options.state_upper.size() > 0;
  if (lower && upper && options.state_lower.size() != options.state_upper.size()) {
    RejectOption("bounds.state_upper.size()", static_cast<double>(options.state_upper.size()),
                 fmt::format("must equal bounds.state_lower.size() = {}", options.state_lower.size()));
  }
  if (lower && upper) {
    for (Index i = 0; i < options.state_lower.size(); ++i) {
      if (!(options.state_upper(i) > options.state_lower(i))) {
        RejectOption(fmt::format("bounds.state_upper({})", i), options.state_upper(i),
                     fmt::format("must be greater than bounds.state_lower({}) = {}", i,
                                 options.state_lower(i)));
      }
    }
  }
  for (Index i = 0; i < options.state_lower.size(); ++i) {
    if (std::isnan(options.state_lower(i))) {
      RejectOption(fmt::format("bounds.state_lower({})", i), options.state_lower(i), "is NaN");
    }
  }
  for (Index i = 0; i < options.state_upper.size(); ++i) {
    if (std::isnan(options.state_upper(i))) {
      RejectOption(fmt::format("bounds.state_upper({})", i), options.state_upper(i), "is NaN");
    }
  }
  if (!(options.max_state_norm > 0.0)) {
    RejectOption("bounds.max_state_norm", options.max_state_norm, "must be positive");
  }
  if (options.max_steps < 1) RejectOption("bounds.max_steps", options.max_steps, "must be at least 1");
}

void Validate(const DetectionOptions& options) {
  if (!(options.imaginary_tolerance >= 0.0) || !std::isfinite(options.imaginary_tolerance)) {
    RejectOption("detect.imaginary_tolerance", options.imaginary_tolerance,
                 "must be finite and non-negative");
  }
}

void Validate(const LocationOptions& options) {
  if (options.max_iterations < 1) {
    RejectOption("location.max_iterations", options.max_iterations, "must be at least 1");
  }
  RequirePositive("location.residual_tolerance", options.residual_tolerance);
  RequirePositive("location.step_tolerance", options.step_tolerance);
  if (options.branch_point_newton_max_unknowns < 0) {
    RejectOption("location.branch_point_newton_max_unknowns", options.branch_point_newton_max_unknowns,
                 "must be non-negative");
  }
}

void Validate(const SwitchOptions& options) {
  RequirePositive("events.probe_step", options.probe_step);
}

void Validate(const ContinuationOptions& options) {
  if (options.direction != 1 && options.direction != -1) {
    RejectOption("direction", options.direction, "must be +1 or -1");
  }
  Validate(options.corrector);
  Validate(options.step);
  Validate(options.bounds);
  Validate(options.detect);
  Validate(options.location);
  Validate(options.events);
  RequirePositive("closure_tolerance", options.closure_tolerance);
}

}  // namespace rubcont
