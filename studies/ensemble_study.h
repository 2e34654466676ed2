// How long the state a sweep has reached lasts at the next speed, as a distribution over perturbed
// copies (level L3; sweeps/ensemble.h, sweeps/rub_sweep.h RubArrivals). The scene's sweep in its
// direction is run from rest plus the impulse up to the last speed of its schedule before the
// speed (the approach; none when the speed comes first); from its final state the copies, each
// perturbed by ensemble.perturbation × each state's scale, run at the speed for `duration` in
// stretches of two windows, each stretch classified as a sweep speed (the sweep's regime rules),
// until they arrive at the target. The copies run on ensemble.threads threads and give the same
// numbers on any number. Nothing here prints or writes.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "solvers/constants.h"
#include "sweeps/rub_runs.h"

namespace rubcont {

struct EnsembleStudyOptions {
  // The scene's sweep in the direction that reaches the state: its schedule up to the last speed
  // before speed_rpm is the approach; its integrators, spectra and regime rules read the copies.
  RubSweepOptions sweep;
  double speed_rpm = 0.0;  // [rpm] > 0: the speed the copies run at
  // [s] simulated per copy, ≥ 2·window: ⌈duration / (2·window)⌉ stretches (StretchCount).
  double duration = 2.0;
  // [s] > 0; a stretch of two windows is classified as a sweep speed. 0.05 s holds 4 periods of an
  // 80 Hz whip (the thesis's whips precess at 79–86 Hz).
  double window = 0.05;
  // copies (1 … 100000), perturbation (≥ 0, in units of each state's scale), the seed of copy 0
  // (copy i: seed + i), threads (0: one per core).
  EnsembleOptions ensemble;
  // What a copy arrives at (e.g. every contact in whirl: the end of a whip).
  ArrivalTarget target;
};

// Throws std::invalid_argument naming the field, its value and the rule (the target checked
// against `structure`).
void Validate(const EnsembleStudyOptions& options, const RubStructure& structure);

enum class EnsembleStudyStatus {
  kComplete,        // every copy ran to its arrival or to the end
  kCopiesFailed,    // some copies failed to integrate (neither arrived nor stayed)
  kApproachFailed,  // the approach sweep failed: no copies were run
};
const char* ToString(EnsembleStudyStatus status);

struct EnsembleStudyResult {
  EnsembleStudyStatus status = EnsembleStudyStatus::kComplete;
  std::string message;           // why, when not kComplete
  EnsembleStudyOptions options;  // as used
  std::string arrival;           // the target in words (Describe)
  SweepApproach approach;
  RubCopies run;                 // the copies, their points and arrivals
  int stretches = 0;             // per copy
  // [s] the end of each stretch: the simulated times of the first copy that did not fail (empty:
  // every copy failed). A window is a whole number of samples, so a stretch is 2·round(window·rate)/rate.
  std::vector<double> stretch_end;
  int reached = 0;   // copies that arrived
  int failed = 0;    // copies whose integration failed
  // Copies with a stretch beyond the penetration limit before they arrived (RubArrival::untrusted),
  // counted all the same; the first of them (−1: none) and why.
  int untrusted = 0;
  int first_untrusted_copy = -1;
  std::string first_untrusted;
  // Arrival times [s] of the copies that arrived: min, quartiles (linear interpolation), max (NaN:
  // none arrived).
  double arrival_min = kNaN;
  double arrival_lower_quartile = kNaN;
  double arrival_median = kNaN;
  double arrival_upper_quartile = kNaN;
  double arrival_max = kNaN;
  double median_cpu_seconds = kNaN;  // CPU time per copy, median over the copies

  // "ensemble at 48 rpm: 3 of 3 reached whirl on every contact, median 0.10 s; 0 failed", or why not.
  std::string BriefReport() const;
};

struct EnsembleStudyProgress {
  std::function<void(const SweepRun& run)> approach;  // after each speed of the approach
  EnsembleProgress copies;  // after each finished copy (from the worker threads, serialized)
};

// The study (above). Throws std::invalid_argument for invalid options (Validate).
EnsembleStudyResult RunEnsembleStudy(const RubStructure& structure, const EnsembleStudyOptions& options,
                                     const EnsembleStudyProgress& progress = {});

// Quantile q ∈ [0, 1] of ascending `sorted` values, interpolated linearly between ranks; NaN when
// there are none.
double SortedQuantile(const std::vector<double>& sorted, double q);

}  // namespace rubcont
