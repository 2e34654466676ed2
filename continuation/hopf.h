// Hopf curves: the Hopf points of a one-parameter problem continued in a second parameter η, with
// their codimension-two points.
//
// Defining system. At a Hopf point a complex pair μ, μ̄ of the stability operator's eigenvalues
// (Problem::Stability, trivial values removed) crosses the imaginary axis. Along the curve the pair
// is followed by continuity: at every evaluation, the two eigenvalues nearest the pair of the last
// accepted point. With their sum and product
//     h = Re(μ₁ + μ₂) / 2,     κ = Re(μ₁ μ₂)     (a conjugate pair, or two real values),
// the unknowns U = (u, λ) and the residual G(U; η) = [F(u, λ; η); h / ρ], ρ the spectral radius
// where the curve starts: eigenvalues are computed to about ε·ρ, so h is scaled by what limits its
// precision, not by the Hopf frequency ω₀ (on case A(a)'s one-contact whip at 81.96 rpm with the
// tanh law, ω₀ = 849 s⁻¹ beside the contact mode's 4.1e5 s⁻¹, and h / ω₀ stalled at 1e-9, above
// the corrector's tolerance). h and κ are symmetric functions of an isolated pair of eigenvalues,
// hence smooth in (u, λ, η) also where the pair meets on the real axis: the curve goes on through a
// Bogdanov–Takens point (κ = 0, the Hopf frequency √κ → 0) onto neutral saddles (κ < 0, two real
// eigenvalues ±√−κ), as the bialternate-product formulation does (Govaerts, "Numerical Methods for
// Bifurcations of Dynamical Equilibria", §4.4; MatCont's Hopf curves), but without its
// n(n−1)/2-square matrix and for any stability operator, including the constrained, slice-reduced
// ones of rotating waves (waves/rotating_wave.h) whose matrix is not F_u. ∂h/∂(u, λ) and ∂h/∂η
// are central differences of the spectrum (2(n + 1) eigenvalue problems per Jacobian, 2 per
// ∂G/∂η; the steps in Jacobian()); their truncation error only slows Newton, the location
// precision is set by the residual.
//
// Codimension-two points (Kuznetsov, "Elements of Applied Bifurcation Theory", §8.4–8.6):
//  - Bogdanov–Takens: the test function "bogdanov_takens" κ / ω₀² changes sign.
//  - zero-Hopf (fold–Hopf) and double Hopf (Hopf–Hopf): a real eigenvalue, or a second pair, of the
//    rest of the spectrum crosses the axis. The Hopf problem's own stability operator is that rest
//    (the pair removed) with the inner problem's StabilityTolerance, so the engine's crossing
//    detection finds and locates them; ContinueHopfCurve renames its Hopf points double-Hopf points
//    and its real crossings zero-Hopf points. A point of the curve is "stable" where the rest is: a
//    Hopf point of an otherwise stable state, where the state loses its stability.
//  - Generalized Hopf (Bautin): the test function "generalized_hopf", the inner problem's first
//    Lyapunov coefficient l1 (Problem::FirstLyapunov, continuation/lyapunov.h), changes sign.
//    Only on curves that start from a Hopf point with a valid l1, and only where its two
//    finite-difference steps agree to 1 % of |l1| at the start (AgreesTo: near the zero, 1 % of
//    |l1| itself would fail); NaN elsewhere, so that a sign change is seen only between points
//    where both values are known. Most of the rub's tanh-law Hopf points have no valid l1
//    (docs/continuation.md, "Sub- or supercritical Hopf"); the exact law has none.
//
// Events: the inner problem's events (validity margins of a piecewise-smooth problem) are the Hopf
// problem's, and it refuses to switch: a Hopf curve ends, located, where its Hopf point reaches a
// switch (e.g. a rolling whirl's Hopf point meets the stick → slip event: a codimension-two point of
// the piecewise-smooth system), with status kSwitchRefused and the event as its last special point.
#pragma once

#include <complex>
#include <string>
#include <vector>

#include "continuation/branch.h"
#include "continuation/continuation.h"
#include "continuation/options.h"
#include "continuation/problem.h"

namespace rubcont {

// The Hopf curve of an inner problem as a Problem: unknowns U = (u, λ), parameter η (the inner
// problem's second parameter), residual [F(u, λ; η); h / ρ]. The inner problem must outlive it.
class HopfProblem : public Problem {
 public:
  // (u, λ): a Hopf point of `inner` at its current η, `critical` ≈ iω₀ its critical eigenvalue
  // (SpecialPoint::critical_value), which picks the pair. Throws std::invalid_argument when the
  // inner problem has no stability operator or no second parameter, when u has the wrong size, or
  // when Im critical is not > 0.
  HopfProblem(Problem& inner, const Vector& u, double lambda, std::complex<double> critical);

  Index Dimension() const override { return n_ + 1; }
  void Residual(const Vector& U, double eta, Vector& G) override;
  void Jacobian(const Vector& U, double eta, Matrix& DG) override;
  void DfDlambda(const Vector& U, double eta, Vector& dG) override;  // ∂G/∂η
  Vector Scale() const override;            // (s, s_λ) of the inner problem
  double LambdaScale() const override { return inner_.SecondParameterScale(); }
  Vector ResidualScale() const override;    // (r, 1): h / ρ is already scaled

  // The rest of the spectrum (the pair removed), with the inner problem's tolerance.
  bool HasStability() const override { return true; }
  Spectrum Stability(const Vector& U, double eta) override;
  double StabilityTolerance() const override { return inner_.StabilityTolerance(); }

  // "lambda" (the inner parameter), "hopf_frequency" (√κ, rad per time unit of the problem; NaN
  // on neutral saddles), then the inner problem's measures.
  std::vector<std::string> MeasureNames() const override;
  Vector Measures(const Vector& U, double eta) override;

  // The inner problem's events; SwitchAt refuses (see above).
  std::vector<std::string> EventNames() const override { return inner_.EventNames(); }
  Vector EventFunctions(const Vector& U, double eta) override;
  bool SwitchAt(int /*event*/, Vector& /*U*/, double /*eta*/) override { return false; }
  std::string PieceLabel() const override { return inner_.PieceLabel(); }

  // κ / ω₀² (Bogdanov–Takens) and the inner problem's first Lyapunov coefficient l1 (generalized
  // Hopf; NaN where it is not known, above).
  std::vector<std::string> TestFunctionNames() const override {
    return {"bogdanov_takens", "generalized_hopf"};
  }
  Vector TestFunctions(const Vector& U, double eta) override;
  SpecialPointType TestFunctionType(int k) const override {
    return k == 0 ? SpecialPointType::kBogdanovTakens : SpecialPointType::kGeneralizedHopf;
  }

  // Passes the point to the inner problem's PointAccepted (e.g. a rotating wave's phase
  // reference), then follows the pair: its values at the point become the reference.
  void PointAccepted(const Vector& U, double eta) override;

 private:
  // The pair at (U, η): sum h and product κ, the two values, and the rest of the spectrum.
  struct Pair {
    bool valid = false;  // false: the spectrum could not be computed
    double h = 0.0;
    double kappa = 0.0;
    std::complex<double> first, second;
    Spectrum rest;
  };
  Pair Evaluate(const Vector& U, double eta);
  void SetEta(double eta);
  double ScaledSum(const Vector& U, double eta);  // h / ρ, NaN where the spectrum fails

  Problem& inner_;
  Index n_;
  Vector s_;
  Vector r_;
  double s_lambda_;
  double omega0_;
  double radius_;  // ρ: the spectral radius at the start
  // |l1| at the start where the inner problem computes it (valid), else 0: no generalized Hopf
  // test on this curve.
  double l1_reference_ = 0.0;
  std::complex<double> reference_first_, reference_second_;
};

// Continues the Hopf curve through a located Hopf point of `problem` in its second parameter η,
// starting at the current η: builds a HopfProblem and runs the engine on it. The branch's λ is η,
// its states are (u, λ), its measures "lambda" (the inner λ), "hopf_frequency", then the inner
// measures. Special points: Bogdanov–Takens (test function), zero-Hopf and double-Hopf (crossings
// of the rest of the spectrum, renamed from the engine's real crossings and Hopf points), folds of
// the curve in η, and the event where it ends. The options apply to the curve
// (bounds.lambda_min/max bound η), with detect.stability on. The curve is always Re μ = 0: from a
// Hopf point that the engine located where a marginal pair's growth rate crosses the problem's
// StabilityTolerance instead (its note says so) the start must first reach Re μ = 0, and can fail
// (studies/hysteresis_map.cpp starts no curve there). The inner problem's η is restored at the
// end. Throws std::invalid_argument when the problem has no second parameter or
// stability operator, or the special point is not a Hopf point.
Branch ContinueHopfCurve(Problem& problem, const SpecialPoint& hopf,
                         const ContinuationOptions& options = {},
                         const StepCallback& callback = {});

}  // namespace rubcont
