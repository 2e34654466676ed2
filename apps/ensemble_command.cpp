#include "apps/ensemble_command.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
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
#include "sweeps/ensemble.h"
#include "sweeps/rub_sweep.h"

namespace rubcont {
namespace {

void Check(const EnsembleRequest& r) {
  auto fail = [](const char* option, const auto& value, const char* rule) {
    throw std::invalid_argument(fmt::format("--{} = {}: {}", option, value, rule));
  };
  if (!(r.speed_rpm > 0.0) || !std::isfinite(r.speed_rpm)) fail("speed", r.speed_rpm, "must be positive");
  ParseDirection("direction", r.direction);
  CheckCopyOptions(r.copies, r.window, r.duration, r.perturbation, r.threads);
}

// Quantile q of sorted values (linear interpolation).
double Quantile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return kNaN;
  const double at = q * static_cast<double>(sorted.size() - 1);
  const std::size_t i = static_cast<std::size_t>(std::floor(at));
  const std::size_t j = std::min(i + 1, sorted.size() - 1);
  return sorted[i] + (at - static_cast<double>(i)) * (sorted[j] - sorted[i]);
}

}  // namespace

int EnsembleCommand(const EnsembleRequest& request, std::ostream& out, std::ostream& err) {
  return Guarded(err, [&] {
    Check(request);
    const Scene scene = LoadScene(request.scene_file);
    const RubStructure structure = SweepStructureOf(scene);
    const ArrivalTarget target =
        ParseUntil(structure, request.until, request.until_above_hz, request.until_contacts);
    const SweepDirection direction = ParseDirection("direction", request.direction);
    const double speed = RpmToRadPerSecond(request.speed_rpm);

    // The approach: the scene's schedule in this direction, up to the last speed before `speed`.
    const SteadyClock::time_point start = SteadyClock::now();
    const SweepApproach approach = ApproachSweep(
        scene, direction, speed, request.quiet ? nullptr : PrintApproachProgress(err, "ensemble", start));
    const std::vector<double>& before = approach.speeds;
    const std::vector<RubRegime>& approach_regime = approach.regimes;
    const Vector& x0 = approach.state;

    // The copies: stretches of two windows at `speed`.
    const int count = StretchCount(request.duration, request.window);
    EnsembleOptions options;
    options.copies = request.copies;
    options.perturbation = request.perturbation;
    options.seed = request.seed;
    options.threads = request.threads;
    const SteadyClock::time_point ensemble_start = SteadyClock::now();
    const RubCopies run = RunRubCopies(
        scene, direction, std::vector<double>(static_cast<std::size_t>(count), speed), request.window, x0,
        options, target, [&](int done, int total) {
          if (request.quiet) return;
          fmt::print(err, "rubcont: [ensemble] copy {}/{} ({:.1f} s)\n", done, total,
                     SecondsSince(ensemble_start));
          err.flush();
        });
    const std::vector<EnsembleCopy>& copies = run.copies;
    const std::vector<RubArrival>& arrivals = run.arrivals;
    const double ensemble_wall = run.wall_seconds;

    // The file.
    const std::filesystem::path file =
        request.out_file ? std::filesystem::path(*request.out_file)
                         : std::filesystem::path("results") / scene.name /
                               fmt::format("ensemble_{:g}rpm.h5", request.speed_rpm);
    std::filesystem::create_directories(file.parent_path().empty() ? "." : file.parent_path());
    ResultWriter writer(file);
    WriteSceneAttributes(writer, scene);
    writer.SetAttribute("/", "level", ToString(ResultLevel(scene, Level::kL3)));
    const std::string g = "/ensemble";
    writer.CreateGroup(g);
    writer.SetAttribute(g, "speed_rpm", request.speed_rpm);
    writer.SetAttribute(g, "direction", request.direction);
    writer.SetAttribute(g, "copies", static_cast<double>(request.copies));
    writer.SetAttribute(g, "duration", request.duration);
    writer.SetAttribute(g, "window", request.window);
    writer.SetAttribute(g, "perturbation", request.perturbation);
    writer.SetAttribute(g, "seed", static_cast<double>(request.seed));
    writer.SetAttribute(g, "until", request.until);
    writer.SetAttribute(g, "until_contacts", request.until_contacts);
    writer.SetAttribute(g, "until_above_hz", request.until_above_hz);
    writer.SetAttribute(g, "arrival", Describe(structure, target));
    writer.SetAttribute(g, "threads", static_cast<double>(request.threads));
    writer.SetAttribute(g, "wall_seconds", ensemble_wall);
    writer.SetAttribute(g, "approach_from_rpm", before.empty() ? kNaN : RadPerSecondToRpm(before.front()));
    writer.SetAttribute(g, "approach_to_rpm", before.empty() ? kNaN : RadPerSecondToRpm(before.back()));
    std::vector<double> arrival, simulated, cpu;
    std::vector<int> reached, failed;
    std::vector<std::string> untrusted;
    for (std::size_t c = 0; c < copies.size(); ++c) {
      arrival.push_back(arrivals[c].reached ? arrivals[c].time : kNaN);
      reached.push_back(arrivals[c].reached ? 1 : 0);
      failed.push_back(arrivals[c].failed ? 1 : 0);
      untrusted.push_back(arrivals[c].untrusted);
      simulated.push_back(arrivals[c].simulated);
      cpu.push_back(copies[c].cpu_seconds);
    }
    writer.WriteDoubles(g + "/arrival_time_s", arrival);
    writer.WriteInts(g + "/reached", reached);
    writer.WriteInts(g + "/failed", failed);
    writer.WriteStrings(g + "/untrusted", untrusted);
    writer.WriteDoubles(g + "/simulated_s", simulated);
    writer.WriteDoubles(g + "/cpu_seconds", cpu);
    // The end of each stretch: the simulated times of a copy that ran them all (a window is a
    // whole number of samples, so a stretch is 2·round(window·rate)/rate).
    std::vector<double> time;
    for (const EnsembleCopy& copy : copies) {
      if (copy.failed) continue;
      double t = 0.0;
      for (const SweepPoint& p : copy.points) time.push_back(t += p.simulated_time);
      break;
    }
    writer.WriteDoubles(g + "/time_s", time);
    for (std::size_t k = 0; k < structure.contacts.size(); ++k) {
      const std::string side = structure.contacts[k].name;
      writer.SetAttribute(g, "approach_regime_" + side, ToString(approach_regime[k]));
      Matrix bp = Matrix::Constant(request.copies, count, kNaN), fraction = bp, slip = bp, regime = bp;
      for (std::size_t c = 0; c < copies.size(); ++c) {
        for (std::size_t i = 0; i < copies[c].points.size(); ++i) {
          const SweepPoint& p = copies[c].points[i];
          const Index r = static_cast<Index>(c), s = static_cast<Index>(i);
          regime(r, s) = static_cast<double>(static_cast<int>(arrivals[c].regimes.regime[k][i]));
          bp(r, s) = arrivals[c].regimes.precession_hz[k][i];
          if (k >= p.channels.size()) continue;
          fraction(r, s) = p.channels[k].active_fraction;
          slip(r, s) = p.channels[k].measures[kSlipVelocityMeasure].mean;
        }
      }
      writer.WriteMatrix(g + "/precession_hz_" + side, bp);
      writer.WriteMatrix(g + "/contact_fraction_" + side, fraction);
      writer.WriteMatrix(g + "/slip_velocity_" + side, slip);
      writer.WriteMatrix(g + "/regime_" + side, regime);
    }
    writer.Commit();

    // The summary.
    std::vector<double> times;
    int failures = 0, untrusted_copies = 0;
    std::string first_untrusted;
    for (std::size_t c = 0; c < arrivals.size(); ++c) {
      const RubArrival& a = arrivals[c];
      if (a.reached) times.push_back(a.time);
      failures += a.failed ? 1 : 0;
      if (a.untrusted.empty()) continue;
      if (untrusted_copies++ == 0) first_untrusted = fmt::format("copy {}: {}", c, a.untrusted);
    }
    std::sort(times.begin(), times.end());
    std::vector<double> sorted_cpu = cpu;
    std::sort(sorted_cpu.begin(), sorted_cpu.end());
    std::string from = "rest (the impulse)";
    if (!before.empty()) {
      from = fmt::format("the {} sweep {:g} → {:g} rpm ({})", request.direction, RadPerSecondToRpm(before.front()),
                         RadPerSecondToRpm(before.back()), RegimeList(structure, approach_regime));
    }
    fmt::print(out, "scene {} from {}\n[ensemble] L3: {} copies at {:g} rpm for {:.4g} s from {}, "
                    "perturbed by {:g} × each state's scale (seed {}):\n",
               scene.name, scene.source, request.copies, request.speed_rpm,
               time.empty() ? request.duration : time.back(), from, request.perturbation, request.seed);
    fmt::print(out, "  {} of {} reached {}", times.size(), copies.size(), Describe(structure, target));
    if (!times.empty()) {
      fmt::print(out, ", after {:.2f} s (min) / {:.2f} / {:.2f} / {:.2f} (quartiles) / {:.2f} s (max), "
                      "in stretches of {:.4g} s",
                 times.front(), Quantile(times, 0.25), Quantile(times, 0.5), Quantile(times, 0.75),
                 times.back(), time.empty() ? 2.0 * request.window : time.front());
    }
    fmt::print(out, "; {} failed\n", failures);
    if (untrusted_copies > 0) {
      fmt::print(out, "  {} untrusted (counted all the same; a contact penetrated beyond "
                      "[analysis.sweep] max_penetration before it arrived), the first {}\n",
                 untrusted_copies, first_untrusted);
    }
    fmt::print(out, "  {:.1f} s wall, CPU per copy {:.1f} s (median)\nwrote {}\n", ensemble_wall,
               Quantile(sorted_cpu, 0.5), file.string());
    const std::filesystem::path out_dir = file.parent_path().empty() ? "." : file.parent_path();
    const FigureOutcome figures = MakeFigures("ensemble.py", file, out_dir);
    if (figures.made) {
      fmt::print(out, "wrote figures (ensemble.py) in {}\n", out_dir.string());
    } else {
      fmt::print(err, "rubcont: warning: {}\n", figures.warning);
    }
    for (std::size_t c = 0; c < copies.size(); ++c) {
      if (copies[c].failed) {
        fmt::print(err, "rubcont: numerical failure: copy {}: {}\n", c, copies[c].points.back().message);
      }
    }
    return failures == 0 ? kExitSuccess : kExitFailure;
  });
}

}  // namespace rubcont
