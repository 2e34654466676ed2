#include "continuation/fold_optimization.h"

#include <catch2/catch.hpp>
#include <cmath>

#include "continuation/continuation.h"
#include "continuation/fold.h"
#include "test_problems.h"

namespace rubcont {
namespace {

using testing::LambdaProblem;
using testing::Vec;

// x³ − x + λ = 0: λ = x − x³ has a local maximum 2/(3√3) at x = 1/√3 and a minimum at −1/√3.
LambdaProblem CubicProblem() {
  return LambdaProblem(
      1, [](const Vector& u, double lambda, double, Vector& F) { F(0) = u(0) * u(0) * u(0) - u(0) + lambda; },
      [](const Vector& u, double, double, Matrix& J) { J(0, 0) = 3.0 * u(0) * u(0) - 1.0; },
      [](const Vector&, double, double, Vector& dF) { dF(0) = 1.0; });
}

TEST_CASE("Ipopt finds both folds of x^3 - x + lambda as the extrema of lambda",
          "[continuation][fold_optimization]") {
  LambdaProblem problem = CubicProblem();
  const double fold_lambda = 2.0 / (3.0 * std::sqrt(3.0));
  FoldOptimizationOptions options;
  const FoldOptimizationResult top = LocateFoldByOptimization(problem, Vec({0.3}), 0.3 - 0.027, options);
  INFO(top.message);
  REQUIRE(top.Solved());
  CHECK(top.lambda == Approx(fold_lambda).epsilon(1e-12));
  CHECK(top.u(0) == Approx(1.0 / std::sqrt(3.0)).epsilon(1e-7));
  CHECK(top.residual_norm <= 1e-11);

  options.sense = -1;
  const FoldOptimizationResult bottom = LocateFoldByOptimization(problem, Vec({-0.3}), -0.3 + 0.027, options);
  INFO(bottom.message);
  REQUIRE(bottom.Solved());
  CHECK(bottom.lambda == Approx(-fold_lambda).epsilon(1e-12));
}

TEST_CASE("the limited-memory Hessian reaches the same fold", "[continuation][fold_optimization]") {
  LambdaProblem problem = CubicProblem();
  FoldOptimizationOptions options;
  options.hessian = FoldHessian::kLimitedMemory;
  options.tolerance = 1e-10;
  const FoldOptimizationResult r = LocateFoldByOptimization(problem, Vec({0.5}), 0.375, options);
  INFO(r.message);
  REQUIRE(r.Solved());
  CHECK(r.lambda == Approx(2.0 / (3.0 * std::sqrt(3.0))).epsilon(1e-9));
}

TEST_CASE("Ipopt and the continuation engine locate the same fold of a 2-D problem to 1e-8",
          "[continuation][fold_optimization]") {
  // x² + y² − 1 + λy = 0, y − x³ − λ = 0 (the fold test's problem at η = 1), scaled unevenly.
  LambdaProblem problem(2, [](const Vector& u, double lambda, double, Vector& F) {
    F(0) = u(0) * u(0) + u(1) * u(1) - 1.0 + lambda * u(1);
    F(1) = u(1) - u(0) * u(0) * u(0) - lambda;
  });
  problem.SetScales(Vec({1.0, 2.0}), 0.5, Vec({3.0, 1.0}));
  ContinuationOptions options;
  options.bounds.lambda_min = -3.0;
  options.bounds.lambda_max = 3.0;
  options.bounds.max_steps = 400;
  const Branch branch = Continue(problem, Vec({1.0, 0.0}), 0.0, options);
  int checked = 0;
  for (const SpecialPoint& fold : branch.special_points) {
    if (fold.type != SpecialPointType::kFold || !fold.converged) continue;
    // Start Ipopt from the branch point before the fold; λ is largest there if the neighbours
    // have smaller λ.
    const BranchPoint& before = branch.points[fold.index];
    FoldOptimizationOptions nlp;
    nlp.sense = before.lambda < fold.lambda ? +1 : -1;
    const FoldOptimizationResult r = LocateFoldByOptimization(problem, before.u, before.lambda, nlp);
    INFO(r.message << "; engine: λ = " << fold.lambda);
    REQUIRE(r.Solved());
    CHECK(std::abs(r.lambda - fold.lambda) <= 1e-8 * std::max(1.0, std::abs(fold.lambda)));
    CHECK((r.u - fold.u).lpNorm<Eigen::Infinity>() <= 1e-6);
    ++checked;
  }
  CHECK(checked >= 1);
}

TEST_CASE("a branch without a fold in range ends on the bound, not at a false fold",
          "[continuation][fold_optimization][failure]") {
  // x³ + x − λ = 0 is monotone: λ has no interior extremum.
  LambdaProblem problem(1, [](const Vector& u, double lambda, double, Vector& F) {
    F(0) = u(0) * u(0) * u(0) + u(0) - lambda;
  });
  FoldOptimizationOptions options;
  options.lambda_min = -2.0;
  options.lambda_max = 2.0;
  const FoldOptimizationResult r = LocateFoldByOptimization(problem, Vec({0.2}), 0.208, options);
  INFO(r.message);
  CHECK(r.status == FoldOptimizationStatus::kAtBound);
  CHECK(r.lambda == Approx(2.0).epsilon(1e-8));
  CHECK(!r.Solved());
}

TEST_CASE("infeasible constraints give a status, not a fold", "[continuation][fold_optimization][failure]") {
  // x² + 1 + λ² = 0 has no real solution.
  LambdaProblem problem(1, [](const Vector& u, double lambda, double, Vector& F) {
    F(0) = u(0) * u(0) + 1.0 + lambda * lambda;
  });
  FoldOptimizationOptions options;
  options.max_iterations = 100;
  const FoldOptimizationResult r = LocateFoldByOptimization(problem, Vec({0.5}), 0.5, options);
  INFO(r.message);
  CHECK(!r.Solved());
  CHECK(r.status != FoldOptimizationStatus::kSolved);
  CHECK(!r.message.empty());
}

TEST_CASE("fold optimization options are validated by name", "[continuation][fold_optimization]") {
  LambdaProblem problem = CubicProblem();
  FoldOptimizationOptions options;
  options.sense = 0;
  CHECK_THROWS_WITH(LocateFoldByOptimization(problem, Vec({0.5}), 0.3, options),
                    Catch::Contains("FoldOptimizationOptions.sense = 0"));
  options = {};
  CHECK_THROWS_WITH(LocateFoldByOptimization(problem, Vec({0.5, 1.0}), 0.3, options),
                    Catch::Contains("u0 has 2 entries"));
}

}  // namespace
}  // namespace rubcont
