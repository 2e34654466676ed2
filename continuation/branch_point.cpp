#include "continuation/branch_point.h"

#include <algorithm>
#include <cmath>

#include <Eigen/LU>
#include <fmt/core.h>

#include "solvers/constants.h"
#include "solvers/finite_difference.h"
#include "solvers/linear_algebra.h"

namespace rubcont {

namespace {

// G(x, β, φ) = [F̂(x) + βφ; DF̂(x)ᵀφ; φᵀφ − 1] into G; DF̂(x) into DF. False if not finite.
bool Residual(ScaledSystem& system, const Vector& x, double beta, const Vector& phi, Vector& G,
              Vector& F, Matrix& DF) {
  const Index n = system.n();
  if (!system.Residual(x, F) || !system.Jacobian(x, DF)) return false;
  G.resize(2 * n + 2);
  G.head(n) = F + beta * phi;
  G.segment(n, n + 1) = DF.transpose() * phi;
  G(2 * n + 1) = phi.squaredNorm() - 1.0;
  return G.allFinite();
}

}  // namespace

BranchPointLocation LocateBranchPoint(ScaledSystem& system, const Vector& x_guess,
                                      const LocationOptions& options) {
  const Index n = system.n();
  BranchPointLocation result;
  Vector x = x_guess;
  Vector F(n), G;
  Matrix DF(n, n + 1), DF_plus(n, n + 1), DF_minus(n, n + 1);
  if (!system.Residual(x, F) || !system.Jacobian(x, DF)) {
    result.message = "the problem is not finite at the guess";
    result.x = x;
    return result;
  }
  Vector phi = SmallestSingularVectors(DF, 1).left.col(0);
  double beta = -phi.dot(F);

  const Index m = 2 * n + 2;
  Matrix J = Matrix::Zero(m, m);
  Eigen::PartialPivLU<Matrix> lu(m);
  double last_step = kInfinity;
  for (int iteration = 0;; ++iteration) {
    if (!Residual(system, x, beta, phi, G, F, DF)) {
      result.message = "non-finite residual";
      break;
    }
    // The null-vector rows DF̂ᵀφ are measured against the size of DF̂'s entries (their backward
    // error), the others as they are: with the stiff contact DF̂ has entries of 6e4 and those rows
    // stall at round-off, 1e-9 (case A(a), tanh law, the Mode 2 whirl's branch point at
    // 66.213 rpm: residual 9.7e-10 after a step of 6e-13).
    const double entries = std::max(1.0, DF.cwiseAbs().maxCoeff());
    result.residual_norm = std::max({G.head(n).lpNorm<Eigen::Infinity>(),
                                     G.segment(n, n + 1).lpNorm<Eigen::Infinity>() / entries,
                                     std::abs(G(2 * n + 1))});
    if (iteration > 0 && result.residual_norm <= options.residual_tolerance &&
        last_step <= options.step_tolerance) {
      result.converged = true;
      break;
    }
    if (iteration >= options.max_iterations) {
      result.message = fmt::format("no convergence in {} iterations (residual {:.3e}, step {:.3e})",
                                   iteration, result.residual_norm, last_step);
      break;
    }
    // Columns: x (n + 1), β (1), φ (n). Rows: F + βφ (n), DFᵀφ (n + 1), φᵀφ − 1 (1).
    J.setZero();
    J.block(0, 0, n, n + 1) = DF;
    J.block(0, n + 1, n, 1) = phi;
    J.block(0, n + 2, n, n) = beta * Matrix::Identity(n, n);
    bool finite = true;
    Vector xp = x;
    for (Index j = 0; j <= n && finite; ++j) {
      const double h = CentralDifferenceStep(x(j), 1.0);
      xp(j) = x(j) + h;
      finite = system.Jacobian(xp, DF_plus);
      xp(j) = x(j) - h;
      finite = finite && system.Jacobian(xp, DF_minus);
      xp(j) = x(j);
      J.block(n, j, n + 1, 1) = (DF_plus - DF_minus).transpose() * phi / (2.0 * h);
    }
    if (!finite) {
      result.message = "non-finite Jacobian near the point";
      break;
    }
    J.block(n, n + 2, n + 1, n) = DF.transpose();
    J.block(2 * n + 1, n + 2, 1, n) = 2.0 * phi.transpose();
    lu.compute(J);
    if (!(lu.rcond() > 1e-14)) {
      result.message = "singular branch-point system: not a simple branch point";
      break;
    }
    const Vector delta = lu.solve(-G);
    last_step = delta.lpNorm<Eigen::Infinity>();
    if (!std::isfinite(last_step)) {
      result.message = "non-finite Newton step";
      break;
    }
    x += delta.head(n + 1);
    beta += delta(n + 1);
    phi += delta.tail(n);
    result.iterations = iteration + 1;
    result.last_correction = last_step;
  }
  result.x = x;
  result.beta = beta;
  result.phi = phi;
  return result;
}

}  // namespace rubcont
