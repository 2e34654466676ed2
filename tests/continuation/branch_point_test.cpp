#include "continuation/branch_point.h"

#include <cmath>

#include <catch2/catch.hpp>

#include "continuation/branch_switching.h"
#include "continuation/continuation.h"
#include "test_problems.h"

namespace rubcont {
namespace {

using testing::LambdaProblem;
using testing::Vec;

// F = (x(λ − 2 − x²), y − λ/2): the trivial branch x = 0, y = λ/2 and the parabola λ = 2 + x²
// meet in a pitchfork at λ* = 2, (x, y) = (0, 1). The left null vector of DF there is (1, 0).
LambdaProblem ShiftedPitchfork() {
  return LambdaProblem(
      2,
      [](const Vector& u, double l, double, Vector& F) {
        F(0) = u(0) * (l - 2.0 - u(0) * u(0));
        F(1) = u(1) - 0.5 * l;
      },
      [](const Vector& u, double l, double, Matrix& J) {
        J << l - 2.0 - 3.0 * u(0) * u(0), 0.0, 0.0, 1.0;
      },
      [](const Vector& u, double, double, Vector& dF) { dF << u(0), -0.5; });
}

TEST_CASE("The branch-point system converges to the pitchfork from a guess off it", "[branch_point]") {
  LambdaProblem problem = ShiftedPitchfork();
  ScaledSystem system(problem);
  system.Refresh();
  Vector guess(3);
  guess << 0.03, 1.04, 2.07;  // off both branches
  const BranchPointLocation bp = LocateBranchPoint(system, guess);
  INFO(bp.message);
  REQUIRE(bp.converged);
  CHECK(std::abs(bp.x(0)) <= 1e-12);
  CHECK(std::abs(bp.x(1) - 1.0) <= 1e-12);
  CHECK(std::abs(bp.x(2) - 2.0) <= 1e-12);
  CHECK(std::abs(bp.beta) <= 1e-12);
  CHECK(std::abs(std::abs(bp.phi(0)) - 1.0) <= 1e-12);
  CHECK(std::abs(bp.phi(1)) <= 1e-12);
  CHECK(bp.iterations <= 8);  // quadratic convergence
}

TEST_CASE("Where DF has full rank the branch-point system has no solution, and says so",
          "[branch_point]") {
  // x − λ = 0, y − λ² = 0: a single smooth curve, no branch point anywhere.
  LambdaProblem problem(
      2,
      [](const Vector& u, double l, double, Vector& F) { F << u(0) - l, u(1) - l * l; },
      [](const Vector&, double, double, Matrix& J) { J.setIdentity(); },
      [](const Vector&, double l, double, Vector& dF) { dF << -1.0, -2.0 * l; });
  ScaledSystem system(problem);
  system.Refresh();
  const BranchPointLocation bp = LocateBranchPoint(system, Vec({0.5, 0.25, 0.5}));
  CHECK_FALSE(bp.converged);
  CHECK_FALSE(bp.message.empty());
}

TEST_CASE("Continuation locates the pitchfork by Newton and switches onto the parabola",
          "[branch_point]") {
  LambdaProblem problem = ShiftedPitchfork();
  ContinuationOptions options;
  options.bounds.lambda_min = 0.0;
  options.bounds.lambda_max = 3.0;
  const Branch trivial = Continue(problem, Vec({0.0, 0.25}), 0.5, options);
  INFO(trivial.BriefReport());
  REQUIRE(trivial.Count(SpecialPointType::kBranchPoint) == 1);
  const SpecialPoint& bp = trivial.special_points.front();
  CHECK(bp.converged);
  CHECK(bp.note.empty());  // not the Illinois fallback
  CHECK(std::abs(bp.lambda - 2.0) <= 1e-12);
  CHECK(std::abs(bp.u(1) - 1.0) <= 1e-12);
  const Branch parabola = ContinueFromBranchPoint(problem, bp, +1, options);
  INFO(parabola.BriefReport());
  REQUIRE(parabola.points.size() > 3);
  for (const BranchPoint& p : parabola.points)
    CHECK(std::abs(p.lambda - 2.0 - p.u(0) * p.u(0)) <= 1e-10);
}

}  // namespace
}  // namespace rubcont
