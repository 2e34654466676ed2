#include "models/textbook.h"

#include <algorithm>
#include <cmath>

#include <catch2/catch.hpp>

#include "solvers/constants.h"
#include "solvers/finite_difference.h"
#include "solvers/ode.h"

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
  const double h = kCentralDifferenceStep;
  oscillator.Rotate(h, plus);
  oscillator.Rotate(-h, minus);
  CHECK(((plus - minus) / (2.0 * h) - g).norm() < 1e-9);
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

// x(t1) from x(t0) = x0, by CVODES BDF at 1e-12.
Vector Flow(OdeSystem& system, const Vector& x0, double t0, double t1) {
  IntegratorOptions options;
  options.relative_tolerance = options.absolute_tolerance = 1e-12;
  options.max_steps = 10000000;
  OdeIntegrator integrator(system, options);
  Vector x1(x0.size());
  REQUIRE(integrator.Integrate(t0, x0, t1, x1).Succeeded());
  return x1;
}

// The times at which x(t) (state 0) crosses 0 upwards in [t0, t1], sampled at `dt` and refined by
// the cubic through the four samples around each crossing, from x(t0) = x0.
std::vector<double> UpwardZeros(OdeSystem& system, const Vector& x0, double t0, double t1,
                                double dt) {
  IntegratorOptions options;
  options.relative_tolerance = options.absolute_tolerance = 1e-12;
  options.max_steps = 10000000;
  OdeIntegrator integrator(system, options);
  const Index m = static_cast<Index>(std::ceil((t1 - t0) / dt)) + 1;
  const Vector times = Vector::LinSpaced(m, t0, t0 + dt * static_cast<double>(m - 1));
  Matrix states;
  REQUIRE(integrator.Sample(t0, x0, times, states).Succeeded());
  std::vector<double> zeros;
  for (Index k = 1; k + 2 < m; ++k) {
    if (!(states(0, k) < 0.0 && states(0, k + 1) >= 0.0)) continue;
    // Lagrange cubic through k − 1 … k + 2, its root by bisection on [t_k, t_k+1].
    auto cubic = [&](double t) {
      double sum = 0.0;
      for (Index i = k - 1; i <= k + 2; ++i) {
        double w = states(0, i);
        for (Index j = k - 1; j <= k + 2; ++j)
          if (j != i) w *= (t - times(j)) / (times(i) - times(j));
        sum += w;
      }
      return sum;
    };
    double a = times(k), b = times(k + 1);
    for (int i = 0; i < 60; ++i) (cubic(0.5 * (a + b)) < 0.0 ? a : b) = 0.5 * (a + b);
    zeros.push_back(0.5 * (a + b));
  }
  return zeros;
}

TEST_CASE("Duffing's start is the linear response: the periodic orbit when β = 0", "[textbook]") {
  DuffingParams p{0.05, 1.0, 0.0, 0.3, 1.4};
  DuffingOscillator linear(p);
  const ForcedStart start = DuffingStart(p);
  // x = A cos(w t − ψ) returns to itself after one forcing period, from the start on.
  const Vector after = Flow(linear, start.x0, 0.0, linear.ForcingPeriod());
  CHECK((after - start.x0).norm() < 1e-9 * start.x0.norm());
  // Its amplitude is F / √((k − w²)² + (c w)²).
  const double w = p.frequency;
  CHECK(start.x0.norm() > 0.0);
  CHECK(std::hypot(start.x0(0), start.x0(1) / w) ==
        Approx(p.force / std::hypot(p.stiffness - w * w, p.damping * w)).epsilon(1e-14));
  // About 20/c time units of settling: 20/(0.05 · 2π/1.4) = 89.1 periods; none without damping.
  CHECK(start.periods == 90);
  p.damping = 0.0;
  CHECK(DuffingStart(p).periods == 0);
  // Hardening (β = 1, the scene's): perturbations decay as e^(−c t/2), so its 20/c time units
  // bring the start e^(−10) = 4.5e-5 of the way to the orbit (measured: 0.033 → 1.3e-6).
  DuffingOscillator hardening({0.05, 1.0, 1.0, 0.3, 1.4});
  const ForcedStart h = DuffingStart(hardening.params());
  const double T = hardening.ForcingPeriod();
  const Vector settled = Flow(hardening, h.x0, 0.0, h.periods * T);
  const Vector orbit = Flow(hardening, settled, 0.0, 2000 * T);
  CHECK((Flow(hardening, orbit, 0.0, T) - orbit).norm() < 1e-9);
  CHECK((settled - orbit).norm() < 1e-4 * (h.x0 - orbit).norm());
}

TEST_CASE("Stuart–Landau's start settles onto the closed-form circle r = √λ", "[textbook]") {
  for (double lambda : {0.05, 0.5, 2.0}) {
    CAPTURE(lambda);
    StuartLandauOscillator oscillator({lambda, 1.2, 0.7});
    const CycleStart start = StuartLandauStart(oscillator.params());
    const Vector end = Flow(oscillator, start.x0, 0.0, start.duration);
    CHECK(end.norm() == Approx(oscillator.OrbitRadius()).epsilon(1e-9));
  }
}

TEST_CASE("van der Pol's start settles onto the cycle: Lindstedt's period for small μ",
          "[textbook]") {
  // ω = 1 − μ²/16 + 17 μ⁴/3072 + O(μ⁶) (Lindstedt–Poincaré): at μ = 0.05 the period 2π/ω to
  // about 1e-11 relative, 1.6e-4 above 2π.
  const double mu = 0.05;
  VanDerPolOscillator small({mu});
  const CycleStart start = VanDerPolStart(small.params());
  const Vector settled = Flow(small, start.x0, 0.0, start.duration);
  const std::vector<double> zeros = UpwardZeros(small, settled, 0.0, 20.0, 1e-3);
  REQUIRE(zeros.size() >= 3);
  const double omega = 1.0 - mu * mu / 16.0 + 17.0 * std::pow(mu, 4) / 3072.0;
  CHECK(zeros[2] - zeros[1] == Approx(kTwoPi / omega).epsilon(1e-8));
  CHECK(zeros[1] - zeros[0] == Approx(kTwoPi / omega).epsilon(1e-8));
  // Relaxation oscillations (μ = 10): settled, two successive periods agree.
  VanDerPolOscillator large({10.0});
  const CycleStart relaxation = VanDerPolStart(large.params());
  const Vector on_cycle = Flow(large, relaxation.x0, 0.0, relaxation.duration);
  const std::vector<double> jumps = UpwardZeros(large, on_cycle, 0.0, 60.0, 1e-3);
  REQUIRE(jumps.size() >= 3);
  CHECK(jumps[2] - jumps[1] == Approx(jumps[1] - jumps[0]).epsilon(1e-7));
}

TEST_CASE("Forced van der Pol's start settles towards the 1:1 locked orbit of averaging theory",
          "[textbook]") {
  const ForcedVanDerPolParams p{0.2, 0.1, 1.0};
  ForcedVanDerPolOscillator oscillator(p);
  const ForcedStart start = ForcedVanDerPolStart(p);
  CHECK(start.periods == 32);  // 40/(μ T) = 31.8
  const double T = oscillator.ForcingPeriod();
  const Vector settled = Flow(oscillator, start.x0, 0.0, start.periods * T);
  // The locked orbit, 1000 periods on: a fixed point of the period map.
  const Vector locked = Flow(oscillator, settled, 0.0, 1000 * T);
  CHECK((Flow(oscillator, locked, 1000 * T, 1001 * T) - locked).norm() < 1e-8);
  // First-order averaging at w = 1: the locked amplitude solves r (r²/4 − 1) = F/μ (r > 2).
  double lo = 2.0, hi = 3.0;
  for (int i = 0; i < 60; ++i) {
    const double r = 0.5 * (lo + hi);
    (r * (r * r / 4.0 - 1.0) < p.force / p.mu ? lo : hi) = r;
  }
  IntegratorOptions options;
  options.relative_tolerance = options.absolute_tolerance = 1e-12;
  OdeIntegrator integrator(oscillator, options);
  Matrix samples;
  REQUIRE(integrator.Sample(0.0, locked, Vector::LinSpaced(20001, 0.0, T), samples).Succeeded());
  CHECK(samples.row(0).maxCoeff() == Approx(0.5 * (lo + hi)).epsilon(5e-3));  // 2.2118 vs 2.2145
  // The start's periods bring it 70 times closer (3.2 → 0.046): the phase relaxes at about
  // F/(2r) ≈ 0.023 per time unit, e^(−0.023 · 32 T) = 0.01.
  CHECK((settled - locked).norm() < 0.02 * (start.x0 - locked).norm());
}

}  // namespace
}  // namespace rubcont
