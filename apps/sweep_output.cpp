#include "apps/sweep_output.h"

#include <cmath>
#include <memory>
#include <stdexcept>

#include <fmt/core.h>
#include <fmt/ostream.h>

#include "apps/atomic_file.h"
#include "solvers/constants.h"

namespace rubcont {
namespace {

std::string Group(SweepDirection direction) { return std::string("/sweeps/") + ToString(direction); }

// The resolved scene without its first line (which names the file it was read from).
std::string SceneBody(const Scene& scene) {
  const std::string resolved = ResolvedSceneToml(scene);
  return resolved.substr(resolved.find('\n') + 1);
}

// Whether the resolved scene `stored_toml` of an earlier file describes the same sweeps as
// `scene`: the same scene apart from the keys that only read the finished speeds (the regime and
// jump rules of sweeps/rub_sweep.h), so that finished speeds can be classified again by other
// rules without integrating them again. A stored scene the current schema rejects is not the same,
// nor one that lacks a key other than those rules: it was written by an earlier version, before
// the key existed, and today's default need not be what its run used (the sweeps' integrator was
// CVODES BDF until 2026-11-26, "explicit" since: such a file read as the same would be labelled
// with the wrong integrator) — unless the key was added with its older behaviour as its default
// (AddedAtOlderBehaviour).
bool SameSweeps(const std::string& stored_toml, const Scene& scene) {
  Scene stored;
  try {
    stored = ParseScene(stored_toml, "stored scene_toml", scene.name);
  } catch (const SceneError&) {
    return false;
  }
  for (const std::string& key : stored.defaulted_keys) {
    if (!IsSweepRule(key) && !AddedAtOlderBehaviour(key)) return false;
  }
  CopySweepRules(scene, stored);
  // The loop's keys do not touch the sweeps (its budget's unit and default changed on 2026-11-30,
  // and a sweep must not be integrated again for that).
  stored.analysis.loop = scene.analysis.loop;
  return SceneBody(stored) == SceneBody(scene);
}

template <class Function>
std::vector<double> PerPoint(const std::vector<SweepPoint>& points, Function&& value) {
  std::vector<double> out;
  out.reserve(points.size());
  for (const SweepPoint& p : points) out.push_back(value(p));
  return out;
}

template <class Function>
std::vector<int> PerPointInt(const std::vector<SweepPoint>& points, Function&& value) {
  std::vector<int> out;
  out.reserve(points.size());
  for (const SweepPoint& p : points) out.push_back(value(p));
  return out;
}

// A channel quantity per point (NaN for failed points, which have no summary).
template <class Function>
std::vector<double> PerChannel(const std::vector<SweepPoint>& points, std::size_t k, Function&& value) {
  return PerPoint(points, [&](const SweepPoint& p) {
    return k < p.channels.size() ? value(p.channels[k]) : kNaN;
  });
}

void WriteAttributes(ResultWriter& writer, const std::string& group, const Scene& scene, const SweepRun& run) {
  const SweepOptions& o = run.stepper().options();
  writer.SetAttribute(group, "direction", ToString(run.direction()));
  writer.SetAttribute(group, "level", ToString(Level::kL3));
  writer.SetAttribute(group, "speeds_planned", static_cast<double>(o.parameters.size()));
  // Every [analysis.sweep] key under its own name (a range as two numbers; `integrator` the
  // scene's choice), then the methods it stands for.
  for (const auto& [key, value] : SweepKeyValues(scene)) {
    if (const auto* text = std::get_if<std::string>(&value)) {
      writer.SetAttribute(group, key, *text);
    } else if (const auto& values = std::get<std::vector<double>>(value); values.size() == 1) {
      writer.SetAttribute(group, key, values[0]);
    } else {
      writer.SetAttribute(group, key, values);
    }
  }
  writer.SetAttribute(group, "integrator_method", ToString(o.integrator.method));
  writer.SetAttribute(group, "max_order", static_cast<double>(o.integrator.max_order));
  if (o.intermittent_integrator) {
    writer.SetAttribute(group, "intermittent_integrator_method",
                        ToString(o.intermittent_integrator->method));
  }
  writer.SetAttribute(group, "velocity_scale", run.structure().law.velocity_scale);
}

void WritePoints(ResultWriter& writer, const std::string& group, const Scene& scene, const SweepRun& run,
                 const std::vector<SweepPoint>& points) {
  const RubStructure& structure = run.structure();
  writer.CreateGroup(group);
  WriteAttributes(writer, group, scene, run);
  const RubSweepRegimes regimes = ClassifySweep(structure, points, run.options().regimes);
  double wall = 0.0;
  for (const SweepPoint& p : points) wall += p.wall_seconds;
  writer.SetAttribute(group, "wall_seconds", wall);
  const bool failed = !points.empty() && points.back().status == SweepPointStatus::kIntegrationFailure;
  const bool complete = points.size() == run.stepper().options().parameters.size() && !failed;
  writer.SetAttribute(group, "status", failed ? "failure" : complete ? "complete" : "partial");

  writer.WriteDoubles(group + "/speed_rpm",
                      PerPoint(points, [](const SweepPoint& p) { return RadPerSecondToRpm(p.parameter); }));
  writer.SetDimensionScales(group, "speed_rpm");  // xarray: speed is the coordinate
  for (std::size_t k = 0; k < structure.contacts.size(); ++k) {
    const std::string side = "_" + structure.contacts[k].name;
    writer.WriteDoubles(group + "/precession_hz" + side, regimes.precession_hz[k]);
    writer.WriteDoubles(group + "/precession_amplitude" + side, PerChannel(points, k, [](const ChannelSummary& c) {
      return c.peak.found ? c.peak.amplitude : kNaN;
    }));
    const int V = kSlipVelocityMeasure, N = kNormalForceMeasure;
    writer.WriteDoubles(group + "/slip_velocity" + side,
                        PerChannel(points, k, [&](const ChannelSummary& c) { return c.measures[V].mean; }));
    writer.WriteDoubles(group + "/slip_velocity_min" + side,
                        PerChannel(points, k, [&](const ChannelSummary& c) { return c.measures[V].min; }));
    writer.WriteDoubles(group + "/slip_velocity_max" + side,
                        PerChannel(points, k, [&](const ChannelSummary& c) { return c.measures[V].max; }));
    writer.WriteDoubles(group + "/slip_ratio" + side, regimes.slip_ratio[k]);
    writer.WriteDoubles(group + "/normal_force" + side,
                        PerChannel(points, k, [&](const ChannelSummary& c) { return c.measures[N].mean; }));
    writer.WriteDoubles(group + "/normal_force_min" + side,
                        PerChannel(points, k, [&](const ChannelSummary& c) { return c.measures[N].min; }));
    writer.WriteDoubles(group + "/normal_force_max" + side,
                        PerChannel(points, k, [&](const ChannelSummary& c) { return c.measures[N].max; }));
    writer.WriteDoubles(group + "/penetration_max" + side, PerChannel(points, k, [](const ChannelSummary& c) {
      return c.measures[kPenetrationMeasure].max;
    }));
    writer.WriteDoubles(group + "/contact_fraction" + side,
                        PerChannel(points, k, [](const ChannelSummary& c) { return c.active_fraction; }));
    writer.WriteDoubles(group + "/orbit_radius" + side,
                        PerChannel(points, k, [](const ChannelSummary& c) { return c.mean_modulus; }));
    std::vector<std::string> regime;
    for (RubRegime r : regimes.regime[k]) regime.push_back(ToString(r));
    writer.WriteStrings(group + "/regime" + side, regime);

    const Vector& band = run.stepper().BandFrequencies();
    Matrix spectrum = Matrix::Constant(static_cast<Index>(points.size()), band.size(), kNaN);
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (k < points[i].channels.size())
        spectrum.row(static_cast<Index>(i)) = points[i].channels[k].spectrum.transpose();
    }
    writer.WriteMatrix(group + "/spectrum_magnitude" + side, spectrum);
    writer.NameSecondAxis(group + "/spectrum_magnitude" + side, "spectrum_frequency_hz");
  }
  writer.WriteDoubles(group + "/spectrum_frequency_hz", run.stepper().BandFrequencies());

  std::vector<std::string> status, message;
  for (const SweepPoint& p : points) {
    status.push_back(ToString(p.status));
    message.push_back(p.message);
  }
  writer.WriteStrings(group + "/status", status);
  writer.WriteStrings(group + "/message", message);
  writer.WriteStrings(group + "/untrusted", regimes.untrusted);
  writer.WriteInts(group + "/settled", PerPointInt(points, [](const SweepPoint& p) {
    return p.status == SweepPointStatus::kSettled ? 1 : 0;
  }));
  writer.WriteInts(group + "/windows", PerPointInt(points, [](const SweepPoint& p) { return p.windows; }));
  writer.WriteInts(group + "/intermittent_windows",
                   PerPointInt(points, [](const SweepPoint& p) { return p.intermittent_windows; }));
  writer.WriteDoubles(group + "/simulated_time", PerPoint(points, [](const SweepPoint& p) { return p.simulated_time; }));
  writer.WriteDoubles(group + "/spectrum_change", PerPoint(points, [](const SweepPoint& p) { return p.spectrum_change; }));
  writer.WriteDoubles(group + "/frequency_change", PerPoint(points, [](const SweepPoint& p) { return p.frequency_change; }));
  writer.WriteDoubles(group + "/wall_seconds", PerPoint(points, [](const SweepPoint& p) { return p.wall_seconds; }));
  auto counter = [&](const char* name, long IntegrationStatistics::*field) {
    writer.WriteDoubles(group + "/" + name, PerPoint(points, [&](const SweepPoint& p) {
      return static_cast<double>(p.statistics.*field);
    }));
  };
  counter("steps", &IntegrationStatistics::steps);
  counter("rhs_evaluations", &IntegrationStatistics::rhs_evaluations);
  counter("jacobian_evaluations", &IntegrationStatistics::jacobian_evaluations);
  counter("linear_solver_setups", &IntegrationStatistics::linear_solver_setups);
  counter("newton_iterations", &IntegrationStatistics::nonlinear_iterations);
  counter("error_test_failures", &IntegrationStatistics::error_test_failures);
  counter("convergence_failures", &IntegrationStatistics::nonlinear_convergence_failures);

  const std::string jumps = group + "/jumps";
  std::vector<std::string> contact, kind;
  std::vector<double> from_rpm, to_rpm, from_hz, to_hz;
  std::vector<int> settled, trusted;
  for (const RubSweepJump& j : regimes.jumps) {
    contact.push_back(structure.contacts[static_cast<std::size_t>(j.contact)].name);
    kind.push_back(ToString(j.kind));
    from_rpm.push_back(j.speed_from_rpm);
    to_rpm.push_back(j.speed_to_rpm);
    from_hz.push_back(j.precession_from_hz);
    to_hz.push_back(j.precession_to_hz);
    settled.push_back(j.settled ? 1 : 0);
    trusted.push_back(j.trusted ? 1 : 0);
  }
  writer.WriteStrings(jumps + "/contact", contact);
  writer.WriteStrings(jumps + "/kind", kind);
  writer.WriteDoubles(jumps + "/speed_from_rpm", from_rpm);
  writer.WriteDoubles(jumps + "/speed_to_rpm", to_rpm);
  writer.WriteDoubles(jumps + "/precession_from_hz", from_hz);
  writer.WriteDoubles(jumps + "/precession_to_hz", to_hz);
  writer.WriteInts(jumps + "/settled", settled);
  writer.WriteInts(jumps + "/trusted", trusted);
}

SweepPointStatus ParseStatus(const std::string& text) {
  for (SweepPointStatus s : {SweepPointStatus::kSettled, SweepPointStatus::kNotSettled,
                             SweepPointStatus::kIntegrationFailure})
    if (text == ToString(s)) return s;
  throw std::runtime_error("sweep result: unknown point status \"" + text + "\"");
}

}  // namespace

SweepDirection ParseDirection(const char* option, const std::string& value) {
  if (value == "up") return SweepDirection::kUp;
  if (value == "down") return SweepDirection::kDown;
  throw std::invalid_argument(fmt::format("--{} = {}: must be up or down", option, value));
}

void CheckCopyOptions(int copies, double window, double duration, double perturbation, int threads) {
  auto fail = [](const char* option, const auto& value, const char* rule) {
    throw std::invalid_argument(fmt::format("--{} = {}: {}", option, value, rule));
  };
  if (copies < 1 || copies > 100000) fail("copies", copies, "must be in 1 … 100000");
  if (!(window > 0.0) || !std::isfinite(window)) fail("window", window, "must be positive");
  if (!(duration >= 2.0 * window) || !std::isfinite(duration)) fail("duration", duration, "must be at least two windows");
  if (!(perturbation >= 0.0) || !std::isfinite(perturbation)) {
    fail("perturbation", perturbation, "must be finite and non-negative");
  }
  if (threads < 0) fail("threads", threads, "must be non-negative (0: one per core)");
}

ArrivalTarget ParseUntil(const RubStructure& structure, const std::string& regime, double above_hz,
                         const std::string& contacts) {
  ArrivalTarget target;
  std::string names;
  for (std::size_t k = 0; k < structure.contacts.size(); ++k) {
    names += ", " + structure.contacts[k].name;
    if (contacts == structure.contacts[k].name) {
      target.contacts = ArrivalContacts::kOne;
      target.contact = static_cast<int>(k);
    }
  }
  if (contacts == "every" || contacts == "any") {
    target.contacts = contacts == "every" ? ArrivalContacts::kEvery : ArrivalContacts::kAny;
  } else if (target.contact < 0) {
    throw std::invalid_argument(fmt::format("--until-contacts = {}: must be every, any{}", contacts, names));
  }
  if (!(above_hz >= 0.0) || !std::isfinite(above_hz)) {
    throw std::invalid_argument(fmt::format("--until-above = {}: must be a precession in Hz (0: by --until)", above_hz));
  }
  if (above_hz > 0.0) target.precession_above_hz = above_hz;
  const std::optional<RubRegime> named = RubRegimeNamed(regime);
  if (named && *named != RubRegime::kUnknown) {  // "unknown" (a failed speed) is no target
    target.regime = *named;
    return target;
  }
  throw std::invalid_argument(fmt::format("--until = {}: must be whirl, whip, intermittent or no_contact", regime));
}

std::string UntilContacts(const RubStructure& structure, const ArrivalTarget& target) {
  switch (target.contacts) {
    case ArrivalContacts::kEvery: return "every";
    case ArrivalContacts::kAny: return "any";
    case ArrivalContacts::kOne: return structure.contacts.at(static_cast<std::size_t>(target.contact)).name;
  }
  return "?";
}

double UntilAboveHz(const ArrivalTarget& target) {
  return std::isnan(target.precession_above_hz) ? 0.0 : target.precession_above_hz;
}

std::function<void(const SweepRun& run)> PrintApproachProgress(std::ostream& err, const std::string& tag,
                                                               SteadyClock::time_point start) {
  return [&err, tag, start](const SweepRun& run) {
    fmt::print(err, "rubcont: [{}] approach {} {:.1f} rpm ({}/{}, {:.1f} s)\n", tag,
               ToString(run.direction()), RadPerSecondToRpm(run.stepper().points().back().parameter),
               run.stepper().points().size(), run.stepper().options().parameters.size(),
               SecondsSince(start));
    err.flush();
  };
}

void WriteSweep(ResultWriter& writer, const Scene& scene, const SweepRun& run) {
  WritePoints(writer, Group(run.direction()), scene, run, run.stepper().points());
}

std::vector<SweepPoint> ReadSweepPoints(const ResultReader& reader, SweepDirection direction) {
  const std::string group = Group(direction);
  if (!reader.Exists(group)) throw std::runtime_error("sweep result: no group " + group);
  const std::vector<double> speed = reader.ReadDoubles(group + "/speed_rpm");
  const std::size_t n = speed.size();
  auto doubles = [&](const std::string& name) {
    std::vector<double> v = reader.ReadDoubles(group + "/" + name);
    if (v.size() != n) throw std::runtime_error(fmt::format("sweep result: {}/{} has {} values for {} speeds", group, name, v.size(), n));
    return v;
  };
  const std::vector<std::string> status = reader.ReadStrings(group + "/status");
  const std::vector<std::string> message = reader.ReadStrings(group + "/message");
  const std::vector<int> windows = reader.ReadInts(group + "/windows");
  // Files written before the intermittent integrator existed used one integrator throughout.
  const std::vector<int> intermittent_windows =
      reader.Exists(group + "/intermittent_windows") ? reader.ReadInts(group + "/intermittent_windows")
                                                     : std::vector<int>(n, 0);
  if (status.size() != n || message.size() != n || windows.size() != n ||
      intermittent_windows.size() != n)
    throw std::runtime_error("sweep result: " + group + ": per-speed lists of different lengths");
  const auto simulated = doubles("simulated_time"), spectrum_change = doubles("spectrum_change"),
             frequency_change = doubles("frequency_change"), wall = doubles("wall_seconds"),
             steps = doubles("steps"), rhs = doubles("rhs_evaluations"),
             jacobians = doubles("jacobian_evaluations"), setups = doubles("linear_solver_setups"),
             newton = doubles("newton_iterations"), error_tests = doubles("error_test_failures"),
             convergence = doubles("convergence_failures");
  std::vector<SweepPoint> points(n);
  for (std::size_t i = 0; i < n; ++i) {
    SweepPoint& p = points[i];
    p.parameter = RpmToRadPerSecond(speed[i]);
    p.status = ParseStatus(status[i]);
    p.message = message[i];
    p.windows = windows[i];
    p.intermittent_windows = intermittent_windows[i];
    p.simulated_time = simulated[i];
    p.spectrum_change = spectrum_change[i];
    p.frequency_change = frequency_change[i];
    p.wall_seconds = wall[i];
    p.statistics.steps = static_cast<long>(steps[i]);
    p.statistics.rhs_evaluations = static_cast<long>(rhs[i]);
    p.statistics.jacobian_evaluations = static_cast<long>(jacobians[i]);
    p.statistics.linear_solver_setups = static_cast<long>(setups[i]);
    p.statistics.nonlinear_iterations = static_cast<long>(newton[i]);
    p.statistics.error_test_failures = static_cast<long>(error_tests[i]);
    p.statistics.nonlinear_convergence_failures = static_cast<long>(convergence[i]);
  }
  for (const char* side : {"left", "right"}) {
    const std::string s = std::string("_") + side;
    const auto bp = doubles("precession_hz" + s), amplitude = doubles("precession_amplitude" + s),
               v = doubles("slip_velocity" + s), v_min = doubles("slip_velocity_min" + s),
               v_max = doubles("slip_velocity_max" + s), f = doubles("normal_force" + s),
               f_min = doubles("normal_force_min" + s), f_max = doubles("normal_force_max" + s),
               fraction = doubles("contact_fraction" + s), radius = doubles("orbit_radius" + s);
    const std::vector<double> depth = reader.Exists(group + "/penetration_max" + s)
                                          ? doubles("penetration_max" + s)
                                          : std::vector<double>(n, kNaN);
    const Matrix spectrum = reader.ReadMatrix(group + "/spectrum_magnitude" + s);
    if (static_cast<std::size_t>(spectrum.rows()) != n)
      throw std::runtime_error("sweep result: " + group + "/spectrum_magnitude" + s + ": wrong row count");
    for (std::size_t i = 0; i < n; ++i) {
      if (points[i].status == SweepPointStatus::kIntegrationFailure) continue;
      ChannelSummary c;
      c.peak.found = !std::isnan(bp[i]);
      c.peak.frequency = c.peak.found ? -bp[i] : 0.0;
      c.peak.amplitude = c.peak.found ? amplitude[i] : 0.0;
      c.active_fraction = fraction[i];
      c.mean_modulus = radius[i];
      c.measures.resize(3);
      c.measures[kSlipVelocityMeasure] = {v[i], v_min[i], v_max[i]};
      c.measures[kNormalForceMeasure] = {f[i], f_min[i], f_max[i]};
      c.measures[kPenetrationMeasure] = {kNaN, kNaN, depth[i]};  // only the largest is kept
      c.spectrum = spectrum.row(static_cast<Index>(i)).transpose();
      points[i].channels.push_back(std::move(c));
    }
  }
  return points;
}

std::optional<std::vector<SweepPoint>> ReadFinishedSweep(const std::filesystem::path& file,
                                                         const Scene& scene, SweepDirection direction) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) return std::nullopt;
  ResultReader reader(file);
  if (!reader.Exists("/sweeps/" + std::string(ToString(direction)))) return std::nullopt;
  if (!SameSweeps(reader.ReadStringAttribute("/", "scene_toml"), scene)) return std::nullopt;
  return ReadSweepPoints(reader, direction);
}

std::filesystem::path CheckpointPath(const std::filesystem::path& h5_file, SweepDirection direction) {
  std::filesystem::path path = h5_file;
  path.replace_filename(h5_file.stem().string() + "." + ToString(direction) + ".checkpoint.h5");
  return path;
}

void WriteSweepCheckpoint(const std::filesystem::path& file, const Scene& scene, const SweepRun& run) {
  std::vector<SweepPoint> points = run.stepper().points();
  if (!points.empty() && points.back().status == SweepPointStatus::kIntegrationFailure) points.pop_back();
  ResultWriter writer(file);
  WriteSceneAttributes(writer, scene);
  WritePoints(writer, Group(run.direction()), scene, run, points);
  writer.WriteDoubles("/checkpoint/state", run.stepper().state());
  writer.SetAttribute("/checkpoint", "direction", ToString(run.direction()));
  writer.SetAttribute("/checkpoint", "next_index", static_cast<double>(points.size()));
  writer.Commit();
}

std::optional<SweepCheckpoint> ReadSweepCheckpoint(const std::filesystem::path& file,
                                                   const Scene& scene, SweepDirection direction) {
  std::error_code ec;
  if (!std::filesystem::exists(file, ec)) return std::nullopt;
  ResultReader reader(file);
  if (!SameSweeps(reader.ReadStringAttribute("/", "scene_toml"), scene)) {
    throw std::invalid_argument(fmt::format(
        "checkpoint {} was written for another scene (or other settings) than {}: delete it or run "
        "without --resume", file.string(), scene.source));
  }
  if (reader.ReadStringAttribute("/checkpoint", "direction") != ToString(direction)) {
    throw std::invalid_argument(fmt::format("checkpoint {} is not for the {} sweep", file.string(),
                                            ToString(direction)));
  }
  SweepCheckpoint checkpoint;
  checkpoint.points = ReadSweepPoints(reader, direction);
  const std::vector<double> state = reader.ReadDoubles("/checkpoint/state");
  checkpoint.state = Eigen::Map<const Vector>(state.data(), static_cast<Index>(state.size()));
  return checkpoint;
}

std::unique_ptr<ResultWriter> OpenStudyResult(const std::filesystem::path& file, const Scene& scene,
                                              const std::string& group) {
  PrepareToWrite(file);
  auto writer = std::make_unique<ResultWriter>(file);
  WriteSceneAttributes(*writer, scene);
  writer->SetAttribute("/", "level", ToString(ResultLevel(scene, Level::kL3)));
  writer->CreateGroup(group);
  return writer;
}

void WriteApproachSpeeds(ResultWriter& writer, const std::string& group, const SweepApproach& approach) {
  const std::vector<double>& speeds = approach.speeds;
  writer.SetAttribute(group, "approach_from_rpm", speeds.empty() ? kNaN : RadPerSecondToRpm(speeds.front()));
  writer.SetAttribute(group, "approach_to_rpm", speeds.empty() ? kNaN : RadPerSecondToRpm(speeds.back()));
}

void WriteJumpTable(ResultWriter& writer, const std::vector<PredictedJump>& rows) {
  const std::string g = "/sweeps/jump_table";
  writer.CreateGroup(g);
  writer.SetAttribute(g, "level",
                      fmt::format("{} jumps, {} bifurcations", ToString(Level::kL3), ToString(Level::kL1)));
  writer.SetAttribute(g, "rule",
                      "a sweep state lies on a branch when the same contacts touch and each "
                      "touching contact's BP is within max(1 Hz, 1 %) of the branch's precession "
                      "at its speed (stable branches first, then the closest normal forces); the "
                      "departure state is tried first, then the "
                      "landing state; the predicting bifurcation is that branch's special point "
                      "nearest the jump's speed interval, within 10 rpm of it (for a whirl <-> "
                      "whip change the contact's tanh knee counts too and wins among equals); "
                      "difference_rpm = middle of the interval minus the bifurcation speed");
  std::vector<std::string> direction, contact, kind, side, branch, bifurcation;
  std::vector<double> from_rpm, to_rpm, from_hz, to_hz, b_rpm, b_hz, difference;
  std::vector<int> stable, settled, trusted;
  for (const PredictedJump& r : rows) {
    direction.push_back(r.direction);
    contact.push_back(r.contact);
    kind.push_back(ToString(r.jump.kind));
    from_rpm.push_back(r.jump.speed_from_rpm);
    to_rpm.push_back(r.jump.speed_to_rpm);
    from_hz.push_back(r.jump.precession_from_hz);
    to_hz.push_back(r.jump.precession_to_hz);
    settled.push_back(r.jump.settled ? 1 : 0);
    trusted.push_back(r.jump.trusted ? 1 : 0);
    side.push_back(r.matched_side);
    branch.push_back(r.branch);
    stable.push_back(r.branch_stable);
    bifurcation.push_back(r.bifurcation);
    b_rpm.push_back(r.bifurcation_speed_rpm);
    b_hz.push_back(r.bifurcation_precession_hz);
    difference.push_back(r.difference_rpm);
  }
  writer.WriteStrings(g + "/direction", direction);
  writer.WriteStrings(g + "/contact", contact);
  writer.WriteStrings(g + "/kind", kind);
  writer.WriteDoubles(g + "/speed_from_rpm", from_rpm);
  writer.WriteDoubles(g + "/speed_to_rpm", to_rpm);
  writer.WriteDoubles(g + "/precession_from_hz", from_hz);
  writer.WriteDoubles(g + "/precession_to_hz", to_hz);
  writer.WriteInts(g + "/settled", settled);
  writer.WriteInts(g + "/trusted", trusted);
  writer.WriteStrings(g + "/matched_side", side);
  writer.WriteStrings(g + "/branch", branch);
  writer.WriteInts(g + "/branch_stable", stable);
  writer.WriteStrings(g + "/bifurcation", bifurcation);
  writer.WriteDoubles(g + "/bifurcation_speed_rpm", b_rpm);
  writer.WriteDoubles(g + "/bifurcation_precession_hz", b_hz);
  writer.WriteDoubles(g + "/difference_rpm", difference);
}

}  // namespace rubcont
