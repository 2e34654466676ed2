// The rub's time-marching runs (level L3) as the studies and the sweep stage drive them: one
// direction of a sweep (SweepRun), the sweep that reaches a state before a speed (ApproachSweep),
// and perturbed copies of a state marched through a schedule of two-window stretches, each
// stretch classified as a sweep speed, with the time each copy arrives at a target
// (RunRubCopies). Each takes the rub structure and the library's options (RubSweepOptions); a
// scene's options are apps/stage_options.h's RubSweepOptionsOf.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "models/rub_model.h"
#include "sweeps/ensemble.h"
#include "sweeps/rub_sweep.h"
#include "sweeps/sweep.h"

namespace rubcont {

// The order of a sweep's speeds: rising (speed-up) or falling (speed-down).
enum class SweepDirection { kUp, kDown };
const char* ToString(SweepDirection direction);  // "up", "down"

// One direction of a rub sweep: what SweepStepper integrates and what the regimes are read with.
struct RubSweepOptions {
  // The order of sweep.parameters: a label of the run (its result group) and the side from which
  // an approach reaches a speed (ApproachSweep).
  SweepDirection direction = SweepDirection::kUp;
  // The schedule (speeds in rad/s, in `direction`'s order), the settle windows, the spectra and the
  // integrators (sweeps/sweep.h).
  SweepOptions sweep;
  // The rules that read whirl, whip, contact and the jumps off the finished speeds.
  RubRegimeOptions regimes;
  // [N·s] ≥ 0, finite: the start of a new sweep is the structure at rest, centred, plus this
  // impulse on the rotor (RubImpulseIncrement).
  double impulse = 1.0;
};

// Throws std::invalid_argument naming the field, its value and the rule (sweep and regimes by
// their own Validate).
void Validate(const RubSweepOptions& options);

// One direction of a rub sweep: the model, its observables and the stepper, which a caller steps
// (SweepStepper::Step) and reads. Not copyable: the stepper refers to the model it owns.
class SweepRun {
 public:
  // A new sweep from rest plus the impulse. Throws std::invalid_argument for invalid options.
  SweepRun(const RubStructure& structure, RubSweepOptions options);
  // Resumes from finished points and the state after the last one (SweepStepper's resuming
  // constructor, with its rules).
  SweepRun(const RubStructure& structure, RubSweepOptions options, std::vector<SweepPoint> finished,
           const Vector& state);
  SweepRun(const SweepRun&) = delete;
  SweepRun& operator=(const SweepRun&) = delete;

  SweepDirection direction() const { return options_.direction; }
  const RubSweepOptions& options() const { return options_; }
  SweepStepper& stepper() { return *stepper_; }
  const SweepStepper& stepper() const { return *stepper_; }
  const RubStructure& structure() const { return system_->structure(); }
  // The finished points read by options().regimes (ClassifySweep).
  RubSweepRegimes Regimes() const;

 private:
  RubSweepOptions options_;
  std::unique_ptr<RubFixedFrame> system_;
  std::unique_ptr<RubSweepObservables> observables_;
  std::unique_ptr<SweepStepper> stepper_;
};

enum class ApproachStatus {
  kReached,  // the state after the last speed before the target speed (or the impulse alone)
  kFailed,   // a speed of the approach failed to integrate (message)
};
const char* ToString(ApproachStatus status);  // "reached", "failed"

// The state a sweep reaches before a speed.
struct SweepApproach {
  ApproachStatus status = ApproachStatus::kReached;
  std::string message;             // why it failed ("" when reached)
  Vector state;                    // the state to continue from (kFailed: the impulse's)
  std::vector<double> speeds;      // [rad/s] the speeds swept, in order (empty: none)
  std::vector<RubRegime> regimes;  // per contact, at the last of them (kUnknown: none)
  // "approach: 2 speeds, 40 → 44 rpm, ending in whirl, whirl", "approach: none (rest and the
  // impulse)", "approach failed: ...".
  std::string BriefReport() const;
};

// The sweep's schedule (options.sweep.parameters) in options.direction up to the last speed
// strictly before `speed` [rad/s] (by more than 1e-9 relative), from rest plus the impulse; the
// impulse alone when no speed of the schedule comes before. `progress` is called after each speed
// with the run. A failed speed ends the approach with status kFailed. Throws
// std::invalid_argument for invalid options.
SweepApproach ApproachSweep(const RubStructure& structure, const RubSweepOptions& options, double speed,
                            const std::function<void(const SweepRun& run)>& progress = {});

// Perturbed copies of a state, each marched through a schedule of stretches (RunRubCopies).
struct RubCopies {
  std::vector<EnsembleCopy> copies;
  std::vector<RubArrival> arrivals;  // per copy, at the target (RubArrivals)
  double wall_seconds = 0.0;
  // The time simulated per stretch (a window is a whole number of samples, so a stretch is
  // 2·round(window·rate)/rate), read off the first copy whose first stretch did not fail;
  // 2·window when none.
  double stretch_seconds = 0.0;
};

// Copies of `x0` (RunEnsemble, perturbed and seeded by `ensemble`) marched through `speeds`
// [rad/s], one stretch of two `window`s [s] per entry (repeat a speed to stay at it), each stretch
// classified as a sweep speed (options.sweep's sample rate, spectra and integrators; options.regimes'
// rules), and when each copy arrives at `target` (RubArrivals). options.sweep's schedule, dwell and
// settle windows are replaced by the stretches; options.direction is not used. Throws
// std::invalid_argument for invalid options.
RubCopies RunRubCopies(const RubStructure& structure, const RubSweepOptions& options,
                       const std::vector<double>& speeds, double window, const Vector& x0,
                       const EnsembleOptions& ensemble, const ArrivalTarget& target,
                       const EnsembleProgress& progress = {});

// The stretches of two `window`s that cover `seconds`: ⌈seconds / (2·window)⌉ (to 1e-9).
int StretchCount(double seconds, double window);

// "left whip, right whip": each contact's name and regime (regimes: one per contact).
std::string RegimeList(const RubStructure& structure, const std::vector<RubRegime>& regimes);

// Throws std::invalid_argument naming the field (prefixed by `name`), its value and the rule: a
// contact index within the structure for ArrivalContacts::kOne, a precession threshold that is NaN
// (by regime) or positive and finite, and a target regime that is not kUnknown.
void Validate(const ArrivalTarget& target, const RubStructure& structure, const char* name = "target");

}  // namespace rubcont
