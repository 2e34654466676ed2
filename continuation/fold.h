// Folds: the minimally augmented fold system, fold location, and two-parameter fold curves.
//
// Minimally augmented system (Govaerts, "Numerical Methods for Bifurcations of Dynamical
// Equilibria", SIAM 2000, §4.3; BifurcationKit's FoldMAProblem). In the inner problem's scaled
// variables (Ĵ = diag(1/r) F_u diag(s), see continuation/scaled_system.h) and with bordering
// vectors b, c ∈ Rⁿ, the bordered system
//     [Ĵ  b] [v]   [0]          [Ĵᵀ c] [w]   [0]
//     [cᵀ 0] [g] = [1],         [bᵀ 0] [g] = [1]
// defines the scalar g(u, λ), which vanishes exactly where Ĵ is singular (as long as the bordered
// matrix is not), with v, w approximating the right and left null vectors. A fold is a regular
// solution of the n + 1 equations  F(u, λ) = 0, g(u, λ) = 0  in the n + 1 unknowns (u, λ).
// Derivatives: dg = −wᵀ dĴ v. In unscaled variables, with ṽ = s .* v and w̃ = w ./ r,
//     g_u = −∇_u(w̃ᵀ F_u ṽ) = −(d/dt) F_u(u + tṽ)ᵀ w̃,     g_λ = −w̃ᵀ (d/dt) F_λ(u + tṽ),
//     g_η = −w̃ᵀ (d/dt) F_η(u + tṽ)     (the Hessian of w̃ᵀF is symmetric),
// each a central difference of two Jacobian (or ∂F/∂λ, ∂F/∂η) evaluations along ṽ. Their
// truncation error only slows Newton's convergence; the location precision is set by the residual
// [F; g], which contains only F and F_u. b ← w/‖w‖ and c ← v/‖v‖ after every Newton iteration and
// accepted continuation point keeps the bordered matrix well conditioned; since bᵀw = cᵀv = 1 the
// new borders point the same way as the old ones, so g keeps its sign convention.
//
// Cusp test (Kuznetsov, "Elements of Applied Bifurcation Theory", §8.2): on a fold curve the
// normal-form coefficient a = ½ ŵᵀ D²F̂(v̂, v̂) (v̂, ŵ the unit null vectors) vanishes at a cusp.
// It is computed as ½ w̃ᵀ (d/dt)[F_u(u + tṽ) ṽ] and changes sign there, where the two fold branches
// of the (λ, η) plane meet; the fold curve also turns back in η at a generic cusp (its tangent
// there is (v, 0, 0)), which the engine would report as a fold of the fold curve at the same point:
// it keeps the cusp and says so in its note. We use a rather than "the λ-extremum along the curve"
// because a is a smooth function with a simple zero at the cusp, independent of which parameter is
// continued, while extrema of λ or η also occur at ordinary points of a fold curve.
#pragma once

#include <Eigen/LU>
#include <string>
#include <vector>

#include "continuation/branch.h"
#include "continuation/continuation.h"
#include "continuation/options.h"
#include "continuation/problem.h"

namespace rubcont {

// The fold curve of an inner problem as a Problem: unknowns U = (u, λ) ∈ Rⁿ⁺¹, parameter η (the
// inner problem's second parameter), residual [F(u, λ; η); g(u, λ; η)]. It can also be used with
// an inner problem without a second parameter, at fixed η, to locate folds (LocateFold).
// The inner problem must outlive it; its events end the curve (it does not change formulation).
class FoldProblem : public Problem {
 public:
  // (u, λ): a point at or near a fold of `inner`. The borders start as the singular vectors of the
  // smallest singular value of Ĵ there.
  FoldProblem(Problem& inner, const Vector& u, double lambda);

  Index Dimension() const override { return n_ + 1; }
  void Residual(const Vector& U, double eta, Vector& G) override;
  void Jacobian(const Vector& U, double eta, Matrix& DG) override;
  // ∂G/∂η; throws std::logic_error when the inner problem has no second parameter.
  void DfDlambda(const Vector& U, double eta, Vector& dG) override;
  Vector Scale() const override;                // (s, s_λ) of the inner problem
  double LambdaScale() const override;          // the inner SecondParameterScale()
  Vector ResidualScale() const override;        // (r, 1): g is already scaled

  // "lambda" (the inner parameter) followed by the inner problem's measures.
  std::vector<std::string> MeasureNames() const override;
  Vector Measures(const Vector& U, double eta) override;

  // The inner problem's events (validity margins of a piecewise-smooth problem); SwitchAt refuses:
  // a fold curve ends, located, where its fold reaches a switch (as Hopf curves do).
  std::vector<std::string> EventNames() const override { return inner_.EventNames(); }
  Vector EventFunctions(const Vector& U, double eta) override;
  bool SwitchAt(int /*event*/, Vector& /*U*/, double /*eta*/) override { return false; }
  std::string PieceLabel() const override { return inner_.PieceLabel(); }

  // One test function, "cusp": the normal-form coefficient a (see above).
  std::vector<std::string> TestFunctionNames() const override { return {"cusp"}; }
  Vector TestFunctions(const Vector& U, double eta) override;
  SpecialPointType TestFunctionType(int /*k*/) const override { return SpecialPointType::kCusp; }

  // Updates the borders to the null vectors at (U, η).
  void PointAccepted(const Vector& U, double eta) override { UpdateBorders(U, eta); }
  void UpdateBorders(const Vector& U, double eta);

  // g and the scaled null vectors v, w at (U, η) (cached for the last point).
  double TestValue(const Vector& U, double eta);
  const Vector& RightNullVector(const Vector& U, double eta);
  const Vector& LeftNullVector(const Vector& U, double eta);
  // The normal-form coefficient a at (U, η).
  double CuspCoefficient(const Vector& U, double eta);

  Problem& inner() { return inner_; }

 private:
  void SetEta(double eta);
  // Factors the bordered matrix at (U, η) and solves for g, v, w unless cached.
  void Evaluate(const Vector& U, double eta);
  // Central difference step along ṽ in scaled variables.
  double DifferenceStep(const Vector& U, const Vector& direction) const;

  Problem& inner_;
  Index n_;
  bool has_eta_;
  Vector s_;      // inner Scale()
  Vector r_inv_;  // 1 / inner ResidualScale()
  double s_lambda_;
  Vector b_, c_;  // borders (scaled space, unit)
  // Cache of the last evaluation.
  bool cached_ = false;
  Vector cached_U_;
  double cached_eta_ = 0.0;
  Matrix J_;      // inner F_u at the cached point (unscaled)
  double g_ = 0.0;
  Vector v_, w_;  // scaled null vectors (cᵀv = bᵀw = 1)
  Matrix M_;
  Eigen::PartialPivLU<Matrix> lu_;
};

struct FoldLocation {
  bool converged = false;
  Vector u;
  double lambda = 0.0;
  int iterations = 0;
  double residual_norm = 0.0;    // ‖[F ./ r; g]‖∞ at (u, λ)
  double last_correction = 0.0;  // ‖ΔÛ‖∞ of the last Newton step (scaled)
  double test_value = 0.0;       // g
  std::string message;
};

// Newton on the minimally augmented system from a guess near a fold, at the current η. Converged
// when ‖[F̂; g]‖∞ ≤ residual_tolerance after a correction of at most step_tolerance.
FoldLocation LocateFold(Problem& problem, const Vector& u_guess, double lambda_guess,
                        const LocationOptions& options = {});

// Continues the fold curve through a located fold of `problem` in its second parameter η, starting
// at the current η: builds a FoldProblem and runs the engine on it. The branch's λ is η, its
// states are (u, λ), its measure "lambda" is the inner λ; cusps are special points of type kCusp.
// The options apply to the fold curve (bounds.lambda_min/max bound η). The inner problem's η is
// restored at the end. Throws std::invalid_argument when the problem has no second parameter or
// the special point is not a fold.
Branch ContinueFoldCurve(Problem& problem, const SpecialPoint& fold,
                         const ContinuationOptions& options = {},
                         const StepCallback& callback = {});

}  // namespace rubcont
