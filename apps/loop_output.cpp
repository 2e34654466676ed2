#include "apps/loop_output.h"

#include <algorithm>
#include <cmath>
#include <memory>
#include <mutex>
#include <ostream>
#include <set>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "apps/branch_output.h"
#include "apps/hdf5_file.h"
#include "apps/level.h"
#include "apps/orbit_output.h"
#include "apps/stage_options.h"
#include "apps/sweep_output.h"
#include "models/units.h"
#include "solvers/constants.h"

namespace rubcont {
namespace {

// The levels that decided corners, "L1, L3"; a flexible scene's as L4 (…).
std::string Levels(const Scene& scene, const LoopResult& result) {
  std::set<std::string> levels;
  for (const LoopCorner& c : result.corners)
    if (!c.level.empty()) levels.insert(c.level);
  std::string s;
  for (const std::string& l : levels) s += (s.empty() ? "" : ", ") + l;
  return scene.flexible.enabled && !s.empty() ? "L4 (" + s + " on the flexible structure)" : s;
}

void WriteRun(ResultWriter& writer, const std::string& group, const RubStructure& structure, const LoopRun& run) {
  writer.CreateGroup(group);
  writer.SetAttribute(group, "end", run.end);
  writer.SetAttribute(group, "message", run.message);
  writer.SetAttribute(group, "cpu_seconds", run.cpu_seconds);
  writer.WriteDoubles(group + "/schedule_rpm", run.schedule_rpm);
  std::vector<double> speed;
  std::vector<int> settled;
  for (const SweepPoint& p : run.points) {
    speed.push_back(RadPerSecondToRpm(p.parameter));
    settled.push_back(p.status == SweepPointStatus::kSettled ? 1 : 0);
  }
  writer.WriteDoubles(group + "/speed_rpm", speed);
  writer.WriteInts(group + "/settled", settled);
  for (std::size_t k = 0; k < structure.contacts.size(); ++k) {
    const std::string side = "_" + structure.contacts[k].name;
    std::vector<std::string> regime;
    std::vector<double> fraction;
    for (std::size_t i = 0; i < run.points.size(); ++i) {
      regime.push_back(ToString(run.regimes.regime[k][i]));
      fraction.push_back(ContactTimeShare(run.points[i], k));
    }
    writer.WriteStrings(group + "/regime" + side, regime);
    writer.WriteDoubles(group + "/precession_hz" + side, run.regimes.precession_hz[k]);
    writer.WriteDoubles(group + "/contact_fraction" + side, fraction);
  }
  const std::string skips = group + "/skips";
  writer.CreateGroup(skips);
  std::vector<double> from, to;
  std::vector<std::string> branch, limit;
  for (const LoopSkip& s : run.skips) {
    from.push_back(s.from_rpm);
    to.push_back(s.to_rpm);
    branch.push_back(s.branch);
    limit.push_back(s.limit);
  }
  writer.WriteDoubles(skips + "/from_rpm", from);
  writer.WriteDoubles(skips + "/to_rpm", to);
  writer.WriteStrings(skips + "/branch", branch);
  writer.WriteStrings(skips + "/limit", limit);
}

void WriteEscapes(ResultWriter& writer, const std::string& group, const LoopEscapeDesign& record) {
  const EscapeDesign& d = record.design;
  writer.CreateGroup(group);
  writer.SetAttribute(group, "direction", record.direction);
  writer.SetAttribute(group, "seen_from_rpm", record.seen_from_rpm);
  writer.SetAttribute(group, "seen_to_rpm", record.seen_to_rpm);
  writer.SetAttribute(group, "target", record.target);
  writer.SetAttribute(group, "status", ToString(d.status));
  writer.SetAttribute(group, "message", d.message);
  writer.SetAttribute(group, "median_rpm", d.leave.median);
  writer.SetAttribute(group, "low_rpm", d.leave.low);
  writer.SetAttribute(group, "high_rpm", d.leave.high);
  writer.SetAttribute(group, "median_lower_rpm", d.median_lower);
  writer.SetAttribute(group, "median_upper_rpm", d.median_upper);
  writer.SetAttribute(group, "median_open", d.median_open);
  writer.SetAttribute(group, "crisis_status", ToString(d.fit.status));
  writer.SetAttribute(group, "critical_rpm", d.fit.critical);
  writer.SetAttribute(group, "critical_lower_rpm", d.fit.critical_lower);
  writer.SetAttribute(group, "critical_upper_rpm", d.fit.critical_upper);
  writer.SetAttribute(group, "lower_bounded", d.fit.lower_bounded ? 1.0 : 0.0);
  writer.SetAttribute(group, "upper_bounded", d.fit.upper_bounded ? 1.0 : 0.0);
  writer.SetAttribute(group, "exponent", d.fit.exponent);
  writer.SetAttribute(group, "amplitude", d.fit.amplitude);
  writer.SetAttribute(group, "cost_g_work_units", d.cost);
  writer.SetAttribute(group, "rounds", static_cast<double>(d.rounds));
  std::vector<double> speed, duration, stretch, rate, lower, upper;
  std::vector<int> copies, escapes, stayed, escape_stretch;
  for (const EscapeObservations& o : d.observations) {
    stretch.push_back(o.stretch);
    escape_stretch.insert(escape_stretch.end(), o.escape_stretch.begin(), o.escape_stretch.end());
    const EscapeRate r = EstimateEscapeRate(o);
    speed.push_back(o.parameter);
    duration.push_back(o.duration);
    copies.push_back(r.copies);
    escapes.push_back(r.escapes);
    stayed.push_back(o.stayed);
    rate.push_back(r.rate);
    lower.push_back(r.lower);
    upper.push_back(r.upper);
  }
  writer.WriteDoubles(group + "/speed_rpm", speed);
  writer.WriteInts(group + "/copies", copies);
  writer.WriteDoubles(group + "/duration_s", duration);
  writer.WriteDoubles(group + "/stretch_s", stretch);
  writer.WriteInts(group + "/escape_stretch", escape_stretch);
  writer.WriteInts(group + "/escapes", escapes);
  writer.WriteInts(group + "/stayed", stayed);
  writer.WriteDoubles(group + "/rate", rate);
  writer.WriteDoubles(group + "/rate_lower", lower);
  writer.WriteDoubles(group + "/rate_upper", upper);
  writer.WriteStrings(group + "/log", d.log);
}

// L2's question k: /loop/orbits/<k> (its family, period 1) and /loop/orbits/<k>_pd1 (the doubled
// family from the doubling the run meets on it), with what was asked as attributes of <k>.
void WriteOrbits(ResultWriter& writer, const std::string& root, std::size_t k, const LoopOrbits& asked) {
  const std::string name = std::to_string(k);
  const RubTransientOrbits& l2 = asked.orbits;
  const ParameterColumn speed{"speed_rpm", kRpmPerRadPerSecond};
  if (l2.start.converged) {
    WritePeriodicOrbitBranch(writer, name, l2.family.orbits, speed, root);
  } else {
    writer.CreateGroup(root);
    writer.SetAttribute(root, "level", ToString(Level::kL2));
    writer.SetAttribute(root, "parameter_name", speed.name);
    writer.CreateGroup(root + "/" + name);
  }
  const std::string g = root + "/" + name;
  writer.SetAttribute(g, "direction", asked.direction);
  writer.SetAttribute(g, "seen_from_rpm", asked.seen_from_rpm);
  writer.SetAttribute(g, "seen_to_rpm", asked.seen_to_rpm);
  writer.SetAttribute(g, "orbit_rpm", asked.orbit_rpm);
  writer.SetAttribute(g, "route", asked.route ? 1.0 : 0.0);
  writer.SetAttribute(g, "tries", asked.tries);
  writer.SetAttribute(g, "converged", l2.start.converged ? 1.0 : 0.0);
  writer.SetAttribute(g, "start_message", l2.start.message);
  writer.SetAttribute(g, "skeleton", asked.skeleton);
  for (std::size_t d = 0; d < l2.family.doublings.size(); ++d) {
    const OrbitPeriodDoubling& doubling = l2.family.doublings[d];
    const std::string pd = fmt::format("{}_pd{}", name, d + 1);
    if (doubling.ok) {
      WritePeriodicOrbitBranch(writer, pd, doubling.branch, speed, root);
    } else {
      writer.CreateGroup(root + "/" + pd);
    }
    const SpecialPoint& at = l2.family.orbits.branch.special_points[doubling.special_point];
    writer.SetAttribute(root + "/" + pd, "doubling_rpm", RadPerSecondToRpm(at.lambda));
    writer.SetAttribute(root + "/" + pd, "period_doubling_multiplier", doubling.multiplier);
    writer.SetAttribute(root + "/" + pd, "start_message", doubling.message);
  }
}

// "50.74 … 50.96" or "below 177.9": an interval with NaN ends said as one-sided.
std::string Interval(double lower, double upper) {
  if (std::isnan(lower) && std::isnan(upper)) return "–";
  if (std::isnan(lower)) return fmt::format("below {:.2f}", upper);
  if (std::isnan(upper)) return fmt::format("above {:.2f}", lower);
  if (lower == upper) return fmt::format("{:.2f}", lower);
  return fmt::format("{:.2f} … {:.2f}", lower, upper);
}

}  // namespace

void WriteLoopResult(const std::filesystem::path& file, const Scene& scene, const RubStructure& structure,
                     const LoopOptions& options, const LoopResult& result) {
  const std::unique_ptr<ResultWriter> writer = OpenStudyResult(file, scene, "/loop");
  WriteLoop(*writer, scene, structure, options, result);
  writer->Commit();
}

void WriteLoop(ResultWriter& writer, const Scene& scene, const RubStructure& structure, const LoopOptions& options,
               const LoopResult& result) {
  const std::string g = "/loop";
  writer.CreateGroup(g);
  writer.SetAttribute(g, "status", ToString(result.status));
  writer.SetAttribute(g, "message", result.message);
  writer.SetAttribute(g, "step_rpm", options.step_rpm);
  writer.SetAttribute(g, "dwell_s", options.dwell);
  writer.SetAttribute(g, "budget_g_work_units", options.budget);
  writer.SetAttribute(g, "g_work_units", result.work);
  writer.SetAttribute(g, "cpu_seconds", result.cpu_seconds);
  writer.SetAttribute(g, "wall_seconds", result.wall_seconds);
  writer.SetAttribute(g, "levels", Levels(scene, result));

  const std::string c = g + "/corners";
  writer.CreateGroup(c);
  auto strings = [&](const char* name, auto get) {
    std::vector<std::string> v;
    for (const LoopCorner& x : result.corners) v.push_back(get(x));
    writer.WriteStrings(c + "/" + name, v);
  };
  auto doubles = [&](const char* name, auto get) {
    std::vector<double> v;
    for (const LoopCorner& x : result.corners) v.push_back(get(x));
    writer.WriteDoubles(c + "/" + name, v);
  };
  strings("direction", [](const LoopCorner& x) { return x.direction; });
  strings("kind", [](const LoopCorner& x) { return x.kind; });
  strings("contact", [](const LoopCorner& x) { return x.contact; });
  doubles("speed_rpm", [](const LoopCorner& x) { return x.speed_rpm; });
  doubles("lower_rpm", [](const LoopCorner& x) { return x.lower_rpm; });
  doubles("upper_rpm", [](const LoopCorner& x) { return x.upper_rpm; });
  strings("interval", [](const LoopCorner& x) { return x.interval; });
  strings("cause", [](const LoopCorner& x) { return x.cause; });
  strings("level", [&](const LoopCorner& x) {
    return x.level.empty() || !scene.flexible.enabled ? x.level : "L4 (" + x.level + ")";
  });
  strings("evidence", [&](const LoopCorner& x) { return g + "/" + x.evidence; });
  doubles("cpu_seconds", [](const LoopCorner& x) { return x.cpu_seconds; });
  doubles("crisis_lower_rpm", [](const LoopCorner& x) { return x.crisis_lower_rpm; });
  doubles("crisis_upper_rpm", [](const LoopCorner& x) { return x.crisis_upper_rpm; });
  strings("note", [](const LoopCorner& x) { return x.note; });
  doubles("seen_from_rpm", [](const LoopCorner& x) { return x.seen_from_rpm; });
  doubles("seen_to_rpm", [](const LoopCorner& x) { return x.seen_to_rpm; });
  doubles("precession_from_hz", [](const LoopCorner& x) { return x.precession_from_hz; });
  doubles("precession_to_hz", [](const LoopCorner& x) { return x.precession_to_hz; });

  writer.WriteStrings(g + "/decisions", result.decisions);
  const LoopOptions& o = options;
  const std::array<double, 2> range{RadPerSecondToRpm(o.waves.search.speed_min), RadPerSecondToRpm(o.waves.search.speed_max)};
  WriteRotatingWaveBranches(writer, result.waves, FrictionLawKind::kTanh, range, g + "/branches");
  writer.CreateGroup(g + "/runs");
  WriteRun(writer, g + "/runs/up", structure, result.up);
  WriteRun(writer, g + "/runs/down", structure, result.down);
  for (std::size_t k = 0; k < result.orbits.size(); ++k) WriteOrbits(writer, g + "/orbits", k, result.orbits[k]);
  writer.CreateGroup(g + "/escapes");
  for (std::size_t k = 0; k < result.escape_designs.size(); ++k) {
    WriteEscapes(writer, fmt::format("{}/escapes/{}", g, k), result.escape_designs[k]);
    const EscapeDesign& d = result.escape_designs[k].design;
    const std::string e = fmt::format("{}/escapes/{}", g, k);
    const LoopRun& run = result.escape_designs[k].direction == "up" ? result.up : result.down;
    writer.WriteDoubles(e + "/schedule_rpm", run.schedule_rpm);
    writer.WriteDoubles(e + "/leave_probability", d.leave.probability);
  }
}

void PrintLoopSummary(std::ostream& out, const Scene& scene, const LoopOptions& options, const LoopResult& result) {
  fmt::print(out, "scene {} from {}: the hysteresis loop of a run with {:g} rpm steps and {:g} s per speed\n",
             scene.name, scene.source, options.step_rpm, options.dwell);
  fmt::print(out, "  {:4}  {:14}  {:11}  {:>9}  {:24}  {:28}  {}\n", "run", "jump", "contact", "speed rpm",
             "interval rpm", "cause", "level");
  for (const LoopCorner& c : result.corners) {
    std::string level = c.level.empty() ? "–" : scene.flexible.enabled ? "L4 (" + c.level + ")" : c.level;
    fmt::print(out, "  {:4}  {:14}  {:11}  {:9.2f}  {:24}  {:28}  {}\n", c.direction, c.kind, c.contact, c.speed_rpm,
               Interval(c.lower_rpm, c.upper_rpm), c.cause, level);
  }
  for (const LoopCorner& c : result.corners) {
    fmt::print(out, "  {} {} {:g} → {:g} rpm ({}): {}; interval: {}{}\n", c.direction, c.kind, c.seen_from_rpm,
               c.seen_to_rpm, c.contact, c.note, c.interval,
               std::isnan(c.crisis_lower_rpm) && std::isnan(c.crisis_upper_rpm)
                   ? std::string()
                   : fmt::format("; the crisis p_c: {} rpm", Interval(c.crisis_lower_rpm, c.crisis_upper_rpm)));
  }
  fmt::print(out, "  the run-up ends in {}; the run-down in {}\n", result.up.end, result.down.end);
  fmt::print(out, "  {}\n  {:.1f} s wall\n", result.BriefReport(), result.wall_seconds);
}

void RunLoopStage(const Scene& scene, StageContext& context) {
  const RubStructure structure = SweepStructureOf(scene);
  const LoopOptions options = LoopOptionsOf(scene);
  LoopProgress progress;
  progress.note = [&](const std::string& line) { context.progress("[loop] " + line); };
  const LoopResult result = ComputeLoop(structure, options, ThreadJobs(ThreadsFor(0)), progress);
  WriteLoop(context.writer, scene, structure, options, result);
  PrintLoopSummary(context.out, scene, options, result);
  if (result.status == LoopStatus::kRunFailed) context.failures.push_back("[loop] " + result.message);
}

namespace {

bool SameStructure(const RubStructure& a, const RubStructure& b) {
  auto same = [](const Matrix& x, const Matrix& y) { return x.rows() == y.rows() && x.cols() == y.cols() && x == y; };
  if (!same(a.mass, b.mass) || !same(a.damping, b.damping) || !same(a.stiffness, b.stiffness) ||
      !same(a.gyroscopic, b.gyroscopic) || a.imbalance != b.imbalance || a.contacts.size() != b.contacts.size()) {
    return false;
  }
  for (std::size_t k = 0; k < a.contacts.size(); ++k) {
    const RubContact &x = a.contacts[k], &y = b.contacts[k];
    if (x.rotor != y.rotor || x.stator != y.stator || x.geometry.clearance != y.geometry.clearance ||
        x.geometry.radius != y.geometry.radius) {
      return false;
    }
  }
  const ContactLaw &p = a.law, &q = b.law;
  return p.stiffness == q.stiffness && p.stiffness2 == q.stiffness2 && p.damping == q.damping &&
         p.friction == q.friction && p.velocity_scale == q.velocity_scale;
}

}  // namespace

std::vector<LoopCrisis> ReadLoopCrises(const std::filesystem::path& file, const Scene& scene) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(file, ec)) return {};
  const ResultReader r(file);
  if (!r.Exists("/loop/corners") || !r.HasAttribute("/", "scene_toml")) return {};
  const Scene made = ParseScene(r.ReadStringAttribute("/", "scene_toml"), file.string(), scene.name);
  if (!SameStructure(SweepStructureOf(made), SweepStructureOf(scene))) return {};
  const std::vector<std::string> level = r.ReadStrings("/loop/corners/level");
  const std::vector<std::string> evidence = r.ReadStrings("/loop/corners/evidence");
  const std::vector<std::string> direction = r.ReadStrings("/loop/corners/direction");
  const std::vector<std::string> kind = r.ReadStrings("/loop/corners/kind");
  const std::vector<std::string> contact = r.ReadStrings("/loop/corners/contact");
  const std::vector<double> from = r.ReadDoubles("/loop/corners/seen_from_rpm");
  const std::vector<double> to = r.ReadDoubles("/loop/corners/seen_to_rpm");
  std::vector<LoopCrisis> out;
  for (std::size_t i = 0; i < level.size(); ++i) {
    if (level[i].find("L3") == std::string::npos || evidence[i].rfind("/loop/escapes/", 0) != 0) continue;
    const std::string g = evidence[i];
    LoopCrisis c{direction[i], kind[i], contact[i], from[i], to[i], {}};
    const std::vector<double> speed = r.ReadDoubles(g + "/speed_rpm");
    const std::vector<double> duration = r.ReadDoubles(g + "/duration_s");
    const std::vector<double> stretch = r.ReadDoubles(g + "/stretch_s");
    const std::vector<int> escapes = r.ReadInts(g + "/escapes");
    const std::vector<int> stayed = r.ReadInts(g + "/stayed");
    const std::vector<int> stretches = r.ReadInts(g + "/escape_stretch");
    std::size_t next = 0;
    for (std::size_t e = 0; e < speed.size(); ++e) {
      EscapeObservations o;
      o.parameter = speed[e];
      o.duration = duration[e];
      o.stretch = stretch[e];
      o.stayed = stayed[e];
      o.escape_stretch.assign(stretches.begin() + static_cast<std::ptrdiff_t>(next),
                              stretches.begin() + static_cast<std::ptrdiff_t>(next + static_cast<std::size_t>(escapes[e])));
      next += static_cast<std::size_t>(escapes[e]);
      c.observations.push_back(o);
    }
    out.push_back(c);
  }
  return out;
}

void SweepJumpsByLoop(std::vector<PredictedJump>& table, const std::vector<LoopCrisis>& crises,
                      const std::vector<double>& up_schedule_rpm, const std::vector<double>& down_schedule_rpm,
                      double dwell, double reach_rpm, const std::string& file_name) {
  for (PredictedJump& row : table) {
    if (!row.bifurcation.empty()) continue;
    const double lo = std::min(row.jump.speed_from_rpm, row.jump.speed_to_rpm);
    const double hi = std::max(row.jump.speed_from_rpm, row.jump.speed_to_rpm);
    for (const LoopCrisis& c : crises) {
      const bool contact = c.contact.find(row.contact) != std::string::npos;
      const double c_lo = std::min(c.seen_from_rpm, c.seen_to_rpm) - reach_rpm;
      const double c_hi = std::max(c.seen_from_rpm, c.seen_to_rpm) + reach_rpm;
      if (c.direction != row.direction || c.kind != ToString(row.jump.kind) || !contact || hi < c_lo || lo > c_hi) continue;
      const CrisisSide side = row.direction == "up" ? CrisisSide::kAbove : CrisisSide::kBelow;
      CrisisOptions crisis;
      crisis.side = side;
      const CrisisFit fit = FitCrisis(c.observations, crisis);
      const LeaveDistribution leave =
          PredictLeave(fit, side, row.direction == "up" ? up_schedule_rpm : down_schedule_rpm, dwell);
      if (std::isnan(leave.median)) continue;
      // The jump must lie where this schedule leaves the state, within the 5–95 % range of the leave
      // speeds (up to the schedule's end where 95 % is not reached): C(c)'s run-up jumps at 100 → 104
      // rpm in its frequency, below the range 120 … 128 its loop's crisis predicts.
      const double beyond = row.direction == "up" ? kInfinity : -kInfinity;
      const double last = std::isnan(leave.high) ? beyond : leave.high;
      if (hi < std::min(leave.low, last) || lo > std::max(leave.low, last)) continue;
      row.bifurcation = fmt::format("crisis of a chaotic whip (L3, {}): this schedule leaves it at {:g} rpm, 5–95 % "
                                    "{:g} … {:g}", file_name, leave.median, leave.low, leave.high);
      row.bifurcation_speed_rpm = leave.median;
      row.difference_rpm = 0.5 * (lo + hi) - leave.median;
      row.matched_side = "departure";
      break;
    }
  }
}

LoopProgress PrintLoopProgress(std::ostream& err, SteadyClock::time_point start) {
  // The two runs are tracked on two threads: one line at a time.
  auto mutex = std::make_shared<std::mutex>();
  LoopProgress progress;
  progress.note = [&err, start, mutex](const std::string& line) {
    std::lock_guard<std::mutex> lock(*mutex);
    fmt::print(err, "rubcont: [loop] {} ({:.1f} s)\n", line, SecondsSince(start));
    err.flush();
  };
  progress.speed = [&err, start, mutex](SweepDirection direction, double rpm) {
    std::lock_guard<std::mutex> lock(*mutex);
    fmt::print(err, "rubcont: [loop] run-{} at {:g} rpm ({:.1f} s)\n", ToString(direction), rpm, SecondsSince(start));
    err.flush();
  };
  return progress;
}

}  // namespace rubcont
