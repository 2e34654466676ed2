#include "apps/ensemble_output.h"

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

void WriteEnsembleResult(const std::filesystem::path& file, const Scene& scene, const RubStructure& structure,
                         const EnsembleStudyResult& result) {
  const EnsembleStudyOptions& o = result.options;
  const std::vector<EnsembleCopy>& copies = result.run.copies;
  const std::vector<RubArrival>& arrivals = result.run.arrivals;
  const std::string g = "/ensemble";
  const std::unique_ptr<ResultWriter> file_writer = OpenStudyResult(file, scene, g);
  ResultWriter& writer = *file_writer;
  writer.SetAttribute(g, "speed_rpm", o.speed_rpm);
  writer.SetAttribute(g, "direction", ToString(o.sweep.direction));
  writer.SetAttribute(g, "copies", static_cast<double>(o.ensemble.copies));
  writer.SetAttribute(g, "duration", o.duration);
  writer.SetAttribute(g, "window", o.window);
  writer.SetAttribute(g, "perturbation", o.ensemble.perturbation);
  writer.SetAttribute(g, "seed", static_cast<double>(o.ensemble.seed));
  writer.SetAttribute(g, "until", ToString(o.target.regime));
  writer.SetAttribute(g, "until_contacts", UntilContacts(structure, o.target));
  writer.SetAttribute(g, "until_above_hz", UntilAboveHz(o.target));
  writer.SetAttribute(g, "arrival", result.arrival);
  writer.SetAttribute(g, "threads", static_cast<double>(o.ensemble.threads));
  writer.SetAttribute(g, "wall_seconds", result.run.wall_seconds);
  WriteApproachSpeeds(writer, g, result.approach);
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
  writer.WriteDoubles(g + "/time_s", result.stretch_end);
  for (std::size_t k = 0; k < structure.contacts.size(); ++k) {
    const std::string side = structure.contacts[k].name;
    writer.SetAttribute(g, "approach_regime_" + side, ToString(result.approach.regimes[k]));
    Matrix bp = Matrix::Constant(o.ensemble.copies, result.stretches, kNaN), fraction = bp, slip = bp, regime = bp;
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
}

void PrintEnsembleSummary(std::ostream& out, const Scene& scene, const RubStructure& structure,
                          const EnsembleStudyResult& result, const std::filesystem::path& file) {
  const EnsembleStudyOptions& o = result.options;
  const std::vector<double>& before = result.approach.speeds;
  const std::vector<double>& time = result.stretch_end;
  std::string from = "rest (the impulse)";
  if (!before.empty()) {
    from = fmt::format("the {} sweep {:g} → {:g} rpm ({})", ToString(o.sweep.direction),
                       RadPerSecondToRpm(before.front()), RadPerSecondToRpm(before.back()),
                       RegimeList(structure, result.approach.regimes));
  }
  fmt::print(out, "scene {} from {}\n[ensemble] L3: {} copies at {:g} rpm for {:.4g} s from {}, "
                  "perturbed by {:g} × each state's scale (seed {}):\n",
             scene.name, scene.source, o.ensemble.copies, o.speed_rpm, time.empty() ? o.duration : time.back(),
             from, o.ensemble.perturbation, o.ensemble.seed);
  fmt::print(out, "  {} of {} reached {}", result.reached, result.run.copies.size(), result.arrival);
  if (result.reached > 0) {
    fmt::print(out, ", after {:.2f} s (min) / {:.2f} / {:.2f} / {:.2f} (quartiles) / {:.2f} s (max), "
                    "in stretches of {:.4g} s",
               result.arrival_min, result.arrival_lower_quartile, result.arrival_median,
               result.arrival_upper_quartile, result.arrival_max, time.empty() ? 2.0 * o.window : time.front());
  }
  fmt::print(out, "; {} failed\n", result.failed);
  if (result.untrusted > 0) {
    fmt::print(out, "  {} untrusted (counted all the same; a contact penetrated beyond "
                    "[analysis.sweep] max_penetration before it arrived), the first copy {}: {}\n",
               result.untrusted, result.first_untrusted_copy, result.first_untrusted);
  }
  fmt::print(out, "  {:.1f} s wall, CPU per copy {:.1f} s (median)\nwrote {}\n", result.run.wall_seconds,
             result.median_cpu_seconds, file.string());
}

void PrintEnsembleFailures(std::ostream& err, const EnsembleStudyResult& result) {
  const std::vector<EnsembleCopy>& copies = result.run.copies;
  for (std::size_t c = 0; c < copies.size(); ++c) {
    if (copies[c].failed) {
      fmt::print(err, "rubcont: numerical failure: copy {}: {}\n", c, copies[c].points.back().message);
    }
  }
}

EnsembleStudyProgress PrintEnsembleProgress(std::ostream& err, SteadyClock::time_point start) {
  // The copies' seconds count from the end of the approach (from `start` without one).
  auto copies_start = std::make_shared<SteadyClock::time_point>(start);
  EnsembleStudyProgress progress;
  const auto approach = PrintApproachProgress(err, "ensemble", start);
  progress.approach = [approach, copies_start](const SweepRun& run) {
    approach(run);
    *copies_start = SteadyClock::now();
  };
  progress.copies = [&err, copies_start](int done, int total) {
    fmt::print(err, "rubcont: [ensemble] copy {}/{} ({:.1f} s)\n", done, total, SecondsSince(*copies_start));
    err.flush();
  };
  return progress;
}

}  // namespace rubcont
