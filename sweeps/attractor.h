// What a long transient settles on (level L3): the leading Lyapunov exponents and a Poincaré
// section, so that a motion can be called (relative) periodic, quasi-periodic or chaotic with
// evidence rather than by the look of a spectrum.
//
// Lyapunov exponents (Benettin, Galgani, Giorgilli & Strelcyn 1980, the QR form of Eckmann &
// Ruelle 1985): the state and k tangent directions Q (n × k) are integrated together over
// intervals of length τ with the variational equations (OdeIntegrator::IntegrateTangents: CVODES
// forward sensitivities seeded with Q, not differences of two trajectories), W = Φ(t + τ, t)·Q;
// then S⁻¹W = Q̃R (Householder QR, S = diag(StateScale())), Q ← S·Q̃, and λ_i = Σ log|R_ii| / T.
// The scaled norm makes metres and metres per second comparable; the exponents do not depend on
// the norm (a fixed change of norm moves log-growths by a bounded amount, nothing per unit time).
// The first `discard` time units are integrated the same way but not counted: the transient dies
// and the directions align with the leading Lyapunov vectors.
//
// Uncertainty: the counted record is cut into `blocks` blocks of whole intervals; each block gives
// its own exponents, and the standard error is their standard deviation over √blocks. An exponent
// is called zero when |λ| ≤ max(3·standard error, zero_tolerance), positive or negative when it
// lies beyond that on either side. Finite records bias a zero exponent by O(1/T) (the growth of a
// neutral direction is bounded, not zero): zero_tolerance says how much is accepted.
//
// Poincaré section: extrema of scalar signals of the state (e.g. the rub's penetrations,
// sweeps/rub_sweep.h), sampled at a fixed interval by the integrator's dense output along the
// whole counted record and located between samples by the parabola through three, the state
// there by the same quadratic interpolation. Samples, not event functions: a signal whose
// derivative hovers at rounding level (a contact's penetration rate in full contact) makes root
// finding stall, and sampling leaves the steps alone. ExcursionMaxima then keeps one maximum per
// excursion: a periodic motion gives one point per channel (or a few), a torus a closed curve in
// the return map (value_j, value_j+1), chaos a cloud.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "solvers/ode.h"
#include "solvers/ode_system.h"

namespace rubcont {

struct AttractorOptions {
  double discard = 0.5;     // time integrated first and not counted (time units) ≥ 0
  double duration = 2.0;    // counted time (time units) > 0
  double interval = 0.005;  // τ: re-orthonormalization interval (time units), > 0, ≤ duration / blocks
  int exponents = 4;        // k, in [1, n]
  int blocks = 10;          // ≥ 2
  double zero_tolerance = 1.0;  // ≥ 0, in 1/time units (see the header comment)
  IntegratorOptions integrator;
};

// Throws std::invalid_argument naming the field, its value and the rule.
void Validate(const AttractorOptions& options);

// Signals sampled for the section: `count` values of the state, every `interval` time units
// (> 0, at most the re-orthonormalization interval).
struct SampledSection {
  int count = 0;
  double interval = 0.0;
  std::function<void(ConstVectorRef x, VectorRef values)> function;
};

// A local maximum or minimum of one signal: its channel, kind (+1 maximum, −1 minimum), time
// (from the start of the counted record), value, and the state there (interpolated).
struct SectionExtremum {
  int channel = 0;
  int kind = 0;
  double t = 0.0;
  double value = 0.0;
  Vector x;
};

enum class ExponentSign { kNegative, kZero, kPositive };
const char* ToString(ExponentSign sign);

enum class AttractorStatus {
  kMeasured,            // the whole record was integrated
  kIntegrationFailure,  // the integrator failed (message); exponents are those of the time reached
};
const char* ToString(AttractorStatus status);

struct AttractorResult {
  AttractorStatus status = AttractorStatus::kMeasured;
  std::string message;
  Vector exponents;        // k, descending, in 1/time units
  Vector standard_errors;  // k
  std::vector<ExponentSign> signs;  // k
  int positive = 0;        // how many exponents are positive, zero, negative
  int zero = 0;
  int negative = 0;
  Vector times;            // end of each counted interval (from the start of the counted record)
  Matrix running;          // k × intervals: the running estimates λ_i(t)
  std::vector<SectionExtremum> extrema;  // in time order per channel
  Vector state;            // the state at the end
  double counted_time = 0.0;
  double cpu_seconds = 0.0;  // CPU time of the calling thread
  IntegrationStatistics statistics;  // summed over the intervals
};

// A section that counts one point per excursion of a noisy oscillating signal: given the values
// of its successive extrema (maxima and minima in time order), the index of the largest value in
// each excursion. An excursion opens at an extremum above the level max(floor, (min + max)/2)
// and closes at the next one below the level minus a quarter of max − min: the hysteresis keeps
// a fast small oscillation riding on the slow one (less than a quarter of the range) from opening
// a second excursion where the slow one crosses the level. Excursions cut by either end of the
// record (open at its first or last value) are left out.
std::vector<std::size_t> ExcursionMaxima(const std::vector<double>& extrema, double floor);

// Called after each interval: time done (including the discard), total time.
using AttractorProgress = std::function<void(double done, double total)>;

// The period of a sequence of section values in returns: the smallest p in [1, max_period] with
// |v_j+p − v_j| ≤ tolerance for every j of the second half of the sequence (the first half is
// left to the transient), or 0 when there is none or the second half holds fewer than
// 2·max_period values: a periodic motion shows period 1 (one point per channel), a
// period-doubled one 2; a torus or chaos none.
int SectionPeriod(const std::vector<double>& values, double tolerance, int max_period);

// How a section's points (columns, in comparable units: scale them first) fill space, from
// their near neighbours: the distance r_k to a point's k-th nearest grows as k^(1/d) on a set of
// dimension d, so the dimension is ln 4 / ln(r₁₆ / r₄), medians over the points (a correlation
// dimension at the scale of the points' spacing: a torus's section is curves, 1; chaos a cloud,
// > 1). Tested on an irrational rotation's curve (1.007) and a two-rotation surface (1.887);
// dropping every other point instead read 1292 on the curve, whose nearest neighbour then often
// stays. On an orbit of q sections the nearest neighbour is q sections later and the points
// slide along the orbit by the period's error, so the dimension reads 1 there too: `apart` (q)
// and the small `nearest` tell the orbit (where the slide is below the integration's noise, the
// points are a cloud of that size: C(a)'s 3:7 orbit at 74.5 rpm read 2.02 with `nearest` 2e-10).
// Pieces: the points linked where nearer than 3 r₄ (a torus round an orbit of q sections cuts
// the section in q closed curves). O(m²) for m points. Points that do not spread (r₁₆ = r₄) give
// an infinite or NaN dimension.
struct SectionDimension {
  double nearest = 0.0;    // median distance to the nearest other point
  double apart = 0.0;      // median of how many points (sections) apart the nearest lies
  double fourth = 0.0;     // median r₄
  double sixteenth = 0.0;  // median r₁₆
  double dimension = 0.0;  // ln 4 / ln(sixteenth / fourth)
  int pieces = 0;
};
// Throws std::invalid_argument for fewer than 17 points.
SectionDimension MeasureSectionDimension(const Matrix& points);

// Integrates `system` from x0 at its current parameter. `section` may be null. Throws
// std::invalid_argument for invalid options, section or sizes; integration failures are a status.
AttractorResult MeasureAttractor(OdeSystem& system, const Vector& x0, const AttractorOptions& options,
                                 const SampledSection* section = nullptr,
                                 const AttractorProgress& progress = {});

}  // namespace rubcont
