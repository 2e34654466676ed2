#include "apps/attractor_command.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <ostream>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "apps/commands.h"
#include "apps/figures.h"
#include "apps/guarded.h"
#include "apps/hdf5_file.h"
#include "apps/level.h"
#include "apps/scene.h"
#include "apps/stage_options.h"
#include "apps/sweep_output.h"
#include "models/units.h"
#include "solvers/constants.h"
#include "solvers/stopwatch.h"
#include "sweeps/attractor.h"
#include "sweeps/rub_sweep.h"

namespace rubcont {
namespace {

void Check(const AttractorRequest& r) {
  auto fail = [](const char* option, const auto& value, const char* rule) {
    throw std::invalid_argument(fmt::format("--{} = {}: {}", option, value, rule));
  };
  auto positive = [&](const char* option, double value) {
    if (!(value > 0.0) || !std::isfinite(value)) fail(option, value, "must be positive");
  };
  positive("from", r.from_rpm);
  if (r.to_rpm) positive("to", *r.to_rpm);
  positive("step", r.step_rpm);
  ParseDirection("direction", r.direction);
  if (r.approach) ParseDirection("approach", *r.approach);
  if (r.to_rpm && (r.direction == "up" ? *r.to_rpm < r.from_rpm : *r.to_rpm > r.from_rpm)) {
    fail("to", *r.to_rpm, "must lie beyond --from in the direction of the schedule");
  }
  positive("duration", r.duration);
  if (!(r.discard >= 0.0) || !std::isfinite(r.discard)) fail("discard", r.discard, "must be finite and ≥ 0");
  if (!(r.interval > 0.0) || !(r.interval <= r.duration / 10.0)) {
    fail("interval", r.interval, "must be positive and at most a tenth of --duration");
  }
  if (r.exponents < 1) fail("exponents", r.exponents, "must be at least 1");
  if (!(r.sample_interval > 0.0) || !(r.sample_interval <= r.interval)) {
    fail("sample", r.sample_interval, "must be positive and at most --interval");
  }
  if (r.tolerance && !(*r.tolerance > 0.0 && *r.tolerance < 1.0)) {
    fail("tolerance", *r.tolerance, "must lie in (0, 1)");
  }
}

std::string FormatExponents(const AttractorResult& result) {
  std::string text;
  for (Index j = 0; j < result.exponents.size(); ++j) {
    text += fmt::format("{}{:+.2f} ± {:.2f}", j ? ", " : "", result.exponents(j), result.standard_errors(j));
  }
  return text;
}

}  // namespace

int AttractorCommand(const AttractorRequest& request, std::ostream& out, std::ostream& err) {
  return Guarded(err, [&] {
    Check(request);
    // CVODES BDF for the approach and the exponents whatever the scene's sweep integrator: the
    // Lyapunov exponents integrate the variational equations as sensitivities, which Odeint's
    // Dormand–Prince does not (the committed attractor runs were made so).
    Scene scene = LoadScene(request.scene_file);
    scene.analysis.sweep.integrator = SweepIntegrator::kBdf;
    const RubStructure structure = SweepStructureOf(scene);
    const SweepDirection direction = ParseDirection("direction", request.direction);
    const std::string approach_name = request.approach.value_or(request.direction);
    const SweepDirection approach_direction = ParseDirection("approach", approach_name);
    const std::vector<double> speeds_rpm =
        SpeedSchedule(request.from_rpm, request.to_rpm.value_or(request.from_rpm), request.step_rpm);
    AttractorOptions options;
    options.duration = request.duration;
    options.discard = request.discard;
    options.interval = request.interval;
    options.exponents = request.exponents;
    options.integrator = SweepOptionsOf(scene, direction).integrator;
    options.integrator.sensitivity_error_control = false;
    if (request.tolerance) {
      options.integrator.relative_tolerance = *request.tolerance;
      options.integrator.absolute_tolerance = *request.tolerance;
    }
    Validate(options);
    if (options.exponents > structure.States()) {
      throw std::invalid_argument(fmt::format("--exponents = {}: must be at most the model's {} states",
                                              options.exponents, structure.States()));
    }

    const SteadyClock::time_point start = SteadyClock::now();
    const SweepApproach approach =
        ApproachSweep(scene, approach_direction, RpmToRadPerSecond(speeds_rpm.front()),
                      request.quiet ? nullptr : PrintApproachProgress(err, "attractor", start));

    RubFixedFrame system(structure);
    const SampledSection section = RubPenetrations(system, request.sample_interval);
    const std::size_t contacts = structure.contacts.size();
    Vector x = approach.state;
    std::vector<AttractorResult> results;
    std::vector<std::vector<RubSectionPoint>> points;  // per speed
    std::vector<int> period;                            // per speed: RubSectionPeriod
    std::vector<std::string> motion;                    // per speed: RubMotion
    for (double rpm : speeds_rpm) {
      const double omega = RpmToRadPerSecond(rpm);
      system.SetParameter(omega);
      const SteadyClock::time_point speed_start = SteadyClock::now();
      double reported = 0.0;
      results.push_back(MeasureAttractor(system, x, options, &section, [&](double done, double total) {
        if (request.quiet || (done < total && done < reported + 0.1 * total)) return;
        reported = done;
        fmt::print(err, "rubcont: [attractor] {:.1f} rpm: {:.2f} of {:.2f} s ({:.1f} s)\n", rpm, done,
                   total, SecondsSince(speed_start));
        err.flush();
      }));
      AttractorResult& r = results.back();
      points.push_back(RubSectionMaxima(system, r.extrema));
      r.extrema = {};  // every ripple's extremum with its state: megabytes per second
      period.push_back(RubSectionPeriod(structure, points.back()));
      motion.push_back(RubMotion(structure, r, points.back()));
      if (!request.quiet) {
        fmt::print(err, "rubcont: [attractor] {:.1f} rpm: {} ({}; {:.1f} s CPU)\n", rpm,
                   motion.back(), FormatExponents(r), r.cpu_seconds);
        err.flush();
      }
      if (r.status != AttractorStatus::kMeasured) break;
      x = r.state;
      // Time restarts at 0 at every speed: with imbalance, keep the forcing's phase (as a sweep).
      if (structure.imbalance != 0.0) system.Rotate(-omega * (options.discard + r.counted_time), x);
    }

    // The file.
    const std::filesystem::path file = request.out_file
                                           ? std::filesystem::path(*request.out_file)
                                           : std::filesystem::path("results") / scene.name / "attractor.h5";
    std::filesystem::create_directories(file.parent_path().empty() ? "." : file.parent_path());
    ResultWriter writer(file);
    WriteSceneAttributes(writer, scene);
    writer.SetAttribute("/", "level", ToString(ResultLevel(scene, Level::kL3)));
    const std::string g = "/attractor";
    writer.CreateGroup(g);
    writer.SetAttribute(g, "direction", request.direction);
    writer.SetAttribute(g, "approach", approach_name);
    writer.SetAttribute(g, "duration", options.duration);
    writer.SetAttribute(g, "discard", options.discard);
    writer.SetAttribute(g, "interval", options.interval);
    writer.SetAttribute(g, "sample_interval", section.interval);
    writer.SetAttribute(g, "exponents", static_cast<double>(options.exponents));
    writer.SetAttribute(g, "blocks", static_cast<double>(options.blocks));
    writer.SetAttribute(g, "zero_tolerance", options.zero_tolerance);
    writer.SetAttribute(g, "integrator", ToString(options.integrator.method));
    writer.SetAttribute(g, "relative_tolerance", options.integrator.relative_tolerance);
    writer.SetAttribute(g, "absolute_tolerance", options.integrator.absolute_tolerance);
    const std::vector<double>& before = approach.speeds;
    writer.SetAttribute(g, "approach_from_rpm", before.empty() ? kNaN : RadPerSecondToRpm(before.front()));
    writer.SetAttribute(g, "approach_to_rpm", before.empty() ? kNaN : RadPerSecondToRpm(before.back()));
    writer.SetAttribute(g, "wall_seconds", SecondsSince(start));
    const Index count = static_cast<Index>(results.size());
    Matrix exponents(count, options.exponents), errors(count, options.exponents);
    std::vector<double> speed, counted, cpu, steps;
    std::vector<int> zero, positive;
    std::vector<std::string> status, message, untrusted;
    writer.CreateGroup(g + "/running");
    for (Index i = 0; i < count; ++i) {
      const AttractorResult& r = results[static_cast<std::size_t>(i)];
      speed.push_back(speeds_rpm[static_cast<std::size_t>(i)]);
      exponents.row(i) = r.exponents.transpose();
      errors.row(i) = r.standard_errors.transpose();
      zero.push_back(r.zero);
      positive.push_back(r.positive);
      status.push_back(ToString(r.status));
      message.push_back(r.message);
      untrusted.push_back(UntrustedSection(structure, points[static_cast<std::size_t>(i)],
                                           scene.analysis.sweep.max_penetration));
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
    for (Index i = 0; i < count; ++i) {
      for (const RubSectionPoint& p : points[static_cast<std::size_t>(i)]) {
        const auto k = static_cast<std::size_t>(p.contact);
        section_speed[k].push_back(speed[static_cast<std::size_t>(i)]);
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

    // The summary.
    std::string from = "rest (the impulse)";
    if (!before.empty()) {
      from = fmt::format("the {} sweep {:g} → {:g} rpm", approach_name,
                         RadPerSecondToRpm(before.front()), RadPerSecondToRpm(before.back()));
    }
    fmt::print(out, "scene {} from {}\n[attractor] L3: {} speed(s) from {}, {:g} s discarded and {:g} s "
                    "counted per speed, {} exponents re-orthonormalized every {:g} s, {} at rtol {:g}:\n",
               scene.name, scene.source, count, from, options.discard, options.duration,
               options.exponents, options.interval, ToString(options.integrator.method),
               options.integrator.relative_tolerance);
    int failures = 0;
    for (Index i = 0; i < count; ++i) {
      const AttractorResult& r = results[static_cast<std::size_t>(i)];
      fmt::print(out, "  {:.1f} rpm: {}: λ = {} 1/s", speed[static_cast<std::size_t>(i)],
                 motion[static_cast<std::size_t>(i)], FormatExponents(r));
      for (std::size_t k = 0; k < contacts; ++k) {
        std::size_t n = 0;
        double low = kNaN, high = kNaN;
        for (const RubSectionPoint& p : points[static_cast<std::size_t>(i)]) {
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
      if (!untrusted[static_cast<std::size_t>(i)].empty()) {
        fmt::print(out, "    untrusted: {}\n", untrusted[static_cast<std::size_t>(i)]);
      }
      if (r.status != AttractorStatus::kMeasured) {
        ++failures;
        fmt::print(err, "rubcont: numerical failure at {:.1f} rpm: {}\n", speed[static_cast<std::size_t>(i)],
                   r.message);
      }
    }
    fmt::print(out, "  {:.1f} s wall\nwrote {}\n", SecondsSince(start), file.string());
    const std::filesystem::path out_dir = file.parent_path().empty() ? "." : file.parent_path();
    const FigureOutcome figures = MakeFigures("attractor.py", file, out_dir);
    if (figures.made) {
      fmt::print(out, "wrote figures (attractor.py) in {}\n", out_dir.string());
    } else {
      fmt::print(err, "rubcont: warning: {}\n", figures.warning);
    }
    return failures == 0 ? kExitSuccess : kExitFailure;
  });
}

}  // namespace rubcont
