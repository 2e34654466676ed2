#include "solvers/scalar_root.h"

#include <cmath>
#include <stdexcept>
#include <utility>

#include <fmt/core.h>

namespace rubcont {

void Validate(const BracketedRootOptions& options) {
  if (options.max_evaluations < 1) {
    throw std::invalid_argument(fmt::format(
        "BracketedRootOptions.max_evaluations = {}: must be at least 1", options.max_evaluations));
  }
  if (!(options.x_tolerance > 0.0)) {
    throw std::invalid_argument(fmt::format(
        "BracketedRootOptions.x_tolerance = {}: must be positive", options.x_tolerance));
  }
}

const char* ToString(BracketedRootStatus status) {
  switch (status) {
    case BracketedRootStatus::kConverged: return "converged";
    case BracketedRootStatus::kMaxEvaluations: return "evaluation limit reached";
    case BracketedRootStatus::kEvaluationFailed: return "function could not be evaluated";
  }
  return "unknown";
}

BracketedRootResult IllinoisRoot(const FallibleScalarFunction& f, double a, double fa, double b,
                                 double fb, const BracketedRootOptions& options) {
  Validate(options);
  if (!(std::isfinite(a) && std::isfinite(b) && std::isfinite(fa) && std::isfinite(fb)) ||
      fa * fb > 0.0) {
    throw std::invalid_argument(fmt::format(
        "IllinoisRoot: f({}) = {} and f({}) = {} must be finite and of opposite signs", a, fa, b,
        fb));
  }
  if (a > b) {
    std::swap(a, b);
    std::swap(fa, fb);
  }
  BracketedRootResult result;
  // fa, fb are the working values (halved by the Illinois rule); true_fa, true_fb are f itself.
  double true_fa = fa;
  double true_fb = fb;
  auto finish = [&](BracketedRootStatus status) {
    result.status = status;
    result.lower = a;
    result.upper = b;
    result.f_lower = true_fa;
    result.f_upper = true_fb;
    if (std::abs(true_fa) <= std::abs(true_fb)) {
      result.x = a;
      result.fx = true_fa;
    } else {
      result.x = b;
      result.fx = true_fb;
    }
    return result;
  };
  if (fa == 0.0) {
    b = a;
    true_fb = true_fa;
    return finish(BracketedRootStatus::kConverged);
  }
  if (fb == 0.0) {
    a = b;
    true_fa = true_fb;
    return finish(BracketedRootStatus::kConverged);
  }
  // `side` remembers which end was retained last: −1 for a, +1 for b. Retaining the same end twice
  // halves its function value (the Illinois modification), which stops regula falsi from
  // converging one-sidedly.
  int side = 0;
  double previous_x = 0.5 * (a + b);
  while (b - a > options.x_tolerance) {
    if (result.evaluations >= options.max_evaluations) {
      return finish(BracketedRootStatus::kMaxEvaluations);
    }
    double x = b - fb * (b - a) / (fb - fa);
    // As in Brent's method: a trial within x_tolerance/2 of the last point moves to x_tolerance/2
    // from it, towards the far end. After a near-exact secant step (f linear, say) this closes the
    // bracket at once instead of shrinking the far end by repeated halvings.
    if (side != 0 && std::abs(x - previous_x) < 0.5 * options.x_tolerance) {
      const double toward = side == +1 ? b : a;  // the retained (far) end
      x = previous_x + std::copysign(0.5 * options.x_tolerance, toward - previous_x);
    }
    // Keep the trial strictly inside the bracket (round-off can push a secant step out).
    if (!(x > a && x < b)) x = 0.5 * (a + b);
    double fx = 0.0;
    ++result.evaluations;
    if (!f(x, fx) || !std::isfinite(fx)) {
      x = 0.5 * (a + b);
      ++result.evaluations;
      if (!f(x, fx) || !std::isfinite(fx)) return finish(BracketedRootStatus::kEvaluationFailed);
    }
    result.last_step = std::abs(x - previous_x);
    previous_x = x;
    if (fx == 0.0) {
      a = b = x;
      true_fa = true_fb = 0.0;
      return finish(BracketedRootStatus::kConverged);
    }
    if ((fx < 0.0) == (fa < 0.0)) {
      a = x;
      fa = true_fa = fx;
      if (side == +1) fb *= 0.5;
      side = +1;
    } else {
      b = x;
      fb = true_fb = fx;
      if (side == -1) fa *= 0.5;
      side = -1;
    }
  }
  return finish(BracketedRootStatus::kConverged);
}

}  // namespace rubcont
