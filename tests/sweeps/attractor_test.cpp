#include "solvers/constants.h"
#include "sweeps/attractor.h"

#include <cmath>

#include <catch2/catch.hpp>

#include "models/textbook.h"

namespace rubcont {
namespace {


IntegratorOptions Tight() {
  IntegratorOptions options;
  options.relative_tolerance = 1e-9;
  options.absolute_tolerance = 1e-9;
  return options;
}

// Two uncoupled Stuart–Landau oscillators, ż_k = (λ_k + iω_k) z_k − |z_k|² z_k: the product of
// their circles is an invariant 2-torus, stable, with Lyapunov exponents 0, 0, −2λ_1, −2λ_2.
class TwoOscillators : public OdeSystem {
 public:
  Index Dimension() const override { return 4; }
  void Rhs(double t, ConstVectorRef x, VectorRef f) override {
    first_.Rhs(t, x.head(2), f.head(2));
    second_.Rhs(t, x.tail(2), f.tail(2));
  }
  bool HasJacobian() const override { return true; }
  void JacobianX(double t, ConstVectorRef x, MatrixRef J) override {
    J.setZero();
    first_.JacobianX(t, x.head(2), J.topLeftCorner(2, 2));
    second_.JacobianX(t, x.tail(2), J.bottomRightCorner(2, 2));
  }
  double Parameter() const override { return 0.0; }
  void SetParameter(double) override {}

 private:
  StuartLandauOscillator first_{{0.5, 1.0, 0.0}};
  StuartLandauOscillator second_{{1.5, std::sqrt(2.0), 0.0}};
};

TEST_CASE("attractor: Lorenz's exponents 0.9056, 0, -14.57 and their exact sum", "[attractor]") {
  LorenzSystem system;
  AttractorOptions options;
  options.discard = 20.0;
  options.duration = 500.0;
  options.interval = 0.1;
  options.exponents = 3;
  options.blocks = 20;
  options.zero_tolerance = 0.02;
  options.integrator = Tight();
  const AttractorResult result = MeasureAttractor(system, Vector::Constant(3, 1.0), options);
  REQUIRE(result.status == AttractorStatus::kMeasured);
  CAPTURE(result.exponents.transpose(), result.standard_errors.transpose());
  // Sprott (2003): 0.9056, 0, −14.5723; a 500-unit record resolves them to a few hundredths.
  CHECK(std::abs(result.exponents(0) - 0.9056) <= 0.03);
  CHECK(std::abs(result.exponents(1)) <= 0.02);
  CHECK(std::abs(result.exponents(2) + 14.5723) <= 0.05);
  // The sum is the mean trace of the Jacobian, −(σ + 1 + β), on every trajectory: only the
  // bounded boundary terms of the QR (O(1/T)) and the integration error remain.
  CHECK(std::abs(result.exponents.sum() + (10.0 + 1.0 + 8.0 / 3.0)) <= 1e-5);  // measured 1.1e-7
  CHECK(result.signs == std::vector<ExponentSign>{ExponentSign::kPositive, ExponentSign::kZero,
                                                  ExponentSign::kNegative});
  CHECK(result.positive == 1);
  CHECK(result.standard_errors(0) > 0.0);
  CHECK(result.running.cols() == 5000);
  CHECK(result.times(4999) == Approx(500.0));
}

TEST_CASE("attractor: a limit cycle has one zero exponent, the radial one is -2 lambda",
          "[attractor]") {
  StuartLandauOscillator system({0.8, 2.0, 0.3});
  AttractorOptions options;
  options.discard = 15.0;  // the radial transient from r = 0.1 decays to ~e^{−24}
  options.duration = 100.0;
  options.interval = 0.5;
  options.exponents = 2;
  options.zero_tolerance = 0.02;
  options.integrator = Tight();
  // The section: x sampled every 0.01 (~314 samples a period): its maxima lie on the circle at
  // x = √λ, once per period, its minima at −√λ.
  SampledSection section;
  section.count = 1;
  section.interval = 0.01;
  section.function = [](ConstVectorRef x, VectorRef values) { values(0) = x(0); };
  const AttractorResult result =
      MeasureAttractor(system, (Vector(2) << 0.1, 0.0).finished(), options, &section);
  REQUIRE(result.status == AttractorStatus::kMeasured);
  CAPTURE(result.exponents.transpose());
  CHECK(std::abs(result.exponents(0)) <= 0.02);
  CHECK(result.exponents(1) == Approx(-2.0 * 0.8).epsilon(1e-3));
  CHECK(result.zero == 1);
  CHECK(result.negative == 1);
  const double period = system.Period();
  std::vector<const SectionExtremum*> maxima;
  double worst_value = 0.0, worst_spacing = 0.0;
  for (const SectionExtremum& e : result.extrema) {
    CHECK(e.x(0) == Approx(e.value).epsilon(1e-6));  // the interpolated state agrees
    if (e.kind < 0) {
      worst_value = std::max(worst_value, std::abs(e.value + std::sqrt(0.8)));
      continue;
    }
    worst_value = std::max(worst_value, std::abs(e.value - std::sqrt(0.8)));
    if (!maxima.empty()) worst_spacing = std::max(worst_spacing, std::abs(e.t - maxima.back()->t - period));
    maxima.push_back(&e);
  }
  CHECK(std::abs(static_cast<double>(maxima.size()) - 100.0 / period) <= 1.0);
  CHECK(result.extrema.size() >= 2 * maxima.size() - 1);
  CAPTURE(worst_value, worst_spacing);
  CHECK(worst_value <= 1e-8);
  CHECK(worst_spacing <= 1e-6);
  // Every maximum is its own excursion.
  std::vector<double> values;
  for (const SectionExtremum& e : result.extrema) values.push_back(e.value);
  CHECK(ExcursionMaxima(values, -1.0).size() >= maxima.size() - 2);
}

TEST_CASE("attractor: a 2-torus has two zero exponents", "[attractor]") {
  TwoOscillators system;
  AttractorOptions options;
  options.discard = 5.0;
  options.duration = 100.0;
  options.interval = 0.5;
  options.exponents = 4;
  options.zero_tolerance = 0.02;
  options.integrator = Tight();
  const AttractorResult result = MeasureAttractor(system, Vector::Constant(4, 0.3), options);
  REQUIRE(result.status == AttractorStatus::kMeasured);
  CAPTURE(result.exponents.transpose());
  CHECK(result.zero == 2);
  CHECK(result.negative == 2);
  CHECK(std::abs(result.exponents(0)) <= 0.02);
  CHECK(std::abs(result.exponents(1)) <= 0.02);
  CHECK(result.exponents(2) == Approx(-1.0).epsilon(1e-3));
  CHECK(result.exponents(3) == Approx(-3.0).epsilon(1e-3));
}

TEST_CASE("attractor: one section point per slow excursion, none for the ripple on it",
          "[attractor]") {
  // Extrema of s(t) = sin t + 0.05 sin 40t, found on a fine grid: the ripple gives ~13 maxima
  // per slow period, the excursions above the level (≈ 0) one per period, their largest value
  // near t = π/2 + 2πj.
  std::vector<double> values, times;
  const double h = 1e-4;
  auto s = [](double t) { return std::sin(t) + 0.05 * std::sin(40.0 * t); };
  for (double t = 0.3; t < 10.0 * kPi; t += h) {
    const double before = s(t - h), here = s(t), after = s(t + h);
    if ((here > before && here >= after) || (here < before && here <= after)) {
      values.push_back(here);
      times.push_back(t);
    }
  }
  REQUIRE(values.size() > 100);
  const std::vector<std::size_t> points = ExcursionMaxima(values, -1.0);
  // The record starts inside the first excursion (sin 0.3 > 0): cut, left out. Four whole ones
  // follow, each crossing the level with ripple (several extrema on both sides of 0 there).
  REQUIRE(points.size() == 4);
  for (std::size_t j = 0; j < points.size(); ++j) {
    CAPTURE(j, times[points[j]]);
    CHECK(std::abs(times[points[j]] - (kPi / 2.0 + kTwoPi * static_cast<double>(j + 1))) < 0.1);
    CHECK(values[points[j]] > 1.0);
  }
  // Without the hysteresis the ripple where sin t crosses 0 would open extra excursions.
  // A floor above the midline: only the excursions above it count (here none reach 2).
  CHECK(ExcursionMaxima(values, 2.0).empty());
  CHECK(ExcursionMaxima({}, 0.0).empty());
}

TEST_CASE("attractor: the section's period, after the first half's transient", "[attractor]") {
  // A decaying transient, then the values alternate: period 2 (to 1e-9).
  std::vector<double> values;
  for (int j = 0; j < 40; ++j) values.push_back((j % 2 ? 1.0 : 3.0) + 5.0 * std::exp(-0.5 * j));
  CHECK(SectionPeriod(values, 1e-3, 8) == 2);
  CHECK(SectionPeriod(values, 1e-12, 8) == 0);  // the transient (e^{-10}) is still there
  // Constant: period 1. Irrational rotation (a torus's section): none.
  CHECK(SectionPeriod(std::vector<double>(20, 7.0), 0.0, 4) == 1);
  std::vector<double> torus;
  for (int j = 0; j < 200; ++j) torus.push_back(std::sin(kTwoPi * 0.5 * (std::sqrt(5.0) - 1.0) * j));
  CHECK(SectionPeriod(torus, 1e-3, 8) == 0);
  // Too short a record to tell: its second half must hold two of the longest period.
  CHECK(SectionPeriod(std::vector<double>(30, 7.0), 0.0, 8) == 0);
  CHECK(SectionPeriod(std::vector<double>(32, 7.0), 0.0, 8) == 1);
}

TEST_CASE("attractor: the section's dimension tells a curve, a surface and an orbit of q sections",
          "[attractor]") {
  const double golden = 0.5 * (std::sqrt(5.0) - 1.0);
  // A torus's section: a closed curve in space visited by an irrational rotation.
  Matrix curve(3, 1000);
  for (Index k = 0; k < curve.cols(); ++k) {
    const double theta = kTwoPi * golden * static_cast<double>(k);
    curve.col(k) << std::cos(theta), std::sin(theta), 0.3 * std::sin(2.0 * theta);
  }
  const SectionDimension on_curve = MeasureSectionDimension(curve);
  CHECK(on_curve.dimension == Approx(1.0).margin(0.1));
  CHECK(on_curve.pieces == 1);
  // A surface: a 3-torus's section, two incommensurate rotations.
  Matrix surface(4, 2000);
  for (Index k = 0; k < surface.cols(); ++k) {
    const double a = kTwoPi * std::sqrt(2.0) * static_cast<double>(k);
    const double b = kTwoPi * std::sqrt(3.0) * static_cast<double>(k);
    surface.col(k) << std::cos(a), std::sin(a), std::cos(b), std::sin(b);
  }
  const SectionDimension on_surface = MeasureSectionDimension(surface);
  CHECK(on_surface.dimension == Approx(2.0).margin(0.3));
  CHECK(on_surface.pieces == 1);
  // An orbit of 7 sections locked at 3:7, sampled with a period 1e-6 of a turn off per section:
  // the points slide along it, 7 sections apart, 7 pieces.
  Matrix orbit(2, 700);
  for (Index k = 0; k < orbit.cols(); ++k) {
    const double theta = kTwoPi * (3.0 / 7.0 + 1e-6) * static_cast<double>(k);
    orbit.col(k) << std::cos(theta), std::sin(theta);
  }
  const SectionDimension on_orbit = MeasureSectionDimension(orbit);
  CHECK(on_orbit.apart == 7.0);
  CHECK(on_orbit.pieces == 7);
  CHECK(on_orbit.nearest == Approx(7.0 * kTwoPi * 1e-6).epsilon(1e-3));
  CHECK(on_orbit.dimension == Approx(1.0).margin(1e-3));
  CHECK_THROWS_WITH(MeasureSectionDimension(Matrix::Zero(2, 16)),
                    Catch::Contains("16 points: need at least 17"));
}

TEST_CASE("attractor: invalid options name the field, a failing integration is a status",
          "[attractor]") {
  LorenzSystem system;
  AttractorOptions options;
  options.duration = 1.0;
  options.interval = 0.5;  // > duration / blocks
  CHECK_THROWS_WITH(MeasureAttractor(system, Vector::Ones(3), options),
                    Catch::Contains("AttractorOptions.interval = 0.5"));
  options.interval = 0.1;
  options.exponents = 4;
  CHECK_THROWS_WITH(MeasureAttractor(system, Vector::Ones(3), options),
                    Catch::Contains("exponents = 4: must be at most the dimension 3"));
  options.exponents = 3;
  options.integrator.max_steps = 2;
  const AttractorResult result = MeasureAttractor(system, Vector::Ones(3), options);
  CHECK(result.status == AttractorStatus::kIntegrationFailure);
  CHECK_THAT(result.message, Catch::Contains("at t = "));
  CHECK(result.counted_time == 0.0);
  CHECK(std::isnan(result.exponents(0)));
}

}  // namespace
}  // namespace rubcont
