#include "studies/lifetime_study.h"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "models/units.h"
#include "solvers/constants.h"
#include "solvers/stopwatch.h"

namespace rubcont {
namespace {

template <class Value>
[[noreturn]] void RejectStudy(const std::string& field, const Value& value, const char* rule) {
  throw std::invalid_argument(fmt::format("{} = {}: {}", field, value, rule));
}

// The speeds of a schedule from `from` to `to` in steps of `step` [rpm]: at most 1000.
void CheckSchedule(const char* field, double from, double to, double step) {
  if (!(step > 0.0) || !std::isfinite(step)) RejectStudy(field, step, "must be positive");
  if (std::abs(to - from) / step > 1000.0) RejectStudy(field, step, "gives more than 1000 speeds");
}

// The first speeds of `speeds` at which the sum of `probability` reaches 5 %, 50 % and 95 %.
PredictedLeave Quantiles(const std::vector<double>& speeds, std::vector<double> probability) {
  PredictedLeave p;
  p.probability = std::move(probability);
  double sum = 0.0;
  for (std::size_t i = 0; i < speeds.size(); ++i) {
    if (std::isnan(p.low_rpm) && sum + p.probability[i] >= 0.05) p.low_rpm = speeds[i];
    if (std::isnan(p.median_rpm) && sum + p.probability[i] >= 0.5) p.median_rpm = speeds[i];
    if (std::isnan(p.high_rpm) && sum + p.probability[i] >= 0.95) p.high_rpm = speeds[i];
    sum += p.probability[i];
  }
  return p;
}

// A start belongs to the study: its approach reached the state, and its ensembles are the first
// speeds of `speeds` (to 1e-9 relative) with `copies` copies each.
void CheckStart(const LifetimeStudyStart& start, const LifetimeStudyOptions& options,
                const std::vector<double>& speeds) {
  if (start.approach.status != ApproachStatus::kReached) {
    RejectStudy("LifetimeStudyStart.approach.status", "failed", "a start must hold an approach that reached its state");
  }
  if (start.escapes.size() > speeds.size()) {
    RejectStudy("LifetimeStudyStart.escapes", start.escapes.size(), "more speeds than the study's schedule");
  }
  for (std::size_t i = 0; i < start.escapes.size(); ++i) {
    const SpeedEscapes& e = start.escapes[i];
    const double speed = e.observations.parameter;
    if (!(std::abs(speed - speeds[i]) <= 1e-9 * std::abs(speeds[i]))) {
      RejectStudy(fmt::format("LifetimeStudyStart.escapes[{}] speed [rpm]", i), speed,
                  fmt::format("must be the schedule's speed {:g} rpm", speeds[i]).c_str());
    }
    if (e.arrival_time.size() != static_cast<std::size_t>(options.sampling.ensemble.copies)) {
      RejectStudy(fmt::format("LifetimeStudyStart.escapes[{}] copies", i), e.arrival_time.size(),
                  fmt::format("must be the study's {} copies", options.sampling.ensemble.copies).c_str());
    }
  }
}

}  // namespace

void Validate(const EscapeSampling& s, const char* name) {
  const std::string prefix = std::string(name) + ".";
  if (s.ensemble.copies < 1 || s.ensemble.copies > 100000) {
    RejectStudy(prefix + "ensemble.copies", s.ensemble.copies, "must be in 1 … 100000");
  }
  Validate(s.ensemble);
  if (!(s.window > 0.0) || !std::isfinite(s.window)) {
    RejectStudy(prefix + "window", s.window, "must be positive (s)");
  }
  if (!(s.duration >= 2.0 * s.window) || !std::isfinite(s.duration)) {
    RejectStudy(prefix + "duration", s.duration, "must be at least two windows (s)");
  }
}

void Validate(const LifetimeStudyOptions& o, const RubStructure& structure) {
  auto field = [](const char* name) { return std::string("LifetimeStudyOptions.") + name; };
  Validate(o.sweep);
  if (!(o.from_rpm > 0.0) || !std::isfinite(o.from_rpm)) RejectStudy(field("from_rpm"), o.from_rpm, "must be positive");
  if (!(o.to_rpm > 0.0) || !std::isfinite(o.to_rpm)) RejectStudy(field("to_rpm"), o.to_rpm, "must be positive");
  const bool up = o.sweep.direction == SweepDirection::kUp;
  if (!((up ? 1.0 : -1.0) * (o.to_rpm - o.from_rpm) > 0.0)) {
    RejectStudy(field("to_rpm"), o.to_rpm,
                up ? "must be above from_rpm (direction up)" : "must be below from_rpm (direction down)");
  }
  CheckSchedule("LifetimeStudyOptions.step_rpm", o.from_rpm, o.to_rpm, o.step_rpm);
  Validate(o.sampling, "LifetimeStudyOptions.sampling");
  Validate(o.target, structure, "LifetimeStudyOptions.target");
  if (o.check_copies < 0 || o.check_copies > 100000) {
    RejectStudy(field("check_copies"), o.check_copies, "must be in 0 … 100000");
  }
  CheckSchedule("LifetimeStudyOptions.check_step_rpm", o.from_rpm, o.to_rpm, o.check_step_rpm);
  if (!(o.check_dwell >= 2.0 * o.sampling.window) || !std::isfinite(o.check_dwell)) {
    RejectStudy(field("check_dwell"), o.check_dwell, "must be at least two windows (s)");
  }
}

SweepApproach ApproachState(const RubStructure& structure, const RubSweepOptions& sweep, double speed_rpm,
                            const std::function<void(const SweepRun& run)>& progress) {
  return ApproachSweep(structure, sweep, RpmToRadPerSecond(speed_rpm), progress);
}

SpeedEscapes ObserveEscapes(const RubStructure& structure, const RubSweepOptions& sweep, const Vector& state,
                            double speed_rpm, const EscapeSampling& sampling, const ArrivalTarget& target,
                            const EnsembleProgress& progress) {
  Validate(sampling);
  Validate(target, structure);
  if (!(speed_rpm > 0.0) || !std::isfinite(speed_rpm)) {
    RejectStudy("ObserveEscapes: speed_rpm", speed_rpm, "must be positive");
  }
  const int stretches = StretchCount(sampling.duration, sampling.window);
  const RubCopies run = RunRubCopies(
      structure, sweep, std::vector<double>(static_cast<std::size_t>(stretches), RpmToRadPerSecond(speed_rpm)),
      sampling.window, state, sampling.ensemble, target, progress);
  SpeedEscapes out;
  EscapeObservations& o = out.observations;
  o.parameter = speed_rpm;
  o.stretch = run.stretch_seconds;
  o.duration = stretches * o.stretch;
  out.arrival_time.assign(run.arrivals.size(), kNaN);
  out.wall_seconds = run.wall_seconds;
  for (std::size_t c = 0; c < run.arrivals.size(); ++c) {
    const RubArrival& a = run.arrivals[c];
    if (!a.untrusted.empty() && out.untrusted++ == 0) {
      out.first_untrusted_copy = static_cast<int>(c);
      out.first_untrusted = a.untrusted;
    }
    if (a.reached) {
      o.escape_stretch.push_back(a.point + 1);
      out.arrival_time[c] = a.time;
    } else if (a.failed) {
      ++out.failed;
      out.failures.push_back({static_cast<int>(c), run.copies[c].points.back().message});
    } else {
      ++o.stayed;
    }
  }
  return out;
}

CheckSweeps RunCheckSweeps(const RubStructure& structure, const RubSweepOptions& sweep, const Vector& state,
                           const std::vector<double>& speeds_rpm, double dwell, double window,
                           const EnsembleOptions& ensemble, const ArrivalTarget& target,
                           const EnsembleProgress& progress) {
  Validate(target, structure);
  if (speeds_rpm.empty()) RejectStudy("RunCheckSweeps: speeds_rpm", "[]", "must hold at least one speed");
  if (!(window > 0.0) || !std::isfinite(window)) {
    RejectStudy("RunCheckSweeps: window", window, "must be positive (s)");
  }
  if (!(dwell >= 2.0 * window) || !std::isfinite(dwell)) {
    RejectStudy("RunCheckSweeps: dwell", dwell, "must be at least two windows (s)");
  }
  const int dwell_stretches = StretchCount(dwell, window);
  std::vector<double> stretch_speeds;
  for (double s : speeds_rpm) {
    stretch_speeds.insert(stretch_speeds.end(), static_cast<std::size_t>(dwell_stretches), RpmToRadPerSecond(s));
  }
  const RubCopies run = RunRubCopies(structure, sweep, stretch_speeds, window, state, ensemble, target, progress);
  CheckSweeps out;
  out.speeds_rpm = speeds_rpm;
  out.wall_seconds = run.wall_seconds;
  for (std::size_t c = 0; c < run.arrivals.size(); ++c) {
    const RubArrival& a = run.arrivals[c];
    out.leave_speed_rpm.push_back(a.reached ? speeds_rpm[static_cast<std::size_t>(a.point / dwell_stretches)] : kNaN);
    out.leave_time.push_back(a.reached ? a.time : kNaN);
    if (a.failed) out.failures.push_back({static_cast<int>(c), run.copies[c].points.back().message});
  }
  out.dwell = dwell_stretches * run.stretch_seconds;
  return out;
}

const char* ToString(LifetimeStatus status) {
  switch (status) {
    case LifetimeStatus::kComplete: return "complete";
    case LifetimeStatus::kCopiesFailed: return "copies failed";
    case LifetimeStatus::kApproachFailed: return "approach failed";
    case LifetimeStatus::kNoEstimate: return "no estimate";
  }
  return "?";
}

int LifetimeStudyResult::Failures() const {
  int failures = static_cast<int>(check.failures.size());
  for (const SpeedEscapes& e : escapes) failures += e.failed;
  return failures;
}

std::string LifetimeStudyResult::BriefReport() const {
  if (status == LifetimeStatus::kApproachFailed || status == LifetimeStatus::kNoEstimate) {
    return fmt::format("lifetime: {}: {}", ToString(status), message);
  }
  int left = 0, copies = 0;
  for (const SpeedEscapes& e : escapes) {
    left += static_cast<int>(e.observations.escape_stretch.size());
    copies += static_cast<int>(e.arrival_time.size());
  }
  std::string text = fmt::format("lifetime: {} speed(s) {:g} → {:g} rpm, {} of {} copies reached {}; crisis law: {}",
                                 speeds_rpm.size(), options.from_rpm, options.to_rpm, left, copies, arrival,
                                 ToString(crisis.status));
  if (crisis.status == CrisisStatus::kLocated) text += fmt::format(", p_c = {:.2f} rpm", crisis.critical);
  if (status != LifetimeStatus::kComplete) text += fmt::format("; {}", message);
  return text;
}

LifetimeStudyResult RunLifetimeStudy(const RubStructure& structure, const LifetimeStudyOptions& options,
                                     const LifetimeStudyProgress& progress, const LifetimeStudyStart* resume) {
  Validate(options, structure);
  const std::vector<double> speeds = SpeedSchedule(options.from_rpm, options.to_rpm, options.step_rpm);
  if (resume != nullptr) CheckStart(*resume, options, speeds);
  const double cpu_start = ProcessCpuSeconds();
  const SteadyClock::time_point start = SteadyClock::now();
  LifetimeStudyResult result;
  result.options = options;
  result.arrival = Describe(structure, options.target);
  result.side = options.sweep.direction == SweepDirection::kUp ? CrisisSide::kAbove : CrisisSide::kBelow;
  auto finish = [&](LifetimeStatus status, std::string message) {
    result.status = status;
    result.message = std::move(message);
    result.wall_seconds = SecondsSince(start);
    result.cpu_seconds = ProcessCpuSeconds() - cpu_start;
    return result;
  };
  auto copies_at = [&](double speed_rpm) -> EnsembleProgress {
    if (!progress.copies) return {};
    return [&progress, speed_rpm](int done, int total) { progress.copies(speed_rpm, done, total); };
  };

  if (resume != nullptr) {
    result.approach = resume->approach;
  } else {
    result.approach = ApproachState(structure, options.sweep, options.from_rpm, progress.approach);
    if (result.approach.status == ApproachStatus::kFailed) {
      return finish(LifetimeStatus::kApproachFailed, result.approach.message);
    }
    if (progress.finished) progress.finished(result.approach, result.escapes);
  }

  // The ensembles, one per speed, all from the approach's state.
  const std::uint64_t copies = static_cast<std::uint64_t>(options.sampling.ensemble.copies);
  result.speeds_rpm = speeds;
  std::vector<EscapeObservations> observations;
  for (std::size_t i = 0; i < result.speeds_rpm.size(); ++i) {
    const double speed = result.speeds_rpm[i];
    const bool finished_before = resume != nullptr && i < resume->escapes.size();
    if (finished_before) {
      result.escapes.push_back(resume->escapes[i]);
    } else {
      EscapeSampling sampling = options.sampling;
      sampling.ensemble.seed = options.sampling.ensemble.seed + i * copies;
      result.escapes.push_back(ObserveEscapes(structure, options.sweep, result.approach.state, speed, sampling,
                                              options.target, copies_at(speed)));
    }
    const SpeedEscapes& escapes = result.escapes.back();
    if (!escapes.Observed()) {
      return finish(LifetimeStatus::kNoEstimate,
                    fmt::format("every copy failed at {:g} rpm: nothing to estimate", speed));
    }
    observations.push_back(escapes.observations);
    result.rates.push_back(EstimateEscapeRate(escapes.observations));
    if (finished_before) continue;
    if (progress.speed) progress.speed(escapes, result.rates.back());
    if (progress.finished) progress.finished(result.approach, result.escapes);
  }
  CrisisOptions crisis;
  crisis.side = result.side;
  result.crisis = FitCrisis(observations, crisis);

  // The check: perturbed sweeps through the same speeds with a long dwell.
  if (options.check_copies > 0) {
    EnsembleOptions check = options.sampling.ensemble;
    check.copies = options.check_copies;
    check.seed = options.sampling.ensemble.seed + result.speeds_rpm.size() * copies;
    result.check = RunCheckSweeps(structure, options.sweep, result.approach.state,
                                  SpeedSchedule(options.from_rpm, options.to_rpm, options.check_step_rpm),
                                  options.check_dwell, options.sampling.window, check, options.target,
                                  copies_at(kNaN));
    if (result.crisis.status == CrisisStatus::kLocated) {
      result.predicted = Quantiles(result.check.speeds_rpm,
                                   SweepLeaveProbabilities(result.crisis, result.side, result.check.speeds_rpm,
                                                           result.check.dwell));
    }
  }
  const int failures = result.Failures();
  if (failures > 0) {
    return finish(LifetimeStatus::kCopiesFailed,
                  fmt::format("{} cop{} failed: counted neither as escaped nor as stayed", failures,
                              failures == 1 ? "y" : "ies"));
  }
  return finish(LifetimeStatus::kComplete, "");
}

}  // namespace rubcont
