#include "continuation/spectrum_crossing.h"

#include <algorithm>
#include <cmath>

namespace rubcont {

namespace {

bool IsReal(std::complex<double> value, double imaginary_tolerance) {
  return std::abs(value.imag()) <= imaginary_tolerance * std::max(1.0, std::abs(value));
}

// The kind of one value, or −1 for the lower member of a complex pair (not counted).
int KindOf(const Spectrum& spectrum, std::complex<double> value, double imaginary_tolerance) {
  const bool real = IsReal(value, imaginary_tolerance);
  if (!real && value.imag() < 0.0) return -1;
  if (spectrum.kind == SpectrumKind::kEigenvalues) {
    return static_cast<int>(real ? SpectralKind::kRealEigenvalue
                                 : SpectralKind::kComplexEigenvalues);
  }
  if (!real) return static_cast<int>(SpectralKind::kComplexMultipliers);
  return static_cast<int>(value.real() >= 0.0 ? SpectralKind::kRealPositiveMultiplier
                                              : SpectralKind::kRealNegativeMultiplier);
}

double MeasureOf(const Spectrum& spectrum, std::complex<double> value) {
  return spectrum.kind == SpectrumKind::kEigenvalues ? value.real() : std::abs(value) - 1.0;
}

}  // namespace

SpectrumCounts CountUnstable(const Spectrum& spectrum, double imaginary_tolerance,
                             double stability_tolerance) {
  SpectrumCounts counts;
  for (Index i = 0; i < spectrum.values.size(); ++i) {
    const std::complex<double> value = spectrum.values(i);
    if (!(MeasureOf(spectrum, value) > stability_tolerance)) continue;
    ++counts.total;
    const int kind = KindOf(spectrum, value, imaginary_tolerance);
    if (kind >= 0) ++counts.unstable[kind];
  }
  return counts;
}

std::vector<SpectralValue> ValuesOfKind(const Spectrum& spectrum, SpectralKind kind,
                                        double imaginary_tolerance) {
  std::vector<SpectralValue> values;
  for (Index i = 0; i < spectrum.values.size(); ++i) {
    const std::complex<double> value = spectrum.values(i);
    if (KindOf(spectrum, value, imaginary_tolerance) != static_cast<int>(kind)) continue;
    values.push_back({MeasureOf(spectrum, value), value});
  }
  std::sort(values.begin(), values.end(),
            [](const SpectralValue& a, const SpectralValue& b) { return a.measure > b.measure; });
  return values;
}

namespace {

bool IsEigenvalueKind(SpectralKind kind) {
  return kind == SpectralKind::kRealEigenvalue || kind == SpectralKind::kComplexEigenvalues;
}

// The factor of the product for one value (single kinds) or one pair of values (pair kinds), with
// the boundary moved out by `shift` (Re μ = shift, |μ| = 1 + shift).
std::complex<double> Factor(SpectralKind kind, std::complex<double> a, std::complex<double> b,
                            double shift) {
  switch (kind) {
    case SpectralKind::kRealEigenvalue: return a - shift;
    case SpectralKind::kComplexEigenvalues: return a + b - 2.0 * shift;
    case SpectralKind::kRealPositiveMultiplier: return a - (1.0 + shift);
    case SpectralKind::kRealNegativeMultiplier: return a + (1.0 + shift);
    case SpectralKind::kComplexMultipliers: return a * b - (1.0 + shift) * (1.0 + shift);
  }
  return a;
}

}  // namespace

LogDeterminant SpectralProduct(const Spectrum& spectrum, SpectralKind kind, double shift) {
  LogDeterminant product;
  if (IsEigenvalueKind(kind) != (spectrum.kind == SpectrumKind::kEigenvalues)) return product;
  std::complex<double> phase = 1.0;
  auto multiply = [&](std::complex<double> factor) {
    const double magnitude = std::abs(factor);
    if (magnitude == 0.0) {
      phase = 0.0;
      return;
    }
    product.log_abs += std::log(magnitude);
    phase *= factor / magnitude;
  };
  const Index n = spectrum.values.size();
  for (Index i = 0; i < n; ++i) {
    if (!IsPairKind(kind)) {
      multiply(Factor(kind, spectrum.values(i), 0.0, shift));
      continue;
    }
    for (Index j = i + 1; j < n; ++j) {
      multiply(Factor(kind, spectrum.values(i), spectrum.values(j), shift));
    }
  }
  // A conjugate-closed spectrum gives a real product: the phase is ±1 up to rounding.
  product.sign = phase.real() > 0.0 ? 1 : (phase.real() < 0.0 ? -1 : 0);
  return product;
}

bool CriticalValueAtZero(const Spectrum& spectrum, SpectralKind kind, double imaginary_tolerance,
                         double shift, SpectralValue& value) {
  const std::vector<SpectralValue> values = ValuesOfKind(spectrum, kind, imaginary_tolerance);
  if (values.empty()) return false;
  value = *std::min_element(values.begin(), values.end(), [shift](const auto& a, const auto& b) {
    return std::abs(a.measure - shift) < std::abs(b.measure - shift);
  });
  if (!IsPairKind(kind)) return true;
  // The pair's own factor, |2 (Re μ − shift)| or ||μ|² − (1 + shift)²|, against the real pairs'.
  const double pair_factor = std::abs(Factor(kind, value.value, std::conj(value.value), shift));
  const Index n = spectrum.values.size();
  for (Index i = 0; i < n; ++i) {
    if (!IsReal(spectrum.values(i), imaginary_tolerance)) continue;
    for (Index j = i + 1; j < n; ++j) {
      if (!IsReal(spectrum.values(j), imaginary_tolerance)) continue;
      const double real_factor =
          std::abs(Factor(kind, spectrum.values(i).real(), spectrum.values(j).real(), shift));
      if (real_factor < pair_factor) return false;
    }
  }
  return true;
}

std::array<int, kSpectralKinds> KindSizes(const Spectrum& spectrum, double imaginary_tolerance) {
  std::array<int, kSpectralKinds> sizes{};
  for (Index i = 0; i < spectrum.values.size(); ++i) {
    const int kind = KindOf(spectrum, spectrum.values(i), imaginary_tolerance);
    if (kind >= 0) ++sizes[kind];
  }
  return sizes;
}

SpecialPointType CrossingType(SpectralKind kind) {
  switch (kind) {
    case SpectralKind::kRealEigenvalue: return SpecialPointType::kRealEigenvalueCrossing;
    case SpectralKind::kComplexEigenvalues: return SpecialPointType::kHopf;
    case SpectralKind::kRealPositiveMultiplier: return SpecialPointType::kMultiplierPlusOne;
    case SpectralKind::kRealNegativeMultiplier: return SpecialPointType::kPeriodDoubling;
    case SpectralKind::kComplexMultipliers: return SpecialPointType::kNeimarkSacker;
  }
  return SpecialPointType::kTestFunction;
}

}  // namespace rubcont
