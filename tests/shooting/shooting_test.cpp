#include "shooting/shooting.h"

#include <cmath>
#include <utility>

#include <catch2/catch.hpp>

#include "models/textbook.h"
#include "models/units.h"
#include "solvers/finite_difference.h"
#include "solvers/newton.h"
#include "tests/shooting/shooting_with.h"
#include "tests/shooting/traced_newton.h"

namespace rubcont {
namespace {

NewtonResult Solve(ShootingProblem& problem, Vector& u, double lambda,
                   const NewtonOptions& options = {}) {
  return NewtonSolve([&](const Vector& v, Vector& F) { problem.Residual(v, lambda, F); },
                     [&](const Vector& v, Matrix& J) { problem.Jacobian(v, lambda, J); }, u,
                     options, problem.Scale(), problem.ResidualScale());
}

// ---------------------------------------------------------------------------------------------
// Stuart–Landau: orbit r = √λ, period 2π/(ω − γλ), multipliers 1 and e^{−2λT}, in closed form.

TEST_CASE("Stuart–Landau orbit, period and multipliers in closed form, single and multiple "
          "shooting, CVODES BDF and Gauss collocation",
          "[shooting]") {
  const double lambda = 0.5;
  StuartLandauOscillator oscillator({lambda, 1.0, 0.4});
  const double radius = oscillator.OrbitRadius();
  const double period = oscillator.Period();
  const double multiplier = oscillator.NontrivialMultiplier();
  // Segments, and Gauss steps per segment (0: BDF): 100 steps of order 8 over the 7.9 period.
  for (const auto& [segments, gauss_steps] : {std::pair{1, 0L}, {5, 0L}, {1, 100L}, {5, 20L}}) {
    CAPTURE(segments, gauss_steps);
    ShootingOptions options = ShootingWith(segments);
    if (gauss_steps > 0) {
      options.integrator.method = IntegrationMethod::kGaussCollocation;
      options.integrator.collocation_steps = gauss_steps;
    }
    ShootingProblem problem(oscillator, OrbitKind::kAutonomous, options);
    REQUIRE(problem.Dimension() == 2 * segments + 1);
    // A guess off the orbit in radius (0.6 against 0.707) and period (10 %).
    Vector u = problem.InitialGuess((Vector(2) << 0.6, 0.1).finished(), 1.1 * period, lambda);
    const NewtonResult newton = Solve(problem, u, lambda);
    INFO(newton.BriefReport());
    REQUIRE(newton.Converged());
    // At the default rtol = atol = 1e-10 the BDF global error over a period is ≈ 3e-9 (measured):
    // the orbit is as accurate as its integration, not as the Newton tolerance.
    for (Index i = 0; i < segments; ++i) {
      CHECK(problem.SegmentStart(u, i).norm() == Approx(radius).epsilon(1e-8));
    }
    CHECK(problem.Period(u, lambda) == Approx(period).epsilon(1e-8));

    const Spectrum spectrum = problem.Stability(u, lambda);
    REQUIRE(spectrum.valid);
    CHECK(spectrum.kind == SpectrumKind::kFloquetMultipliers);
    CHECK(spectrum.trivial_removed == 1);
    REQUIRE(spectrum.values.size() == 1);
    CHECK(std::abs(spectrum.values(0).real() - multiplier) < 1e-8);  // multiplier ≈ 3.9e-4
    CHECK(spectrum.values(0).imag() == 0.0);
    CHECK(spectrum.Stable());
    const FloquetResult floquet = problem.Floquet(u, lambda);
    CHECK(std::abs(floquet.trivial(0) - 1.0) < 1e-8);
    CHECK(floquet.invariance_defect < 1e-8);

    // Measures: period first, then max/min of each state (max x = √λ on the circle), refined by a
    // parabola through 64 samples per segment: error ≈ (2π/64)⁴/24 ≈ 4e-6 relative.
    const std::vector<std::string> names = problem.MeasureNames();
    REQUIRE(names.size() == 5);
    CHECK(names[0] == "period");
    CHECK(names[1] == "max_x0");
    const Vector measures = problem.Measures(u, lambda);
    CHECK(measures(0) == problem.Period(u, lambda));
    CHECK(measures(1) == Approx(radius).epsilon(1e-5));
    CHECK(measures(2) == Approx(-radius).epsilon(1e-5));
  }
}

// ---------------------------------------------------------------------------------------------
// Relative periodic orbits.
//
// A system on C² ≅ R⁴, equivariant under z ↦ e^{iφ} z (both coordinates), built so that its
// relative periodic orbit is known independently:
//   ż₁ = z₁ (1 − |z₁|² + i h),    ż₂ = i h z₂ + z₁ G(s),
//   s = z₂ z̄₁ = p + i q (invariant),  h = ω₀ + κ p²,  G(s) = q + i (μ (1 − p²) q − p).
// Then r = |z₁| obeys ṙ = r (1 − r²) (attracting r = 1) and, on r = 1, ṡ = G(s): (p, q) is a van der
// Pol oscillator. The orbit with |z₁| = 1 and s on the van der Pol cycle returns after the van der
// Pol period T rotated by φ = ∫₀ᵀ h dt = ω₀ T + κ ∫₀ᵀ p² dt: x(T) = R_φ x(0). Its multipliers are
// 1 (time), 1 (rotation), e^{−2T} (radial) and the van der Pol one, exp ∫₀ᵀ μ (1 − p²) dt. In the
// fixed frame it is quasi-periodic: no periodic orbit exists near it.
class ModulatedOscillator : public OdeSystem {
 public:
  double mu = 1.0, omega = 1.0, kappa = 0.5;

  Index Dimension() const override { return 4; }
  void Rhs(double, ConstVectorRef x, VectorRef f) override {
    const std::complex<double> z1(x(0), x(1)), z2(x(2), x(3));
    const std::complex<double> s = z2 * std::conj(z1);
    const double p = s.real(), q = s.imag();
    const double h = omega + kappa * p * p;
    const std::complex<double> G(q, mu * (1 - p * p) * q - p);
    const std::complex<double> i(0.0, 1.0);
    const std::complex<double> dz1 = z1 * (1.0 - std::norm(z1) + i * h);
    const std::complex<double> dz2 = i * h * z2 + z1 * G;
    f << dz1.real(), dz1.imag(), dz2.real(), dz2.imag();
  }
  double Parameter() const override { return mu; }
  void SetParameter(double value) override { mu = value; }
  bool HasRotationSymmetry() const override { return true; }
  void Rotate(double phi, VectorRef x) const override {
    const std::complex<double> r = std::polar(1.0, phi);
    const std::complex<double> z1 = r * std::complex<double>(x(0), x(1));
    const std::complex<double> z2 = r * std::complex<double>(x(2), x(3));
    x << z1.real(), z1.imag(), z2.real(), z2.imag();
  }
  void RotationGenerator(ConstVectorRef x, VectorRef g) const override {
    g << -x(1), x(0), -x(3), x(2);
  }
};

TEST_CASE("shooting Jacobian and ∂F/∂λ agree with finite differences (autonomous, forced, relative — "
          "single and multiple)",
          "[shooting]") {
  // Tight integration so that differences (step ~1e-6 relative) see only O(1e-12 / 1e-6) noise.
  StuartLandauOscillator oscillator({0.3, 1.0, 0.7});
  DuffingOscillator duffing({0.05, 1.0, 1.0, 0.3, 1.5});
  ModulatedOscillator modulated;
  struct Case {
    OdeSystem* system;
    OrbitKind kind;
    int segments;
    Vector x0;
    double period;
    double rotation = 0.0;
  };
  const std::vector<Case> cases = {
      {&oscillator, OrbitKind::kAutonomous, 1, (Vector(2) << 0.5, 0.1).finished(), 8.0},
      {&oscillator, OrbitKind::kAutonomous, 3, (Vector(2) << 0.5, 0.1).finished(), 8.0},
      {&duffing, OrbitKind::kForced, 1, (Vector(2) << 0.4, -0.2).finished(), 0.0},
      {&duffing, OrbitKind::kForced, 3, (Vector(2) << 0.4, -0.2).finished(), 0.0},
      {&modulated, OrbitKind::kRelative, 1, (Vector(4) << 1.0, 0.0, 1.9, 0.1).finished(), 6.8, 1.3},
      {&modulated, OrbitKind::kRelative, 2, (Vector(4) << 1.0, 0.0, 1.9, 0.1).finished(), 6.8, 1.3},
  };
  for (const Case& c : cases) {
    CAPTURE(ToString(c.kind), c.segments);
    const double lambda = c.system->Parameter();
    ShootingProblem problem(*c.system, c.kind, ShootingWith(c.segments, 1e-12));
    Vector u = problem.InitialGuess(c.x0, c.period, lambda, c.rotation);
    // Off the trajectory, so that every block of F is nonzero.
    u.head(c.segments * c.system->Dimension()).array() += 0.01;
    Matrix J, difference_jacobian;
    problem.Jacobian(u, lambda, J);
    const Vector typical = problem.Scale();
    FiniteDifferenceJacobian([&](const Vector& v, Vector& F) { problem.Residual(v, lambda, F); },
                             u, u.size(), difference_jacobian, {}, &typical);
    // Compared in the scaled variables Newton uses. A residual that is an integration result is
    // reproducible only to ≈ 1e-12 (measured: the round-off of thousands of steps; tightening rtol
    // below 1e-12 does not lower it), so its central differences (step 6e-6) carry ≈ 2e-7 of
    // noise: entries are compared absolutely, to 1e-6 of the largest. A wrong block (a sign, a
    // missing f(y_i)·Δτ or −g(R_φ x_0) term) is off by far more.
    const Matrix scaled_error = problem.ResidualScale().cwiseInverse().asDiagonal() *
                                (J - difference_jacobian) * typical.asDiagonal();
    const Matrix scaled_jacobian =
        problem.ResidualScale().cwiseInverse().asDiagonal() * J * typical.asDiagonal();
    CHECK(scaled_error.cwiseAbs().maxCoeff() <= 1e-6 * scaled_jacobian.cwiseAbs().maxCoeff());

    Vector sensitivity;
    problem.DfDlambda(u, lambda, sensitivity);
    ShootingOptions fd_options = ShootingWith(c.segments, 1e-12);
    fd_options.lambda_derivative = LambdaDerivative::kFiniteDifference;
    ShootingProblem fd_problem(*c.system, c.kind, fd_options);
    fd_problem.SetPhaseReference(problem.InitialGuess(c.x0, c.period, lambda, c.rotation), lambda);
    Vector difference;
    fd_problem.DfDlambda(u, lambda, difference);
    CHECK((sensitivity - difference).norm() <= 1e-6 * difference.norm());
    CHECK(difference.norm() > 1e-3);  // the comparison is not between two zeros
  }
}

TEST_CASE("integrations are cached: Residual, Jacobian, ∂F/∂λ and Stability at one point "
          "integrate twice",
          "[shooting]") {
  StuartLandauOscillator oscillator({0.5, 1.0, 0.0});
  ShootingProblem problem(oscillator, OrbitKind::kAutonomous, ShootingWith(4));
  const Vector u = problem.InitialGuess((Vector(2) << 0.7, 0.0).finished(), 6.0, 0.5);
  problem.ResetStatistics();
  Vector F, F_again, dF;
  Matrix J;
  problem.Residual(u, 0.5, F);
  problem.Jacobian(u, 0.5, J);
  problem.DfDlambda(u, 0.5, dF);
  problem.Stability(u, 0.5);
  problem.Residual(u, 0.5, F_again);
  CHECK(F_again == F);  // the residual of a point does not change when sensitivities arrive
  CHECK(problem.statistics().residual_integrations == 4);     // one per segment
  CHECK(problem.statistics().sensitivity_integrations == 4);  // one per segment
  CHECK(problem.statistics().cache_hits == 3);
}

TEST_CASE("a cheap Jacobian without sensitivity error control, with accurate multipliers",
          "[shooting]") {
  StuartLandauOscillator oscillator({0.5, 1.0, 0.4});
  ShootingOptions options = ShootingWith(3);
  options.integrator.sensitivity_error_control = false;  // Newton's Jacobian
  ShootingProblem problem(oscillator, OrbitKind::kAutonomous, options);
  Vector u = problem.InitialGuess((Vector(2) << 0.6, 0.1).finished(), 8.0, 0.5);
  const NewtonResult newton = Solve(problem, u, 0.5);
  REQUIRE(newton.Converged());
  problem.ResetStatistics();
  const Spectrum spectrum = problem.Stability(u, 0.5);
  // Stability integrated the three segments again, under error control.
  CHECK(problem.statistics().sensitivity_integrations == 3);
  REQUIRE(spectrum.valid);
  CHECK(std::abs(spectrum.values(0).real() - oscillator.NontrivialMultiplier()) < 1e-8);
  problem.Stability(u, 0.5);
  CHECK(problem.statistics().sensitivity_integrations == 3);  // cached
}

// A trajectory that blows up in finite time: ẋ = x², ẏ = 1.
class BlowUp : public OdeSystem {
 public:
  Index Dimension() const override { return 2; }
  void Rhs(double, ConstVectorRef x, VectorRef f) override {
    f(0) = x(0) * x(0);
    f(1) = 1.0;
  }
  double Parameter() const override { return 0.0; }
  void SetParameter(double) override {}
};

TEST_CASE("integration failures give NaN residuals and a reason, never an exception", "[shooting]") {
  BlowUp system;
  ShootingProblem problem(system, OrbitKind::kAutonomous, ShootingWith(2));
  Vector u = problem.InitialGuess((Vector(2) << 0.1, 0.0).finished(), 1.0, 0.0);
  u(u.size() - 1) = 30.0;  // x reaches infinity at t = 10
  Vector F;
  problem.Residual(u, 0.0, F);
  CHECK_FALSE(F.allFinite());
  CHECK(problem.LastFailure().status == IntegrationStatus::kStateBound);
  CHECK_THAT(problem.LastFailure().message, Catch::Contains("segment"));
  const NewtonResult newton = Solve(problem, u, 0.0);
  CHECK(newton.status == NewtonStatus::kNonFinite);
  CHECK_FALSE(problem.Stability(u, 0.0).valid);

  u(u.size() - 1) = -1.0;  // a negative period is not an orbit
  problem.Residual(u, 0.0, F);
  CHECK_FALSE(F.allFinite());
  CHECK_THAT(problem.LastFailure().message, Catch::Contains("period"));
}

TEST_CASE("shooting problems reject mismatched kinds, options and sizes", "[shooting]") {
  StuartLandauOscillator oscillator;
  DuffingOscillator duffing;
  CHECK_THROWS_WITH(ShootingProblem(oscillator, OrbitKind::kForced), Catch::Contains("kForced"));
  CHECK_THROWS_WITH(ShootingProblem(duffing, OrbitKind::kAutonomous),
                    Catch::Contains("ForcingPeriod"));
  CHECK_THROWS_WITH(ShootingProblem(duffing, OrbitKind::kRelative),
                    Catch::Contains("ForcingPeriod"));
  ShootingOptions options;
  options.segments = 3;
  options.mesh = {0.0, 0.5, 0.4, 1.0};
  CHECK_THROWS_WITH(ShootingProblem(oscillator, OrbitKind::kAutonomous, options),
                    Catch::Contains("mesh[2]"));
  ShootingProblem problem(oscillator, OrbitKind::kAutonomous);
  Vector F;
  CHECK_THROWS_WITH(problem.Residual(Vector::Zero(5), 0.5, F), Catch::Contains("u has 5"));
}

// The van der Pol oscillator with the two quadratures ∫ p² dt and ∫ μ (1 − p²) dt.
class VanDerPolWithQuadratures : public OdeSystem {
 public:
  double mu = 1.0;
  Index Dimension() const override { return 4; }
  void Rhs(double, ConstVectorRef x, VectorRef f) override {
    f << x(1), mu * (1 - x(0) * x(0)) * x(1) - x(0), x(0) * x(0), mu * (1 - x(0) * x(0));
  }
  double Parameter() const override { return mu; }
  void SetParameter(double value) override { mu = value; }
};

struct VanDerPolReference {
  double period = 0.0;
  double integral_p2 = 0.0;          // ∫₀ᵀ p² dt
  double log_multiplier = 0.0;       // ∫₀ᵀ μ (1 − p²) dt
};

// The van der Pol cycle from a transient and two successive crossings of the section q = 0
// (falling: the maximum of p), with explicit Runge–Kutta at tolerance 1e-12: nothing here uses
// shooting.
VanDerPolReference ComputeVanDerPolReference(double mu) {
  VanDerPolWithQuadratures system;
  system.mu = mu;
  IntegratorOptions options;
  options.method = IntegrationMethod::kExplicitRungeKutta;
  options.explicit_order = 8;
  options.relative_tolerance = options.absolute_tolerance = 1e-12;
  OdeIntegrator integrator(system, options);
  Vector x(4), y(4);
  x << 2.0, 0.0, 0.0, 0.0;
  REQUIRE(integrator.Integrate(0.0, x, 60.0, y).Succeeded());  // onto the cycle
  EventOptions section;
  section.count = 1;
  section.function = [](double, ConstVectorRef z, VectorRef g) { g(0) = z(1); };
  section.directions = {-1};
  section.terminal = true;
  integrator.SetEvents(section);
  IntegrationResult first = integrator.Integrate(0.0, y, 100.0, x);
  REQUIRE(first.stopped_at_event);
  x(2) = x(3) = 0.0;
  // Start the second run just past the section so that it does not stop at t = 0.
  REQUIRE(integrator.Integrate(first.t_reached, x, first.t_reached + 1e-3, y).Succeeded());
  IntegrationResult second = integrator.Integrate(first.t_reached + 1e-3, y, 1e3, y);
  REQUIRE(second.stopped_at_event);
  VanDerPolReference reference;
  reference.period = second.t_reached - first.t_reached;
  reference.integral_p2 = y(2);
  reference.log_multiplier = y(3);
  return reference;
}

TEST_CASE("relative periodic orbit: period, rotation and multipliers against an independent "
          "quadrature, single and multiple shooting",
          "[shooting][relative]") {
  ModulatedOscillator system;
  const VanDerPolReference reference = ComputeVanDerPolReference(system.mu);
  const double rotation = system.omega * reference.period + system.kappa * reference.integral_p2;
  REQUIRE(reference.period == Approx(6.6632868593).epsilon(1e-8));  // van der Pol, μ = 1
  const double van_der_pol_multiplier = std::exp(reference.log_multiplier);
  const double radial_multiplier = std::exp(-2.0 * reference.period);

  // Single shooting from a rough guess: z₁ = 1, s near the cycle, T 3 % long, φ where z₁ has
  // turned to after that time.
  ShootingProblem single(system, OrbitKind::kRelative, ShootingWith(1, 1e-12));
  REQUIRE(single.Dimension() == 4 + 2);
  Vector x0(4);
  x0 << 1.0, 0.0, 1.9, 0.1;
  const double period_guess = 1.03 * reference.period;
  OdeIntegrator integrator(system);
  Vector end(4);
  REQUIRE(integrator.Integrate(0.0, x0, period_guess, end).Succeeded());
  Vector u = single.InitialGuess(x0, period_guess, system.mu, std::atan2(end(1), end(0)));
  NewtonResult newton = Solve(single, u, system.mu);
  INFO(newton.BriefReport());
  REQUIRE(newton.Converged());

  // Multiple shooting (4 segments) from the single-shooting orbit with T and φ disturbed. (From
  // the rough guess above, undamped Newton on 4 segments diverges: single shooting keeps every
  // iterate on a trajectory, multiple shooting does not.)
  ShootingProblem multiple(system, OrbitKind::kRelative, ShootingWith(4, 1e-12));
  Vector u_multiple = multiple.InitialGuess(single.SegmentStart(u, 0), 1.01 * u(4), system.mu,
                                            u(5) + 0.1);
  newton = Solve(multiple, u_multiple, system.mu);
  INFO(newton.BriefReport());
  REQUIRE(newton.Converged());

  for (ShootingProblem* problem : {&single, &multiple}) {
    const Vector& v = problem == &single ? u : u_multiple;
    CAPTURE(problem->SegmentCount());
    CHECK(problem->Period(v, system.mu) == Approx(reference.period).epsilon(1e-10));
    // φ ≈ 11 rad here: 1e-8 is 1e-9 relative, for both computations at tolerance 1e-12.
    CHECK(std::remainder(problem->Rotation(v) - rotation, kTwoPi) ==
          Approx(0.0).epsilon(0).margin(1e-8));
    const Vector x = problem->SegmentStart(v, 0);
    CHECK(std::hypot(x(0), x(1)) == Approx(1.0).epsilon(1e-10));  // on |z₁| = 1
    // The sampled orbit closes up to the rotation: x(T) = R_φ x(0).
    const OrbitSamples orbit = problem->Orbit(v, system.mu);
    REQUIRE(orbit.valid);
    Vector closed = orbit.states.col(0);
    system.Rotate(orbit.rotation, closed);
    CHECK((orbit.states.col(orbit.states.cols() - 1) - closed).norm() < 1e-9);

    const Spectrum spectrum = problem->Stability(v, system.mu);
    REQUIRE(spectrum.valid);
    CHECK(spectrum.trivial_removed == 2);
    REQUIRE(spectrum.values.size() == 2);
    CHECK(spectrum.values(0).real() == Approx(van_der_pol_multiplier).epsilon(1e-6));
    const FloquetResult floquet = problem->Floquet(v, system.mu);
    CHECK(std::abs(floquet.trivial(0) - 1.0) < 1e-8);
    CHECK(std::abs(floquet.trivial(1) - 1.0) < 1e-8);
    CHECK(problem->MeasureNames()[1] == "rotation");
  }
  // The radial multiplier e^{−2T} ≈ 1.6e-6 is below what one period's STM resolves (its entries
  // carry errors ~1e-10 · ‖M‖); over a quarter period (e^{−3.3}) each segment resolves it.
  const Spectrum spectrum = multiple.Stability(u_multiple, system.mu);
  CHECK(spectrum.values(1).real() == Approx(radial_multiplier).epsilon(1e-5));
  CHECK(std::abs(single.Stability(u, system.mu).values(1).real() - radial_multiplier) < 1e-8);
}

TEST_CASE("fixed-frame shooting cannot converge on the quasi-periodic motion that RPO shooting "
          "finds",
          "[shooting][relative]") {
  // The same system shot as an ordinary autonomous orbit, x(T) = x(0), from the guess that the
  // RPO problem solves: there is no periodic orbit nearby (φ/2π ≈ 0.15 + an irrational part), so
  // Newton wanders. Its residual never drops below 0.1 (the RPO problem converges to 1e-13).
  ModulatedOscillator system;
  ShootingProblem problem(system, OrbitKind::kAutonomous, ShootingWith(1));
  Vector x0(4);
  x0 << 1.0, 0.0, 1.9, 0.1;
  Vector u = problem.InitialGuess(x0, 6.66, system.mu);
  const testing::TracedNewton traced =
      testing::NewtonWithSmallestResidual(problem, u, system.mu, 12);
  INFO(traced.result.BriefReport());
  CHECK_FALSE(traced.result.Converged());
  CHECK(traced.smallest_residual > 0.1);
}

}  // namespace
}  // namespace rubcont
