// Where a state that a sweep reaches ceases to exist, from the lifetimes of perturbed copies
// (level L3; sweeps/lifetime.h for the statistics). The study, and the three blocks it is made of
// (each usable alone, e.g. by a study that walks along a state):
//
//   (a) ApproachState: the state the scene's sweep in its direction reaches before a speed (its
//       schedule up to the last speed before it, from rest plus the impulse).
//   (b) ObserveEscapes: at one speed, copies of a state perturbed and run for a duration in
//       stretches of two windows until they arrive at a target (RubArrivals): the interval-censored
//       escape observations of sweeps/lifetime.h, and per copy the time it arrived.
//   (c) RunCheckSweeps: copies of a state swept through a schedule with a dwell per speed: per copy
//       the speed and the time at which it arrived.
//   (d) RunLifetimeStudy: (a) once; (b) at each speed from_rpm, from_rpm ± step_rpm, … to_rpm (the
//       i-th speed's copies seeded from seed + i·copies), the escape rate κ per speed and the crisis
//       law κ = A·(p − p_c)^γ over them (beyond p_c in the sweep's direction; p in rpm); then (c)
//       through from_rpm … to_rpm in steps of check_step_rpm (seeded after the last speed's copies),
//       beside the probabilities the fitted law predicts for that schedule.
//
// Speeds are in rpm, as the crisis law is fitted in them (its amplitude in 1/s per rpm^γ); the
// sweep options' schedule is in rad/s (sweeps/rub_runs.h). Numerical outcomes are statuses: an
// approach that fails, a speed at which every copy fails (nothing to estimate), copies that fail.
// Nothing here prints or writes.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "solvers/constants.h"
#include "sweeps/lifetime.h"
#include "sweeps/rub_runs.h"

namespace rubcont {

// How the copies at one speed are run (ObserveEscapes).
struct EscapeSampling {
  // copies ≥ 1 (at most 100000), perturbation (≥ 0, in units of each state's scale), the seed of
  // copy 0 (copy i: seed + i), threads (0: one per core; the numbers do not depend on it).
  EnsembleOptions ensemble;
  // [s] simulated per copy, ≥ 2·window: ⌈duration / (2·window)⌉ stretches (StretchCount).
  double duration = 5.0;
  // [s] > 0: each stretch of two windows is classified as a sweep speed. 0.05 s holds 4
  // periods of an 80 Hz whip (the thesis's whips precess at 79–86 Hz).
  double window = 0.05;
};

// Throws std::invalid_argument naming the field (prefixed by `name`), its value and the rule.
void Validate(const EscapeSampling& sampling, const char* name = "EscapeSampling");

// A failed copy and the integrator's message.
struct CopyFailure {
  int copy = 0;
  std::string message;
};

// What the copies at one speed did (ObserveEscapes).
struct SpeedEscapes {
  // parameter = the speed [rpm]; stretch = the simulated time of a stretch [s]; duration = the
  // stretches × stretch [s]; escape_stretch of each copy that arrived; stayed = those that did not.
  EscapeObservations observations;
  std::vector<double> arrival_time;  // [s] per copy, NaN: stayed or failed
  int failed = 0;                    // copies whose integration failed (neither escaped nor stayed)
  std::vector<CopyFailure> failures;  // those copies, in copy order
  // Copies with a stretch beyond the penetration limit (RubRegimeOptions::max_penetration) before
  // they arrived (RubArrival::untrusted): counted all the same.
  int untrusted = 0;
  int first_untrusted_copy = -1;     // the first of them (−1: none)
  std::string first_untrusted;       // why it is untrusted
  double wall_seconds = 0.0;
  // Whether anything can be estimated: at least one copy escaped or stayed.
  bool Observed() const { return !observations.escape_stretch.empty() || observations.stayed > 0; }
};

// Per copy, where a check sweep left the state (RunCheckSweeps).
struct CheckSweeps {
  std::vector<double> speeds_rpm;       // the schedule
  double dwell = 0.0;                   // [s] simulated per speed: whole stretches
  std::vector<double> leave_speed_rpm;  // per copy: the speed at which it arrived; NaN: stayed to the end
  std::vector<double> leave_time;       // [s] per copy, from the start of the sweep; NaN: stayed
  std::vector<CopyFailure> failures;    // copies whose integration failed
  double wall_seconds = 0.0;
};

// (a) The state the sweep (options.sweep's schedule in options.direction, from rest plus
// options.impulse) reaches before `speed_rpm`; ApproachSweep (sweeps/rub_runs.h).
SweepApproach ApproachState(const RubStructure& structure, const RubSweepOptions& sweep, double speed_rpm,
                            const std::function<void(const SweepRun& run)>& progress = {});

// (b) Copies of `state` at `speed_rpm` (> 0) run for sampling.duration in stretches of two
// windows until they arrive at `target`; the sweep's integrators, spectra and regime rules read the
// stretches. An escape is a copy that arrived (in stretch j = the stretch of its arrival + 1). Throws
// std::invalid_argument for invalid options; failed copies are counted and listed.
SpeedEscapes ObserveEscapes(const RubStructure& structure, const RubSweepOptions& sweep, const Vector& state,
                            double speed_rpm, const EscapeSampling& sampling, const ArrivalTarget& target,
                            const EnsembleProgress& progress = {});

// (c) `ensemble.copies` copies of `state` swept through `speeds_rpm` (each > 0, in order), staying
// ⌈dwell / (2·window)⌉ stretches of two windows at each, until they arrive at `target`. Throws
// std::invalid_argument for invalid options.
CheckSweeps RunCheckSweeps(const RubStructure& structure, const RubSweepOptions& sweep, const Vector& state,
                           const std::vector<double>& speeds_rpm, double dwell, double window,
                           const EnsembleOptions& ensemble, const ArrivalTarget& target,
                           const EnsembleProgress& progress = {});

struct LifetimeStudyOptions {
  // The scene's sweep in the direction that reaches the state: its schedule up to the last speed
  // before from_rpm is the approach, its direction the side on which the state ends (crisis law
  // beyond p_c in it), its integrators and regime rules those of every copy.
  RubSweepOptions sweep;
  double from_rpm = 0.0;  // [rpm] > 0: the first speed of the ensembles
  double to_rpm = 0.0;    // [rpm] > 0, beyond from_rpm in sweep.direction: the last
  double step_rpm = 1.0;  // [rpm] > 0, at most 1000 speeds
  // The copies per speed: the i-th speed's are seeded from sampling.ensemble.seed + i·copies.
  EscapeSampling sampling;
  // What a copy arrives at: leaving the state (e.g. every contact in whirl: the end of a whip).
  ArrivalTarget target;
  int check_copies = 4;         // 0 … 100000 perturbed check sweeps (0: none)
  double check_step_rpm = 0.5;  // [rpm] > 0, at most 1000 speeds: the check sweeps' schedule
  // [s] simulated per speed of the check sweeps, ≥ 2 windows. A sweep leaves a state whose mean
  // lifetime is shorter than its dwell: the thesis's sweeps dwell 1.5 s per speed, ours 0.75 s.
  double check_dwell = 5.0;
};

// Throws std::invalid_argument naming the field, its value and the rule (the target checked
// against `structure`).
void Validate(const LifetimeStudyOptions& options, const RubStructure& structure);

enum class LifetimeStatus {
  kComplete,        // every copy ran (the crisis fit has its own status)
  kCopiesFailed,    // some copies failed: counted neither as escaped nor as stayed
  kApproachFailed,  // the approach sweep failed: nothing else was run
  kNoEstimate,      // every copy failed at a speed: the study stopped there
};
const char* ToString(LifetimeStatus status);

// Where the sweeps of a schedule are predicted to leave the state: the first speeds at which the
// cumulative leave probability reaches 5 %, 50 % and 95 % (NaN: beyond the schedule).
struct PredictedLeave {
  std::vector<double> probability;  // per speed of the schedule (empty: no located crisis law)
  double low_rpm = kNaN;
  double median_rpm = kNaN;
  double high_rpm = kNaN;
};

struct LifetimeStudyResult {
  LifetimeStatus status = LifetimeStatus::kComplete;
  std::string message;            // why, when not kComplete
  LifetimeStudyOptions options;   // as used
  std::string arrival;            // the target in words (Describe)
  SweepApproach approach;
  std::vector<double> speeds_rpm;       // the ensembles' speeds
  std::vector<SpeedEscapes> escapes;    // per speed run (kNoEstimate: up to the one that failed)
  std::vector<EscapeRate> rates;        // per speed with observations
  CrisisSide side = CrisisSide::kAbove;
  CrisisFit crisis;                     // over the speeds (kComplete / kCopiesFailed only)
  CheckSweeps check;                    // empty when options.check_copies = 0
  PredictedLeave predicted;             // for check.speeds_rpm with check.dwell
  double wall_seconds = 0.0;
  double cpu_seconds = 0.0;             // of the process (all threads)

  // Failed copies over the ensembles and the check sweeps.
  int Failures() const;
  // "lifetime: 4 speed(s) 50 → 53 rpm, 12 of 12 copies reached whip on every contact; crisis law:
  // too few speeds" (", p_c = … rpm" when located), or why there is none.
  std::string BriefReport() const;
};

struct LifetimeStudyProgress {
  // After each speed of the approach.
  std::function<void(const SweepRun& run)> approach;
  // After each finished copy (from the worker threads, serialized): the speed of the ensemble
  // [rpm] (NaN: the check sweeps), copies done, total.
  std::function<void(double speed_rpm, int done, int total)> copies;
  // After each speed's ensemble, with its estimated rate.
  std::function<void(const SpeedEscapes& escapes, const EscapeRate& rate)> speed;
  // After the approach and after each speed's ensemble: everything finished so far, all that a
  // study resumed from it needs (a checkpoint: LifetimeStudyStart).
  std::function<void(const SweepApproach& approach, const std::vector<SpeedEscapes>& escapes)> finished;
};

// What an interrupted study had finished (a checkpoint): the approach, which reached its state, and
// the ensembles of the first escapes.size() speeds of the study's schedule, in order. The copies of
// the i-th speed are seeded as always (seed + i·copies), so a study resumed from it gives the
// numbers of one run without interruption.
struct LifetimeStudyStart {
  SweepApproach approach;
  std::vector<SpeedEscapes> escapes;
};

// (d) The study (above), from `resume` when given (the approach and those speeds are not run
// again). Throws std::invalid_argument for invalid options (Validate) and for a start that does not
// belong to these options (another schedule, another number of copies, an approach that failed).
LifetimeStudyResult RunLifetimeStudy(const RubStructure& structure, const LifetimeStudyOptions& options,
                                     const LifetimeStudyProgress& progress = {},
                                     const LifetimeStudyStart* resume = nullptr);

}  // namespace rubcont
