#include "apps/lifetime_command.h"

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
#include "sweeps/lifetime.h"

namespace rubcont {
namespace {

void Check(const LifetimeRequest& r) {
  auto fail = [](const char* option, const auto& value, const char* rule) {
    throw std::invalid_argument(fmt::format("--{} = {}: {}", option, value, rule));
  };
  ParseDirection("direction", r.direction);
  if (!(r.from_rpm > 0.0) || !std::isfinite(r.from_rpm)) fail("from", r.from_rpm, "must be positive");
  if (!(r.to_rpm > 0.0) || !std::isfinite(r.to_rpm)) fail("to", r.to_rpm, "must be positive");
  const double sign = r.direction == "up" ? 1.0 : -1.0;
  if (!(sign * (r.to_rpm - r.from_rpm) > 0.0)) {
    fail("to", r.to_rpm, r.direction == "up" ? "must be above --from (direction up)"
                                             : "must be below --from (direction down)");
  }
  if (!(r.step_rpm > 0.0) || !std::isfinite(r.step_rpm)) fail("step", r.step_rpm, "must be positive");
  if (std::abs(r.to_rpm - r.from_rpm) / r.step_rpm > 1000.0) fail("step", r.step_rpm, "gives more than 1000 speeds");
  CheckCopyOptions(r.copies, r.window, r.duration, r.perturbation, r.threads);
  if (r.check_copies < 0 || r.check_copies > 100000) fail("check-copies", r.check_copies, "must be in 0 … 100000");
  if (!(r.check_step_rpm > 0.0) || !std::isfinite(r.check_step_rpm)) {
    fail("check-step", r.check_step_rpm, "must be positive");
  }
  if (std::abs(r.to_rpm - r.from_rpm) / r.check_step_rpm > 1000.0) {
    fail("check-step", r.check_step_rpm, "gives more than 1000 speeds");
  }
  if (!(r.check_dwell >= 2.0 * r.window) || !std::isfinite(r.check_dwell)) {
    fail("check-dwell", r.check_dwell, "must be at least two windows");
  }
}

}  // namespace

int LifetimeCommand(const LifetimeRequest& request, std::ostream& out, std::ostream& err) {
  return Guarded(err, [&] {
    Check(request);
    const Scene scene = LoadScene(request.scene_file);
    const RubStructure structure = SweepStructureOf(scene);
    const ArrivalTarget target =
        ParseUntil(structure, request.until, request.until_above_hz, request.until_contacts);
    const SweepDirection direction = ParseDirection("direction", request.direction);
    const CrisisSide side = direction == SweepDirection::kUp ? CrisisSide::kAbove : CrisisSide::kBelow;
    const double cpu_start = ProcessCpuSeconds();
    const SteadyClock::time_point start = SteadyClock::now();
    auto progress = [&](const std::string& what) {
      return [&err, &request, what, start](int done, int total) {
        if (request.quiet) return;
        fmt::print(err, "rubcont: [lifetime] {} copy {}/{} ({:.1f} s)\n", what, done, total, SecondsSince(start));
        err.flush();
      };
    };

    const SweepApproach approach = ApproachSweep(
        scene, direction, RpmToRadPerSecond(request.from_rpm),
        request.quiet ? nullptr : PrintApproachProgress(err, "lifetime", start));
    EnsembleOptions options;
    options.copies = request.copies;
    options.perturbation = request.perturbation;
    options.threads = request.threads;

    // The ensembles, one per speed, all from the approach's state.
    const std::vector<double> speeds = SpeedSchedule(request.from_rpm, request.to_rpm, request.step_rpm);
    const int stretches = StretchCount(request.duration, request.window);
    std::vector<EscapeObservations> observations;
    std::vector<EscapeRate> rates;
    std::vector<int> failed, untrusted;
    std::string first_untrusted;  // why, for the summary
    Matrix arrival = Matrix::Constant(static_cast<Index>(speeds.size()), request.copies, kNaN);
    for (std::size_t i = 0; i < speeds.size(); ++i) {
      options.seed = request.seed + i * static_cast<std::uint64_t>(request.copies);
      const RubCopies run = RunRubCopies(
          scene, direction, std::vector<double>(static_cast<std::size_t>(stretches), RpmToRadPerSecond(speeds[i])),
          request.window, approach.state, options, target, progress(fmt::format("{:g} rpm", speeds[i])));
      EscapeObservations o;
      o.parameter = speeds[i];
      o.stretch = run.stretch_seconds;
      o.duration = stretches * o.stretch;
      failed.push_back(0);
      untrusted.push_back(0);
      for (std::size_t c = 0; c < run.arrivals.size(); ++c) {
        const RubArrival& a = run.arrivals[c];
        if (!a.untrusted.empty()) {
          ++untrusted.back();
          if (first_untrusted.empty()) {
            first_untrusted = fmt::format("{:g} rpm, copy {}: {}", speeds[i], c, a.untrusted);
          }
        }
        if (a.reached) {
          o.escape_stretch.push_back(a.point + 1);
          arrival(static_cast<Index>(i), static_cast<Index>(c)) = a.time;
        } else if (a.failed) {
          ++failed.back();
          fmt::print(err, "rubcont: numerical failure: {:g} rpm, copy {}: {}\n", speeds[i], c,
                     run.copies[c].points.back().message);
        } else {
          ++o.stayed;
        }
      }
      if (o.escape_stretch.empty() && o.stayed == 0) {
        throw std::runtime_error(fmt::format("every copy failed at {:g} rpm: nothing to estimate", speeds[i]));
      }
      observations.push_back(o);
      rates.push_back(EstimateEscapeRate(o));
      if (!request.quiet) {
        fmt::print(err, "rubcont: [lifetime] {:g} rpm: {} of {} left, κ = {:.4g} /s\n", speeds[i],
                   o.escape_stretch.size(), request.copies, rates.back().rate);
      }
    }
    CrisisOptions crisis_options;
    crisis_options.side = side;
    const CrisisFit fit = FitCrisis(observations, crisis_options);

    // The check: perturbed sweeps through the same speeds with a long dwell.
    const std::vector<double> schedule = SpeedSchedule(request.from_rpm, request.to_rpm, request.check_step_rpm);
    const int dwell_stretches = StretchCount(request.check_dwell, request.window);
    std::vector<double> jump_speed, jump_time, leave;
    double check_stretch = 2.0 * request.window;
    int check_failures = 0;
    if (request.check_copies > 0) {
      std::vector<double> stretch_speeds;
      for (double s : schedule) {
        stretch_speeds.insert(stretch_speeds.end(), static_cast<std::size_t>(dwell_stretches), RpmToRadPerSecond(s));
      }
      EnsembleOptions check = options;
      check.copies = request.check_copies;
      check.seed = request.seed + speeds.size() * static_cast<std::uint64_t>(request.copies);
      const RubCopies run = RunRubCopies(scene, direction, stretch_speeds, request.window, approach.state, check,
                                         target, progress("check sweep"));
      for (std::size_t c = 0; c < run.arrivals.size(); ++c) {
        const RubArrival& a = run.arrivals[c];
        jump_speed.push_back(a.reached ? schedule[static_cast<std::size_t>(a.point / dwell_stretches)] : kNaN);
        jump_time.push_back(a.reached ? a.time : kNaN);
        if (a.failed) {
          ++check_failures;
          fmt::print(err, "rubcont: numerical failure: check sweep {}: {}\n", c, run.copies[c].points.back().message);
        }
      }
      check_stretch = run.stretch_seconds;
      if (fit.status == CrisisStatus::kLocated) {
        leave = SweepLeaveProbabilities(fit, side, schedule, dwell_stretches * check_stretch);
      }
    }
    const double wall = SecondsSince(start), cpu = ProcessCpuSeconds() - cpu_start;

    // The file.
    const std::filesystem::path file = request.out_file ? std::filesystem::path(*request.out_file)
                                                        : std::filesystem::path("results") / scene.name / "lifetime.h5";
    std::filesystem::create_directories(file.parent_path().empty() ? "." : file.parent_path());
    ResultWriter writer(file);
    WriteSceneAttributes(writer, scene);
    writer.SetAttribute("/", "level", ToString(ResultLevel(scene, Level::kL3)));
    const std::string g = "/lifetime";
    writer.CreateGroup(g);
    writer.SetAttribute(g, "direction", request.direction);
    writer.SetAttribute(g, "copies", static_cast<double>(request.copies));
    writer.SetAttribute(g, "duration", observations.front().duration);
    writer.SetAttribute(g, "window", request.window);
    writer.SetAttribute(g, "stretch", observations.front().stretch);
    writer.SetAttribute(g, "perturbation", request.perturbation);
    writer.SetAttribute(g, "seed", static_cast<double>(request.seed));
    writer.SetAttribute(g, "until", request.until);
    writer.SetAttribute(g, "until_contacts", request.until_contacts);
    writer.SetAttribute(g, "until_above_hz", request.until_above_hz);
    writer.SetAttribute(g, "arrival", Describe(structure, target));
    writer.SetAttribute(g, "threads", static_cast<double>(request.threads));
    writer.SetAttribute(g, "wall_seconds", wall);
    writer.SetAttribute(g, "cpu_seconds", cpu);
    writer.SetAttribute(g, "approach_from_rpm",
                        approach.speeds.empty() ? kNaN : RadPerSecondToRpm(approach.speeds.front()));
    writer.SetAttribute(g, "approach_to_rpm",
                        approach.speeds.empty() ? kNaN : RadPerSecondToRpm(approach.speeds.back()));
    std::vector<double> rate, lower, upper;
    std::vector<int> escapes, stayed;
    std::vector<std::string> status;
    for (std::size_t i = 0; i < speeds.size(); ++i) {
      rate.push_back(rates[i].rate);
      lower.push_back(rates[i].lower);
      upper.push_back(rates[i].upper);
      escapes.push_back(rates[i].escapes);
      stayed.push_back(observations[i].stayed);
      status.push_back(ToString(rates[i].status));
    }
    writer.WriteDoubles(g + "/speed_rpm", speeds);
    writer.WriteInts(g + "/escapes", escapes);
    writer.WriteInts(g + "/stayed", stayed);
    writer.WriteInts(g + "/failed", failed);
    writer.WriteInts(g + "/untrusted", untrusted);
    writer.WriteDoubles(g + "/escape_rate", rate);
    writer.WriteDoubles(g + "/rate_lower", lower);
    writer.WriteDoubles(g + "/rate_upper", upper);
    writer.WriteStrings(g + "/rate_status", status);
    writer.WriteMatrix(g + "/arrival_time_s", arrival);
    const std::string c = g + "/crisis";
    writer.CreateGroup(c);
    writer.SetAttribute(c, "status", ToString(fit.status));
    writer.SetAttribute(c, "message", fit.message);
    writer.SetAttribute(c, "critical_speed_rpm", fit.critical);
    writer.SetAttribute(c, "critical_lower_rpm", fit.critical_lower);
    writer.SetAttribute(c, "critical_upper_rpm", fit.critical_upper);
    writer.SetAttribute(c, "lower_bounded", fit.lower_bounded ? 1.0 : 0.0);
    writer.SetAttribute(c, "upper_bounded", fit.upper_bounded ? 1.0 : 0.0);
    writer.SetAttribute(c, "exponent", fit.exponent);
    writer.SetAttribute(c, "amplitude", fit.amplitude);
    writer.SetAttribute(c, "log_likelihood", fit.log_likelihood);
    if (request.check_copies > 0) {
      const std::string k = g + "/check";
      writer.CreateGroup(k);
      writer.SetAttribute(k, "dwell", dwell_stretches * check_stretch);
      writer.SetAttribute(k, "step_rpm", request.check_step_rpm);
      writer.WriteDoubles(k + "/speed_rpm", schedule);
      writer.WriteDoubles(k + "/predicted_leave_probability",
                          leave.empty() ? std::vector<double>(schedule.size(), kNaN) : leave);
      writer.WriteDoubles(k + "/jump_speed_rpm", jump_speed);
      writer.WriteDoubles(k + "/jump_time_s", jump_time);
    }
    writer.Commit();

    // The summary.
    fmt::print(out, "scene {} from {}\n[lifetime] L3: {} copies per speed for {:.4g} s (stretches of {:.4g} s), "
                    "from the {} sweep's state at {} ({}), until {}:\n",
               scene.name, scene.source, request.copies, observations.front().duration,
               observations.front().stretch, request.direction,
               approach.speeds.empty() ? std::string("rest (the impulse)")
                                       : fmt::format("{:g} rpm", RadPerSecondToRpm(approach.speeds.back())),
               RegimeList(structure, approach.regimes), Describe(structure, target));
    for (std::size_t i = 0; i < speeds.size(); ++i) {
      const EscapeRate& r = rates[i];
      fmt::print(out, "  {:7g} rpm: {:3} of {} left", speeds[i], r.escapes, r.copies);
      if (r.status == EscapeRateStatus::kEstimated) {
        fmt::print(out, ", κ = {:.3g} /s [{:.3g}, {:.3g}], mean lifetime {:.3g} s", r.rate, r.lower, r.upper, 1.0 / r.rate);
      } else if (r.status == EscapeRateStatus::kNoEscape) {
        fmt::print(out, ", κ < {:.3g} /s (mean lifetime > {:.3g} s)", r.upper, 1.0 / r.upper);
      } else {
        fmt::print(out, ", all in the first stretch: κ > {:.3g} /s", r.lower);
      }
      fmt::print(out, "{}{}\n", failed[i] ? fmt::format("; {} failed", failed[i]) : std::string(),
                 untrusted[i] ? fmt::format("; {} untrusted", untrusted[i]) : std::string());
    }
    if (!first_untrusted.empty()) {
      fmt::print(out, "  untrusted copies (counted all the same; a contact penetrated beyond "
                      "[analysis.sweep] max_penetration before it arrived): the first at {}\n",
                 first_untrusted);
    }
    if (fit.status == CrisisStatus::kLocated) {
      // The ends the likelihood does not bound: towards the speeds with escapes the interval is open
      // up to the first of them, away from them down to the end of the search range.
      const bool above = side == CrisisSide::kAbove;
      const char* near_end = "the first speed with escapes";
      const char* far_end = "the end of the search";
      std::string interval = fmt::format("{:.2f} … {:.2f} rpm", fit.critical_lower, fit.critical_upper);
      if (!fit.lower_bounded && !fit.upper_bounded) {
        interval = "not bounded within the search range";
      } else if (!fit.lower_bounded) {
        interval = fmt::format("below {:.2f} rpm (open down to {}, {:.2f})", fit.critical_upper,
                               above ? far_end : near_end, fit.critical_lower);
      } else if (!fit.upper_bounded) {
        interval = fmt::format("above {:.2f} rpm (open up to {}, {:.2f})", fit.critical_lower,
                               above ? near_end : far_end, fit.critical_upper);
      }
      fmt::print(out, "  crisis law κ = A·({})^γ, A = {:.3g} /s per rpm^γ, γ = {:.3g}: the state ends at "
                      "p_c = {:.2f} rpm, 95 % interval {}{}\n",
                 side == CrisisSide::kAbove ? "p − p_c" : "p_c − p", fit.amplitude, fit.exponent, fit.critical,
                 interval, fit.message.empty() ? "" : "; " + fit.message);
    } else {
      fmt::print(out, "  crisis law: {} ({})\n", ToString(fit.status), fit.message);
    }
    if (request.check_copies > 0) {
      fmt::print(out, "  check: {} sweeps {:g} → {:g} rpm in {:g} rpm steps, {:.4g} s per speed, left at:",
                 request.check_copies, request.from_rpm, request.to_rpm, request.check_step_rpm,
                 dwell_stretches * check_stretch);
      for (double s : jump_speed) fmt::print(out, " {}", std::isnan(s) ? std::string("(stayed)") : fmt::format("{:g}", s));
      fmt::print(out, " rpm\n");
      if (!leave.empty()) {
        double sum = 0.0, median = kNaN, low = kNaN, high = kNaN;
        for (std::size_t i = 0; i < schedule.size(); ++i) {
          if (std::isnan(low) && sum + leave[i] >= 0.05) low = schedule[i];
          if (std::isnan(median) && sum + leave[i] >= 0.5) median = schedule[i];
          if (std::isnan(high) && sum + leave[i] >= 0.95) high = schedule[i];
          sum += leave[i];
        }
        auto text = [](double s) { return std::isnan(s) ? std::string("beyond the range") : fmt::format("{:g} rpm", s); };
        fmt::print(out, "  predicted by the crisis law for this schedule: leaves at {} (median), 90 % between {} and {}\n",
                   text(median), text(low), text(high));
      }
    }
    fmt::print(out, "  {:.1f} s wall, {:.1f} s CPU\nwrote {}\n", wall, cpu, file.string());
    const std::filesystem::path out_dir = file.parent_path().empty() ? "." : file.parent_path();
    const FigureOutcome figures = MakeFigures("lifetime.py", file, out_dir);
    if (figures.made) {
      fmt::print(out, "wrote figures (lifetime.py) in {}\n", out_dir.string());
    } else {
      fmt::print(err, "rubcont: warning: {}\n", figures.warning);
    }
    int failures = check_failures;
    for (int f : failed) failures += f;
    return failures == 0 ? kExitSuccess : kExitFailure;
  });
}

}  // namespace rubcont
