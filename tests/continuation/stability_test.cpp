// Eigenvalue and Floquet-multiplier crossings: Hopf, period doubling, Neimark–Sacker.
#include <cmath>
#include <complex>
#include <functional>

#include <catch2/catch.hpp>

#include "continuation/continuation.h"
#include "test_problems.h"

namespace rubcont {
namespace {

using testing::EigenvaluesOf;
using testing::LambdaProblem;
using testing::Vec;

// Brusselator: ẋ = a − (b + 1)x + x²y, ẏ = bx − x²y, λ = b. Equilibrium (a, b/a); Hopf at
// b = 1 + a² with frequency a.
LambdaProblem Brusselator(double a) {
  auto jacobian = [a](const Vector& u, double b, double, Matrix& J) {
    const double x = u(0), y = u(1);
    J << -(b + 1) + 2 * x * y, x * x, b - 2 * x * y, -x * x;
    (void)a;
  };
  LambdaProblem problem(
      2,
      [a](const Vector& u, double b, double, Vector& F) {
        const double x = u(0), y = u(1);
        F << a - (b + 1) * x + x * x * y, b * x - x * x * y;
      },
      jacobian, [](const Vector& u, double, double, Vector& dF) { dF << -u(0), u(0); });
  problem.SetStabilityFromJacobian();
  return problem;
}

TEST_CASE("the Hopf point of the Brusselator is located to 1e-8", "[continuation][hopf]") {
  const double a = 2.0;
  LambdaProblem problem = Brusselator(a);
  ContinuationOptions options;
  options.detect.stability = true;
  options.bounds.lambda_max = 8.0;
  const Branch branch = Continue(problem, Vec({a, 1.0 / a}), 1.0, options);
  INFO(branch.BriefReport());
  REQUIRE(branch.status == BranchStatus::kReachedLambdaBound);
  REQUIRE(branch.Count(SpecialPointType::kHopf) == 1);
  CHECK(branch.special_points.size() == 1u);
  const SpecialPoint& hopf = branch.special_points.front();
  CHECK(hopf.converged);
  CHECK(std::abs(hopf.lambda - (1.0 + a * a)) <= 1e-8);
  CHECK(hopf.frequency == Approx(a).epsilon(1e-8));
  CHECK(std::abs(hopf.critical_value.real()) <= 1e-8);
  // Stability is stored with every point: stable before, a complex pair unstable after.
  for (const BranchPoint& p : branch.points) {
    REQUIRE(p.spectrum.valid);
    CHECK(p.num_unstable == (p.lambda > 1.0 + a * a ? 2 : 0));
  }
  CHECK(branch.statistics.stability_evaluations >= static_cast<long>(branch.points.size()));
}

TEST_CASE("stability is computed only when the options ask for it", "[continuation][hopf]") {
  LambdaProblem problem = Brusselator(2.0);
  ContinuationOptions options;
  options.bounds.lambda_max = 8.0;
  const Branch branch = Continue(problem, Vec({2.0, 0.5}), 1.0, options);
  CHECK(branch.statistics.stability_evaluations == 0);
  CHECK(branch.Count(SpecialPointType::kHopf) == 0);
  for (const BranchPoint& p : branch.points) CHECK(p.num_unstable == -1);
}

TEST_CASE("a Hopf point with nonlinear parameter dependence is located to 1e-8",
          "[continuation][hopf]") {
  // Hopf normal form with μ(λ) = sin λ − 0.3, ω(λ) = 1 + λ: the origin loses stability at
  // λ = asin 0.3 with frequency 1 + asin 0.3.
  LambdaProblem problem(
      2,
      [](const Vector& u, double l, double, Vector& F) {
        const double mu = std::sin(l) - 0.3, w = 1.0 + l, r2 = u.squaredNorm();
        F << mu * u(0) - w * u(1) - u(0) * r2, w * u(0) + mu * u(1) - u(1) * r2;
      });
  problem.SetStability([](const Vector&, double l, double) {
    const double mu = std::sin(l) - 0.3, w = 1.0 + l;
    Matrix J(2, 2);
    J << mu, -w, w, mu;
    return EigenvaluesOf(J);
  });
  ContinuationOptions options;
  options.detect.stability = true;
  options.bounds.lambda_max = 1.0;
  const Branch branch = Continue(problem, Vec({0.0, 0.0}), -0.5, options);
  INFO(branch.BriefReport());
  REQUIRE(branch.Count(SpecialPointType::kHopf) == 1);
  const SpecialPoint& hopf = branch.special_points.front();
  CHECK(std::abs(hopf.lambda - std::asin(0.3)) <= 1e-8);
  CHECK(std::abs(hopf.frequency - (1.0 + std::asin(0.3))) <= 1e-8);
}

// u = (λ, 0) with Floquet multipliers that are known functions of λ: each crosses the unit circle
// at λ = 2.
struct MultiplierCase {
  SpecialPointType expected;
  std::function<ComplexVector(double)> multipliers;
};

TEST_CASE("Floquet multiplier crossings: period doubling, Neimark-Sacker and +1",
          "[continuation][floquet]") {
  const auto r = [](double l) { return 0.5 + 0.25 * l; };
  const MultiplierCase cases[] = {
      {SpecialPointType::kPeriodDoubling,
       [r](double l) { return (ComplexVector(2) << -r(l), 0.3).finished(); }},
      {SpecialPointType::kNeimarkSacker,
       [r](double l) {
         return (ComplexVector(3) << std::polar(r(l), 1.0), std::polar(r(l), -1.0), 0.2)
             .finished();
       }},
      {SpecialPointType::kMultiplierPlusOne,
       [r](double l) { return (ComplexVector(2) << r(l), -0.1).finished(); }},
  };
  const int which = GENERATE(0, 1, 2);
  const MultiplierCase& c = cases[which];
  LambdaProblem problem(
      2, [](const Vector& u, double l, double, Vector& F) { F << u(0) - l, u(1); },
      [](const Vector&, double, double, Matrix& J) { J.setIdentity(); },
      [](const Vector&, double, double, Vector& dF) { dF << -1.0, 0.0; });
  problem.SetStability([c](const Vector&, double l, double) {
    Spectrum spectrum;
    spectrum.kind = SpectrumKind::kFloquetMultipliers;
    spectrum.values = c.multipliers(l);
    spectrum.valid = true;
    return spectrum;
  });
  ContinuationOptions options;
  options.detect.stability = true;
  options.bounds.lambda_max = 4.0;
  const Branch branch = Continue(problem, Vec({0.0, 0.0}), 0.0, options);
  INFO(branch.BriefReport());
  REQUIRE(branch.special_points.size() == 1u);
  const SpecialPoint& sp = branch.special_points.front();
  CHECK(sp.type == c.expected);
  CHECK(sp.converged);
  CHECK(std::abs(sp.lambda - 2.0) <= 1e-8);
  CHECK(std::abs(std::abs(sp.critical_value) - 1.0) <= 1e-8);
  if (c.expected == SpecialPointType::kPeriodDoubling) {
    CHECK(sp.critical_value.real() == Approx(-1.0).epsilon(0).margin(1e-8));
  }
  if (c.expected == SpecialPointType::kNeimarkSacker) CHECK(sp.frequency == Approx(1.0));
  if (c.expected == SpecialPointType::kMultiplierPlusOne) {
    CHECK(sp.critical_value.real() == Approx(1.0).epsilon(0).margin(1e-8));
  }
  const int unstable_after = c.expected == SpecialPointType::kNeimarkSacker ? 2 : 1;
  CHECK(branch.points.back().num_unstable == unstable_after);
  CHECK(branch.points.front().num_unstable == 0);
}

TEST_CASE("a complex pair colliding on the real axis is not a crossing",
          "[continuation][floquet]") {
  // Eigenvalues 1 ± i(1 − λ) for λ < 1 and 1 ± (λ − 1) after: always unstable, no crossing.
  LambdaProblem problem(
      1, [](const Vector& u, double l, double, Vector& F) { F(0) = u(0) - l; });
  problem.SetStability([](const Vector&, double l, double) {
    Spectrum spectrum;
    spectrum.valid = true;
    if (l < 1.0) {
      spectrum.values = (ComplexVector(2) << std::complex<double>(1.0, 1.0 - l),
                         std::complex<double>(1.0, l - 1.0)).finished();
    } else {
      spectrum.values = (ComplexVector(2) << 1.0 + (l - 1.0), 1.0 - (l - 1.0) * 0.5).finished();
    }
    return spectrum;
  });
  ContinuationOptions options;
  options.detect.stability = true;
  options.bounds.lambda_max = 1.5;
  const Branch branch = Continue(problem, Vec({0.0}), 0.0, options);
  CHECK(branch.special_points.empty());
  for (const BranchPoint& p : branch.points) CHECK(p.num_unstable == 2);
}

// u = λ with a prescribed spectrum values(λ), continued from λ = 0.25 in steps of 0.1 (about 0.07
// in λ), so that one step holds the crossing and the collision the cases below put close together.
Branch ContinueWithSpectrum(std::function<ComplexVector(double)> values, double lambda_max) {
  LambdaProblem problem(
      1, [](const Vector& u, double l, double, Vector& F) { F(0) = u(0) - l; });
  problem.SetStability([values = std::move(values)](const Vector&, double l, double) {
    Spectrum spectrum;
    spectrum.valid = true;
    spectrum.values = values(l);
    return spectrum;
  });
  ContinuationOptions options;
  options.detect.stability = true;
  options.step.initial = options.step.max = 0.1;
  options.bounds.lambda_max = lambda_max;
  return Continue(problem, Vec({0.25}), 0.25, options);
}

// Whether one step of the branch goes from below `low` to above `high`.
bool OneStepSpans(const Branch& branch, double low, double high) {
  for (size_t i = 1; i < branch.points.size(); ++i) {
    if (branch.points[i - 1].lambda < low && branch.points[i].lambda > high) return true;
  }
  return false;
}

std::complex<double> Sqrt(double x) { return std::sqrt(std::complex<double>(x, 0.0)); }

TEST_CASE("a Hopf point in a step where another pair collides on the real axis is located",
          "[continuation][hopf]") {
  // Pair A = (λ − 0.3) ± i crosses the axis at λ = 0.3; pair D = −2 ± 3i stays stable. Pair
  // B = 5 ± √c(λ), unstable throughout, meets on the real axis within the same step: (a) it stays
  // real after λ = 0.3005 (the step's end counts two more unstable real values and no new pair:
  // by the counts, a real crossing); (b) it is real only on (0.2995, 0.3005), around A's crossing
  // (the counts are right, but there the second complex value is D's: the order statistic jumps
  // from A's Re ≈ 0 to −2). Either way the Hopf point is A's, located on the spectral product,
  // and there is no other special point.
  const bool stays_real = GENERATE(true, false);
  const Branch branch = ContinueWithSpectrum(
      [stays_real](double l) {
        const std::complex<double> root =
            Sqrt(stays_real ? l - 0.3005 : (l - 0.2995) * (0.3005 - l));
        return (ComplexVector(7) << 5.0 + root, 5.0 - root, std::complex<double>(l - 0.3, 1.0),
                std::complex<double>(l - 0.3, -1.0), -1.0, std::complex<double>(-2.0, 3.0),
                std::complex<double>(-2.0, -3.0))
            .finished();
      },
      0.6);
  INFO(branch.BriefReport());
  REQUIRE(OneStepSpans(branch, 0.2995, 0.3005));  // else the test tests nothing
  REQUIRE(branch.special_points.size() == 1u);
  const SpecialPoint& hopf = branch.special_points.front();
  CHECK(hopf.type == SpecialPointType::kHopf);
  CHECK(hopf.converged);
  CHECK(std::abs(hopf.lambda - 0.3) <= 1e-8);
  CHECK(hopf.frequency == Approx(1.0).epsilon(1e-8));
  CHECK(std::abs(hopf.critical_value.real()) <= 1e-8);
}

TEST_CASE("a neutral saddle changes the bialternate product's sign and is no Hopf point",
          "[continuation][hopf]") {
  // Real eigenvalues 1 and λ − 1.3: their sum vanishes at λ = 0.3 (a neutral saddle), no value
  // crosses the axis before λ = 1.3, where a real one does. Pair C = 5 ± √(λ − 0.3005) collides
  // in the same step, so that the step is judged by the products.
  const Branch branch = ContinueWithSpectrum(
      [](double l) {
        const std::complex<double> root = Sqrt(l - 0.3005);
        return (ComplexVector(4) << 5.0 + root, 5.0 - root, 1.0, l - 1.3).finished();
      },
      1.6);
  INFO(branch.BriefReport());
  REQUIRE(OneStepSpans(branch, 0.3, 0.3005));
  REQUIRE(branch.special_points.size() == 1u);
  const SpecialPoint& crossing = branch.special_points.front();
  CHECK(crossing.type == SpecialPointType::kRealEigenvalueCrossing);
  CHECK(crossing.converged);
  CHECK(std::abs(crossing.lambda - 1.3) <= 1e-8);
}

TEST_CASE("a real value that crosses 0 and meets another into a pair is no Hopf point",
          "[continuation][hopf]") {
  // Values 0.5 ± √D(λ), D = 0.25 − 25(λ − 0.3): the lower one crosses 0 at λ = 0.3, both meet at
  // λ = 0.31 and leave as the unstable pair 0.5 ± i√−D; a stable pair −2 ± 3i stays. A step over
  // both sees one more unstable value and one more unstable pair (by the counts, a Hopf point
  // whose critical value jumps from −2 to 0.5) — it is the real crossing, as on case A(a)'s tanh
  // Mode 2 whirl at its 52.33 rpm branch point.
  const Branch branch = ContinueWithSpectrum(
      [](double l) {
        const std::complex<double> root = Sqrt(0.25 - 25.0 * (l - 0.3));
        return (ComplexVector(4) << 0.5 + root, 0.5 - root, std::complex<double>(-2.0, 3.0),
                std::complex<double>(-2.0, -3.0))
            .finished();
      },
      0.6);
  INFO(branch.BriefReport());
  REQUIRE(OneStepSpans(branch, 0.3, 0.31));
  REQUIRE(branch.special_points.size() == 1u);
  const SpecialPoint& crossing = branch.special_points.front();
  CHECK(crossing.type == SpecialPointType::kRealEigenvalueCrossing);
  CHECK(crossing.converged);
  CHECK(std::abs(crossing.lambda - 0.3) <= 1e-8);
  CHECK(std::abs(crossing.critical_value) <= 1e-8);
}

}  // namespace
}  // namespace rubcont
