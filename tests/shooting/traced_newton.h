// Newton on a shooting problem at fixed λ, recording the smallest scaled residual it reached: the
// tests of motions shooting cannot converge on (quasi-periodic in the frame it shoots in) assert
// that Newton fails and never came near a solution on the way.
#pragma once

#include <cmath>

#include "shooting/shooting.h"
#include "solvers/constants.h"
#include "solvers/newton.h"

namespace rubcont::testing {

struct TracedNewton {
  NewtonResult result;
  double smallest_residual = kInfinity;  // ‖F ./ ResidualScale()‖∞ over every evaluation
};

inline TracedNewton NewtonWithSmallestResidual(ShootingProblem& problem, Vector& u, double lambda,
                                               int max_iterations) {
  NewtonOptions options;
  options.max_iterations = max_iterations;
  TracedNewton traced;
  const Vector residual_scale = problem.ResidualScale();
  traced.result = NewtonSolve(
      [&](const Vector& v, Vector& F) {
        problem.Residual(v, lambda, F);
        const double norm = F.cwiseQuotient(residual_scale).lpNorm<Eigen::Infinity>();
        if (norm < traced.smallest_residual) traced.smallest_residual = norm;
      },
      [&](const Vector& v, Matrix& J) { problem.Jacobian(v, lambda, J); }, u, options,
      problem.Scale(), residual_scale);
  return traced;
}

}  // namespace rubcont::testing
