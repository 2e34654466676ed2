#include "solvers/spectrum.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <stdexcept>
#include <vector>

#include <fmt/core.h>
#include <unsupported/Eigen/FFT>

#include "solvers/constants.h"

namespace rubcont {

namespace {

// |W(δ)| / W(0) of the Hann window's transform in the continuous limit: sinc(δ)/(1 − δ²).
double HannGain(double delta) {
  if (std::abs(delta) < 1e-12) return 1.0;
  if (std::abs(std::abs(delta) - 1.0) < 1e-12) return 0.5;
  return std::sin(kPi * delta) / (kPi * delta * (1.0 - delta * delta));
}

}  // namespace

AmplitudeSpectrum TwoSidedSpectrum(const ComplexVector& samples, double sample_rate) {
  const Index n = samples.size();
  if (n < 4) {
    throw std::invalid_argument(
        fmt::format("TwoSidedSpectrum: {} samples: need at least 4", n));
  }
  if (!(sample_rate > 0.0) || !std::isfinite(sample_rate)) {
    throw std::invalid_argument(
        fmt::format("TwoSidedSpectrum: sample_rate = {}: must be positive and finite", sample_rate));
  }
  // Periodic Hann window and the Hann-weighted mean.
  Vector w(n);
  for (Index i = 0; i < n; ++i) w(i) = 0.5 - 0.5 * std::cos(kTwoPi * static_cast<double>(i) / n);
  const double sum_w = w.sum();
  const std::complex<double> mean = (samples.array() * w.array()).sum() / sum_w;
  std::vector<std::complex<double>> windowed(static_cast<std::size_t>(n));
  for (Index i = 0; i < n; ++i) windowed[static_cast<std::size_t>(i)] = (samples(i) - mean) * w(i);
  std::vector<std::complex<double>> transform;
  Eigen::FFT<double> fft;
  fft.fwd(transform, windowed);

  AmplitudeSpectrum s;
  s.sample_rate = sample_rate;
  s.frequency.resize(n);
  s.magnitude.resize(n);
  // Ascending order: DFT indices n − n/2 … n − 1 (negative), then 0 … n − n/2 − 1.
  const Index negatives = n / 2;
  for (Index j = 0; j < n; ++j) {
    const Index k = j < negatives ? n - negatives + j : j - negatives;  // DFT index
    const Index signed_k = j - negatives;
    s.frequency(j) = static_cast<double>(signed_k) * sample_rate / static_cast<double>(n);
    s.magnitude(j) = std::abs(transform[static_cast<std::size_t>(k)]) / sum_w;
  }
  return s;
}

SpectralPeak DominantPeak(const AmplitudeSpectrum& spectrum, PeakSide side, double min_frequency) {
  SpectralPeak peak;
  const Index n = spectrum.frequency.size();
  const double df = spectrum.BinWidth();
  const double lowest = std::max(min_frequency, 2.0 * df * (1.0 - 1e-9));
  double best = -1.0;
  for (Index j = 0; j < n; ++j) {
    const double f = spectrum.frequency(j);
    if (std::abs(f) < lowest) continue;
    if (side == PeakSide::kNegative && f >= 0.0) continue;
    if (side == PeakSide::kPositive && f <= 0.0) continue;
    if (spectrum.magnitude(j) > best) {
      best = spectrum.magnitude(j);
      peak.bin = j;
    }
  }
  if (best < 0.0) return peak;
  peak.found = true;
  const Index k = peak.bin;
  const double b = spectrum.magnitude(k);
  const double a = k > 0 ? spectrum.magnitude(k - 1) : 0.0;
  const double c = k + 1 < n ? spectrum.magnitude(k + 1) : 0.0;
  double delta = 0.0;
  if (b > 0.0) {
    // Two-point Hann interpolation towards the larger neighbour: |δ| = (2r − 1)/(1 + r).
    const double r = std::max(a, c) / b;
    delta = std::clamp((2.0 * r - 1.0) / (1.0 + r), 0.0, 0.5);
    if (a > c) delta = -delta;
  }
  peak.offset = delta;
  peak.frequency = spectrum.frequency(k) + delta * df;
  peak.amplitude = b / HannGain(delta);
  return peak;
}

double SpectralDistance(const AmplitudeSpectrum& a, const AmplitudeSpectrum& b) {
  if (a.magnitude.size() != b.magnitude.size()) {
    throw std::invalid_argument(fmt::format("SpectralDistance: spectra of {} and {} bins",
                                            a.magnitude.size(), b.magnitude.size()));
  }
  const double scale = std::max(a.magnitude.norm(), b.magnitude.norm());
  if (scale == 0.0) return 0.0;
  return (a.magnitude - b.magnitude).norm() / scale;
}

}  // namespace rubcont
