// The forced Duffing oscillator ẍ + 0.05 ẋ + x + x³ = 0.3 cos(w t) continued in w over [0.5, 2.5]
// by shooting through the continuation engine, with Floquet stability: the resonance curve bends
// to the right and folds twice, and both folds of its hysteresis loop are located and checked
// against the folds of an independent harmonic balance (duffing_harmonic_balance.h: Moore–Spence
// system, no time integration, no continuation engine).
#include <cmath>
#include <utility>
#include <vector>

#include <catch2/catch.hpp>

#include "continuation/continuation.h"
#include "duffing_harmonic_balance.h"
#include "models/textbook.h"
#include "shooting/shooting.h"
#include "solvers/constants.h"
#include "solvers/finite_difference.h"
#include "solvers/newton.h"

namespace rubcont {
namespace {

using testing::DuffingHarmonicBalance;

struct HarmonicBalanceFold {
  double frequency;
  double x0;  // x(0) on the fold
  double v0;  // ẋ(0) on the fold
};

// The two folds of the response curve by harmonic balance with H = 25 harmonics, in increasing w.
std::vector<HarmonicBalanceFold> HarmonicBalanceFolds(const DuffingParams& params) {
  const DuffingHarmonicBalance balance(params, 25);
  std::vector<HarmonicBalanceFold> folds;
  for (const auto& guess : DuffingHarmonicBalance::OneTermFolds(params, 0.5, 2.5)) {
    const auto fold = balance.LocateFold(balance.FirstHarmonic(guess.amplitude, guess.phase),
                                         guess.frequency);
    INFO(fold.newton.BriefReport());
    REQUIRE(fold.newton.Converged());
    folds.push_back({fold.frequency, balance.Displacement0(fold.coefficients),
                     balance.Velocity0(fold.coefficients, fold.frequency)});
  }
  return folds;
}

TEST_CASE("harmonic balance folds of the Duffing curve are converged in the harmonics",
          "[duffing][branch]") {
  DuffingParams params;
  const auto one_term = DuffingHarmonicBalance::OneTermFolds(params, 0.5, 2.5);
  REQUIRE(one_term.size() == 2);
  const auto folds = HarmonicBalanceFolds(params);
  REQUIRE(folds.size() == 2);
  // The same folds with twice the harmonics.
  const DuffingHarmonicBalance fine(params, 50);
  for (std::size_t k = 0; k < 2; ++k) {
    CAPTURE(k);
    const auto fold = fine.LocateFold(fine.FirstHarmonic(one_term[k].amplitude, one_term[k].phase),
                                      one_term[k].frequency);
    REQUIRE(fold.newton.Converged());
    CHECK(fold.frequency == Approx(folds[k].frequency).epsilon(0).margin(1e-12));
    CHECK(fine.Displacement0(fold.coefficients) == Approx(folds[k].x0).epsilon(0).margin(1e-12));
  }
  // The lower fold (jump up on a downward sweep) below the upper one (jump down on an upward
  // sweep), which lies near the backbone estimate w⁴ − w² = ¾(F/c)²: w ≈ 2.39.
  CHECK(folds[0].frequency < folds[1].frequency);
  CHECK(folds[1].frequency == Approx(2.39).epsilon(0).margin(0.05));
}

TEST_CASE("Duffing resonance curve over w in [0.5, 2.5]: both folds located by single and "
          "multiple shooting and by Gauss collocation, matching harmonic balance, the middle "
          "branch unstable",
          "[duffing][branch][shooting]") {
  DuffingParams params;
  params.frequency = 0.5;
  DuffingOscillator duffing(params);
  const auto hb = HarmonicBalanceFolds(params);
  REQUIRE(hb.size() == 2);

  // The start: the one solution at w = 0.5 from its one-term approximation.
  const auto start = DuffingHarmonicBalance::OneTermSolutions(params);
  REQUIRE(start.size() == 1);
  const auto [amplitude, phase] = start[0];
  const Vector x0 = (Vector(2) << amplitude * std::cos(phase),
                     amplitude * params.frequency * std::sin(phase)).finished();

  // Segments, and Gauss collocation steps per segment (0: ERK8).
  for (const auto& [segments, gauss_steps] : {std::pair{1, 0L}, {3, 0L}, {1, 40L}}) {
    CAPTURE(segments, gauss_steps);
    // The settings of bench/duffing_branch_bench.cpp: an explicit 8th-order Runge–Kutta (Duffing is
    // not stiff) with the variational equations under error control, or Gauss collocation of
    // order 8 on 40 steps per period, and a step controller that
    // lets the step grow (Newton takes 3 iterations even on tiny steps, so the default target of
    // 3 keeps the step where it starts); every corrector residual is followed by a Jacobian at the
    // same point, so the residual integrates the sensitivities too.
    ShootingOptions shooting;
    shooting.segments = segments;
    shooting.integrator.method = IntegrationMethod::kExplicitRungeKutta;
    shooting.integrator.explicit_order = 8;
    if (gauss_steps > 0) {
      shooting.integrator.method = IntegrationMethod::kGaussCollocation;
      shooting.integrator.collocation_steps = gauss_steps;
    }
    shooting.sensitivities_in_residual = true;
    ShootingProblem problem(duffing, OrbitKind::kForced, shooting);
    const Vector u0 = problem.InitialGuess(x0, 0.0, params.frequency);

    ContinuationOptions options;
    options.bounds.lambda_min = 0.5;
    options.bounds.lambda_max = 2.5;
    options.detect.stability = true;
    options.step.max = 1.0;
    options.step.target_angle = 0.3;
    options.step.target_iterations = 5;
    const Branch branch = Continue(problem, u0, params.frequency, options);
    INFO(branch.BriefReport() << " — " << branch.message);
    REQUIRE(branch.status == BranchStatus::kReachedLambdaBound);
    // Placed on the bound by the engine's location on the arc, to its tolerance (1e-10; ERK8
    // lands within 1e-14, Gauss 1.1e-12).
    CHECK(branch.points.back().lambda == Approx(2.5).epsilon(0).margin(1e-10));

    // Exactly two folds, nothing else (no period doubling or torus on this curve), the upper one
    // (w ≈ 2.39) first along the branch.
    REQUIRE(branch.special_points.size() == 2);
    for (const SpecialPoint& p : branch.special_points) {
      CHECK(p.type == SpecialPointType::kFold);
      CHECK(p.converged);
    }
    const SpecialPoint& upper = branch.special_points[0];
    const SpecialPoint& lower = branch.special_points[1];
    // Integration at rtol = atol = 1e-10 leaves a global error of a few 1e-9 in the orbit; the
    // located folds agree with harmonic balance to that level.
    CHECK(upper.lambda == Approx(hb[1].frequency).epsilon(0).margin(1e-8));
    CHECK(lower.lambda == Approx(hb[0].frequency).epsilon(0).margin(1e-8));
    CHECK(upper.u(0) == Approx(hb[1].x0).epsilon(0).margin(1e-7));
    CHECK(upper.u(1) == Approx(hb[1].v0).epsilon(0).margin(1e-7));
    CHECK(lower.u(0) == Approx(hb[0].x0).epsilon(0).margin(1e-7));
    CHECK(lower.u(1) == Approx(hb[0].v0).epsilon(0).margin(1e-7));

    // Stability from the Floquet multipliers: stable up to the upper fold, one multiplier > 1
    // between the folds (the saddle), stable again after the lower fold. Liouville on every point:
    // μ₁ μ₂ = e^{−cT}.
    int before = 0, between = 0, after = 0;
    for (Index i = 0; i < branch.Size(); ++i) {
      const BranchPoint& p = branch.points[i];
      REQUIRE(p.spectrum.valid);
      REQUIRE(p.spectrum.values.size() == 2);
      const double period = kTwoPi / p.lambda;
      const std::complex<double> det = p.spectrum.values(0) * p.spectrum.values(1);
      CHECK(det.real() == Approx(std::exp(-params.damping * period)).epsilon(1e-6));
      if (i <= upper.index) {
        CHECK(p.num_unstable == 0);
        ++before;
      } else if (i <= lower.index) {
        CHECK(p.num_unstable == 1);
        CHECK(p.spectrum.values(0).imag() == 0.0);
        CHECK(p.spectrum.values(0).real() > 1.0);
        ++between;
      } else {
        CHECK(p.num_unstable == 0);
        ++after;
      }
    }
    CHECK(before > 3);
    CHECK(between > 3);
    CHECK(after > 3);
  }
}

}  // namespace
}  // namespace rubcont

namespace rubcont {
namespace {

// Where finite differences fail: the monodromy matrix of the Duffing saddle orbit at w = 1.5, by
// forward sensitivities and by central differences of the flow map, both integrated at the same
// tolerance. Liouville's formula det M = e^{−cT} is the exact reference for the determinant, and
// the STM of a tighter integration for the entries.
TEST_CASE("Duffing saddle at w = 1.5: the monodromy by finite differences of the flow is several "
          "times less accurate than by sensitivities at the same tolerance, for 2n integrations",
          "[duffing][monodromy]") {
  DuffingParams params;
  params.frequency = 1.5;
  DuffingOscillator duffing(params);
  const double w = params.frequency, period = kTwoPi / w;
  const auto guesses = testing::DuffingHarmonicBalance::OneTermSolutions(params);
  REQUIRE(guesses.size() == 3);
  const auto [amplitude, phase] = guesses[1];  // the middle orbit: a saddle

  ShootingOptions shooting;  // CVODES BDF, rtol = atol = 1e-10, sensitivities under error control
  ShootingProblem problem(duffing, OrbitKind::kForced, shooting);
  Vector u = problem.InitialGuess(
      (Vector(2) << amplitude * std::cos(phase), amplitude * w * std::sin(phase)).finished(), 0.0, w);
  REQUIRE(NewtonSolve([&](const Vector& v, Vector& F) { problem.Residual(v, w, F); },
                      [&](const Vector& v, Matrix& J) { problem.Jacobian(v, w, J); }, u, {},
                      problem.Scale(), problem.ResidualScale())
              .Converged());
  const Vector x0 = problem.SegmentStart(u, 0);
  const Matrix sensitivities = problem.SegmentMonodromies(u, w).at(0);

  // Reference: the STM at rtol = atol = 1e-13.
  IntegratorOptions tight = shooting.integrator;
  tight.relative_tolerance = tight.absolute_tolerance = 1e-13;
  OdeIntegrator reference_integrator(duffing, tight);
  Vector x1(2);
  Matrix reference;
  REQUIRE(reference_integrator.Integrate(0.0, x0, period, x1, &reference).Succeeded());

  // Central differences of the flow at the shooting tolerance, with the optimal step for smooth
  // functions (∛ε relative): the integration error, not round-off, is the noise they amplify.
  OdeIntegrator integrator(duffing, shooting.integrator);
  Matrix differences;
  FiniteDifferenceJacobian(
      [&](const Vector& x, Vector& end) {
        REQUIRE(integrator.Integrate(0.0, x, period, end).Succeeded());
      },
      x0, 2, differences);

  const double liouville = std::exp(-params.damping * period);
  const double scale = reference.cwiseAbs().maxCoeff();
  const double sensitivity_error = (sensitivities - reference).cwiseAbs().maxCoeff() / scale;
  const double difference_error = (differences - reference).cwiseAbs().maxCoeff() / scale;
  const double sensitivity_det_error = std::abs(sensitivities.determinant() - liouville);
  const double difference_det_error = std::abs(differences.determinant() - liouville);
  INFO("entries: sensitivities " << sensitivity_error << ", differences " << difference_error
                                 << "; det: " << sensitivity_det_error << ", "
                                 << difference_det_error);
  CHECK(sensitivity_error < 1e-7);
  CHECK(sensitivity_det_error < 1e-7);
  // The differences see the integration error divided by the step (measured: 1.1e-8 against
  // 1.9e-9 in the entries, 3.3e-8 against 2.2e-9 in the determinant), and cost 2n = 4 integrations
  // where the sensitivities cost one (with n more columns in it: bench/duffing_branch_bench.cpp
  // times both along the whole branch).
  CHECK(difference_error > 3 * sensitivity_error);
  CHECK(difference_det_error > 3 * sensitivity_det_error);
}

}  // namespace
}  // namespace rubcont
