#include "continuation/branch_switching.h"

#include <cmath>
#include <stdexcept>

#include <catch2/catch.hpp>

#include "continuation/continuation.h"
#include "solvers/constants.h"
#include "test_problems.h"

namespace rubcont {
namespace {

using testing::LambdaProblem;
using testing::Vec;

// x(λ − x²) = 0: the trivial branch x = 0 and the parabola λ = x² meet at a pitchfork at 0.
LambdaProblem Pitchfork() {
  return LambdaProblem(
      1, [](const Vector& u, double l, double, Vector& F) { F(0) = u(0) * (l - u(0) * u(0)); },
      [](const Vector& u, double l, double, Matrix& J) { J(0, 0) = l - 3 * u(0) * u(0); },
      [](const Vector& u, double, double, Vector& dF) { dF(0) = u(0); });
}

// x(λ − x) = 0: the branches x = 0 and x = λ cross obliquely at a transcritical point at 0.
LambdaProblem Transcritical() {
  return LambdaProblem(
      1, [](const Vector& u, double l, double, Vector& F) { F(0) = u(0) * (l - u(0)); },
      [](const Vector& u, double l, double, Matrix& J) { J(0, 0) = l - 2 * u(0); },
      [](const Vector& u, double, double, Vector& dF) { dF(0) = u(0); });
}

ContinuationOptions Bounded() {
  ContinuationOptions options;
  options.bounds.lambda_min = -1.0;
  options.bounds.lambda_max = 1.0;
  return options;
}

TEST_CASE("the pitchfork of x(λ − x²) is detected, located, and both new branches traced",
          "[continuation][branch_point]") {
  LambdaProblem problem = Pitchfork();
  const Branch trivial = Continue(problem, Vec({0.0}), -1.0, Bounded());
  INFO(trivial.BriefReport());
  REQUIRE(trivial.status == BranchStatus::kReachedLambdaBound);
  REQUIRE(trivial.Count(SpecialPointType::kBranchPoint) == 1);
  CHECK(trivial.Count(SpecialPointType::kFold) == 0);
  const SpecialPoint& bp = trivial.special_points.front();
  CHECK(bp.converged);
  CHECK(std::abs(bp.lambda) <= 1e-10);
  CHECK(std::abs(bp.u(0)) <= 1e-12);

  const BranchSwitch change = ComputeBranchSwitch(problem, bp);
  REQUIRE(change.ok);
  CHECK(std::abs(change.tangent(0)) ==
        Approx(1.0).epsilon(0).margin(1e-6));  // the other branch is vertical
  CHECK(change.angle == Approx(kPi / 2).epsilon(0).margin(1e-6));

  double end_x[2] = {0.0, 0.0};
  for (int side : {+1, -1}) {
    const Branch other = ContinueFromBranchPoint(problem, bp, side, Bounded());
    INFO(other.BriefReport());
    REQUIRE(other.status == BranchStatus::kReachedLambdaBound);
    CHECK(other.points.front().lambda == bp.lambda);  // starts at the branch point
    for (size_t i = 1; i < other.points.size(); ++i) {
      const BranchPoint& p = other.points[i];
      CHECK(std::abs(p.u(0) * p.u(0) - p.lambda) <= 1e-10);  // on the parabola, not x = 0
      CHECK(p.u(0) * side > 0.0);
    }
    CHECK(other.points.back().lambda == Approx(1.0).epsilon(0).margin(1e-12));
    end_x[side > 0 ? 0 : 1] = other.points.back().u(0);
    // Nothing is detected in the first step out of the branch point.
    CHECK(other.Count(SpecialPointType::kBranchPoint) == 0);
  }
  CHECK(end_x[0] == Approx(1.0).epsilon(0).margin(1e-9));
  CHECK(end_x[1] == Approx(-1.0).epsilon(0).margin(1e-9));
}

// x(λ − x²) = 0 in coordinates that mix the unknowns, (x, y) = (a + b, a − b), with y = λ/2 on
// every branch, and a Jacobian that is off by 1e-6 (as a shooting Jacobian is consistent with
// its residual only to the integration's accuracy): near the branch point the computed tangent
// is any direction of the nearly two-dimensional kernel.
LambdaProblem MixedPitchfork() {
  return LambdaProblem(
      2,
      [](const Vector& u, double l, double, Vector& F) {
        const double x = u(0) + u(1), y = u(0) - u(1);
        F(0) = x * (l - x * x);
        F(1) = y - 0.5 * l;
      },
      [](const Vector& u, double l, double, Matrix& J) {
        const double x = u(0) + u(1), d = l - 3 * x * x;
        J << d + 1e-6, d - 1e-6, 1, -1;
      },
      [](const Vector& u, double, double, Vector& dF) {
        dF(0) = u(0) + u(1);
        dF(1) = -0.5;
      });
}

TEST_CASE("a branch point located on the determinant keeps the incoming tangent for switching",
          "[continuation][branch_point]") {
  LambdaProblem problem = MixedPitchfork();
  ContinuationOptions options = Bounded();
  options.location.branch_point_newton_max_unknowns = 0;  // Illinois on det, as for shooting
  const Vector start = Vec({-0.25, 0.25});               // x = 0, y = λ/2 at λ = −1
  const Branch trivial = Continue(problem, start, -1.0, options);
  INFO(trivial.BriefReport());
  REQUIRE(trivial.Count(SpecialPointType::kBranchPoint) == 1);
  const SpecialPoint& bp = trivial.special_points.front();
  CHECK(std::abs(bp.lambda) <= 1e-8);
  // The stored tangent is the trivial branch's, x' = a' + b' = 0, up to the Jacobian's error over
  // the distance of the last point before it (4.7e-5); the other branch's would give √2.
  REQUIRE(bp.tangent.size() == 3);
  CHECK(std::abs(bp.tangent(0) + bp.tangent(1)) <= 1e-3);
  for (int side : {+1, -1}) {
    const Branch other = ContinueFromBranchPoint(problem, bp, side, options);
    INFO(other.BriefReport());
    REQUIRE(other.status == BranchStatus::kReachedLambdaBound);
    const BranchPoint& end = other.points.back();
    const double x = end.u(0) + end.u(1);
    CHECK(x * x == Approx(end.lambda).epsilon(0).margin(1e-9));  // on the parabola, not on x = 0
    CHECK(x * side > 0.5);
  }
}

TEST_CASE("switching at a transcritical point follows the oblique branch x = λ",
          "[continuation][branch_point]") {
  LambdaProblem problem = Transcritical();
  const Branch trivial = Continue(problem, Vec({0.0}), -1.0, Bounded());
  REQUIRE(trivial.Count(SpecialPointType::kBranchPoint) == 1);
  const SpecialPoint& bp = trivial.special_points.front();
  CHECK(std::abs(bp.lambda) <= 1e-10);
  const BranchSwitch change = ComputeBranchSwitch(problem, bp);
  REQUIRE(change.ok);
  // The ABE gives the direction (1, 1)/√2 and the angle π/4 between the branches.
  CHECK(change.tangent(0) == Approx(M_SQRT1_2).epsilon(0).margin(1e-6));
  CHECK(change.tangent(1) == Approx(M_SQRT1_2).epsilon(0).margin(1e-6));
  CHECK(change.angle == Approx(kPi / 4).epsilon(0).margin(1e-6));
  for (int side : {+1, -1}) {
    const Branch other = ContinueFromBranchPoint(problem, bp, side, Bounded());
    INFO(other.BriefReport());
    REQUIRE(other.status == BranchStatus::kReachedLambdaBound);
    for (const BranchPoint& p : other.points) CHECK(std::abs(p.u(0) - p.lambda) <= 1e-10);
    CHECK(other.points.back().lambda == Approx(side).epsilon(0).margin(1e-12));
  }
}

TEST_CASE("branch switching rejects points that are not branch points",
          "[continuation][branch_point]") {
  LambdaProblem problem = Pitchfork();
  SpecialPoint fold;
  fold.type = SpecialPointType::kFold;
  fold.u = Vec({0.0});
  CHECK_THROWS_AS(ContinueFromBranchPoint(problem, fold, 1), std::invalid_argument);
  // A regular point of the trivial branch: the kernel is one-dimensional, the ABE has no root
  // pair, and the start fails with a status.
  SpecialPoint regular;
  regular.type = SpecialPointType::kBranchPoint;
  regular.u = Vec({0.0});
  regular.lambda = 0.5;
  regular.tangent = Vec({0.0, 1.0});
  const Branch branch = ContinueFromBranchPoint(problem, regular, 1, Bounded());
  CHECK(branch.status == BranchStatus::kStartFailed);
}

}  // namespace
}  // namespace rubcont
