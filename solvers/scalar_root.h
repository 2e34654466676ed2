// Bracketed scalar root finding: the Illinois variant of regula falsi (Dowell & Jarratt 1971).
// Superlinear (order ≈ 1.44) on smooth functions, and the bracket always shrinks from both sides,
// so the bracket width is an honest error bound. The continuation engine uses it to locate zeros
// of test functions along arclength, where each evaluation is a Newton solve that may fail.
#pragma once

#include <functional>

namespace rubcont {

struct BracketedRootOptions {
  int max_evaluations = 60;   // function evaluations before giving up (≥ 1)
  double x_tolerance = 1e-12; // converged when the bracket is at most this wide (> 0, units of x)
};

// Throws std::invalid_argument naming the field, the value and the rule.
void Validate(const BracketedRootOptions& options);

enum class BracketedRootStatus {
  kConverged,         // bracket width ≤ x_tolerance, or f vanished exactly
  kMaxEvaluations,    // evaluation budget spent; x is the best point so far
  kEvaluationFailed,  // f could not be evaluated at a trial point (and at the bracket midpoint)
};

const char* ToString(BracketedRootStatus status);

struct BracketedRootResult {
  BracketedRootStatus status = BracketedRootStatus::kMaxEvaluations;
  double x = 0.0;          // the bracket end with the smaller |f| (where f was evaluated)
  double fx = 0.0;         // f(x)
  double lower = 0.0;      // final bracket [lower, upper] (lower < upper), f changes sign in it
  double upper = 0.0;
  double f_lower = 0.0;    // f at the final bracket's ends: both small beside the first bracket's
  double f_upper = 0.0;    // values at a zero, not at a jump or a pole of f
  double last_step = 0.0;  // |change of the trial point| in the last iteration
  int evaluations = 0;
  bool Converged() const { return status == BracketedRootStatus::kConverged; }
};

// f(x, value) sets value = f(x) and returns true, or returns false when f cannot be evaluated at x.
using FallibleScalarFunction = std::function<bool(double x, double& value)>;

// Finds a zero of f in the bracket [a, b] given f(a) = fa and f(b) = fb of opposite signs (either
// may be zero). Throws std::invalid_argument when they do not bracket a sign change. When a trial
// point fails to evaluate, the bracket midpoint is tried once before giving up. A sign change
// through a jump or a pole also converges (the bracket closes on it); f_lower and f_upper tell it
// from a zero.
BracketedRootResult IllinoisRoot(const FallibleScalarFunction& f, double a, double fa, double b,
                                 double fb, const BracketedRootOptions& options = {});

}  // namespace rubcont
