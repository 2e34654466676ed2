#include "models/textbook.h"

#include <cmath>

#include <catch2/catch.hpp>

#include "solvers/constants.h"
#include "solvers/finite_difference.h"

namespace rubcont {
namespace {

// Checks the analytic ∂f/∂x and ∂f/∂p of `system` at (t, x) against central differences.
void CheckDerivatives(OdeSystem& system, double t, const Vector& x) {
  const Index n = system.Dimension();
  Matrix J(n, n);
  system.JacobianX(t, x, J);
  const JacobianCheck check = CheckJacobian(
      [&](const Vector& y, Vector& f) {
        f.resize(n);
        system.Rhs(t, y, f);
      },
      x, J, 1e-7);
  CAPTURE(check.worst_row, check.worst_col, check.analytic_value, check.difference_value);
  CHECK(check.ok);

  Vector analytic(n);
  system.DfDparameter(t, x, analytic);
  const double p = system.Parameter();
  const Vector parameter = Vector::Constant(1, p);
  Matrix dfdp(n, 1);
  dfdp.col(0) = analytic;
  const JacobianCheck parameter_check = CheckJacobian(
      [&](const Vector& q, Vector& f) {
        f.resize(n);
        system.SetParameter(q(0));
        system.Rhs(t, x, f);
        system.SetParameter(p);
      },
      parameter, dfdp, 1e-7);
  CAPTURE(parameter_check.worst_row, parameter_check.analytic_value,
          parameter_check.difference_value);
  CHECK(parameter_check.ok);
}

TEST_CASE("Duffing: analytic Jacobian and ∂f/∂w match differences — forcing period 2π/w",
          "[textbook]") {
  DuffingOscillator duffing({0.05, 1.0, 1.0, 0.3, 1.4});
  CheckDerivatives(duffing, 0.7, (Vector(2) << 1.3, -0.4).finished());
  CheckDerivatives(duffing, 3.1, (Vector(2) << -0.2, 2.0).finished());
  CHECK(duffing.ForcingPeriod() == Approx(kTwoPi / 1.4).epsilon(1e-15));
  duffing.SetParameter(2.0);
  CHECK(duffing.ForcingPeriod() == Approx(kPi).epsilon(1e-15));
  CHECK_THROWS_WITH(DuffingOscillator({0.05, 1.0, 1.0, 0.3, 0.0}), Catch::Contains("frequency"));
}

TEST_CASE("Stuart–Landau: derivatives, equivariance, and the closed-form orbit", "[textbook]") {
  StuartLandauOscillator oscillator({0.4, 1.2, 0.7});
  const Vector x = (Vector(2) << 0.3, -0.8).finished();
  CheckDerivatives(oscillator, 0.0, x);
  // f(R_φ x) = R_φ f(x).
  const double phi = 0.9;
  Vector rotated = x, f(2), f_rotated(2);
  oscillator.Rotate(phi, rotated);
  oscillator.Rhs(0.0, x, f);
  oscillator.Rhs(0.0, rotated, f_rotated);
  oscillator.Rotate(phi, f);
  CHECK((f_rotated - f).norm() < 1e-15);
  // The generator is d/dφ R_φ x at φ = 0.
  Vector g(2), plus = x, minus = x;
  oscillator.RotationGenerator(x, g);
  oscillator.Rotate(1e-6, plus);
  oscillator.Rotate(-1e-6, minus);
  CHECK(((plus - minus) / 2e-6 - g).norm() < 1e-9);
  // On the circle r = √λ the field is tangent with angular velocity ω − γλ.
  Vector on_orbit(2);
  on_orbit << oscillator.OrbitRadius(), 0.0;
  oscillator.Rhs(0.0, on_orbit, f);
  CHECK(f(0) == Approx(0.0).epsilon(0).margin(1e-15));
  CHECK(f(1) / on_orbit(0) == Approx(oscillator.AngularVelocity()).epsilon(1e-14));
  CHECK(oscillator.AngularVelocity() == Approx(1.2 - 0.7 * 0.4));
  CHECK(oscillator.Period() == Approx(kTwoPi / (1.2 - 0.7 * 0.4)));
  CHECK(oscillator.NontrivialMultiplier() == Approx(std::exp(-0.8 * oscillator.Period())));
}

TEST_CASE("van der Pol: derivatives and scales", "[textbook]") {
  for (double mu : {1.0, 10.0, 1000.0, -10.0}) {
    CAPTURE(mu);
    VanDerPolOscillator oscillator({mu});
    CheckDerivatives(oscillator, 0.0, (Vector(2) << 1.7, -0.03 * mu).finished());
    CHECK(oscillator.StateScale()(1) == Approx(std::max(2.0, 4 * std::abs(mu) / 3)));
  }
  CHECK_THROWS_WITH(VanDerPolOscillator({kNaN}), Catch::Contains("mu"));
}

TEST_CASE("Forced van der Pol: derivatives, forcing period and scales", "[textbook]") {
  ForcedVanDerPolOscillator oscillator({2.0, 0.3, 1.2});
  CheckDerivatives(oscillator, 0.7, (Vector(2) << 1.3, -0.4).finished());
  CheckDerivatives(oscillator, 5.3, (Vector(2) << -2.1, 3.0).finished());
  CHECK(oscillator.ForcingPeriod() == Approx(kTwoPi / 1.2).epsilon(1e-15));
  CHECK(oscillator.StateScale()(1) == Approx(8.0 / 3.0));
  CHECK_THROWS_WITH(ForcedVanDerPolOscillator({0.2, 0.1, -1.0}), Catch::Contains("frequency"));
  CHECK_THROWS_WITH(ForcedVanDerPolOscillator({0.2, kNaN, 1.0}), Catch::Contains("force"));
}

}  // namespace
}  // namespace rubcont
