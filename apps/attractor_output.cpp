#include "apps/attractor_output.h"

#include <algorithm>
#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "apps/hdf5_file.h"
#include "apps/sweep_output.h"
#include "models/units.h"
#include "solvers/constants.h"

namespace rubcont {
namespace {

std::string FormatExponents(const AttractorResult& result) {
  std::string text;
  for (Index j = 0; j < result.exponents.size(); ++j) {
    text += fmt::format("{}{:+.2f} ± {:.2f}", j ? ", " : "", result.exponents(j), result.standard_errors(j));
  }
  return text;
}

}  // namespace

void WriteAttractorResult(const std::filesystem::path& file, const Scene& scene, const RubStructure& structure,
                          const AttractorStudyResult& result) {
  const AttractorStudyOptions& o = result.options;
  const AttractorOptions& options = o.attractor;
  const std::size_t contacts = structure.contacts.size();
  const std::string g = "/attractor";
  const std::unique_ptr<ResultWriter> file_writer = OpenStudyResult(file, scene, g);
  ResultWriter& writer = *file_writer;
  writer.SetAttribute(g, "direction", ToString(o.direction));
  writer.SetAttribute(g, "approach", ToString(o.approach.direction));
  writer.SetAttribute(g, "duration", options.duration);
  writer.SetAttribute(g, "discard", options.discard);
  writer.SetAttribute(g, "interval", options.interval);
  writer.SetAttribute(g, "sample_interval", o.sample_interval);
  writer.SetAttribute(g, "exponents", static_cast<double>(options.exponents));
  writer.SetAttribute(g, "blocks", static_cast<double>(options.blocks));
  writer.SetAttribute(g, "zero_tolerance", options.zero_tolerance);
  writer.SetAttribute(g, "integrator", ToString(options.integrator.method));
  writer.SetAttribute(g, "relative_tolerance", options.integrator.relative_tolerance);
  writer.SetAttribute(g, "absolute_tolerance", options.integrator.absolute_tolerance);
  WriteApproachSpeeds(writer, g, result.approach);
  writer.SetAttribute(g, "wall_seconds", result.wall_seconds);
  const Index count = static_cast<Index>(result.speeds.size());
  Matrix exponents(count, options.exponents), errors(count, options.exponents);
  std::vector<double> speed, counted, cpu, steps;
  std::vector<int> zero, positive, period;
  std::vector<std::string> status, message, untrusted, motion;
  writer.CreateGroup(g + "/running");
  for (Index i = 0; i < count; ++i) {
    const AttractorSpeed& s = result.speeds[static_cast<std::size_t>(i)];
    const AttractorResult& r = s.result;
    speed.push_back(s.speed_rpm);
    exponents.row(i) = r.exponents.transpose();
    errors.row(i) = r.standard_errors.transpose();
    zero.push_back(r.zero);
    positive.push_back(r.positive);
    period.push_back(s.section_period);
    motion.push_back(s.motion);
    status.push_back(ToString(r.status));
    message.push_back(r.message);
    untrusted.push_back(s.untrusted);
    counted.push_back(r.counted_time);
    cpu.push_back(r.cpu_seconds);
    steps.push_back(static_cast<double>(r.statistics.steps));
    writer.WriteMatrix(fmt::format("{}/running/{}", g, i), r.running);
    writer.WriteDoubles(fmt::format("{}/running/{}_time_s", g, i), r.times);
  }
  writer.WriteDoubles(g + "/speed_rpm", speed);
  writer.WriteMatrix(g + "/exponents", exponents);
  writer.WriteMatrix(g + "/standard_errors", errors);
  writer.WriteInts(g + "/zero_exponents", zero);
  writer.WriteInts(g + "/positive_exponents", positive);
  writer.WriteInts(g + "/section_period", period);
  writer.WriteStrings(g + "/motion", motion);
  writer.WriteStrings(g + "/status", status);
  writer.WriteStrings(g + "/message", message);
  writer.WriteStrings(g + "/untrusted", untrusted);
  writer.WriteDoubles(g + "/counted_s", counted);
  writer.WriteDoubles(g + "/cpu_seconds", cpu);
  writer.WriteDoubles(g + "/steps", steps);
  std::vector<std::vector<double>> section_speed(contacts), section_time(contacts),
      section_penetration(contacts), section_force(contacts);
  for (const AttractorSpeed& s : result.speeds) {
    for (const RubSectionPoint& p : s.section) {
      const auto k = static_cast<std::size_t>(p.contact);
      section_speed[k].push_back(s.speed_rpm);
      section_time[k].push_back(p.t);
      section_penetration[k].push_back(p.penetration);
      section_force[k].push_back(p.normal_force);
    }
  }
  for (std::size_t k = 0; k < contacts; ++k) {
    const std::string side = structure.contacts[k].name;
    writer.WriteDoubles(g + "/section_speed_rpm_" + side, section_speed[k]);
    writer.WriteDoubles(g + "/section_time_s_" + side, section_time[k]);
    writer.WriteDoubles(g + "/section_penetration_" + side, section_penetration[k]);
    writer.WriteDoubles(g + "/section_normal_force_" + side, section_force[k]);
  }
  writer.Commit();
}

void PrintAttractorSummary(std::ostream& out, std::ostream& err, const Scene& scene,
                           const RubStructure& structure, const AttractorStudyResult& result,
                           const std::filesystem::path& file) {
  const AttractorOptions& options = result.options.attractor;
  const std::vector<double>& before = result.approach.speeds;
  std::string from = "rest (the impulse)";
  if (!before.empty()) {
    from = fmt::format("the {} sweep {:g} → {:g} rpm", ToString(result.options.approach.direction),
                       RadPerSecondToRpm(before.front()), RadPerSecondToRpm(before.back()));
  }
  fmt::print(out, "scene {} from {}\n[attractor] L3: {} speed(s) from {}, {:g} s discarded and {:g} s "
                  "counted per speed, {} exponents re-orthonormalized every {:g} s, {} at rtol {:g}:\n",
             scene.name, scene.source, result.speeds.size(), from, options.discard, options.duration,
             options.exponents, options.interval, ToString(options.integrator.method),
             options.integrator.relative_tolerance);
  for (const AttractorSpeed& s : result.speeds) {
    const AttractorResult& r = s.result;
    fmt::print(out, "  {:.1f} rpm: {}: λ = {} 1/s", s.speed_rpm, s.motion, FormatExponents(r));
    for (std::size_t k = 0; k < structure.contacts.size(); ++k) {
      std::size_t n = 0;
      double low = kNaN, high = kNaN;
      for (const RubSectionPoint& p : s.section) {
        if (p.contact != static_cast<int>(k)) continue;
        low = n == 0 ? p.normal_force : std::min(low, p.normal_force);
        high = n == 0 ? p.normal_force : std::max(high, p.normal_force);
        ++n;
      }
      if (n == 0) {
        fmt::print(out, "; {} no section point", structure.contacts[k].name);
      } else {
        fmt::print(out, "; {} {} maxima, N {:.0f} … {:.0f} N", structure.contacts[k].name, n, low, high);
      }
    }
    fmt::print(out, "; {:.1f} s CPU\n", r.cpu_seconds);
    if (!s.untrusted.empty()) fmt::print(out, "    untrusted: {}\n", s.untrusted);
    if (r.status != AttractorStatus::kMeasured) {
      fmt::print(err, "rubcont: numerical failure at {:.1f} rpm: {}\n", s.speed_rpm, r.message);
    }
  }
  fmt::print(out, "  {:.1f} s wall\nwrote {}\n", result.wall_seconds, file.string());
}

AttractorStudyProgress PrintAttractorProgress(std::ostream& err, SteadyClock::time_point start) {
  AttractorStudyProgress progress;
  progress.approach = PrintApproachProgress(err, "attractor", start);
  // Each speed's integration every tenth of its time, with the seconds since the speed began.
  struct Speed {
    double rpm = kNaN;
    double reported = 0.0;
    SteadyClock::time_point start;
  };
  auto current = std::make_shared<Speed>();
  progress.integration = [&err, current](double rpm, double done, double total) {
    if (!(rpm == current->rpm)) *current = {rpm, 0.0, SteadyClock::now()};
    if (done < total && done < current->reported + 0.1 * total) return;
    current->reported = done;
    fmt::print(err, "rubcont: [attractor] {:.1f} rpm: {:.2f} of {:.2f} s ({:.1f} s)\n", rpm, done, total,
               SecondsSince(current->start));
    err.flush();
  };
  progress.speed = [&err](const AttractorSpeed& s) {
    fmt::print(err, "rubcont: [attractor] {:.1f} rpm: {} ({}; {:.1f} s CPU)\n", s.speed_rpm, s.motion,
               FormatExponents(s.result), s.result.cpu_seconds);
    err.flush();
  };
  return progress;
}

}  // namespace rubcont
