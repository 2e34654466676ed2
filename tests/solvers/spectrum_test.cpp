#include "solvers/constants.h"
#include "solvers/spectrum.h"

#include <cmath>
#include <complex>
#include <stdexcept>

#include <catch2/catch.hpp>

namespace rubcont {
namespace {

using Catch::Matchers::Contains;
using Complex = std::complex<double>;

ComplexVector Tone(Index n, double sample_rate, double frequency, Complex amplitude,
                   Complex offset = 0.0) {
  ComplexVector z(n);
  for (Index i = 0; i < n; ++i)
    z(i) = offset + amplitude * std::exp(Complex(0.0, kTwoPi * frequency * i / sample_rate));
  return z;
}

TEST_CASE("A tone on a bin has its amplitude there and Hann's halves beside it", "[sweep]") {
  const Index n = 256;
  const double fs = 512.0;  // bins of 2 Hz
  const AmplitudeSpectrum s = TwoSidedSpectrum(Tone(n, fs, -40.0, Complex(0.3, 0.4), Complex(7.0, -2.0)), fs);
  REQUIRE(s.frequency.size() == n);
  CHECK(s.frequency(0) == Approx(-256.0));
  CHECK(s.frequency(n - 1) == Approx(254.0));
  CHECK(s.BinWidth() == Approx(2.0));
  const Index k = n / 2 - 20;  // −40 Hz
  REQUIRE(s.frequency(k) == Approx(-40.0));
  CHECK(s.magnitude(k) == Approx(0.5).epsilon(1e-12));
  CHECK(s.magnitude(k - 1) == Approx(0.25).epsilon(1e-12));
  CHECK(s.magnitude(k + 1) == Approx(0.25).epsilon(1e-12));
  // The offset (7 − 2j) is removed: nothing at 0 Hz, nothing anywhere else.
  for (Index j = 0; j < n; ++j)
    if (std::abs(j - k) > 1) CHECK(s.magnitude(j) < 1e-12);
}

TEST_CASE("The refined peak recovers frequency and amplitude between bins", "[sweep]") {
  const Index n = 1024;
  const double fs = 4096.0;  // bins of 4 Hz
  std::mt19937 random(7);
  std::uniform_real_distribution<double> offset(-0.5, 0.5);
  double worst_frequency = 0.0, worst_amplitude = 0.0;
  for (int trial = 0; trial < 200; ++trial) {
    const double f = -84.0 - 4.0 * trial * 0.37 + 4.0 * offset(random);
    const AmplitudeSpectrum s = TwoSidedSpectrum(Tone(n, fs, f, std::polar(2.5e-4, 0.1 * trial)), fs);
    const SpectralPeak peak = DominantPeak(s, PeakSide::kNegative);
    REQUIRE(peak.found);
    worst_frequency = std::max(worst_frequency, std::abs(peak.frequency - f) / s.BinWidth());
    worst_amplitude = std::max(worst_amplitude, std::abs(peak.amplitude / 2.5e-4 - 1.0));
  }
  // Without refinement the error would reach ½ bin and the amplitude 15 % (Hann scalloping).
  CHECK(worst_frequency < 1e-4);
  CHECK(worst_amplitude < 1e-4);
}

TEST_CASE("The dominant peak is taken on the requested side, away from 0 Hz", "[sweep]") {
  const Index n = 512;
  const double fs = 512.0;
  ComplexVector z = Tone(n, fs, -30.25, 1.0) + Tone(n, fs, 50.5, 2.0) + Tone(n, fs, -3.0, 5.0);
  const AmplitudeSpectrum s = TwoSidedSpectrum(z, fs);
  CHECK(DominantPeak(s, PeakSide::kNegative, 5.0).frequency ==
        Approx(-30.25).epsilon(0).margin(1e-3));
  CHECK(DominantPeak(s, PeakSide::kPositive).frequency == Approx(50.5).epsilon(0).margin(1e-3));
  CHECK(DominantPeak(s, PeakSide::kAny, 5.0).frequency == Approx(50.5).epsilon(0).margin(1e-3));
  // Without the minimum the −3 Hz tone (3 bins from 0) wins on the negative side.
  CHECK(DominantPeak(s, PeakSide::kNegative).frequency == Approx(-3.0).epsilon(0).margin(1e-3));
  // Within 2 bins of 0 nothing counts: a −1 Hz tone is not a peak at −1 Hz.
  const AmplitudeSpectrum slow = TwoSidedSpectrum(Tone(n, fs, -1.0, 5.0), fs);
  CHECK(DominantPeak(slow, PeakSide::kNegative).frequency <= -1.5);
  // A purely positive signal has no negative peak worth the name but still a largest bin.
  const SpectralPeak none = DominantPeak(TwoSidedSpectrum(Tone(n, fs, 50.0, 1.0), fs), PeakSide::kNegative);
  CHECK(none.found);
  CHECK(none.amplitude < 1e-12);
}

TEST_CASE("Spectral distance is relative and zero for equal spectra", "[sweep]") {
  const AmplitudeSpectrum a = TwoSidedSpectrum(Tone(64, 64.0, 10.0, 1.0), 64.0);
  AmplitudeSpectrum b = a;
  CHECK(SpectralDistance(a, b) == 0.0);
  b.magnitude *= 1.1;
  CHECK(SpectralDistance(a, b) == Approx(0.1 / 1.1).epsilon(1e-12));
  AmplitudeSpectrum zero = a;
  zero.magnitude.setZero();
  CHECK(SpectralDistance(zero, zero) == 0.0);
  const AmplitudeSpectrum shorter = TwoSidedSpectrum(Tone(32, 64.0, 10.0, 1.0), 64.0);
  CHECK_THROWS_AS(SpectralDistance(a, shorter), std::invalid_argument);
  CHECK_THROWS_WITH(TwoSidedSpectrum(ComplexVector::Zero(3), 1.0), Contains("at least 4"));
}

}  // namespace
}  // namespace rubcont
