#include "solvers/scalar_root.h"

#include <cmath>
#include <stdexcept>

#include <catch2/catch.hpp>

namespace rubcont {
namespace {

TEST_CASE("Illinois finds the root of cos x − x within the bracket tolerance", "[scalar_root]") {
  int evaluations = 0;
  auto f = [&evaluations](double x, double& value) {
    ++evaluations;
    value = std::cos(x) - x;
    return true;
  };
  BracketedRootOptions options;
  options.x_tolerance = 1e-13;
  const BracketedRootResult r = IllinoisRoot(f, 0.0, 1.0, 1.0, std::cos(1.0) - 1.0, options);
  REQUIRE(r.Converged());
  const double root = 0.7390851332151607;  // the Dottie number
  CHECK(std::abs(r.x - root) <= 1e-13);
  CHECK(r.lower <= root);
  CHECK(r.upper >= root);
  CHECK(r.upper - r.lower <= 1e-13);
  CHECK(r.evaluations == evaluations);
  CHECK(evaluations <= 12);  // superlinear: bisection would need 44
}

TEST_CASE("a near-exact secant step closes the bracket at once", "[scalar_root]") {
  int evaluations = 0;
  auto f = [&evaluations](double x, double& value) {
    ++evaluations;
    value = 0.5 * (x - 0.3);
    return true;
  };
  const BracketedRootResult r = IllinoisRoot(f, 0.0, -0.15, 1.0, 0.35);
  REQUIRE(r.Converged());
  CHECK(std::abs(r.x - 0.3) <= 1e-12);
  CHECK(evaluations <= 3);
}

TEST_CASE("a failed evaluation falls back to the midpoint once, then reports",
          "[scalar_root]") {
  auto fails_left = [](double x, double& value) {
    if (x < 0.4) return false;  // the secant's first trial (x ≈ 0.33) cannot be evaluated
    value = x - 0.7;
    return true;
  };
  const BracketedRootResult r = IllinoisRoot(fails_left, 0.0, -1.0, 1.0, 2.0);
  REQUIRE(r.Converged());
  CHECK(std::abs(r.x - 0.7) <= 1e-12);
  auto always_fails = [](double, double&) { return false; };
  const BracketedRootResult bad = IllinoisRoot(always_fails, 0.0, -1.0, 1.0, 1.0);
  CHECK(bad.status == BracketedRootStatus::kEvaluationFailed);
}

TEST_CASE("Illinois needs a sign change and valid options", "[scalar_root]") {
  auto f = [](double x, double& value) {
    value = x;
    return true;
  };
  CHECK_THROWS_AS(IllinoisRoot(f, 1.0, 1.0, 2.0, 2.0), std::invalid_argument);
  BracketedRootOptions options;
  options.x_tolerance = 0.0;
  CHECK_THROWS_WITH(IllinoisRoot(f, -1.0, -1.0, 2.0, 2.0, options),
                    Catch::Contains("x_tolerance"));
  // An exact zero at an end is a root.
  const BracketedRootResult r = IllinoisRoot(f, 0.0, 0.0, 2.0, 2.0);
  CHECK(r.Converged());
  CHECK(r.x == 0.0);
}

TEST_CASE("a jump or a pole converges like a zero, and the values at the ends tell them apart",
          "[scalar_root]") {
  // The k-th eigenvalue's real part when the spectrum's order changes within a step.
  auto jump = [](double x, double& value) {
    value = x < 0.3 ? -2.0 : 3.0;
    return true;
  };
  BracketedRootOptions options;
  options.x_tolerance = 1e-9;
  const BracketedRootResult r = IllinoisRoot(jump, 0.0, -2.0, 1.0, 3.0, options);
  REQUIRE(r.Converged());
  CHECK(r.lower <= 0.3);
  CHECK(r.upper >= 0.3);
  CHECK(r.f_lower == -2.0);  // as large as at the start: what tells a jump from a zero
  CHECK(r.f_upper == 3.0);   // (continuation's ArcRoot::discontinuous)
  // A pole, 1/(x − 0.3): the ends grow as the bracket shrinks.
  auto pole = [](double x, double& value) {
    value = 1.0 / (x - 0.3);
    return true;
  };
  const BracketedRootResult p = IllinoisRoot(pole, 0.0, -1.0 / 0.3, 1.0, 1.0 / 0.7, options);
  REQUIRE(p.Converged());
  CHECK(std::abs(p.lower - 0.3) <= 1e-9);
  CHECK(std::max(std::abs(p.f_lower), std::abs(p.f_upper)) > 1e6);
  // At a zero both ends come down.
  auto root = [](double x, double& value) {
    value = std::cos(x) - x;
    return true;
  };
  const BracketedRootResult z = IllinoisRoot(root, 0.0, 1.0, 1.0, std::cos(1.0) - 1.0, options);
  REQUIRE(z.Converged());
  CHECK(std::max(std::abs(z.f_lower), std::abs(z.f_upper)) < 1e-8);
}

}  // namespace
}  // namespace rubcont
