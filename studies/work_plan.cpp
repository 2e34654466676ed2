#include "studies/work_plan.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "sweeps/rub_sweep.h"

namespace rubcont {
namespace {

[[noreturn]] void RejectPlan(const std::string& field, double value, const std::string& rule) {
  throw std::invalid_argument(fmt::format("WorkLimits.{} = {}: {}", field, value, rule));
}

// A duration for people: seconds up to an hour, then hours, days or years.
std::string Span(double seconds) {
  if (seconds < 3600.0) return fmt::format("{:.0f} s", seconds);
  if (seconds < 2 * 86400.0) return fmt::format("{:.3g} h", seconds / 3600.0);
  if (seconds < 365.25 * 86400.0) return fmt::format("{:.3g} days", seconds / 86400.0);
  return fmt::format("{:.3g} years", seconds / (365.25 * 86400.0));
}

std::string Bytes(double bytes) {
  if (bytes < 1e6) return fmt::format("{:.3g} kB", bytes / 1e3);
  if (bytes < 1e9) return fmt::format("{:.3g} MB", bytes / 1e6);
  return fmt::format("{:.3g} GB", bytes / 1e9);
}

// "(CPU estimated at …)" of a message about `work`.
std::string CpuBasis(const PlannedWork& work) {
  if (!work.cpu_basis.empty()) return "(CPU estimated at " + work.cpu_basis + ")";
  return fmt::format("(CPU estimated at {:g} s per simulated second)", kCpuSecondsPerSimulatedSecond);
}

}  // namespace

void Validate(const WorkLimits& limits) {
  if (!(limits.max_items > 0.0)) RejectPlan("max_items", limits.max_items, "must be positive");
  if (!(limits.max_cpu_seconds > 0.0)) RejectPlan("max_cpu_seconds", limits.max_cpu_seconds, "must be positive");
  if (!(limits.max_memory_bytes > 0.0)) RejectPlan("max_memory_bytes", limits.max_memory_bytes, "must be positive");
}

PlannedWork MarchingWork(std::string key, std::string value, std::string what, double runs,
                         double seconds, double bytes_per_run, double cost_factor) {
  PlannedWork work;
  work.key = std::move(key);
  work.value = std::move(value);
  work.what = std::move(what);
  work.items = runs;
  work.simulated_seconds = runs * seconds;
  work.cpu_seconds = work.simulated_seconds * kCpuSecondsPerSimulatedSecond * cost_factor;
  work.memory_bytes = runs * bytes_per_run;
  return work;
}

double SweepSpeedBytes(int contacts, double band_hz, double analysis_length) {
  return contacts * (2.0 * band_hz * analysis_length + 1.0) * sizeof(double) + 1024.0;
}

PlannedWork SweepWork(std::string key, std::string what, double from_rpm, double to_rpm,
                      double step_rpm, double dwell, double bytes_per_speed) {
  const double speeds = SpeedCount(from_rpm, to_rpm, step_rpm);
  return MarchingWork(std::move(key),
                      fmt::format("[{:g}, {:g}] in steps of {:g} rpm", std::min(from_rpm, to_rpm),
                                  std::max(from_rpm, to_rpm), step_rpm),
                      std::move(what), speeds, dwell, bytes_per_speed + 2 * sizeof(double));
}

PlannedWork CopiesWork(std::string key, std::string value, std::string what, double runs,
                       double duration, double window, double bytes_per_stretch) {
  const double stretches = std::ceil(duration / (2.0 * window) - 1e-9);
  return MarchingWork(std::move(key), std::move(value), std::move(what), runs, duration,
                      stretches * bytes_per_stretch);
}

PlannedWork MapWork(std::string key, std::string value, int eta_points, int speed_points) {
  PlannedWork work;
  work.key = std::move(key);
  work.value = std::move(value);
  work.what = "branch sets (one per grid value)";
  work.items = eta_points;
  work.memory_bytes = 5.0 * sizeof(int) * eta_points * static_cast<double>(speed_points);
  return work;
}

std::string Describe(const PlannedWork& work) {
  std::string text = fmt::format("{:.3g} {}", work.items, work.what);
  if (work.simulated_seconds > 0.0) text += fmt::format(", {:.3g} s simulated", work.simulated_seconds);
  if (work.cpu_seconds > 0.0) text += fmt::format(", ≈ {} of CPU", Span(work.cpu_seconds));
  if (work.memory_bytes > 0.0) text += fmt::format(", {} of memory", Bytes(work.memory_bytes));
  return text;
}

std::string ExcessiveWork(const std::vector<PlannedWork>& plan, const WorkLimits& limits) {
  Validate(limits);
  double cpu_seconds = 0.0, memory_bytes = 0.0;
  for (const PlannedWork& work : plan) {
    cpu_seconds += work.cpu_seconds;
    memory_bytes += work.memory_bytes;
  }
  for (const PlannedWork& work : plan) {
    std::string over;
    if (!(work.items <= limits.max_items)) {
      over = fmt::format("{:.3g} {}", limits.max_items, work.what);
    } else if (!(work.cpu_seconds <= limits.max_cpu_seconds)) {
      over = fmt::format("{} of CPU", Span(limits.max_cpu_seconds));
    } else if (!(work.memory_bytes <= limits.max_memory_bytes)) {
      over = fmt::format("{} of memory", Bytes(limits.max_memory_bytes));
    }
    if (!over.empty()) {
      return fmt::format("{} = {} plans {}: over the limit of {} {}", work.key, work.value, Describe(work), over,
                         CpuBasis(work));
    }
  }
  // Items each within the limits may still add up beyond them: the largest is named.
  const bool cpu = !(cpu_seconds <= limits.max_cpu_seconds);
  if (!cpu && memory_bytes <= limits.max_memory_bytes) return {};
  const PlannedWork* largest = &plan.front();
  for (const PlannedWork& work : plan) {
    if (cpu ? work.cpu_seconds > largest->cpu_seconds : work.memory_bytes > largest->memory_bytes) {
      largest = &work;
    }
  }
  return fmt::format("{} = {} plans {}, and the plan {} in all: over the limit of {} {}", largest->key,
                     largest->value, Describe(*largest),
                     cpu ? fmt::format("≈ {} of CPU", Span(cpu_seconds)) : Bytes(memory_bytes) + " of memory",
                     cpu ? Span(limits.max_cpu_seconds) + " of CPU" : Bytes(limits.max_memory_bytes) + " of memory",
                     CpuBasis(*largest));
}

}  // namespace rubcont
