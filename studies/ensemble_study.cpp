#include "studies/ensemble_study.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "models/units.h"
#include "solvers/stopwatch.h"

namespace rubcont {

double SortedQuantile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return kNaN;
  const double at = q * static_cast<double>(sorted.size() - 1);
  const std::size_t i = static_cast<std::size_t>(std::floor(at));
  const std::size_t j = std::min(i + 1, sorted.size() - 1);
  return sorted[i] + (at - static_cast<double>(i)) * (sorted[j] - sorted[i]);
}

void Validate(const EnsembleStudyOptions& o, const RubStructure& structure) {
  auto fail = [](const char* field, double value, const char* rule) {
    throw std::invalid_argument(fmt::format("EnsembleStudyOptions.{} = {}: {}", field, value, rule));
  };
  Validate(o.sweep);
  if (!(o.speed_rpm > 0.0) || !std::isfinite(o.speed_rpm)) fail("speed_rpm", o.speed_rpm, "must be positive");
  if (!(o.window > 0.0) || !std::isfinite(o.window)) fail("window", o.window, "must be positive (s)");
  if (!(o.duration >= 2.0 * o.window) || !std::isfinite(o.duration)) {
    fail("duration", o.duration, "must be at least two windows (s)");
  }
  if (o.ensemble.copies < 1 || o.ensemble.copies > 100000) {
    fail("ensemble.copies", o.ensemble.copies, "must be in 1 … 100000");
  }
  Validate(o.ensemble);
  Validate(o.target, structure, "EnsembleStudyOptions.target");
}

const char* ToString(EnsembleStudyStatus status) {
  switch (status) {
    case EnsembleStudyStatus::kComplete: return "complete";
    case EnsembleStudyStatus::kCopiesFailed: return "copies failed";
    case EnsembleStudyStatus::kApproachFailed: return "approach failed";
  }
  return "?";
}

std::string EnsembleStudyResult::BriefReport() const {
  if (status == EnsembleStudyStatus::kApproachFailed) return "ensemble: " + message;
  std::string text = fmt::format("ensemble at {:g} rpm: {} of {} reached {}", options.speed_rpm, reached,
                                 run.copies.size(), arrival);
  if (reached > 0) text += fmt::format(", median {:.3g} s", arrival_median);
  return text + fmt::format("; {} failed", failed);
}

EnsembleStudyResult RunEnsembleStudy(const RubStructure& structure, const EnsembleStudyOptions& options,
                                     const EnsembleStudyProgress& progress) {
  Validate(options, structure);
  EnsembleStudyResult result;
  result.options = options;
  result.arrival = Describe(structure, options.target);
  const double speed = RpmToRadPerSecond(options.speed_rpm);
  result.approach = ApproachSweep(structure, options.sweep, speed, progress.approach);
  if (result.approach.status == ApproachStatus::kFailed) {
    result.status = EnsembleStudyStatus::kApproachFailed;
    result.message = result.approach.message;
    return result;
  }

  // The copies: stretches of two windows at `speed`.
  result.stretches = StretchCount(options.duration, options.window);
  result.run = RunRubCopies(structure, options.sweep,
                            std::vector<double>(static_cast<std::size_t>(result.stretches), speed),
                            options.window, result.approach.state, options.ensemble, options.target,
                            progress.copies);
  const std::vector<EnsembleCopy>& copies = result.run.copies;
  const std::vector<RubArrival>& arrivals = result.run.arrivals;
  for (const EnsembleCopy& copy : copies) {
    if (copy.failed) continue;
    double t = 0.0;
    for (const SweepPoint& p : copy.points) result.stretch_end.push_back(t += p.simulated_time);
    break;
  }
  std::vector<double> times, cpu;
  for (std::size_t c = 0; c < arrivals.size(); ++c) {
    const RubArrival& a = arrivals[c];
    if (a.reached) times.push_back(a.time);
    result.failed += a.failed ? 1 : 0;
    cpu.push_back(copies[c].cpu_seconds);
    if (!a.untrusted.empty() && result.untrusted++ == 0) {
      result.first_untrusted_copy = static_cast<int>(c);
      result.first_untrusted = a.untrusted;
    }
  }
  result.reached = static_cast<int>(times.size());
  std::sort(times.begin(), times.end());
  std::sort(cpu.begin(), cpu.end());
  if (!times.empty()) {
    result.arrival_min = times.front();
    result.arrival_lower_quartile = SortedQuantile(times, 0.25);
    result.arrival_median = SortedQuantile(times, 0.5);
    result.arrival_upper_quartile = SortedQuantile(times, 0.75);
    result.arrival_max = times.back();
  }
  result.median_cpu_seconds = SortedQuantile(cpu, 0.5);
  if (result.failed > 0) {
    result.status = EnsembleStudyStatus::kCopiesFailed;
    result.message = fmt::format("{} of {} copies failed to integrate", result.failed, copies.size());
  }
  return result;
}

}  // namespace rubcont
