#include "continuation/branch_switching.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <fmt/core.h>

#include "continuation/scaled_system.h"
#include "solvers/finite_difference.h"
#include "solvers/linear_algebra.h"

namespace rubcont {

namespace {

// Smallest singular value of DF̂ relative to ‖DF̂‖ below which the kernel is taken as 2-D.
constexpr double kKernelTolerance = 1e-6;

}  // namespace

BranchSwitch ComputeBranchSwitch(Problem& problem, const SpecialPoint& branch_point) {
  BranchSwitch result;
  ScaledSystem system(problem);
  const Index n = system.n();
  if (branch_point.u.size() != n) {
    throw std::invalid_argument(fmt::format(
        "ComputeBranchSwitch: the branch point has {} unknowns; Dimension() = {}",
        branch_point.u.size(), n));
  }
  Vector x;
  system.ToScaled(branch_point.u, branch_point.lambda, x);
  Matrix DF;
  if (!system.Jacobian(x, DF)) {
    result.message = "non-finite Jacobian at the branch point";
    return result;
  }
  const NullVectors null = SmallestSingularVectors(DF, 2);
  result.singular_value = null.singular_values(0);
  // A simple branch point has a two-dimensional kernel: the smallest singular value must vanish
  // to the precision of the location (about 1e-10 of ‖DF̂‖), not merely be small.
  const double norm = DF.norm();
  if (!(result.singular_value <= kKernelTolerance * norm)) {
    result.message = fmt::format(
        "not a branch point: the kernel of DF is one-dimensional (smallest singular value "
        "{:.3e}, ‖DF‖ = {:.3e})",
        result.singular_value, norm);
    return result;
  }
  const Vector psi = null.left.col(0);
  // Kernel basis: τ₁ = the incoming tangent projected onto span(right), φ ⊥ τ₁ in that span.
  const Matrix& K = null.right;
  Vector tau1;
  if (branch_point.tangent.size() == n + 1) {
    tau1 = K * (K.transpose() * branch_point.tangent);
  }
  if (tau1.size() == 0 || tau1.norm() < 1e-3) tau1 = K.col(0);
  tau1 /= tau1.norm();
  Vector phi = K.col(0) - tau1.dot(K.col(0)) * tau1;
  if (phi.norm() < 0.5) phi = K.col(1) - tau1.dot(K.col(1)) * tau1;
  phi /= phi.norm();

  // ψᵀ D²F̂(p, q) by central differences of DF̂ along q.
  const double h = CentralDifferenceStep(x.lpNorm<Eigen::Infinity>(), 1.0);
  auto second = [&](const Vector& p, const Vector& q) {
    Matrix DF_plus, DF_minus;
    system.Jacobian(x + h * q, DF_plus);
    system.Jacobian(x - h * q, DF_minus);
    return psi.dot((DF_plus - DF_minus) * p) / (2.0 * h);
  };
  result.a11 = second(tau1, tau1);
  result.a22 = second(phi, phi);
  result.a12 = 0.5 * (second(tau1, phi) + second(phi, tau1));
  if (!std::isfinite(result.a11 + result.a12 + result.a22)) {
    result.message = "non-finite second derivatives at the branch point";
    return result;
  }
  // Root directions of the quadratic form Q = [[a11, a12], [a12, a22]]: with eigenvalues
  // μ₁ < 0 < μ₂ and eigenvectors e₁, e₂, Q(d) = 0 for d = √μ₂ e₁ ± √(−μ₁) e₂.
  Eigen::Matrix2d Q;
  Q << result.a11, result.a12, result.a12, result.a22;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(Q);
  const double mu1 = eigen.eigenvalues()(0);
  const double mu2 = eigen.eigenvalues()(1);
  const double size = std::max(std::abs(mu1), std::abs(mu2));
  if (!(size > 0.0) || !(mu1 < -1e-8 * size && mu2 > 1e-8 * size)) {
    result.message = fmt::format(
        "not a simple branch point: the algebraic branching equation has no pair of real roots "
        "(a11 = {:.3e}, a12 = {:.3e}, a22 = {:.3e})",
        result.a11, result.a12, result.a22);
    return result;
  }
  const Eigen::Vector2d e1 = eigen.eigenvectors().col(0);
  const Eigen::Vector2d e2 = eigen.eigenvectors().col(1);
  const Eigen::Vector2d root_a = (std::sqrt(mu2) * e1 + std::sqrt(-mu1) * e2).normalized();
  const Eigen::Vector2d root_b = (std::sqrt(mu2) * e1 - std::sqrt(-mu1) * e2).normalized();
  // The incoming branch is the root closer to (1, 0); take the other.
  const Eigen::Vector2d other =
      std::abs(root_a(0)) <= std::abs(root_b(0)) ? root_a : root_b;
  const Eigen::Vector2d incoming =
      std::abs(root_a(0)) <= std::abs(root_b(0)) ? root_b : root_a;
  result.angle = std::acos(std::min(1.0, std::abs(other.dot(incoming))));
  Vector tangent = other(0) * tau1 + other(1) * phi;
  tangent /= tangent.norm();
  Index largest = 0;
  tangent.head(n).cwiseAbs().maxCoeff(&largest);
  const bool flip = std::abs(tangent(n)) > 1e-8 ? tangent(n) < 0.0 : tangent(largest) < 0.0;
  if (flip) tangent = -tangent;
  result.tangent = tangent;
  result.du = tangent.head(n).cwiseProduct(system.scale());
  result.dlambda = tangent(n) * system.lambda_scale();
  result.ok = true;
  return result;
}

Branch ContinueFromBranchPoint(Problem& problem, const SpecialPoint& branch_point, int side,
                               const ContinuationOptions& options, const StepCallback& callback) {
  if (branch_point.type != SpecialPointType::kBranchPoint) {
    throw std::invalid_argument(fmt::format(
        "ContinueFromBranchPoint: the special point is a {}, not a branch point",
        ToString(branch_point.type)));
  }
  Continuation continuation(problem, options);
  continuation.StartFromBranchPoint(branch_point, side);
  return RunToEnd(continuation, callback);
}

}  // namespace rubcont
