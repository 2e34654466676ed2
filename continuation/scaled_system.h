// The engine's view of a Problem: scaled variables and the bordered Newton corrector.
//
// Scaling. With s = Scale(), s_λ = LambdaScale() and r = ResidualScale() the engine works in
//     x̂ = (û, λ̂) = (u ./ s, λ / s_λ) ∈ Rⁿ⁺¹,     F̂(x̂) = F(s .* û, s_λ λ̂) ./ r,
// so DF̂ = [diag(1/r) F_u diag(s),  F_λ s_λ ./ r]. Arclength, tangents, step lengths, turning
// angles, Newton corrections and residuals are all measured in these variables: a state whose
// entries are metres ~1e-4, newtons ~1e3 and rad/s ~1e2 is, to the engine, a vector of O(1)
// numbers, and a scaled step of 0.01 changes every unknown by about 1 % of its typical size.
// Without this, the largest unit dominates the arclength (the metres never move), the turning
// angle sees only the newtons, and an absolute Newton tolerance is either unattainable for the
// forces or meaningless for the metres.
#pragma once

#include <Eigen/LU>

#include "continuation/branch.h"
#include "continuation/options.h"
#include "continuation/problem.h"
#include "solvers/linear_algebra.h"
#include "solvers/types.h"

namespace rubcont {

class ScaledSystem {
 public:
  // `statistics` (optional) receives evaluation counts.
  explicit ScaledSystem(Problem& problem, BranchStatistics* statistics = nullptr);

  // Re-reads Dimension() and the scales (after SwitchAt may have changed the formulation).
  // Throws std::invalid_argument when a scale has the wrong size or a non-positive entry.
  void Refresh();

  Problem& problem() { return problem_; }
  Index n() const { return n_; }
  const Vector& scale() const { return scale_; }
  double lambda_scale() const { return lambda_scale_; }
  const Vector& residual_scale() const { return residual_scale_; }

  // x̂ (n + 1) from (u, λ) and back.
  void ToScaled(const Vector& u, double lambda, Vector& x) const;
  void ToUnscaled(const Vector& x, Vector& u, double& lambda) const;
  Vector StateOf(const Vector& x) const { return x.head(n_).cwiseProduct(scale_); }
  double LambdaOf(const Vector& x) const { return x(n_) * lambda_scale_; }
  // A direction (du, dλ) in scaled variables (not normalized).
  Vector ScaledDirection(const Vector& du, double dlambda) const;

  // F̂(x̂) into F (n). Returns false when it is not finite. Throws std::invalid_argument when the
  // problem returns the wrong number of equations.
  bool Residual(const Vector& x, Vector& F);
  // DF̂(x̂) = [F̂_û F̂_λ̂] into DF (n × (n + 1)). Returns false when it is not finite.
  bool Jacobian(const Vector& x, Matrix& DF);

 private:
  Problem& problem_;
  BranchStatistics* statistics_;
  Index n_ = 0;
  Vector scale_;
  Vector residual_scale_;
  Vector residual_inverse_;
  double lambda_scale_ = 1.0;
  // Workspace (sized by Refresh).
  Vector u_;
  Vector F_;
  Matrix J_;
  Vector dF_;
};

enum class CorrectorStatus {
  kConverged,
  kMaxIterations,  // iteration limit without meeting both tolerances
  kSingular,       // the bordered matrix is singular to working precision
  kDiverged,       // the residual grew by CorrectorOptions::divergence_factor
  kNonFinite,      // the problem returned NaN or Inf (e.g. a failed integration)
};

const char* ToString(CorrectorStatus status);

// A point on the branch with what the detectors need.
struct CorrectedPoint {
  Vector x;                // (û, λ̂)
  Vector tangent;          // unit null vector of DF̂, oriented so that borderᵀ tangent > 0
  LogDeterminant det;      // of [DF̂; borderᵀ] at the last Jacobian of the corrector
  int iterations = 0;      // LU factorizations
  double residual_norm = 0.0;  // ‖F̂‖∞ at x
  double step_norm = 0.0;      // last ‖Δx̂‖∞
};

// Newton on the bordered system  F̂(x̂) = 0,  bᵀ(x̂ − x̂_ref) = σ  (Keller's pseudo-arclength
// condition when b is the previous tangent), Jacobian [DF̂; bᵀ]. Converged when ‖F̂‖∞ ≤
// residual_tolerance after a correction with ‖Δx̂‖∞ ≤ step_tolerance (at least one iteration).
// The tangent at the solution is computed from the LU of the last iteration, whose Jacobian is at
// the previous iterate, within step_tolerance of the solution: [DF̂; bᵀ] z = e_{n+1}, τ = z/‖z‖.
// So a step costs no Jacobian beyond the Newton iterations, and τ is oriented continuously
// (bᵀτ > 0). The same LU gives the sign of det [DF̂; bᵀ], which has the sign of det [DF̂; τᵀ]
// because bᵀτ > 0 — the branch-point test function (Allgower & Georg, §8.1).
class BorderedCorrector {
 public:
  BorderedCorrector(ScaledSystem& system, const CorrectorOptions& options);

  // Resizes the workspace after ScaledSystem::Refresh.
  void Resize();

  // Solves from `guess` (n + 1). border: unit vector (n + 1). With `accept_singular_solution`, an
  // iterate that already solves the system to tolerance where the bordered matrix is singular (a
  // branch point hit exactly, as a secant on a linear test function does) is returned as
  // converged with det.sign = 0 and the border as its tangent; otherwise that is kSingular.
  CorrectorStatus Correct(const Vector& x_ref, const Vector& border, double sigma,
                          const Vector& guess, CorrectedPoint& out,
                          bool accept_singular_solution = false);

  // The tangent and det at x (no correction): factors [DF̂(x); borderᵀ]. Returns false when that
  // matrix is singular or not finite.
  bool TangentAt(const Vector& x, const Vector& border, Vector& tangent, LogDeterminant& det);

  ScaledSystem& system() { return system_; }
  const CorrectorOptions& options() const { return options_; }

 private:
  // Factors [DF_; borderᵀ] into lu_; false when singular.
  bool Factor(const Vector& border);
  void SolveTangent(Vector& tangent);

  ScaledSystem& system_;
  CorrectorOptions options_;
  Vector F_;
  Matrix DF_;
  Matrix A_;
  DenseLu lu_;
  Vector rhs_;
  Vector delta_;
};

}  // namespace rubcont
