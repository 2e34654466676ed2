#include "solvers/finite_difference.h"

#include <cmath>

#include <catch2/catch.hpp>

namespace rubcont {
namespace {

// f(x) = (x0² x1, sin(x0) + 1e3 x1, 1e-4 exp(x1)) with unknowns of very different magnitude.
void Function(const Vector& x, Vector& f) {
  f.resize(3);
  f << x(0) * x(0) * x(1), std::sin(x(0)) + 1e3 * x(1), 1e-4 * std::exp(x(1));
}

Matrix ExactJacobian(const Vector& x) {
  Matrix J(3, 2);
  J << 2 * x(0) * x(1), x(0) * x(0),
       std::cos(x(0)), 1e3,
       0.0, 1e-4 * std::exp(x(1));
  return J;
}

TEST_CASE("central differences match the exact Jacobian to 1e-8", "[finite_difference]") {
  Vector x(2);
  x << 0.7, -1.3e-4;
  const Vector typical = (Vector(2) << 1.0, 1e-4).finished();
  Matrix J;
  FiniteDifferenceJacobian(Function, x, 3, J, {}, &typical);
  const Matrix exact = ExactJacobian(x);
  CHECK((J - exact).cwiseAbs().maxCoeff() <= 1e-8 * exact.cwiseAbs().maxCoeff());
}

TEST_CASE("CheckJacobian accepts the exact Jacobian and rejects a wrong entry", "[finite_difference]") {
  Vector x(2);
  x << 0.7, -1.3e-4;
  const Vector typical = (Vector(2) << 1.0, 1e-4).finished();
  Matrix J = ExactJacobian(x);
  CHECK(CheckJacobian(Function, x, J, 1e-6, &typical).ok);
  J(1, 0) *= -1.0;  // a sign error
  const JacobianCheck check = CheckJacobian(Function, x, J, 1e-6, &typical);
  CHECK_FALSE(check.ok);
  CHECK(check.worst_row == 1);
  CHECK(check.worst_col == 0);
}

TEST_CASE("directional derivative equals J v", "[finite_difference]") {
  Vector x(2), v(2);
  x << 0.3, 0.2;
  v << -0.5, 2.0;
  Vector dfdv;
  FiniteDifferenceDirectional(Function, x, v, 3, dfdv);
  const Vector exact = ExactJacobian(x) * v;
  CHECK((dfdv - exact).norm() <= 1e-7 * exact.norm());
}

}  // namespace
}  // namespace rubcont
