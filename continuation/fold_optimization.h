// Fold location as an optimization (Ipopt): a fold of a branch of F(u, λ) = 0 in λ is a local
// extremum of λ on the solution manifold, so it solves the equality-constrained NLP
//     min  −σ·λ̂   subject to  F̂(û, λ̂) = 0,          σ = +1 (largest λ) or −1 (smallest λ),
// in the engine's scaled variables (û = u ./ Scale(), λ̂ = λ / LambdaScale(), F̂ = F ./
// ResidualScale(); continuation/scaled_system.h). At a regular fold the constraint Jacobian
// [F̂_û F̂_λ̂] has full row rank (LICQ), its null space is the fold's null vector (v, 0), and the
// Lagrangian's curvature along it is the fold's quadratic coefficient wᵀD²F(v, v) ≠ 0, so the
// fold is a non-degenerate KKT point; the multipliers are the left null vector w scaled by
// 1 / (wᵀF̂_λ̂). This is an independent route to the minimally augmented system of
// continuation/fold.h: nothing is shared but F and its first derivatives.
//
// Derivatives: the constraint Jacobian is the problem's Jacobian and DfDlambda; the Lagrangian's
// Hessian Σ y_i ∇²F̂_i is the central difference of F̂'ᵀy (one Jacobian pair per unknown,
// symmetrized), or Ipopt's limited-memory quasi-Newton approximation.
//
// Ipopt 3.11 (MUMPS); its output is silenced. Expected numerical outcomes are statuses, never
// exceptions; the problem is left at its current second parameter.
#pragma once

#include <string>

#include "continuation/problem.h"
#include "solvers/constants.h"
#include "solvers/types.h"

namespace rubcont {

enum class FoldHessian {
  kFiniteDifference,  // central differences of the Jacobian (quadratic convergence near the fold)
  kLimitedMemory,     // Ipopt's L-BFGS approximation (no second derivatives; slower near the end)
};

struct FoldOptimizationOptions {
  int sense = +1;                    // +1: the fold where λ is locally largest; −1: smallest
  int max_iterations = 200;          // Ipopt max_iter (≥ 1)
  // Ipopt tol on the scaled KKT error (> 0). Its dual part has a round-off floor of about
  // ε_machine·‖F̂'‖·‖y‖ (~1e-9 for the rub model's rotating waves, whose contact stiffness makes
  // ‖F̂'‖ ~ 1e4), so it cannot be much smaller; it hardly matters for λ: a dual error ε moves the
  // point along the branch by O(ε) and λ by O(ε²) at a fold.
  double tolerance = 1e-8;
  // Ipopt constr_viol_tol on ‖F̂‖∞ (> 0): sets the precision of λ (error ≈ this / |wᵀF̂_λ̂|).
  double constraint_tolerance = 1e-10;
  FoldHessian hessian = FoldHessian::kFiniteDifference;
  // Bounds on λ (problem units). A solution on a bound is not a fold (status kAtBound): the
  // branch has no extremum of λ in between.
  double lambda_min = -kInfinity;
  double lambda_max = kInfinity;
  // A converged point is confirmed as a fold when the smallest singular value of F̂_û is at most
  // this times the norm of the constraint Jacobian [F̂_û F̂_λ̂] (∈ (0, 1)).
  double singular_tolerance = 1e-6;
};

// Throws std::invalid_argument naming the field, value and rule.
void Validate(const FoldOptimizationOptions& options);

enum class FoldOptimizationStatus {
  kSolved,           // converged to a fold (F_u singular there)
  kAtBound,          // converged with λ on one of its bounds: no fold between the bounds
  kNotSingular,      // converged, but F_u is regular there: not a fold (e.g. a degenerate start)
  kInfeasible,       // Ipopt found the constraints locally infeasible
  kMaxIterations,    // Ipopt's iteration limit
  kFailed,           // any other Ipopt failure (restoration failed, evaluation error, ...)
};

const char* ToString(FoldOptimizationStatus status);

struct FoldOptimizationResult {
  FoldOptimizationStatus status = FoldOptimizationStatus::kFailed;
  Vector u;
  double lambda = 0.0;
  int iterations = 0;
  int ipopt_status = 0;            // Ipopt's ApplicationReturnStatus
  double residual_norm = 0.0;      // ‖F̂‖∞ at the result
  double singular_ratio = 0.0;     // σ_min(F̂_û) / ‖[F̂_û F̂_λ̂]‖₂ at the result
  std::string message;             // one sentence with numbers

  bool Solved() const { return status == FoldOptimizationStatus::kSolved; }
};

// Solves the NLP from (u0, λ0), a point on or near the branch close to the fold. Start on the
// branch (F(u0, λ0) ≈ 0): from an infeasible start Ipopt may wander to another singular point of
// F = 0 (another fold, or a degenerate solution such as a rotating wave without contact), which
// the singularity check cannot tell from the wanted fold. Throws std::invalid_argument for invalid
// options or a u0 of the wrong size.
FoldOptimizationResult LocateFoldByOptimization(Problem& problem, const Vector& u0, double lambda0,
                                                const FoldOptimizationOptions& options = {});

}  // namespace rubcont
