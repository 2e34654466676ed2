#include "continuation/fold.h"

#include <cmath>
#include <stdexcept>

#include <catch2/catch.hpp>

#include "continuation/continuation.h"
#include "solvers/finite_difference.h"
#include "test_problems.h"

namespace rubcont {
namespace {

using testing::LambdaProblem;
using testing::Vec;

// x³ − ηx + λ = 0: folds where 3x² = η, λ = 2x³, i.e. on 27λ² = 4η³; a cusp at the origin.
LambdaProblem CuspProblem(double eta) {
  LambdaProblem problem(
      1,
      [](const Vector& u, double l, double eta, Vector& F) {
        F(0) = u(0) * u(0) * u(0) - eta * u(0) + l;
      },
      [](const Vector& u, double, double eta, Matrix& J) { J(0, 0) = 3 * u(0) * u(0) - eta; },
      [](const Vector&, double, double, Vector& dF) { dF(0) = 1.0; });
  problem.EnableSecondParameter(eta);
  return problem;
}

TEST_CASE("the fold curve of x³ − ηx + λ satisfies 27λ² = 4η³ and has a cusp at the origin",
          "[continuation][fold][cusp]") {
  LambdaProblem problem = CuspProblem(1.0);
  ContinuationOptions options;
  options.bounds.lambda_min = -1.0;
  options.bounds.lambda_max = 1.0;
  const Branch branch = Continue(problem, Vec({1.3}), -1.0, options);
  REQUIRE(branch.Count(SpecialPointType::kFold) == 2);
  const SpecialPoint& fold = branch.special_points.front();

  ContinuationOptions curve_options;
  curve_options.direction = -1;  // η decreasing, towards the cusp
  curve_options.bounds.lambda_min = -1.0;
  curve_options.bounds.lambda_max = 1.5;
  const Branch curve = ContinueFoldCurve(problem, fold, curve_options);
  INFO(curve.BriefReport());
  REQUIRE(curve.status == BranchStatus::kReachedLambdaBound);
  CHECK(problem.SecondParameter() == 1.0);  // restored
  const Vector eta = curve.Lambda();
  const Vector lambda = curve.Measure("lambda");
  const Vector x = curve.StateComponent(0);
  for (Index i = 0; i < eta.size(); ++i) {
    CHECK(std::abs(27 * lambda(i) * lambda(i) - 4 * eta(i) * eta(i) * eta(i)) <= 1e-8);
    CHECK(std::abs(3 * x(i) * x(i) - eta(i)) <= 1e-9);
  }
  // Through the cusp onto the other fold branch: x and λ change sign, η comes back up to 1.5.
  CHECK(x(0) * x(eta.size() - 1) < 0.0);
  CHECK(eta(eta.size() - 1) == Approx(1.5).epsilon(0).margin(1e-12));
  REQUIRE(curve.Count(SpecialPointType::kCusp) == 1);
  CHECK(curve.Count(SpecialPointType::kFold) == 0);  // the η-turn at the cusp is the cusp
  const SpecialPoint& cusp = curve.special_points.front();
  CHECK(cusp.type == SpecialPointType::kCusp);
  CHECK(cusp.label == "cusp");
  CHECK(cusp.converged);
  CHECK(std::abs(cusp.lambda) <= 1e-8);  // η
  CHECK(std::abs(cusp.u(0)) <= 1e-8);    // x
  CHECK(std::abs(cusp.u(1)) <= 1e-8);    // λ
  CHECK(cusp.note.find("turns back") != std::string::npos);
}

TEST_CASE("LocateFold converges from a guess near the fold", "[continuation][fold]") {
  LambdaProblem problem = CuspProblem(1.0);
  const FoldLocation fold = LocateFold(problem, Vec({0.5}), 0.38);
  REQUIRE(fold.converged);
  CHECK(fold.u(0) == Approx(1.0 / std::sqrt(3.0)).epsilon(1e-12));
  CHECK(fold.lambda == Approx(2.0 / (3.0 * std::sqrt(3.0))).epsilon(1e-12));
  CHECK(fold.residual_norm <= 1e-11);
  CHECK(fold.iterations <= 8);
}

TEST_CASE("the fold problem's Jacobian and η-derivative match finite differences",
          "[continuation][fold]") {
  // A 2-D problem with a fold: x² + y² − 1 + λ·y·η = 0, y − x³ − λ = 0.
  LambdaProblem inner(
      2,
      [](const Vector& u, double l, double eta, Vector& F) {
        F << u(0) * u(0) + u(1) * u(1) - 1.0 + l * u(1) * eta, u(1) - u(0) * u(0) * u(0) - l;
      },
      [](const Vector& u, double l, double eta, Matrix& J) {
        J << 2 * u(0), 2 * u(1) + l * eta, -3 * u(0) * u(0), 1.0;
      },
      [](const Vector& u, double, double eta, Vector& dF) { dF << u(1) * eta, -1.0; });
  inner.EnableSecondParameter(0.7);
  FoldProblem fold(inner, Vec({0.6, 0.5}), 0.2);
  const Vector U = Vec({0.55, 0.45, 0.25});
  Matrix DG;
  fold.Jacobian(U, 0.7, DG);
  auto residual = [&](const Vector& x, Vector& G) { fold.Residual(x, 0.7, G); };
  const JacobianCheck check = CheckJacobian(residual, U, DG, 1e-6);
  INFO("worst (" << check.worst_row << ", " << check.worst_col << "): " << check.analytic_value
                 << " vs " << check.difference_value);
  CHECK(check.ok);
  Vector dG, G_plus, G_minus;
  fold.DfDlambda(U, 0.7, dG);
  const double h = 1e-6;
  fold.Residual(U, 0.7 + h, G_plus);
  fold.Residual(U, 0.7 - h, G_minus);
  CHECK(((G_plus - G_minus) / (2 * h) - dG).lpNorm<Eigen::Infinity>() <= 1e-6);
}

TEST_CASE("fold curves need a second parameter and a fold", "[continuation][fold]") {
  LambdaProblem problem(
      1, [](const Vector& u, double l, double, Vector& F) { F(0) = u(0) * u(0) - l; });
  SpecialPoint fold;
  fold.type = SpecialPointType::kFold;
  fold.u = Vec({0.0});
  CHECK_THROWS_WITH(ContinueFoldCurve(problem, fold), Catch::Contains("second parameter"));
  problem.EnableSecondParameter(0.0);
  fold.type = SpecialPointType::kHopf;
  CHECK_THROWS_WITH(ContinueFoldCurve(problem, fold), Catch::Contains("not a fold"));
}

}  // namespace
}  // namespace rubcont
