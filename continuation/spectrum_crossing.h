// Classification of a spectrum for crossing detection: which eigenvalues (Floquet multipliers) are
// unstable, by kind, and a continuous test function for each kind of crossing.
//
// Eigenvalues μ: real (|Im μ| ≤ tol·max(1, |μ|)) or a complex pair (counted once, by Im μ > 0);
// unstable when Re μ > StabilityTolerance. Multipliers μ: real positive, real negative, or a
// complex pair; unstable when |μ| > 1 + StabilityTolerance. A crossing of a kind is declared
// between two points when the number of unstable values of that kind changes, and the total number
// changes the same way (a complex pair that collides on the real axis changes the kinds but not the
// total: that is no crossing). Its test function is the (k+1)-th largest instability measure of
// that kind, k = the smaller of the two counts: an order statistic of continuous functions, hence
// continuous, and its zero is the crossing (Re μ = 0, or |μ| = 1; the tolerance only decides the
// counts).
#pragma once

#include <array>
#include <complex>
#include <vector>

#include "continuation/problem.h"

namespace rubcont {

enum class SpectralKind {
  kRealEigenvalue,
  kComplexEigenvalues,
  kRealPositiveMultiplier,
  kRealNegativeMultiplier,
  kComplexMultipliers,
};
constexpr int kSpectralKinds = 5;

struct SpectrumCounts {
  std::array<int, kSpectralKinds> unstable{};  // indexed by SpectralKind
  int total = 0;                               // complex pairs count twice, as in UnstableCount
};

SpectrumCounts CountUnstable(const Spectrum& spectrum, double imaginary_tolerance,
                             double stability_tolerance);

struct SpectralValue {
  double measure = 0.0;          // Re μ, or |μ| − 1: vanishes on the stability boundary
  std::complex<double> value;    // the eigenvalue or multiplier (Im ≥ 0 for pairs)
};

// The values of one kind, by decreasing measure (unstable when measure > StabilityTolerance).
std::vector<SpectralValue> ValuesOfKind(const Spectrum& spectrum, SpectralKind kind,
                                        double imaginary_tolerance);

// The special point a crossing of this kind is (kFold-like kinds map to kRealEigenvalueCrossing
// and kMultiplierPlusOne; the engine reports those only when its fold and branch-point tests did
// not fire in the same step).
SpecialPointType CrossingType(SpectralKind kind);

}  // namespace rubcont
