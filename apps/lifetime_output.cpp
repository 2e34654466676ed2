#include "apps/lifetime_output.h"

#include <cmath>
#include <memory>
#include <optional>
#include <ostream>
#include <stdexcept>
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

// The crisis law's line: p_c with its interval, saying which ends the likelihood does not bound.
void PrintCrisis(std::ostream& out, const CrisisFit& fit, CrisisSide side) {
  if (fit.status != CrisisStatus::kLocated) {
    fmt::print(out, "  crisis law: {} ({})\n", ToString(fit.status), fit.message);
    return;
  }
  // Towards the speeds with escapes the interval is open up to the first of them, away from them
  // down to the end of the search range.
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
             above ? "p − p_c" : "p_c − p", fit.amplitude, fit.exponent, fit.critical, interval,
             fit.message.empty() ? "" : "; " + fit.message);
}

}  // namespace

void WriteLifetimeResult(const std::filesystem::path& file, const Scene& scene, const RubStructure& structure,
                         const LifetimeStudyResult& result) {
  const LifetimeStudyOptions& o = result.options;
  const EscapeObservations& first = result.escapes.front().observations;
  const std::string g = "/lifetime";
  const std::unique_ptr<ResultWriter> file_writer = OpenStudyResult(file, scene, g);
  ResultWriter& writer = *file_writer;
  writer.SetAttribute(g, "direction", ToString(o.sweep.direction));
  writer.SetAttribute(g, "copies", static_cast<double>(o.sampling.ensemble.copies));
  writer.SetAttribute(g, "duration", first.duration);
  writer.SetAttribute(g, "window", o.sampling.window);
  writer.SetAttribute(g, "stretch", first.stretch);
  writer.SetAttribute(g, "perturbation", o.sampling.ensemble.perturbation);
  writer.SetAttribute(g, "seed", static_cast<double>(o.sampling.ensemble.seed));
  writer.SetAttribute(g, "until", ToString(o.target.regime));
  writer.SetAttribute(g, "until_contacts", UntilContacts(structure, o.target));
  writer.SetAttribute(g, "until_above_hz", UntilAboveHz(o.target));
  writer.SetAttribute(g, "arrival", result.arrival);
  writer.SetAttribute(g, "threads", static_cast<double>(o.sampling.ensemble.threads));
  writer.SetAttribute(g, "wall_seconds", result.wall_seconds);
  writer.SetAttribute(g, "cpu_seconds", result.cpu_seconds);
  WriteApproachSpeeds(writer, g, result.approach);
  std::vector<double> rate, lower, upper;
  std::vector<int> escapes, stayed, failed, untrusted;
  std::vector<std::string> status;
  Matrix arrival = Matrix::Constant(static_cast<Index>(result.escapes.size()), o.sampling.ensemble.copies, kNaN);
  for (std::size_t i = 0; i < result.escapes.size(); ++i) {
    const SpeedEscapes& e = result.escapes[i];
    const EscapeRate& r = result.rates[i];
    rate.push_back(r.rate);
    lower.push_back(r.lower);
    upper.push_back(r.upper);
    escapes.push_back(r.escapes);
    stayed.push_back(e.observations.stayed);
    failed.push_back(e.failed);
    untrusted.push_back(e.untrusted);
    status.push_back(ToString(r.status));
    for (std::size_t c = 0; c < e.arrival_time.size(); ++c) {
      arrival(static_cast<Index>(i), static_cast<Index>(c)) = e.arrival_time[c];
    }
  }
  writer.WriteDoubles(g + "/speed_rpm", result.speeds_rpm);
  writer.WriteInts(g + "/escapes", escapes);
  writer.WriteInts(g + "/stayed", stayed);
  writer.WriteInts(g + "/failed", failed);
  writer.WriteInts(g + "/untrusted", untrusted);
  writer.WriteDoubles(g + "/escape_rate", rate);
  writer.WriteDoubles(g + "/rate_lower", lower);
  writer.WriteDoubles(g + "/rate_upper", upper);
  writer.WriteStrings(g + "/rate_status", status);
  writer.WriteMatrix(g + "/arrival_time_s", arrival);
  const CrisisFit& fit = result.crisis;
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
  if (o.check_copies > 0) {
    const CheckSweeps& check = result.check;
    const std::string k = g + "/check";
    writer.CreateGroup(k);
    writer.SetAttribute(k, "dwell", check.dwell);
    writer.SetAttribute(k, "step_rpm", o.check_step_rpm);
    writer.WriteDoubles(k + "/speed_rpm", check.speeds_rpm);
    writer.WriteDoubles(k + "/predicted_leave_probability",
                        result.predicted.probability.empty() ? std::vector<double>(check.speeds_rpm.size(), kNaN)
                                                             : result.predicted.probability);
    writer.WriteDoubles(k + "/jump_speed_rpm", check.leave_speed_rpm);
    writer.WriteDoubles(k + "/jump_time_s", check.leave_time);
  }
  writer.Commit();
}

std::filesystem::path LifetimeCheckpointPath(const std::filesystem::path& h5_file) {
  std::filesystem::path path = h5_file;
  path.replace_filename(h5_file.stem().string() + ".checkpoint.h5");
  return path;
}

void WriteLifetimeCheckpoint(const std::filesystem::path& file, const Scene& scene, const std::string& request,
                             const SweepApproach& approach, const std::vector<SpeedEscapes>& escapes) {
  ResultWriter writer(file);
  WriteSceneAttributes(writer, scene);
  const std::string g = "/checkpoint";
  writer.CreateGroup(g);
  writer.SetAttribute(g, "request", request);
  const std::string a = g + "/approach";
  writer.CreateGroup(a);
  writer.SetAttribute(a, "message", approach.message);
  writer.WriteDoubles(a + "/state", approach.state);
  writer.WriteDoubles(a + "/speed_rad_s", approach.speeds);
  std::vector<std::string> regimes;
  for (RubRegime r : approach.regimes) regimes.emplace_back(ToString(r));
  writer.WriteStrings(a + "/regimes", regimes);
  for (std::size_t i = 0; i < escapes.size(); ++i) {
    const SpeedEscapes& e = escapes[i];
    const std::string s = fmt::format("{}/speed{}", g, i);
    writer.CreateGroup(s);
    writer.SetAttribute(s, "speed_rpm", e.observations.parameter);
    writer.SetAttribute(s, "stretch", e.observations.stretch);
    writer.SetAttribute(s, "duration", e.observations.duration);
    writer.SetAttribute(s, "stayed", static_cast<double>(e.observations.stayed));
    writer.SetAttribute(s, "failed", static_cast<double>(e.failed));
    writer.SetAttribute(s, "untrusted", static_cast<double>(e.untrusted));
    writer.SetAttribute(s, "first_untrusted_copy", static_cast<double>(e.first_untrusted_copy));
    writer.SetAttribute(s, "first_untrusted", e.first_untrusted);
    writer.SetAttribute(s, "wall_seconds", e.wall_seconds);
    writer.WriteInts(s + "/escape_stretch", e.observations.escape_stretch);
    writer.WriteDoubles(s + "/arrival_time_s", e.arrival_time);
    std::vector<int> copies;
    std::vector<std::string> messages;
    for (const CopyFailure& f : e.failures) {
      copies.push_back(f.copy);
      messages.push_back(f.message);
    }
    writer.WriteInts(s + "/failure_copy", copies);
    writer.WriteStrings(s + "/failure_message", messages);
  }
  writer.Commit();
}

std::optional<LifetimeStudyStart> ReadLifetimeCheckpoint(const std::filesystem::path& file, const Scene& scene,
                                                         const std::string& request) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) return std::nullopt;
  const ResultReader reader(file);
  const std::string g = "/checkpoint";
  if (reader.ReadStringAttribute("/", "scene_toml") != ResolvedSceneToml(scene) ||
      reader.ReadStringAttribute(g, "request") != request) {
    throw std::invalid_argument(fmt::format(
        "checkpoint {} was written for another scene or other options than this lifetime study of {} "
        "(it holds: {}): --fresh starts again and overwrites it",
        file.string(), scene.source, reader.ReadStringAttribute(g, "request")));
  }
  LifetimeStudyStart start;
  const std::string a = g + "/approach";
  start.approach.message = reader.ReadStringAttribute(a, "message");
  const std::vector<double> state = reader.ReadDoubles(a + "/state");
  start.approach.state = Eigen::Map<const Vector>(state.data(), static_cast<Index>(state.size()));
  start.approach.speeds = reader.ReadDoubles(a + "/speed_rad_s");
  for (const std::string& name : reader.ReadStrings(a + "/regimes")) {
    const std::optional<RubRegime> regime = RubRegimeNamed(name);
    if (!regime) throw std::runtime_error(fmt::format("{}: {}/regimes: \"{}\" is no regime", file.string(), a, name));
    start.approach.regimes.push_back(*regime);
  }
  for (std::size_t i = 0;; ++i) {
    const std::string s = fmt::format("{}/speed{}", g, i);
    if (!reader.Exists(s)) break;
    SpeedEscapes e;
    auto count = [&](const char* name) { return static_cast<int>(reader.ReadDoubleAttribute(s, name)); };
    e.observations.parameter = reader.ReadDoubleAttribute(s, "speed_rpm");
    e.observations.stretch = reader.ReadDoubleAttribute(s, "stretch");
    e.observations.duration = reader.ReadDoubleAttribute(s, "duration");
    e.observations.stayed = count("stayed");
    e.failed = count("failed");
    e.untrusted = count("untrusted");
    e.first_untrusted_copy = count("first_untrusted_copy");
    e.first_untrusted = reader.ReadStringAttribute(s, "first_untrusted");
    e.wall_seconds = reader.ReadDoubleAttribute(s, "wall_seconds");
    e.observations.escape_stretch = reader.ReadInts(s + "/escape_stretch");
    e.arrival_time = reader.ReadDoubles(s + "/arrival_time_s");
    const std::vector<int> copies = reader.ReadInts(s + "/failure_copy");
    const std::vector<std::string> messages = reader.ReadStrings(s + "/failure_message");
    if (copies.size() != messages.size()) {
      throw std::runtime_error(fmt::format("{}: {}: {} failed copies but {} messages", file.string(), s,
                                           copies.size(), messages.size()));
    }
    for (std::size_t c = 0; c < copies.size(); ++c) e.failures.push_back({copies[c], messages[c]});
    start.escapes.push_back(std::move(e));
  }
  return start;
}

void PrintLifetimeSummary(std::ostream& out, const Scene& scene, const RubStructure& structure,
                          const LifetimeStudyResult& result, const std::filesystem::path& file) {
  const LifetimeStudyOptions& o = result.options;
  const EscapeObservations& first = result.escapes.front().observations;
  fmt::print(out, "scene {} from {}\n[lifetime] L3: {} copies per speed for {:.4g} s (stretches of {:.4g} s), "
                  "from the {} sweep's state at {} ({}), until {}:\n",
             scene.name, scene.source, o.sampling.ensemble.copies, first.duration, first.stretch,
             ToString(o.sweep.direction),
             result.approach.speeds.empty()
                 ? std::string("rest (the impulse)")
                 : fmt::format("{:g} rpm", RadPerSecondToRpm(result.approach.speeds.back())),
             RegimeList(structure, result.approach.regimes), result.arrival);
  std::string first_untrusted;  // where, and why
  for (std::size_t i = 0; i < result.rates.size(); ++i) {
    const EscapeRate& r = result.rates[i];
    const SpeedEscapes& e = result.escapes[i];
    fmt::print(out, "  {:7g} rpm: {:3} of {} left", result.speeds_rpm[i], r.escapes, r.copies);
    if (r.status == EscapeRateStatus::kEstimated) {
      fmt::print(out, ", κ = {:.3g} /s [{:.3g}, {:.3g}], mean lifetime {:.3g} s", r.rate, r.lower, r.upper, 1.0 / r.rate);
    } else if (r.status == EscapeRateStatus::kNoEscape) {
      fmt::print(out, ", κ < {:.3g} /s (mean lifetime > {:.3g} s)", r.upper, 1.0 / r.upper);
    } else {
      fmt::print(out, ", all in the first stretch: κ > {:.3g} /s", r.lower);
    }
    fmt::print(out, "{}{}\n", e.failed ? fmt::format("; {} failed", e.failed) : std::string(),
               e.untrusted ? fmt::format("; {} untrusted", e.untrusted) : std::string());
    if (first_untrusted.empty() && e.untrusted > 0) {
      first_untrusted = fmt::format("{:g} rpm, copy {}: {}", result.speeds_rpm[i], e.first_untrusted_copy,
                                    e.first_untrusted);
    }
  }
  if (!first_untrusted.empty()) {
    fmt::print(out, "  untrusted copies (counted all the same; a contact penetrated beyond "
                    "[analysis.sweep] max_penetration before it arrived): the first at {}\n",
               first_untrusted);
  }
  PrintCrisis(out, result.crisis, result.side);
  if (o.check_copies > 0) {
    const CheckSweeps& check = result.check;
    fmt::print(out, "  check: {} sweeps {:g} → {:g} rpm in {:g} rpm steps, {:.4g} s per speed, left at:",
               o.check_copies, o.from_rpm, o.to_rpm, o.check_step_rpm, check.dwell);
    for (double s : check.leave_speed_rpm) {
      fmt::print(out, " {}", std::isnan(s) ? std::string("(stayed)") : fmt::format("{:g}", s));
    }
    fmt::print(out, " rpm\n");
    if (!result.predicted.probability.empty()) {
      auto text = [](double s) { return std::isnan(s) ? std::string("beyond the range") : fmt::format("{:g} rpm", s); };
      fmt::print(out, "  predicted by the crisis law for this schedule: leaves at {} (median), 90 % between {} and {}\n",
                 text(result.predicted.median_rpm), text(result.predicted.low_rpm), text(result.predicted.high_rpm));
    }
  }
  fmt::print(out, "  {:.1f} s wall, {:.1f} s CPU\nwrote {}\n", result.wall_seconds, result.cpu_seconds, file.string());
}

void PrintLifetimeFailures(std::ostream& err, const LifetimeStudyResult& result) {
  for (const SpeedEscapes& e : result.escapes) {
    for (const CopyFailure& f : e.failures) {
      fmt::print(err, "rubcont: numerical failure: {:g} rpm, copy {}: {}\n", e.observations.parameter, f.copy,
                 f.message);
    }
  }
  for (const CopyFailure& f : result.check.failures) {
    fmt::print(err, "rubcont: numerical failure: check sweep {}: {}\n", f.copy, f.message);
  }
}

LifetimeStudyProgress PrintLifetimeProgress(std::ostream& err, SteadyClock::time_point start) {
  LifetimeStudyProgress progress;
  progress.approach = PrintApproachProgress(err, "lifetime", start);
  progress.copies = [&err, start](double speed_rpm, int done, int total) {
    const std::string what = std::isnan(speed_rpm) ? std::string("check sweep") : fmt::format("{:g} rpm", speed_rpm);
    fmt::print(err, "rubcont: [lifetime] {} copy {}/{} ({:.1f} s)\n", what, done, total, SecondsSince(start));
    err.flush();
  };
  progress.speed = [&err](const SpeedEscapes& escapes, const EscapeRate& rate) {
    fmt::print(err, "rubcont: [lifetime] {:g} rpm: {} of {} left, κ = {:.4g} /s\n", escapes.observations.parameter,
               escapes.observations.escape_stretch.size(), escapes.arrival_time.size(), rate.rate);
  };
  return progress;
}

}  // namespace rubcont
