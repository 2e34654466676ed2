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
//
// The order statistic jumps where a value of the kind leaves it within the step (a complex pair
// collides on the real axis, or two real values meet and become a pair): the (k+1)-th largest is
// then another value. SpectralProduct is a test function that does not depend on kinds or order:
// a symmetric polynomial of the whole spectrum that vanishes on the boundary (Govaerts, "Numerical
// Methods for Bifurcations of Dynamical Equilibria", §4.4: det A for a real crossing, the
// bialternate product det(2A ⊙ I) for Hopf), continuous through collisions, whose sign changes
// with every (odd number of) crossing.
#pragma once

#include <array>
#include <complex>
#include <vector>

#include "continuation/problem.h"
#include "solvers/linear_algebra.h"

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

// The kinds that are complex pairs (Hopf, Neimark–Sacker).
inline bool IsPairKind(SpectralKind kind) {
  return kind == SpectralKind::kComplexEigenvalues || kind == SpectralKind::kComplexMultipliers;
}

// The product over the spectrum of the factor that vanishes on the boundary for this kind, moved
// out by `shift` (the counts' StabilityTolerance: then the product changes sign where a count does,
// and a neutral value whose computed Re μ wanders about 0 by rounding, e.g. an undamped mode,
// changes neither):
//   real eigenvalue through s:               Π (μ_i − s)                (det(A − s))
//   complex pair through Re μ = s:           Π_{i<j} (μ_i + μ_j − 2s)   (the bialternate product
//                                            det(2(A − s) ⊙ I); also 0 at a neutral saddle)
//   real multiplier through ±(1 + s):        Π (μ_i ∓ (1 + s))
//   complex pair through |μ| = 1 + s:        Π_{i<j} (μ_i μ_j − (1 + s)²) (also 0 at a real pair)
// as sign and log |·| (the products overflow). Real for a conjugate-closed spectrum; sign = 0 when
// a factor is exactly 0, or for a kind that is not of the spectrum's (eigenvalues vs multipliers).
LogDeterminant SpectralProduct(const Spectrum& spectrum, SpectralKind kind, double shift);

// The value of `kind` nearest the shifted boundary (smallest |measure − shift|); false when the
// kind has none. For the pair kinds also false when a real pair of the spectrum lies nearer its
// own zero of the product than any complex pair does: the product's zero there is a neutral
// saddle, not a crossing.
bool CriticalValueAtZero(const Spectrum& spectrum, SpectralKind kind, double imaginary_tolerance,
                         double shift, SpectralValue& value);

// The number of values of each kind (stable and unstable), to tell whether kinds changed.
std::array<int, kSpectralKinds> KindSizes(const Spectrum& spectrum, double imaginary_tolerance);

// The special point a crossing of this kind is (kFold-like kinds map to kRealEigenvalueCrossing
// and kMultiplierPlusOne; the engine reports those only when its fold and branch-point tests did
// not fire in the same step).
SpecialPointType CrossingType(SpectralKind kind);

}  // namespace rubcont
