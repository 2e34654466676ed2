// Newton's method for F(x) = 0 with scaled convergence tests. Expected numerical outcomes
// (no convergence, singular Jacobian, non-finite residual) are returned as a status, never thrown.
#pragma once

#include <functional>
#include <string>

#include "solvers/types.h"

namespace rubcont {

struct NewtonOptions {
  int max_iterations = 12;            // Newton iterations before giving up (≥ 1)
  double step_tolerance = 1e-10;      // converged when ‖Δx ./ x_scale‖∞ ≤ this ...
  double residual_tolerance = 1e-9;   // ... and ‖F ./ F_scale‖∞ ≤ this (F_scale: see NewtonSolve),
                                      // or when the residual is below this and an iteration no
                                      // longer halves it (round-off floor of an ill-conditioned
                                      // system: further steps only move x by noise)
  double divergence_factor = 1e6;     // stop when the scaled residual grows by this factor
  // Where a full step's residual is non-finite or larger than the last iterate's, the step is
  // halved, up to this many times (≥ 0; 0: full steps always). For maps whose integration fails
  // off a stiff manifold (a torus circle refined in K: shooting/modulated_torus.h).
  int max_step_halvings = 0;
};

// Throws std::invalid_argument naming the field, the value and the rule.
void Validate(const NewtonOptions& options);

enum class NewtonStatus {
  kConverged,
  kMaxIterations,     // iteration limit reached without meeting both tolerances
  kSingularJacobian,  // LU pivot vanished: the Jacobian is not invertible at an iterate
  kDiverged,          // residual grew by divergence_factor over its initial value
  kNonFinite,         // residual or Jacobian produced NaN or Inf
};

const char* ToString(NewtonStatus status);

struct NewtonResult {
  NewtonStatus status = NewtonStatus::kMaxIterations;
  int iterations = 0;           // Jacobian factorizations performed
  double residual_norm = 0.0;   // final ‖F ./ F_scale‖∞
  double step_norm = 0.0;       // last ‖Δx ./ x_scale‖∞
  bool Converged() const { return status == NewtonStatus::kConverged; }
  std::string BriefReport() const;
};

// Residual(x, F) writes F (size n); Jacobian(x, J) writes J (n × n).
using ResidualFunction = std::function<void(const Vector& x, Vector& F)>;
using JacobianFunction = std::function<void(const Vector& x, Matrix& J)>;

// Solves F(x) = 0 from the initial guess x (overwritten with the last iterate). x_scale and
// F_scale (size n, entries > 0; empty means all ones) are the typical magnitudes of the unknowns
// and of the equations; both tests are made on the scaled quantities, so that metres ~1e-4 and
// newtons ~1e3 in one system are judged fairly.
NewtonResult NewtonSolve(const ResidualFunction& residual, const JacobianFunction& jacobian,
                         Vector& x, const NewtonOptions& options = {},
                         const Vector& x_scale = Vector(), const Vector& F_scale = Vector());

}  // namespace rubcont
