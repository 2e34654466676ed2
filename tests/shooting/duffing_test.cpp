// Forced Duffing oscillator ẍ + 0.05 ẋ + x + x³ = 0.3 cos(w t) in its bistable band: the three
// coexisting periodic orbits by shooting, checked against an independent high-order harmonic
// balance (duffing_harmonic_balance.h) and against Liouville's formula for their multipliers.
#include <cmath>

#include <catch2/catch.hpp>

#include "models/textbook.h"
#include "duffing_harmonic_balance.h"
#include "shooting/shooting.h"
#include "solvers/constants.h"
#include "solvers/newton.h"

namespace rubcont {
namespace {

using testing::DuffingHarmonicBalance;

// First-harmonic amplitude of a sampled orbit on a uniform grid over one period (the last sample
// repeats the first): trapezoidal Fourier sums, spectrally accurate for a smooth periodic x(t).
double FirstHarmonicAmplitude(const OrbitSamples& orbit, double w) {
  const Index m = orbit.times.size() - 1;
  double a = 0.0, b = 0.0;
  for (Index j = 0; j < m; ++j) {
    a += orbit.states(0, j) * std::cos(w * orbit.times(j));
    b += orbit.states(0, j) * std::sin(w * orbit.times(j));
  }
  return 2.0 * std::hypot(a, b) / static_cast<double>(m);
}

TEST_CASE("harmonic balance is converged in the number of harmonics", "[duffing]") {
  DuffingParams params;
  params.frequency = 1.5;
  const auto guesses = DuffingHarmonicBalance::OneTermSolutions(params);
  REQUIRE(guesses.size() == 3);
  const DuffingHarmonicBalance coarse(params, 25), fine(params, 50);
  for (const auto& [amplitude, phase] : guesses) {
    Vector c = coarse.FirstHarmonic(amplitude, phase);
    REQUIRE(coarse.Solve(c).Converged());
    Vector c_fine = Vector::Zero(fine.Size());
    c_fine.head(c.size()) = c;
    REQUIRE(fine.Solve(c_fine).Converged());
    CHECK(std::abs(coarse.Displacement0(c) - fine.Displacement0(c_fine)) < 1e-13);
    CHECK(std::abs(coarse.Velocity0(c) - fine.Velocity0(c_fine)) < 1e-13);
  }
}

TEST_CASE("Duffing at w = 1.5: the three coexisting orbits by single and multiple shooting match "
          "harmonic balance — two stable, the middle one unstable",
          "[duffing][shooting]") {
  DuffingParams params;  // c = 0.05, k = 1, β = 1, F = 0.3
  params.frequency = 1.5;
  DuffingOscillator duffing(params);
  const double w = params.frequency;
  const double period = kTwoPi / w;
  const DuffingHarmonicBalance balance(params, 25);
  const auto guesses = DuffingHarmonicBalance::OneTermSolutions(params);
  REQUIRE(guesses.size() == 3);

  for (int segments : {1, 4}) {
    CAPTURE(segments);
    std::vector<double> amplitudes;
    std::vector<int> unstable_counts;
    for (const auto& [amplitude, phase] : guesses) {
      CAPTURE(amplitude);
      // Harmonic balance from the one-term solution.
      Vector c = balance.FirstHarmonic(amplitude, phase);
      REQUIRE(balance.Solve(c).Converged());

      // Shooting from the same one-term solution: x(0) = A cos ψ, ẋ(0) = A w sin ψ.
      ShootingOptions options;
      options.segments = segments;
      ShootingProblem problem(duffing, OrbitKind::kForced, options);
      REQUIRE(problem.Dimension() == 2 * segments);
      const Vector x0 =
          (Vector(2) << amplitude * std::cos(phase), amplitude * w * std::sin(phase)).finished();
      Vector u = problem.InitialGuess(x0, 0.0, w);
      const NewtonResult newton =
          NewtonSolve([&](const Vector& v, Vector& F) { problem.Residual(v, w, F); },
                      [&](const Vector& v, Matrix& J) { problem.Jacobian(v, w, J); }, u, {},
                      problem.Scale(), problem.ResidualScale());
      INFO(newton.BriefReport());
      REQUIRE(newton.Converged());

      // The state at t = 0 (the forcing fixes the phase) and the first-harmonic amplitude. At the
      // default rtol = atol = 1e-10 the integration's global error moves the large orbits' start
      // by up to 5.3e-8 (measured: 1.39 orbit, 4 segments; 1.2e-8 with one), the small one's less.
      const Vector x = problem.SegmentStart(u, 0);
      CHECK(x(0) == Approx(balance.Displacement0(c)).epsilon(0).margin(1e-7));
      CHECK(x(1) == Approx(balance.Velocity0(c)).epsilon(0).margin(1e-7));
      const OrbitSamples orbit = problem.Orbit(u, w);
      REQUIRE(orbit.valid);
      CHECK(orbit.period == Approx(period).epsilon(1e-15));
      const double first_harmonic = FirstHarmonicAmplitude(orbit, w);
      CHECK(first_harmonic ==
            Approx(DuffingHarmonicBalance::FirstHarmonicAmplitude(c)).epsilon(0).margin(1e-8));
      amplitudes.push_back(first_harmonic);

      // Liouville: μ₁ μ₂ = det M = exp(∮ tr J dt) = e^{−cT}. The STM from sensitivities at
      // rtol 1e-10 carries errors ~1e-8 relative to ‖M‖ (up to ≈ 5 on the saddle).
      const Spectrum spectrum = problem.Stability(u, w);
      REQUIRE(spectrum.valid);
      REQUIRE(spectrum.values.size() == 2);
      CHECK(spectrum.trivial_removed == 0);
      const std::complex<double> determinant = spectrum.values(0) * spectrum.values(1);
      CHECK(determinant.real() == Approx(std::exp(-params.damping * period)).epsilon(1e-7));
      CHECK(std::abs(determinant.imag()) < 1e-12);
      unstable_counts.push_back(spectrum.UnstableCount());
      if (spectrum.UnstableCount() == 1) {
        // A saddle: one real multiplier outside the unit circle, one inside.
        CHECK(spectrum.values(0).imag() == 0.0);
        CHECK(spectrum.values(0).real() > 1.0);
        CHECK(std::abs(spectrum.values(1)) < 1.0);
      }
    }
    // Small and large responses stable, the middle one a saddle; amplitudes ordered and distinct.
    CHECK(unstable_counts == std::vector<int>{0, 1, 0});
    CHECK(amplitudes[0] < amplitudes[1]);
    CHECK(amplitudes[1] < amplitudes[2]);
  }
}

}  // namespace
}  // namespace rubcont
