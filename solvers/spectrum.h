// Spectra of uniformly sampled complex signals: the two-sided amplitude spectrum, its dominant
// peak refined below the bin width, and the distance between two spectra. Sweeps (sweeps/sweep.h)
// read a response's precession from them; the rub's modulated orbits (shooting/modulated_orbit.h)
// their modulation period.
//
// AmplitudeSpectrum: the complex samples z_0 … z_{N−1} of the analysed stretch, minus their Hann-weighted
// mean (so the static offset does not leak), times the periodic Hann window w_n = ½ − ½cos(2πn/N),
// Fourier transformed (Eigen's FFT, kissfft) and scaled by 1/Σw: a tone a·e^{j2πft} with f on a
// bin gives amplitude |a| there. Bins are ordered by frequency, −fs/2 … fs/2 − fs/N.
//
// Peak refinement (below the bin width Δf = fs/N): for the Hann window the transform of a tone at
// f = (k + δ)Δf has |X_{k±1}| / |X_k| = (1 ± δ)/(2 ∓ δ) (continuous-window limit, error O(1/N²)),
// so from the larger neighbour ratio r, |δ| = (2r − 1)/(1 + r), signed towards that neighbour.
// It is exact for a single complex tone up to O(N⁻²) and needs no fit; the amplitude follows
// from the window's transform |W(δ)| = sinc(δ)/(1 − δ²) (Harris 1978; the ratio form is the
// classical two-point interpolation for the Hann window, e.g. Grandke 1983).
#pragma once

#include "solvers/types.h"

namespace rubcont {

struct AmplitudeSpectrum {
  double sample_rate = 0.0;  // fs [samples per time unit]
  Vector frequency;          // N bin frequencies, ascending: −fs/2 … fs/2 − fs/N [cycles per time unit]
  Vector magnitude;          // N amplitudes (Hann, scaled by 1/Σw: a tone on a bin gives its amplitude)
  double BinWidth() const { return frequency.size() > 0 ? sample_rate / frequency.size() : 0.0; }
};

// The two-sided amplitude spectrum of uniform complex samples (N ≥ 4 of them) at rate fs > 0.
// Throws std::invalid_argument for fewer than 4 samples or a non-positive rate.
AmplitudeSpectrum TwoSidedSpectrum(const ComplexVector& samples, double sample_rate);

enum class PeakSide {
  kNegative,  // f < 0: clockwise rotation of x + jy (backward precession for the rub model)
  kPositive,  // f > 0
  kAny,
};

struct SpectralPeak {
  bool found = false;      // false: no bin on that side at |f| ≥ the minimum
  double frequency = 0.0;  // refined frequency [cycles per time unit], signed
  double amplitude = 0.0;  // refined amplitude (same unit as the samples)
  Index bin = 0;           // index of the largest bin in AmplitudeSpectrum::frequency
  double offset = 0.0;     // δ: refined offset from that bin, in bins, |δ| ≤ ½
};

// The largest bin on `side` with |f| ≥ max(min_frequency, 2Δf) (the two bins nearest 0 hold the
// Hann leakage of what is left of the mean), refined as in the header comment.
SpectralPeak DominantPeak(const AmplitudeSpectrum& spectrum, PeakSide side, double min_frequency = 0.0);

// ‖|A| − |B|‖₂ / max(‖A‖₂, ‖B‖₂) over all bins (0 when both are zero). Same length required.
double SpectralDistance(const AmplitudeSpectrum& a, const AmplitudeSpectrum& b);

}  // namespace rubcont
