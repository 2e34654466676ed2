#include "sweeps/rub_runs.h"

#include <cmath>
#include <stdexcept>

#include <fmt/core.h>

#include "models/units.h"
#include "solvers/stopwatch.h"

namespace rubcont {

const char* ToString(SweepDirection direction) {
  return direction == SweepDirection::kUp ? "up" : "down";
}

void Validate(const RubSweepOptions& options) {
  Validate(options.sweep);
  Validate(options.regimes);
  if (!(options.impulse >= 0.0) || !std::isfinite(options.impulse)) {
    throw std::invalid_argument(fmt::format("RubSweepOptions.impulse = {}: must be finite and ≥ 0 (N·s)",
                                            options.impulse));
  }
}

SweepRun::SweepRun(const RubStructure& structure, RubSweepOptions options) : options_(std::move(options)) {
  system_ = std::make_unique<RubFixedFrame>(structure);
  observables_ = std::make_unique<RubSweepObservables>(*system_);
  const Vector x0 = RubImpulseIncrement(system_->structure(), options_.impulse);
  stepper_ = std::make_unique<SweepStepper>(*system_, *observables_, options_.sweep, x0);
}

SweepRun::SweepRun(const RubStructure& structure, RubSweepOptions options, std::vector<SweepPoint> finished,
                   const Vector& state)
    : options_(std::move(options)) {
  system_ = std::make_unique<RubFixedFrame>(structure);
  observables_ = std::make_unique<RubSweepObservables>(*system_);
  stepper_ = std::make_unique<SweepStepper>(*system_, *observables_, options_.sweep, std::move(finished), state);
}

RubSweepRegimes SweepRun::Regimes() const {
  return ClassifySweep(structure(), stepper_->points(), options_.regimes);
}

const char* ToString(ApproachStatus status) {
  return status == ApproachStatus::kReached ? "reached" : "failed";
}

std::string SweepApproach::BriefReport() const {
  if (status == ApproachStatus::kFailed) return "approach failed: " + message;
  if (speeds.empty()) return "approach: none (rest and the impulse)";
  std::string ending;
  for (std::size_t k = 0; k < regimes.size(); ++k) ending += fmt::format("{}{}", k ? ", " : "", ToString(regimes[k]));
  return fmt::format("approach: {} speed(s), {:g} → {:g} rpm, ending in {}", speeds.size(),
                     RadPerSecondToRpm(speeds.front()), RadPerSecondToRpm(speeds.back()), ending);
}

SweepApproach ApproachSweep(const RubStructure& structure, const RubSweepOptions& options, double speed,
                            const std::function<void(const SweepRun& run)>& progress) {
  const double sign = options.direction == SweepDirection::kUp ? 1.0 : -1.0;
  SweepApproach approach;
  for (double p : options.sweep.parameters)
    if (sign * (speed - p) > 1e-9 * speed) approach.speeds.push_back(p);
  approach.state = RubImpulseIncrement(structure, options.impulse);
  approach.regimes.assign(structure.contacts.size(), RubRegime::kUnknown);
  if (approach.speeds.empty()) return approach;
  RubSweepOptions schedule = options;
  schedule.sweep.parameters = approach.speeds;
  SweepRun run(structure, schedule);
  while (!run.stepper().Done() && !run.stepper().Failed()) {
    run.stepper().Step();
    if (progress) progress(run);
  }
  if (run.stepper().Failed()) {
    approach.status = ApproachStatus::kFailed;
    approach.message = "the approach sweep failed: " + run.stepper().points().back().message;
    return approach;
  }
  const RubSweepRegimes regimes = run.Regimes();
  for (std::size_t k = 0; k < approach.regimes.size(); ++k) approach.regimes[k] = regimes.regime[k].back();
  approach.state = run.stepper().state();
  return approach;
}

RubCopies RunRubCopies(const RubStructure& structure, const RubSweepOptions& options,
                       const std::vector<double>& speeds, double window, const Vector& x0,
                       const EnsembleOptions& ensemble, const ArrivalTarget& target,
                       const EnsembleProgress& progress) {
  SweepOptions stretches = options.sweep;
  stretches.parameters = speeds;
  stretches.window = window;
  stretches.settle_windows = 1;
  stretches.dwell = 2.0 * window;
  stretches.analysis_length = 2.0 * window;
  RubCopies out;
  const SteadyClock::time_point start = SteadyClock::now();
  out.copies = RunEnsemble(
      [&] { return std::make_unique<RubFixedFrame>(structure); },
      [](OdeSystem& system) { return std::make_unique<RubSweepObservables>(static_cast<RubFixedFrame&>(system)); },
      stretches, x0, ensemble, progress);
  out.wall_seconds = SecondsSince(start);
  out.stretch_seconds = 2.0 * window;
  for (const EnsembleCopy& copy : out.copies) {
    if (!copy.points.empty() && copy.points.front().status != SweepPointStatus::kIntegrationFailure) {
      out.stretch_seconds = copy.points.front().simulated_time;
      break;
    }
  }
  out.arrivals = RubArrivals(structure, out.copies, target, options.regimes);
  return out;
}

int StretchCount(double seconds, double window) {
  return static_cast<int>(std::ceil(seconds / (2.0 * window) - 1e-9));
}

std::string RegimeList(const RubStructure& structure, const std::vector<RubRegime>& regimes) {
  std::string list;
  for (std::size_t k = 0; k < regimes.size(); ++k) {
    list += fmt::format("{}{} {}", k ? ", " : "", structure.contacts[k].name, ToString(regimes[k]));
  }
  return list;
}

void Validate(const ArrivalTarget& target, const RubStructure& structure, const char* name) {
  const int contacts = static_cast<int>(structure.contacts.size());
  if (target.contacts == ArrivalContacts::kOne && (target.contact < 0 || target.contact >= contacts)) {
    throw std::invalid_argument(fmt::format("{}.contact = {}: must index one of the structure's {} contacts",
                                            name, target.contact, contacts));
  }
  if (!std::isnan(target.precession_above_hz) &&
      !(target.precession_above_hz > 0.0 && std::isfinite(target.precession_above_hz))) {
    throw std::invalid_argument(fmt::format("{}.precession_above_hz = {}: must be NaN (by regime) or a "
                                            "positive precession in Hz", name, target.precession_above_hz));
  }
  if (target.regime == RubRegime::kUnknown) {
    throw std::invalid_argument(fmt::format("{}.regime = {}: must be whirl, whip, intermittent or no_contact",
                                            name, ToString(target.regime)));
  }
}

}  // namespace rubcont
