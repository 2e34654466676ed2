// van der Pol ẍ − μ(1 − x²)ẋ + x = 0: where single shooting fails and multiple shooting works.
//
// What was measured (and is asserted below):
// * μ = 10 and μ = 1000, attracting cycles: single shooting does NOT fail for lack of
//   conditioning. In scaled unknowns its Jacobian has condition ≈ 2, and from a guess on the slow
//   manifold it converges (Newton tolerances 1e-8 against an integration at rtol 1e-11 / 1e-12).
//   What it cannot give is stability: the nontrivial multiplier e^{−311.8} (μ = 10) is far below
//   the error of a one-period STM, which returns round-off (≈ 5e-9). Forty segments resolve it.
// * μ = −10, the same cycle repelling (time reversed): single shooting fails. The one-period STM
//   has entries ≈ e^{+311.8}; the scaled Jacobian's condition is ≈ 1e16 and NewtonSolve stops
//   with kSingularJacobian at the first iteration. With 80 segments (growth ≤ e^{8} each) Newton
//   converges in two iterations and the multiplier e^{+311.8} comes out to 1e-4 in its logarithm.
// * Measured but not asserted (it depends on the guess): from a cold guess, undamped Newton on
//   uniform multiple shooting can diverge where single shooting converges — segment boundaries in
//   the fast jumps make the problem strongly nonlinear. Start multiple shooting from a converged
//   or transient orbit, or place mesh boundaries in the slow phases.
#include <cmath>

#include <catch2/catch.hpp>

#include "models/textbook.h"
#include "shooting/shooting.h"
#include "solvers/newton.h"
#include "tests/shooting/shooting_with.h"

namespace rubcont {
namespace {

// van der Pol with the quadrature L̇ = μ (1 − x²) = div f, so that L over one period is the log of
// the nontrivial multiplier (Liouville: μ₁ μ₂ = exp ∮ div f dt, μ₁ = 1).
class VanDerPolWithDivergence : public OdeSystem {
 public:
  explicit VanDerPolWithDivergence(double mu) : mu_(mu) {}
  Index Dimension() const override { return 3; }
  void Rhs(double, ConstVectorRef x, VectorRef f) override {
    f(0) = x(1);
    f(1) = mu_ * (1 - x(0) * x(0)) * x(1) - x(0);
    f(2) = mu_ * (1 - x(0) * x(0));
  }
  double Parameter() const override { return mu_; }
  void SetParameter(double mu) override { mu_ = mu; }
  Vector StateScale() const override {
    return (Vector(3) << 2.0, std::max(2.0, 4 * std::abs(mu_) / 3), 1.0).finished();
  }

 private:
  double mu_;
};

struct CycleReference {
  double period = 0.0;
  double log_multiplier = 0.0;
};

// The cycle without shooting: a transient, then the time between two successive maxima of x
// (v falling through 0), with BDF at rtol = atol = 1e-12.
CycleReference ComputeReference(double mu) {
  VanDerPolWithDivergence system(mu);
  IntegratorOptions options;
  options.relative_tolerance = options.absolute_tolerance = 1e-12;
  OdeIntegrator integrator(system, options);
  Vector x(3), y(3);
  x << 2.0, 0.0, 0.0;
  REQUIRE(integrator.Integrate(0.0, x, 10 * mu + 50, y).Succeeded());
  EventOptions section;
  section.count = 1;
  section.function = [](double, ConstVectorRef z, VectorRef g) { g(0) = z(1); };
  section.directions = {-1};
  section.terminal = true;
  integrator.SetEvents(section);
  const IntegrationResult first = integrator.Integrate(0.0, y, 1e6, x);
  REQUIRE(first.stopped_at_event);
  x(2) = 0.0;
  const double t1 = first.t_reached + 1e-6 * mu;  // step off the section
  REQUIRE(integrator.Integrate(first.t_reached, x, t1, y).Succeeded());
  const IntegrationResult second = integrator.Integrate(t1, y, 1e6, x);
  REQUIRE(second.stopped_at_event);
  return {second.t_reached - first.t_reached, x(2)};
}

// Newton tolerances above the integration error: the residual of a shooting problem is only as
// smooth as its integration (step-sequence changes make it jump at the level of the global
// error, ≈ 100·rtol here), so asking for 1e-10 against rtol 1e-11 makes Newton wander.
NewtonOptions ShootingNewton() {
  NewtonOptions options;
  options.max_iterations = 25;
  options.residual_tolerance = 1e-8;
  options.step_tolerance = 1e-8;
  return options;
}

NewtonResult SolveVdp(ShootingProblem& problem, Vector& u, double mu) {
  return NewtonSolve([&](const Vector& v, Vector& F) { problem.Residual(v, mu, F); },
                     [&](const Vector& v, Matrix& J) { problem.Jacobian(v, mu, J); }, u,
                     ShootingNewton(), problem.Scale(), problem.ResidualScale());
}

// 2-norm condition number of the Jacobian in the scaled variables NewtonSolve works in.
double ScaledCondition(ShootingProblem& problem, const Vector& u, double mu) {
  Matrix J;
  problem.Jacobian(u, mu, J);
  const Matrix scaled =
      problem.ResidualScale().cwiseInverse().asDiagonal() * J * problem.Scale().asDiagonal();
  Eigen::JacobiSVD<Matrix> svd(scaled);
  const Vector& s = svd.singularValues();
  return s(0) / s(s.size() - 1);
}

// A guess from the relaxation asymptotics: x0 on the slow manifold at x = 1.5 (v = x/(μ(1 − x²))),
// T = (3 − 2 ln 2) μ + 7.014 μ^{−1/3}.
Vector SlowManifoldPoint(double mu) {
  return (Vector(2) << 1.5, 1.5 / (mu * (1 - 2.25))).finished();
}
double AsymptoticPeriod(double mu) {
  return (3 - 2 * std::log(2.0)) * mu + 7.014 * std::pow(mu, -1.0 / 3.0);
}

TEST_CASE("van der Pol μ = 10: single shooting converges but cannot resolve the contracting "
          "multiplier — 40 segments can, and only a structured Floquet method keeps it",
          "[van_der_pol][shooting]") {
  const double mu = 10.0;
  const CycleReference reference = ComputeReference(mu);
  REQUIRE(reference.log_multiplier == Approx(-311.844).epsilon(0).margin(1e-3));
  VanDerPolOscillator oscillator({mu});

  ShootingProblem single(oscillator, OrbitKind::kAutonomous, ShootingWith(1, 1e-11));
  Vector u = single.InitialGuess(SlowManifoldPoint(mu), AsymptoticPeriod(mu), mu);
  NewtonResult newton = SolveVdp(single, u, mu);
  INFO(newton.BriefReport());
  REQUIRE(newton.Converged());
  CHECK(single.Period(u, mu) == Approx(reference.period).epsilon(1e-8));
  CHECK(ScaledCondition(single, u, mu) < 10.0);  // well conditioned
  // The one-period STM returns round-off for a multiplier of e^{−311.8}.
  const double single_log = std::log(std::abs(single.Stability(u, mu).values(0)));
  CHECK(single_log > -100.0);

  ShootingProblem multiple(oscillator, OrbitKind::kAutonomous, ShootingWith(40, 1e-11));
  Vector v = multiple.InitialGuess(single.SegmentStart(u, 0), single.Period(u, mu), mu);
  newton = SolveVdp(multiple, v, mu);
  INFO(newton.BriefReport());
  REQUIRE(newton.Converged());
  // Every segment restarts BDF at order 1, and the restarts' errors add up: measured, the period
  // error at rtol 1e-11 is 2e-7 with 40 segments against 1e-8 with one (and ten times smaller at
  // rtol 1e-12 for both): multiple shooting buys robustness and stability, not accuracy.
  CHECK(multiple.Period(v, mu) == Approx(reference.period).epsilon(3e-8));
  const Spectrum spectrum = multiple.Stability(v, mu);
  REQUIRE(spectrum.valid);
  CHECK(std::log(std::abs(spectrum.values(0))) ==
        Approx(reference.log_multiplier).epsilon(0).margin(0.01));
  CHECK(std::abs(multiple.Floquet(v, mu).trivial(0) - 1.0) < 1e-6);

  // The same 40 factors without deflation: multipliers 1 and e^{−311.8}.
  const std::vector<Matrix> factors = multiple.SegmentMonodromies(v, mu);
  REQUIRE(factors.size() == 40);
  const ComplexVector schur = ProductEigenvalues(factors, FloquetMethod::kPeriodicSchur);
  const ComplexVector product = ProductEigenvalues(factors, FloquetMethod::kProduct);
  const ComplexVector pencil = ProductEigenvalues(factors, FloquetMethod::kPencil);
  CHECK(std::abs(schur(0) - 1.0) < 1e-6);
  CHECK(std::log(std::abs(schur(1))) == Approx(reference.log_multiplier).epsilon(0).margin(0.01));
  // The explicit product keeps only ε·‖Π M‖; QZ on the lifted pencil does no better (its error
  // is not confined to the factors): both are off by more than 100 in log μ, i.e. 1e43 or more.
  CHECK_FALSE(std::abs(std::log(std::abs(product(1))) - reference.log_multiplier) < 100.0);
  CHECK_FALSE(std::abs(std::log(std::abs(pencil(1))) - reference.log_multiplier) < 100.0);
}

TEST_CASE("van der Pol μ = −10 (the repelling cycle): single shooting fails with a singular "
          "Jacobian, 80 segments converge",
          "[van_der_pol][shooting]") {
  const double mu = 10.0;
  const CycleReference reference = ComputeReference(mu);
  // The attracting cycle first; its time reversal (x(−t), −ẋ(−t)) is the μ = −10 cycle.
  VanDerPolOscillator attracting({mu});
  ShootingProblem stable(attracting, OrbitKind::kAutonomous, ShootingWith(1, 1e-11));
  Vector u = stable.InitialGuess(SlowManifoldPoint(mu), AsymptoticPeriod(mu), mu);
  REQUIRE(SolveVdp(stable, u, mu).Converged());
  const double period = stable.Period(u, mu);
  OdeIntegrator integrator(attracting, ShootingWith(1, 1e-11).integrator);

  VanDerPolOscillator repelling({-mu});
  for (int segments : {1, 80}) {
    CAPTURE(segments);
    // Segment starts X_i = (x(T − s_i), −ẋ(T − s_i)), s_i = T i/N, sampled on the attracting cycle.
    Vector times(segments);
    for (int k = 0; k < segments; ++k) times(k) = period * (k + 1) / segments;
    Matrix samples;
    REQUIRE(integrator.Sample(0.0, u.head(2), times, samples).Succeeded());
    Matrix starts(2, segments);
    for (int i = 0; i < segments; ++i) {
      const int k = segments - 1 - i;  // times(k) = T − s_i
      starts(0, i) = samples(0, k);
      starts(1, i) = -samples(1, k);
    }
    ShootingProblem problem(repelling, OrbitKind::kAutonomous, ShootingWith(segments, 1e-11));
    Vector v = problem.Pack(starts, period);
    problem.SetPhaseReference(v, -mu);
    const NewtonResult newton = SolveVdp(problem, v, -mu);
    INFO(newton.BriefReport());
    if (segments == 1) {
      // One period multiplies the error of the guess (1e-10) by e^{311.8}: cond ≈ 1e16.
      CHECK(newton.status == NewtonStatus::kSingularJacobian);
      CHECK(ScaledCondition(problem, v, -mu) > 1e14);
    } else {
      REQUIRE(newton.Converged());
      CHECK(newton.iterations <= 4);
      CHECK(problem.Period(v, -mu) == Approx(reference.period).epsilon(1e-8));
      const Spectrum spectrum = problem.Stability(v, -mu);
      REQUIRE(spectrum.valid);
      CHECK(spectrum.UnstableCount() == 1);
      CHECK(std::log(std::abs(spectrum.values(0))) ==
            Approx(-reference.log_multiplier).epsilon(0).margin(0.01));
    }
  }
}

TEST_CASE("van der Pol μ = 1000 (stiff relaxation): single and multiple shooting converge with "
          "BDF from the asymptotic guess — the multiplier underflows",
          "[van_der_pol][shooting]") {
  const double mu = 1000.0;
  const CycleReference reference = ComputeReference(mu);
  REQUIRE(reference.log_multiplier == Approx(-2.887e6).epsilon(1e-3));  // e^{−2.9e6} = 0
  VanDerPolOscillator oscillator({mu});
  for (int segments : {1, 20}) {
    CAPTURE(segments);
    ShootingProblem problem(oscillator, OrbitKind::kAutonomous, ShootingWith(segments, 1e-12));
    Vector u = problem.InitialGuess(SlowManifoldPoint(mu), AsymptoticPeriod(mu), mu);
    const NewtonResult newton = SolveVdp(problem, u, mu);
    INFO(newton.BriefReport());
    REQUIRE(newton.Converged());
    CHECK(problem.Period(u, mu) == Approx(reference.period).epsilon(1e-8));
    const Spectrum spectrum = problem.Stability(u, mu);
    REQUIRE(spectrum.valid);
    CHECK(spectrum.Stable());
    if (segments == 1) {
      CHECK(ScaledCondition(problem, u, mu) < 10.0);
      CHECK(std::abs(spectrum.values(0)) > 1e-20);  // round-off of a one-period STM
    } else {
      CHECK(std::abs(spectrum.values(0)) < 1e-100);  // towards e^{−2.9e6}
    }
  }
}


// Equidistributing the collocation mesh (ShootingOptions::adapt_mesh_every, AUTO-07p's lever):
// van der Pol at μ = 10 spends a few per cent of its period in two fast jumps, which a uniform
// mesh of 160 steps resolves poorly (period error 3.2e-4). The same 160 steps moved to the jumps
// on the solved orbit (PointAccepted) give 2.1e-8 (measured), the reference's own accuracy; a
// second pass keeps it there.
TEST_CASE("an adapted collocation mesh resolves van der Pol's relaxation jumps at equal cost",
          "[van_der_pol][shooting][gauss]") {
  const double mu = 10.0;
  const CycleReference reference = ComputeReference(mu);
  VanDerPolOscillator oscillator({mu});
  ShootingOptions options = ShootingWith(4, 1e-11);
  options.integrator.method = IntegrationMethod::kGaussCollocation;
  // The start: the orbit on a fine uniform mesh (a coarse one cannot integrate the guess's jumps).
  options.integrator.collocation_steps = 200;
  ShootingProblem fine(oscillator, OrbitKind::kAutonomous, options);
  Vector u = fine.InitialGuess(SlowManifoldPoint(mu), AsymptoticPeriod(mu), mu);
  REQUIRE(SolveVdp(fine, u, mu).Converged());
  options.integrator.collocation_steps = 40;
  options.adapt_mesh_every = 1;
  ShootingProblem problem(oscillator, OrbitKind::kAutonomous, options);
  problem.SetPhaseReference(u, mu);
  const NewtonResult first = SolveVdp(problem, u, mu);
  INFO(first.BriefReport());
  REQUIRE(first.Converged());
  CHECK(problem.CollocationMeshes().empty());
  CHECK(problem.CollocationStepFractions().sum() == Approx(1.0));
  const double uniform_error = std::abs(problem.Period(u, mu) - reference.period);
  const long steps = options.integrator.collocation_steps;
  CHECK(problem.CollocationStepFractions().maxCoeff() == Approx(0.25 / steps));
  double adapted_error[2];
  for (double& error : adapted_error) {
    problem.PointAccepted(u, mu);
    REQUIRE(problem.CollocationMeshes().size() == 4);
    for (const std::vector<double>& mesh : problem.CollocationMeshes()) CHECK(static_cast<long>(mesh.size()) == steps + 1);
    REQUIRE(SolveVdp(problem, u, mu).Converged());
    error = std::abs(problem.Period(u, mu) - reference.period);
  }
  INFO("period errors: uniform " << uniform_error << ", adapted " << adapted_error[0] << ", "
                                 << adapted_error[1]);
  CHECK(adapted_error[0] < 1e-3 * uniform_error);
  CHECK(adapted_error[1] < 1e-3 * uniform_error);
  // The slow phases take the long steps.
  CHECK(problem.CollocationStepFractions().maxCoeff() > 0.5 / steps);
}

}  // namespace
}  // namespace rubcont
