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
