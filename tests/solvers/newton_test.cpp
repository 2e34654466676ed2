#include "solvers/newton.h"

#include <cmath>
#include <stdexcept>

#include <catch2/catch.hpp>

namespace rubcont {
namespace {

TEST_CASE("Newton converges quadratically on a scaled 2×2 system", "[newton]") {
  // x0 = 2e-4 m, x1 = 1500 N solve: 1e7 x0² − 0.4 = 0 and x1 − 7.5e6 x0 = 0.
  auto residual = [](const Vector& x, Vector& F) {
    F.resize(2);
    F << 1e7 * x(0) * x(0) - 0.4, x(1) - 7.5e6 * x(0);
  };
  auto jacobian = [](const Vector& x, Matrix& J) {
    J.resize(2, 2);
    J << 2e7 * x(0), 0.0, -7.5e6, 1.0;
  };
  Vector x(2);
  x << 3e-4, 1000.0;
  const Vector x_scale = (Vector(2) << 1e-4, 1e3).finished();
  const Vector F_scale = (Vector(2) << 1.0, 1e3).finished();
  const NewtonResult result = NewtonSolve(residual, jacobian, x, {}, x_scale, F_scale);
  REQUIRE(result.Converged());
  CHECK(result.iterations <= 6);
  CHECK(x(0) == Approx(2e-4).epsilon(1e-12));
  CHECK(x(1) == Approx(1500.0).epsilon(1e-12));
}

TEST_CASE("Newton reports a singular Jacobian as a status", "[newton]") {
  auto residual = [](const Vector& x, Vector& F) { F = Vector::Constant(1, x(0) * x(0) + 1.0); };
  auto jacobian = [](const Vector& x, Matrix& J) { J = Matrix::Constant(1, 1, 2.0 * x(0)); };
  Vector x = Vector::Zero(1);
  const NewtonResult result = NewtonSolve(residual, jacobian, x);
  CHECK(result.status == NewtonStatus::kSingularJacobian);
}

TEST_CASE("Newton reports non-convergence, never throws", "[newton]") {
  // x² + 1 = 0 has no real root: the iteration wanders.
  auto residual = [](const Vector& x, Vector& F) { F = Vector::Constant(1, x(0) * x(0) + 1.0); };
  auto jacobian = [](const Vector& x, Matrix& J) { J = Matrix::Constant(1, 1, 2.0 * x(0)); };
  Vector x = Vector::Constant(1, 0.7);
  const NewtonResult result = NewtonSolve(residual, jacobian, x);
  CHECK_FALSE(result.Converged());
}

TEST_CASE("Newton with step halvings: a full step into a region without a residual is halved",
          "[newton]") {
  // x² − 4 = 0, with no residual (NaN) beyond x = 10, as a map whose integration fails there.
  // From 0.1 the full step lands at 20.05: without halvings that ends the solve, with them the
  // step is halved until its residual is finite and smaller, and Newton goes on to 2.
  auto residual = [](const Vector& x, Vector& F) {
    F = Vector::Constant(1, x(0) > 10.0 ? std::nan("") : x(0) * x(0) - 4.0);
  };
  auto jacobian = [](const Vector& x, Matrix& J) { J = Matrix::Constant(1, 1, 2.0 * x(0)); };
  Vector x = Vector::Constant(1, 0.1);
  CHECK(NewtonSolve(residual, jacobian, x).status == NewtonStatus::kNonFinite);
  NewtonOptions options;
  options.max_step_halvings = 4;
  options.max_iterations = 30;
  x = Vector::Constant(1, 0.1);
  const NewtonResult result = NewtonSolve(residual, jacobian, x, options);
  INFO(result.BriefReport());
  REQUIRE(result.Converged());
  CHECK(x(0) == Approx(2.0).epsilon(1e-12));
  // Without halvings the same start converges where the full steps keep a residual: from 3.
  x = Vector::Constant(1, 3.0);
  const NewtonResult full = NewtonSolve(residual, jacobian, x);
  CHECK(full.Converged());
  CHECK(x(0) == Approx(2.0).epsilon(1e-12));
}

TEST_CASE("invalid Newton options are rejected with the field name", "[newton]") {
  NewtonOptions options;
  options.max_iterations = 0;
  CHECK_THROWS_WITH(Validate(options), Catch::Contains("max_iterations"));
  options = NewtonOptions();
  options.max_step_halvings = -1;
  CHECK_THROWS_WITH(Validate(options), Catch::Contains("max_step_halvings"));
}

}  // namespace
}  // namespace rubcont
