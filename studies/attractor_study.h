// What the motion is at each speed of a schedule, from long transients (level L3;
// sweeps/attractor.h): the leading Lyapunov exponents by the variational equations, the verdict
// they give (sweeps/rub_sweep.h RubMotion: rotating wave, relative periodic orbit, relative
// 2-torus, chaotic) and a Poincaré section of each contact's successive penetration maxima, one per
// modulation or impact, with the normal force there (sampled every `sample_interval` seconds:
// RubPenetrations, RubSectionMaxima). The approach sweep is run from rest plus the impulse up to
// the last speed of its schedule before the first speed; each speed then starts from the state the
// previous one ended in, integrates attractor.discard seconds uncounted and attractor.duration
// counted, re-orthonormalizing attractor.exponents tangent directions every attractor.interval. A
// speed whose integration fails ends the schedule there. Nothing here prints or writes.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "sweeps/attractor.h"
#include "sweeps/rub_runs.h"
#include "sweeps/rub_sweep.h"

namespace rubcont {

struct AttractorStudyOptions {
  // The sweep that reaches the state before the first speed (its direction may differ from the
  // schedule's: stepping back down from where a speed-up sweep arrived); its regime rules'
  // max_penetration marks untrusted sections.
  RubSweepOptions approach;
  // The schedule [rpm]: from_rpm, from_rpm ± step_rpm, … to_rpm in `direction` (SpeedSchedule).
  double from_rpm = 0.0;  // > 0
  double to_rpm = 0.0;    // > 0, at from_rpm or beyond it in `direction`
  double step_rpm = 4.0;  // > 0
  SweepDirection direction = SweepDirection::kUp;
  // The record per speed (discard, duration, interval, exponents ≤ the model's states, blocks,
  // zero_tolerance) and the integrator of the state with its tangents (CVODES BDF: the exponents
  // need forward sensitivities).
  AttractorOptions attractor;
  // [s] > 0, ≤ attractor.interval: the section's samples. 2 µs is ~20 per period of the contact's
  // ~20 kHz oscillation; every 20 µs A(a)'s periodic whip's maxima scattered by 71 N of 3108 N,
  // every 2 µs by 13 N (RubPenetrations).
  double sample_interval = 2e-6;
};

// Throws std::invalid_argument naming the field, its value and the rule.
void Validate(const AttractorStudyOptions& options, const RubStructure& structure);

// One speed of the schedule.
struct AttractorSpeed {
  double speed_rpm = 0.0;
  // MeasureAttractor's result, without its extrema (every ripple's extremum with its state:
  // megabytes per second; the section below keeps what is read off them).
  AttractorResult result;
  std::vector<RubSectionPoint> section;  // the penetration maxima (RubSectionMaxima)
  int section_period = 0;                // RubSectionPeriod (0: none)
  std::string motion;                    // RubMotion
  std::string untrusted;                 // UntrustedSection: why, or ""
};

enum class AttractorStudyStatus {
  kMeasured,            // every speed of the schedule was measured
  kIntegrationFailure,  // a speed failed (message): the schedule ends with it
  kApproachFailed,      // the approach sweep failed: no speed was measured
};
const char* ToString(AttractorStudyStatus status);

struct AttractorStudyResult {
  AttractorStudyStatus status = AttractorStudyStatus::kMeasured;
  std::string message;             // why, when not kMeasured
  AttractorStudyOptions options;   // as used
  SweepApproach approach;
  std::vector<AttractorSpeed> speeds;  // in schedule order, up to the first failure
  double wall_seconds = 0.0;

  // "attractor: 2 speed(s) 48 → 52 rpm: rotating wave, relative periodic orbit", or why not.
  std::string BriefReport() const;
};

struct AttractorStudyProgress {
  std::function<void(const SweepRun& run)> approach;  // after each speed of the approach
  // During a speed [rpm]: MeasureAttractor's time done (including the discard) of its total.
  std::function<void(double speed_rpm, double done, double total)> integration;
  std::function<void(const AttractorSpeed& speed)> speed;  // after each speed
};

// The study (above). Throws std::invalid_argument for invalid options (Validate).
AttractorStudyResult RunAttractorStudy(const RubStructure& structure, const AttractorStudyOptions& options,
                                       const AttractorStudyProgress& progress = {});

}  // namespace rubcont
