#include "solvers/newton.h"

#include <cmath>
#include <stdexcept>

#include <fmt/core.h>

namespace rubcont {

void Validate(const NewtonOptions& options) {
  if (options.max_iterations < 1) {
    throw std::invalid_argument(fmt::format(
        "NewtonOptions.max_iterations = {}: must be at least 1", options.max_iterations));
  }
  if (!(options.step_tolerance > 0.0)) {
    throw std::invalid_argument(fmt::format(
        "NewtonOptions.step_tolerance = {}: must be positive", options.step_tolerance));
  }
  if (!(options.residual_tolerance > 0.0)) {
    throw std::invalid_argument(fmt::format(
        "NewtonOptions.residual_tolerance = {}: must be positive", options.residual_tolerance));
  }
  if (options.max_step_halvings < 0) {
    throw std::invalid_argument(fmt::format(
        "NewtonOptions.max_step_halvings = {}: must be ≥ 0", options.max_step_halvings));
  }
  if (!(options.divergence_factor > 1.0)) {
    throw std::invalid_argument(fmt::format(
        "NewtonOptions.divergence_factor = {}: must be greater than 1", options.divergence_factor));
  }
}

const char* ToString(NewtonStatus status) {
  switch (status) {
    case NewtonStatus::kConverged: return "converged";
    case NewtonStatus::kMaxIterations: return "iteration limit reached";
    case NewtonStatus::kSingularJacobian: return "singular Jacobian";
    case NewtonStatus::kDiverged: return "diverged";
    case NewtonStatus::kNonFinite: return "non-finite residual or Jacobian";
  }
  return "unknown";
}

std::string NewtonResult::BriefReport() const {
  return fmt::format("Newton: {} after {} iterations, |F| = {:.3e}, |dx| = {:.3e}",
                     ToString(status), iterations, residual_norm, step_norm);
}

NewtonResult NewtonSolve(const ResidualFunction& residual, const JacobianFunction& jacobian,
                         Vector& x, const NewtonOptions& options, const Vector& x_scale,
                         const Vector& F_scale) {
  Validate(options);
  const Index n = x.size();
  const Vector xs = x_scale.size() == 0 ? Vector::Ones(n) : x_scale;
  const Vector fs = F_scale.size() == 0 ? Vector::Ones(n) : F_scale;
  if (xs.size() != n || fs.size() != n) {
    throw std::invalid_argument(fmt::format(
        "NewtonSolve: x_scale has size {} and F_scale size {}; both must be empty or {}",
        xs.size(), fs.size(), n));
  }

  NewtonResult result;
  Vector F(n);
  Matrix J(n, n);
  residual(x, F);
  result.residual_norm = F.cwiseQuotient(fs).lpNorm<Eigen::Infinity>();
  const double initial_norm = result.residual_norm;
  if (!std::isfinite(result.residual_norm)) {
    result.status = NewtonStatus::kNonFinite;
    return result;
  }
  Eigen::PartialPivLU<Matrix> lu;
  for (int iteration = 1; iteration <= options.max_iterations; ++iteration) {
    jacobian(x, J);
    if (!J.allFinite()) {
      result.status = NewtonStatus::kNonFinite;
      return result;
    }
    // Solve in scaled variables: (diag(1/fs) J diag(xs)) Δx̂ = −F ./ fs, Δx = xs .* Δx̂.
    const Matrix scaled = fs.cwiseInverse().asDiagonal() * J * xs.asDiagonal();
    lu.compute(scaled);
    const double rcond = lu.rcond();
    if (!(rcond > 1e-14)) {
      result.status = NewtonStatus::kSingularJacobian;
      return result;
    }
    Vector step_scaled = lu.solve(-F.cwiseQuotient(fs));
    const Vector from = x;
    const double previous_norm = result.residual_norm;
    for (int halving = 0;; ++halving) {
      x = from + xs.cwiseProduct(step_scaled);
      residual(x, F);
      result.residual_norm = F.cwiseQuotient(fs).lpNorm<Eigen::Infinity>();
      if (halving == options.max_step_halvings ||
          (std::isfinite(result.residual_norm) && result.residual_norm <= previous_norm)) {
        break;
      }
      step_scaled *= 0.5;
    }
    result.iterations = iteration;
    result.step_norm = step_scaled.lpNorm<Eigen::Infinity>();
    if (!std::isfinite(result.residual_norm) || !std::isfinite(result.step_norm)) {
      result.status = NewtonStatus::kNonFinite;
      return result;
    }
    const bool at_floor = previous_norm <= options.residual_tolerance &&
                          result.residual_norm > 0.5 * previous_norm;
    if (result.residual_norm <= options.residual_tolerance &&
        (result.step_norm <= options.step_tolerance || at_floor)) {
      result.status = NewtonStatus::kConverged;
      return result;
    }
    if (result.residual_norm > options.divergence_factor * std::max(initial_norm, 1e-300)) {
      result.status = NewtonStatus::kDiverged;
      return result;
    }
  }
  result.status = NewtonStatus::kMaxIterations;
  return result;
}

}  // namespace rubcont
