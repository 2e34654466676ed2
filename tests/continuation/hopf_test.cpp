#include "continuation/hopf.h"

#include <cmath>
#include <stdexcept>

#include <catch2/catch.hpp>

#include "continuation/continuation.h"
#include "test_problems.h"

namespace rubcont {
namespace {

using testing::LambdaProblem;
using testing::Vec;

// The first Hopf point the engine finds on the equilibria from (u0, λ0) in the given direction.
SpecialPoint FirstHopf(LambdaProblem& problem, const Vector& u0, double lambda0, int direction,
                       double lambda_bound) {
  ContinuationOptions options;
  options.detect.stability = true;
  options.direction = direction;
  (direction > 0 ? options.bounds.lambda_max : options.bounds.lambda_min) = lambda_bound;
  const Branch branch = Continue(problem, u0, lambda0, options);
  INFO(branch.BriefReport());
  REQUIRE(branch.Count(SpecialPointType::kHopf) >= 1);
  for (const SpecialPoint& sp : branch.special_points) {
    if (sp.type == SpecialPointType::kHopf) return sp;
  }
  return {};
}

// The Bogdanov–Takens normal form ẋ = y, ẏ = λ + ηy + x² − xy. Equilibria (x₀, 0) with x₀² = −λ;
// the Jacobian [[0, 1], [2x₀, η − x₀]] has trace η − x₀ and determinant −2x₀: Hopf points where
// η = x₀ < 0, on the curve λ = −η² with frequency √(−2η); it goes on through the Bogdanov–Takens
// point (0, 0) onto neutral saddles (η = x₀ > 0, κ = −2η).
LambdaProblem BogdanovTakens(double eta) {
  auto jacobian = [](const Vector& u, double, double eta, Matrix& J) {
    J << 0.0, 1.0, 2.0 * u(0) - u(1), eta - u(0);
  };
  LambdaProblem problem(
      2,
      [](const Vector& u, double l, double eta, Vector& F) {
        F(0) = u(1);
        F(1) = l + eta * u(1) + u(0) * u(0) - u(0) * u(1);
      },
      jacobian, [](const Vector&, double, double, Vector& dF) { dF = Vec({0.0, 1.0}); });
  problem.SetStabilityFromJacobian();
  problem.EnableSecondParameter(eta);
  return problem;
}

TEST_CASE("the Hopf curve of the Bogdanov-Takens form is λ = −η² through its BT point",
          "[continuation][hopf]") {
  LambdaProblem problem = BogdanovTakens(-2.0);
  // Equilibria x₀ = −√(−λ) at η = −2: the Hopf point at λ = −4, eigenvalues ±2i.
  const SpecialPoint hopf = FirstHopf(problem, Vec({-std::sqrt(6.0), 0.0}), -6.0, +1, -1.0);
  REQUIRE(hopf.converged);
  CHECK(hopf.lambda == Approx(-4.0).epsilon(1e-9));
  CHECK(hopf.frequency == Approx(2.0).epsilon(1e-8));

  ContinuationOptions options;
  options.bounds.lambda_min = -2.5;
  options.bounds.lambda_max = 0.8;
  options.step.max = 0.05;
  const Branch curve = ContinueHopfCurve(problem, hopf, options);
  INFO(curve.BriefReport());
  REQUIRE(curve.status == BranchStatus::kReachedLambdaBound);
  CHECK(problem.SecondParameter() == -2.0);  // restored
  const Vector eta = curve.Lambda();
  const Vector lambda = curve.Measure("lambda");
  const Vector frequency = curve.Measure("hopf_frequency");
  CHECK(eta(0) == -2.0);
  CHECK(eta(eta.size() - 1) == Approx(0.8).epsilon(0).margin(1e-12));
  for (Index i = 0; i < eta.size(); ++i) {
    INFO("η = " << eta(i));
    CHECK(std::abs(lambda(i) + eta(i) * eta(i)) <= 1e-9);
    CHECK(std::abs(curve.StateComponent(0)(i) - eta(i)) <= 1e-9);  // x₀ = η
    if (eta(i) < -1e-3) {
      CHECK(frequency(i) == Approx(std::sqrt(-2.0 * eta(i))).epsilon(1e-7));
    } else if (eta(i) > 1e-3) {
      CHECK(std::isnan(frequency(i)));  // a neutral saddle
    }
  }
  REQUIRE(curve.special_points.size() == 1);
  const SpecialPoint& bt = curve.special_points.front();
  CHECK(bt.type == SpecialPointType::kBogdanovTakens);
  CHECK(bt.label == "bogdanov_takens");
  CHECK(bt.converged);
  CHECK(std::abs(bt.lambda) <= 1e-8);  // η
  CHECK(std::abs(bt.u(2)) <= 1e-8);    // λ
}

// The Bautin normal form ẇ = (λ + i)w + ηw|w|² − w|w|⁴ (w = a + ib; Kuznetsov, Elements, §8.3)
// in the coordinates x = a, y = b + a² (quadratic terms, and finite-difference errors from the
// higher ones): the origin has Hopf points at λ = 0 for every η, with l1 = 2η (ω = 1, |q| = 1),
// and a generalized Hopf point at η = 0. Stability from a central-difference Jacobian, l1 from
// the Problem's (EnableFirstLyapunov).
LambdaProblem Bautin(double eta) {
  auto residual = [](const Vector& u, double l, double eta, Vector& F) {
    const double a = u(0), b = u(1) - u(0) * u(0);
    const double r2 = a * a + b * b;
    const double g = l + eta * r2 - r2 * r2;
    const double fa = g * a - b, fb = a + g * b;
    F.resize(2);
    F << fa, fb + 2.0 * a * fa;  // ẏ = ḃ + 2a ȧ
  };
  LambdaProblem problem(2, residual);
  problem.SetStability([residual](const Vector& u, double l, double eta) {
    Matrix J(2, 2);
    Vector plus, minus;
    for (Index j = 0; j < 2; ++j) {
      const double h = 1e-6;
      Vector v = u;
      v(j) += h;
      residual(v, l, eta, plus);
      v(j) -= 2.0 * h;
      residual(v, l, eta, minus);
      J.col(j) = (plus - minus) / (2.0 * h);
    }
    return testing::EigenvaluesOf(J);
  });
  problem.EnableSecondParameter(eta);
  problem.EnableFirstLyapunov();
  return problem;
}

TEST_CASE("the Hopf curve of the Bautin form has its generalized Hopf point where l1 changes sign",
          "[continuation][hopf]") {
  LambdaProblem problem = Bautin(-0.5);
  const SpecialPoint hopf = FirstHopf(problem, Vec({0.0, 0.0}), -0.5, +1, 0.5);
  REQUIRE(hopf.converged);
  CHECK(std::abs(hopf.lambda) <= 1e-8);
  CHECK(problem.FirstLyapunov(hopf.u, hopf.lambda, hopf.critical_value).l1 < 0.0);

  ContinuationOptions options;
  options.bounds.lambda_min = -0.6;
  options.bounds.lambda_max = 0.4;
  const Branch curve = ContinueHopfCurve(problem, hopf, options);
  INFO(curve.BriefReport());
  REQUIRE(curve.status == BranchStatus::kReachedLambdaBound);
  for (Index i = 0; i < curve.Lambda().size(); ++i) {
    CHECK(std::abs(curve.Measure("lambda")(i)) <= 1e-9);  // Hopf at λ = 0 for every η
  }
  REQUIRE(curve.special_points.size() == 1);
  const SpecialPoint& bautin = curve.special_points.front();
  CHECK(bautin.type == SpecialPointType::kGeneralizedHopf);
  CHECK(bautin.label == "generalized_hopf");
  CHECK(bautin.converged);
  CHECK(std::abs(bautin.lambda) <= 1e-7);  // η
  // Subcritical beyond it.
  problem.SetSecondParameter(0.3);
  CHECK(problem.FirstLyapunov(hopf.u, 0.0, hopf.critical_value).l1 > 0.0);
}

// The fold–Hopf normal form (Kuznetsov, Elements, §8.5) with a second, decoupled oscillator:
//     ξ̇ = λ + ξ² + x² + y²,   (x + iy)˙ = (η + ξ + ξ² + 2i)(x + iy),
//     (p + iq)˙ = (−η − 0.2 + 3i)(p + iq).
// Equilibria (ξ, 0, 0, 0, 0) with ξ² = −λ; eigenvalues 2ξ, η + ξ + ξ² ± 2i and −η − 0.2 ± 3i. The
// Hopf curve of the pair ±2i: λ = −ξ², η = −ξ − ξ²; on it the real eigenvalue 2ξ crosses 0 at
// η = 0 (zero-Hopf: the fold curve λ = 0 touches it) and the second pair crosses the axis at
// η = −0.2 (double Hopf, ξ = (√1.8 − 1)/2). The rest of the spectrum is stable for η ∈ (0, ¼).
LambdaProblem FoldHopf(double eta) {
  auto jacobian = [](const Vector& u, double, double eta, Matrix& J) {
    const double xi = u(0), x = u(1), y = u(2);
    const double a = eta + xi + xi * xi, da = 1.0 + 2.0 * xi, b = -eta - 0.2;
    J.setZero(5, 5);
    J.row(0) << 2.0 * xi, 2.0 * x, 2.0 * y, 0.0, 0.0;
    J.row(1) << da * x, a, -2.0, 0.0, 0.0;
    J.row(2) << da * y, 2.0, a, 0.0, 0.0;
    J.row(3) << 0.0, 0.0, 0.0, b, -3.0;
    J.row(4) << 0.0, 0.0, 0.0, 3.0, b;
  };
  LambdaProblem problem(
      5,
      [](const Vector& u, double l, double eta, Vector& F) {
        const double xi = u(0), x = u(1), y = u(2), p = u(3), q = u(4);
        const double a = eta + xi + xi * xi, b = -eta - 0.2;
        F << l + xi * xi + x * x + y * y, a * x - 2.0 * y, 2.0 * x + a * y, b * p - 3.0 * q,
            3.0 * p + b * q;
      },
      jacobian,
      [](const Vector&, double, double, Vector& dF) { dF = Vec({1.0, 0.0, 0.0, 0.0, 0.0}); });
  problem.SetStabilityFromJacobian();
  problem.EnableSecondParameter(eta);
  return problem;
}

TEST_CASE("the Hopf curve of the fold-Hopf form has its zero-Hopf and double-Hopf points",
          "[continuation][hopf]") {
  LambdaProblem problem = FoldHopf(0.21);
  // At η = 0.21 the Hopf point is at ξ = −0.3, λ = −0.09.
  const SpecialPoint hopf =
      FirstHopf(problem, Vec({-0.1, 0.0, 0.0, 0.0, 0.0}), -0.01, -1, -0.2);
  REQUIRE(hopf.converged);
  CHECK(hopf.lambda == Approx(-0.09).epsilon(1e-9));

  ContinuationOptions options;
  options.direction = -1;
  options.bounds.lambda_min = -0.5;
  options.bounds.lambda_max = 0.24;
  options.step.max = 0.05;
  const Branch curve = ContinueHopfCurve(problem, hopf, options);
  INFO(curve.BriefReport());
  REQUIRE(curve.status == BranchStatus::kReachedLambdaBound);
  const Vector eta = curve.Lambda();
  const Vector lambda = curve.Measure("lambda");
  const Vector frequency = curve.Measure("hopf_frequency");
  const Vector xi = curve.StateComponent(0);
  CHECK(eta(eta.size() - 1) == Approx(-0.5).epsilon(0).margin(1e-12));
  for (Index i = 0; i < eta.size(); ++i) {
    INFO("η = " << eta(i));
    CHECK(std::abs(lambda(i) + xi(i) * xi(i)) <= 1e-9);
    CHECK(std::abs(eta(i) + xi(i) + xi(i) * xi(i)) <= 1e-9);
    CHECK(frequency(i) == Approx(2.0).epsilon(1e-9));
    if (std::abs(eta(i)) > 1e-6) CHECK((curve.points[i].num_unstable == 0) == (eta(i) > 0.0));
  }
  REQUIRE(curve.Count(SpecialPointType::kZeroHopf) == 1);
  REQUIRE(curve.Count(SpecialPointType::kDoubleHopf) == 1);
  CHECK(curve.Count(SpecialPointType::kBogdanovTakens) == 0);
  for (const SpecialPoint& sp : curve.special_points) {
    INFO(sp.Name() << " at η = " << sp.lambda);
    CHECK(sp.converged);
    if (sp.type == SpecialPointType::kZeroHopf) {
      CHECK(std::abs(sp.lambda) <= 1e-8);
      CHECK(std::abs(sp.u(0)) <= 1e-8);  // ξ
      CHECK(ToString(sp.type) == std::string("zero-Hopf"));
    } else if (sp.type == SpecialPointType::kDoubleHopf) {
      CHECK(sp.lambda == Approx(-0.2).epsilon(1e-8));
      CHECK(sp.u(0) == Approx((std::sqrt(1.8) - 1.0) / 2.0).epsilon(1e-8));
      CHECK(sp.frequency == Approx(3.0).epsilon(1e-8));
    }
  }
}

TEST_CASE("ContinueHopfCurve refuses a point that is no Hopf point", "[continuation][hopf]") {
  LambdaProblem problem = BogdanovTakens(-2.0);
  SpecialPoint fold;
  fold.type = SpecialPointType::kFold;
  fold.u = Vec({0.0, 0.0});
  CHECK_THROWS_AS(ContinueHopfCurve(problem, fold), std::invalid_argument);
  SpecialPoint real_crossing;
  real_crossing.type = SpecialPointType::kHopf;
  real_crossing.u = Vec({-2.0, 0.0});
  real_crossing.lambda = -4.0;
  real_crossing.critical_value = {0.0, 0.0};  // no frequency
  CHECK_THROWS_AS(ContinueHopfCurve(problem, real_crossing), std::invalid_argument);
}

}  // namespace
}  // namespace rubcont
