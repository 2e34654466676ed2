// Where a run through a schedule of parameter values leaves a transient state, from escape rates
// measured where they matter (a sequential design): the end of the speed-up whip in `rubcont loop`
// (level L3).
//
// The question. A run visits p_1, p_2, … (a run-up's speeds, or a run-down's) and stays `dwell` at
// each, starting on a state that exists as an attractor only on one side of p_c and beyond it
// survives as a transient with exponential lifetimes, rate κ(p) (a chaotic saddle after a boundary
// crisis: sweeps/lifetime.h). It leaves the state at p_i with probability
//     q_i = S_{i−1} (1 − e^{−κ(p_i)·dwell}),  S_0 = 1,  S_i = S_{i−1} − q_i,
// so the speed at which it jumps is a random variable: its median and 5–95 % range are the run-to-
// run spread of a machine run up on that schedule, and they are set by κ where κ·dwell is of
// order 0.05–1, not by p_c. A fixed grid of speeds × copies spends most of its time where that
// distribution has no mass (the rare escapes near p_c); this design does not.
//
// The method. Ensembles (copies at one parameter for a duration, EscapeRunner) are measured in
// batches. After each batch the crisis law κ = A (p − p_c)^γ is fitted to all of them
// (FitCrisis), the leave distribution predicted for the schedule, and the 95 % interval of its
// median found by profile likelihood: the medians of every law within the likelihood-ratio region
// ℓ ≥ ℓ_max − 1.92 (χ²₁(0.95)/2; scanned over p_c and γ, exact in A). The design stops when that
// interval is at most `target_width` wide (or the budget is spent); otherwise the next ensemble
// goes where the cumulative hazard's uncertainty comes from: the value that maximizes
// (κ̂·dwell)² × (the drop of 1/escapes an ensemble there is expected to bring) per copy-second, over
// the values the run can still be on at its 95 % point — with copies long enough to see escapes at
// the fitted rate (2/κ̂, within the duration limits): longer copies where rates are small, which is
// also what bounds p_c from below. A value deepest in the state that still leaks is followed by
// the next one towards the state first (a bracket on the state's side), and the interval counts
// only with enough evidence (min_escapes, floor_hazard).
// Before a law can be fitted (fewer than two values with escapes) the design brackets: the value
// the run was seen to leave at first, then its neighbours towards the state, doubling the duration
// where no copy has left.
//
// Test: tests/sweeps/escape_design_test.cpp, on the tent map past its boundary crisis, whose
// escape rate is known in closed form.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "sweeps/lifetime.h"

namespace rubcont {

// One ensemble to measure: `copies` copies at `parameter` for `duration` [s] each, with seeds
// seed, seed + 1, … (the runner's outcome must depend on these alone, so that a design is
// reproducible on any number of threads or processes).
struct EscapeRequest {
  double parameter = 0.0;
  int copies = 8;
  double duration = 2.0;
  std::uint64_t seed = 1;
};

// The outcomes of a batch of requests: one EscapeObservations per request, in order, and what
// they cost in the budget's unit (EscapeDesignOptions::cost_unit: copy-seconds, CPU seconds, work
// units).
struct EscapeBatch {
  std::vector<EscapeObservations> observations;
  double cost = 0.0;
};
using EscapeRunner = std::function<EscapeBatch(const std::vector<EscapeRequest>& requests)>;

struct EscapeDesignOptions {
  CrisisSide side = CrisisSide::kAbove;  // kAbove: the state ends at high p (a run-up leaves it)
  // The run's parameter values in the order visited (≥ 1), and how long it stays at each [s] > 0.
  std::vector<double> schedule;
  double dwell = 1.5;
  // The values at which ensembles may be measured (≥ 2, distinct; usually the schedule's values
  // over the bracket), and the one at which the state was seen to be gone first (the bracket's
  // far end: a run was seen to leave on its way there). `first` must be one of the candidates.
  std::vector<double> candidates;
  double first = 0.0;
  int copies = 8;              // per ensemble, ≥ 1
  double min_duration = 2.0;   // [s] of one copy, > 0
  double max_duration = 40.0;  // [s] ≥ min_duration
  // Stop when the 95 % interval of the median leave value is at most this wide (parameter units,
  // > 0; e.g. 4 rpm for "±2 rpm").
  double target_width = 4.0;
  double budget = 200.0;  // in the runner's cost unit, > 0: no batch starts once it is spent
  std::string cost_unit = "s";  // how reports name that unit ("s": seconds; "M": million work units)
  // Evidence before the interval counts: asymptotic intervals from a few copies near p_c exclude
  // the truth far more often than 5 % (on the tent map of tests/sweeps/escape_design_test.cpp,
  // designs that stopped at the first interval narrow enough covered the true median in 90 of 100).
  // At least this many escapes in all, ≥ 0,
  int min_escapes = 20;
  // and a value towards the state from the median's interval whose 95 % upper rate times `dwell`
  // is at most this (> 0): the chance to leave there is measured small, not extrapolated. With
  // these two (and target_width 4 units, 1-unit steps) the median's interval covered the true
  // median in 198 of 200 designs and p_c's interval the true p_c in 183 of 200 (92 %: the profile
  // interval of p_c is short of its nominal 95 % with this little data), at a mean cost of 310
  // copy-seconds (median 288, largest 953); 0.05 and 30 cost 445–410 for no better coverage.
  double floor_hazard = 0.1;
  std::uint64_t seed = 1;  // of the ensembles (batch k, request r: seed + 1000·(k·16 + r) + copy)
  int max_rounds = 60;     // batches, ≥ 1
};

// Throws std::invalid_argument naming the field, its value and the rule.
void Validate(const EscapeDesignOptions& options);

// The leave distribution of a run (header comment) for the law `fit`.
struct LeaveDistribution {
  std::vector<double> probability;  // q_i per schedule value
  double stay = 1.0;                // S_n: the run keeps the state to the end of the schedule
  // The first schedule value at which the cumulative probability reaches 5 %, 50 %, 95 %; NaN when
  // it does not within the schedule.
  double low = 0.0, median = 0.0, high = 0.0;
};
LeaveDistribution PredictLeave(const CrisisFit& fit, CrisisSide side, const std::vector<double>& schedule,
                               double dwell);

// The 95 % profile-likelihood interval of the leave distribution's median for `observations` and
// their crisis fit (FitCrisis with CrisisOptions{side}): the medians of every law within the
// likelihood-ratio region ℓ ≥ ℓ_max − 1.92, scanned over p_c and γ, exact in A (the design's rule,
// header comment). lower ≤ upper in value; both NaN, with `open` saying why, when there is no law
// or the run may keep the state to the end of the schedule.
struct LeaveMedianInterval {
  double lower = 0.0;
  double upper = 0.0;
  std::string open;
};
LeaveMedianInterval MedianInterval(const std::vector<EscapeObservations>& observations, const CrisisFit& fit,
                                   CrisisSide side, const std::vector<double>& schedule, double dwell);

// Whether escape times look exponential — a chaotic saddle's memoryless leaking — rather than a
// deterministic passage (every copy leaving after about the same time: a slow drift past a
// bifurcation, which a crisis law would also fit). Over the ensembles with at least 5 escapes that
// did not all leave in their first stretch, the coefficient of variation of the escape times
// (stretch midpoints) is compared with an exponential's at the ensemble's own rate, truncated at
// its duration and binned by its stretch: a leak shows it at some value — where rates are high a
// copy's landing (the 0.1–0.2 s it takes to settle where it arrives, counted in its time) bunches
// even a leak's times (A(a)'s whip at 186 rpm, 2 rpm / 1.5 s: 0.39 of the exponential's spread, the
// smallest of its ensembles) — a passage at none: every qualifying ensemble below half of it.
struct LifetimeShape {
  bool resolved = false;     // some ensemble qualified
  bool exponential = false;  // some qualifying ensemble's spread is at least half the exponential's
  double largest_ratio = 0.0;  // the largest observed / expected coefficient of variation (NaN: none)
  std::string message;        // the numbers, in words
};
LifetimeShape CheckExponential(const std::vector<EscapeObservations>& observations);

enum class EscapeDesignStatus {
  kConverged,  // the median's 95 % interval is at most target_width wide
  kBudget,     // the budget was spent first (the interval is what the data give)
  kRounds,     // max_rounds batches were spent first
  kNoEscape,   // no copy left at any candidate within max_duration: no end of the state found
  kNoLaw,      // escapes seen, but no crisis law could be fitted (FitCrisis's status in the message)
};
const char* ToString(EscapeDesignStatus status);

struct EscapeDesign {
  EscapeDesignStatus status = EscapeDesignStatus::kNoLaw;
  std::string message;
  std::vector<EscapeObservations> observations;  // every ensemble, in the order measured
  CrisisFit fit;                                 // with its profile interval of p_c
  LeaveDistribution leave;                       // predicted from `fit`
  // The median's 95 % profile-likelihood interval (lower ≤ upper in value); NaN when an end lies
  // beyond the schedule (the run may keep the state to its end), and then `median_open` says so.
  double median_lower = 0.0, median_upper = 0.0;
  std::string median_open;  // "" or why the interval is open
  double cost = 0.0;          // the runner's cost, summed
  std::string cost_unit = "s";  // EscapeDesignOptions::cost_unit
  int rounds = 0;
  std::vector<std::string> log;  // one line per batch: what was measured and why, the fit after it
  std::string BriefReport() const;
};

// Runs the design (header comment). `progress` is called with each log line as it is made.
// Throws std::invalid_argument for invalid options; a runner's exception propagates.
EscapeDesign RunEscapeDesign(const EscapeDesignOptions& options, const EscapeRunner& run,
                             const std::function<void(const std::string&)>& progress = {});

}  // namespace rubcont
