#include "studies/attractor_study.h"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "models/units.h"
#include "solvers/stopwatch.h"

namespace rubcont {

void Validate(const AttractorStudyOptions& o, const RubStructure& structure) {
  auto fail = [](const char* field, const auto& value, const std::string& rule) {
    throw std::invalid_argument(fmt::format("AttractorStudyOptions.{} = {}: {}", field, value, rule));
  };
  Validate(o.approach);
  if (!(o.from_rpm > 0.0) || !std::isfinite(o.from_rpm)) fail("from_rpm", o.from_rpm, "must be positive");
  if (!(o.to_rpm > 0.0) || !std::isfinite(o.to_rpm)) fail("to_rpm", o.to_rpm, "must be positive");
  if (!(o.step_rpm > 0.0) || !std::isfinite(o.step_rpm)) fail("step_rpm", o.step_rpm, "must be positive");
  if (o.direction == SweepDirection::kUp ? o.to_rpm < o.from_rpm : o.to_rpm > o.from_rpm) {
    fail("to_rpm", o.to_rpm, "must lie at from_rpm or beyond it in the direction of the schedule");
  }
  Validate(o.attractor);
  if (o.attractor.exponents > structure.States()) {
    fail("attractor.exponents", o.attractor.exponents,
         fmt::format("must be at most the model's {} states", structure.States()));
  }
  if (!(o.sample_interval > 0.0) || !(o.sample_interval <= o.attractor.interval)) {
    fail("sample_interval", o.sample_interval, "must be positive and at most attractor.interval (s)");
  }
}

const char* ToString(AttractorStudyStatus status) {
  switch (status) {
    case AttractorStudyStatus::kMeasured: return "measured";
    case AttractorStudyStatus::kIntegrationFailure: return "integration failure";
    case AttractorStudyStatus::kApproachFailed: return "approach failed";
  }
  return "?";
}

std::string AttractorStudyResult::BriefReport() const {
  if (status == AttractorStudyStatus::kApproachFailed) return "attractor: " + message;
  std::string text = fmt::format("attractor: {} speed(s)", speeds.size());
  if (!speeds.empty()) {
    text += fmt::format(" {:g} → {:g} rpm:", speeds.front().speed_rpm, speeds.back().speed_rpm);
    for (std::size_t i = 0; i < speeds.size(); ++i) text += (i ? ", " : " ") + speeds[i].motion;
  }
  if (status != AttractorStudyStatus::kMeasured) text += "; " + message;
  return text;
}

AttractorStudyResult RunAttractorStudy(const RubStructure& structure, const AttractorStudyOptions& options,
                                       const AttractorStudyProgress& progress) {
  Validate(options, structure);
  const SteadyClock::time_point start = SteadyClock::now();
  AttractorStudyResult result;
  result.options = options;
  const std::vector<double> speeds_rpm = SpeedSchedule(options.from_rpm, options.to_rpm, options.step_rpm);
  result.approach = ApproachSweep(structure, options.approach, RpmToRadPerSecond(speeds_rpm.front()),
                                  progress.approach);
  if (result.approach.status == ApproachStatus::kFailed) {
    result.status = AttractorStudyStatus::kApproachFailed;
    result.message = result.approach.message;
    result.wall_seconds = SecondsSince(start);
    return result;
  }

  RubFixedFrame system(structure);
  const SampledSection section = RubPenetrations(system, options.sample_interval);
  Vector x = result.approach.state;
  for (double rpm : speeds_rpm) {
    const double omega = RpmToRadPerSecond(rpm);
    system.SetParameter(omega);
    AttractorSpeed speed;
    speed.speed_rpm = rpm;
    AttractorProgress integration;
    if (progress.integration) {
      integration = [&progress, rpm](double done, double total) { progress.integration(rpm, done, total); };
    }
    speed.result = MeasureAttractor(system, x, options.attractor, &section, integration);
    AttractorResult& r = speed.result;
    speed.section = RubSectionMaxima(system, r.extrema);
    r.extrema = {};  // every ripple's extremum with its state: megabytes per second
    speed.section_period = RubSectionPeriod(structure, speed.section);
    speed.motion = RubMotion(structure, r, speed.section);
    speed.untrusted = UntrustedSection(structure, speed.section, options.approach.regimes.max_penetration);
    result.speeds.push_back(std::move(speed));
    if (progress.speed) progress.speed(result.speeds.back());
    const AttractorResult& done = result.speeds.back().result;
    if (done.status != AttractorStatus::kMeasured) {
      result.status = AttractorStudyStatus::kIntegrationFailure;
      result.message = fmt::format("{:.1f} rpm: {}", rpm, done.message);
      break;
    }
    x = done.state;
    // Time restarts at 0 at every speed: with imbalance, keep the forcing's phase (as a sweep).
    if (structure.imbalance != 0.0) system.Rotate(-omega * (options.attractor.discard + done.counted_time), x);
  }
  result.wall_seconds = SecondsSince(start);
  return result;
}

}  // namespace rubcont
