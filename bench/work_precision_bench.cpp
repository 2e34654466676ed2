// Work-precision benchmark (issue 7): for one scene, three questions answered by every method,
// each answer with its error against a reference and its CPU time (user + system time of this
// process, solvers/stopwatch.h, so that the other jobs on a shared machine do not count).
//
//   q1  the dominant precession [Hz] of the motion at a given speed (the whip);
//   q2  the speed-up whirl → whip jump speed [rpm];
//   q3  the speed-down jump speed [rpm].
//
// Methods (each a curve of the chart, each setting a point):
//   L0  closed form (models/analytic.h): the whirl of the first family (Mode 1, then Mode 2) that
//       rolls at the bottom of the speed range ends at its first transition going up (q2) and, from
//       the top, going down (q3); its whip turns at the μ crossing whatever the speed (q1).
//   L1  rotating-wave branch sets (waves/rotating_wave_branches.h) read by
//       studies/whirl_limits.h: exact friction; tanh at ε = 1e-1 … 1e-6 m/s; tanh at the scene's ε
//       with the location tolerance of the special points from "not located" to 1e-12.
//   L2  the modulated whip at the q1 speed (shooting/modulated_orbit.h), single and multiple
//       shooting at several tolerances, started from the end of one L3 q1 run (3 s, 0.5 s
//       windows), whose CPU time it includes. It answers q1 only.
//   L3  time-marching sweeps (apps/sweep_output.h: the scene's model, tanh at its ε) over short
//       windows: q2 and q3 from 4 rpm below (above) to 4 rpm above (below) the L1 limit, started on
//       the stable whirl there (the L1 rotating wave, in the fixed frame: the state the full sweep
//       arrives with) and stopped at the first whirl → whip jump; q1 at the q1 speed alone, from
//       rest plus the scene's impulse. Speed steps, dwell, window and tolerances vary.
//
// The reference (docs/studies/work_precision.md): the model every level can compute is the
// scene's time-marching model, tanh friction at the scene's ε. q2, q3: the stability limits of
// its whirl (L1, tanh at the scene's ε) at the tightest location tolerance, shown converged by the
// next tightest. q1: the dominant precession of the modulated whip (L2) at the tightest tolerance,
// shown converged by the next tightest. Their difference is printed as the reference's own error.
//
// Usage: work_precision_bench SCENE OUTDIR [--q1-speed RPM] [--quick]
// Writes OUTDIR/work_precision.csv (question, level, method, setting, value, error,
// error_estimate, cpu_s, status, note) and OUTDIR/summary.txt (also printed): the references with
// their convergence, and the ratios of CPU time at equal accuracy. --quick runs a few settings per
// method (a smoke test of the harness, minutes instead of ten).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "apps/scene.h"
#include "apps/stage_options.h"
#include "bench/bench_main.h"
#include "models/analytic.h"
#include "models/units.h"
#include "shooting/modulated_orbit.h"
#include "solvers/constants.h"
#include "solvers/stopwatch.h"
#include "studies/whirl_limits.h"
#include "sweeps/rub_runs.h"
#include "sweeps/rub_sweep.h"

namespace rubcont {
namespace {

// One answer: a row of the CSV.
struct Row {
  std::string question, level, method, setting;
  double value = kNaN;
  double error = kNaN;           // |value − reference| (filled at the end)
  double error_estimate = kNaN;  // what the method itself says about its error
  double cpu_s = kNaN;
  std::string status = "ok";
  std::string note;
};

std::string Quoted(std::string text) {
  std::replace(text.begin(), text.end(), '"', '\'');
  return "\"" + text + "\"";
}

// ------------------------------------------------------------------------------------------------
// L0: the closed form.

// Rolling at both contacts at precession Ω: N > 0 and 0 ≤ μ_req ≤ μ at each.
bool Rolls(const TwoPointParams& p, CircularMode mode, double precession) {
  const CircularOrbit o = SolveCircularOrbit(p, mode, precession);
  for (int k = 0; k < 2; ++k) {
    if (!(o.NormalForce(k) > 0.0) || o.MuRequired(k) < 0.0 || o.MuRequired(k) > p.friction) return false;
  }
  return true;
}

struct L0Answers {
  Row q1, q2, q3;
};

L0Answers AnswerL0(const TwoPointParams& p, double speed_min, double speed_max, double q1_speed) {
  L0Answers a;
  for (Row* r : {&a.q1, &a.q2, &a.q3}) {
    r->level = "L0";
    r->method = "closed form";
    r->setting = "exact law, rigid contact";
  }
  a.q1.question = "q1";
  a.q2.question = "q2";
  a.q3.question = "q3";
  if (p.Rci(0) != p.Rci(1)) {
    for (Row* r : {&a.q1, &a.q2, &a.q3}) {
      r->status = "no_answer";
      r->note = "unequal RCIs: the closed form rolls both contacts only with equal RCIs";
    }
    return a;
  }
  const double rci = p.Rci(0);
  const double bottom = rci * speed_min, top = rci * speed_max;
  AnalyticOptions grid;
  grid.min_precession_hz = 1.0;
  grid.max_precession_hz = RadPerSecondToHz(1.02 * top);
  grid.precession_points = static_cast<int>((grid.max_precession_hz - 1.0) / 0.05) + 1;
  auto answer = [&]() {
    for (CircularMode mode : {CircularMode::kMode1, CircularMode::kMode2}) {
      if (!Rolls(p, mode, bottom)) continue;
      const AnalyticCurve curve = ComputeAnalyticCurve(p, mode, grid);
      a.q2.note = a.q3.note = a.q1.note = std::string(ToString(mode)) + ", rolling at " +
                                            fmt::format("{:.3f}", RadPerSecondToHz(bottom)) + " Hz";
      a.q2.value = a.q3.value = a.q1.value = kNaN;
      // Going up: the first transition after which the whirl no longer rolls.
      for (const Transition& t : curve.transitions) {
        const double Omega = HzToRadPerSecond(t.precession_hz);
        if (Omega <= bottom || Rolls(p, mode, Omega * (1 + 1e-9))) continue;
        a.q2.value = RadPerSecondToRpm(Omega / rci);
        a.q2.note += fmt::format("; ends at {} ({} contact, {:.4f} Hz)", ToString(t.type),
                                 t.contact == 0 ? "left" : "right", t.precession_hz);
        if (t.type == TransitionType::kMuCrossing) a.q1.value = t.precession_hz;
        break;
      }
      // Going down from the top, if the same mode rolls there.
      if (Rolls(p, mode, top)) {
        for (auto t = curve.transitions.rbegin(); t != curve.transitions.rend(); ++t) {
          const double Omega = kTwoPi * t->precession_hz;
          if (Omega >= top || Rolls(p, mode, Omega * (1 - 1e-9))) continue;
          a.q3.value = RadPerSecondToRpm(Omega / rci);
          a.q3.note += fmt::format("; ends at {} ({} contact, {:.4f} Hz)", ToString(t->type),
                                   t->contact == 0 ? "left" : "right", t->precession_hz);
          break;
        }
      }
      return;
    }
  };
  // The closed form takes about a millisecond: repeat it for a measurable CPU time.
  int runs = 0;
  const double start = ProcessCpuSeconds();
  do {
    answer();
    ++runs;
  } while (ProcessCpuSeconds() - start < 0.2);
  const double cpu = (ProcessCpuSeconds() - start) / runs;
  for (Row* r : {&a.q1, &a.q2, &a.q3}) {
    r->cpu_s = cpu;
    if (!std::isfinite(r->value)) {
      r->status = "no_answer";
      if (r->note.empty()) r->note = "neither mode rolls at the bottom of the speed range";
    }
  }
  if (std::isfinite(a.q1.value)) {
    a.q1.note += fmt::format("; the circular whip turns at the μ crossing at every speed ({:g} rpm "
                             "asked)", RadPerSecondToRpm(q1_speed));
  } else {
    a.q1.note += "; no μ crossing ends the whirl: no whip";
  }
  return a;
}

// ------------------------------------------------------------------------------------------------
// L1: rotating-wave branch sets.

struct BranchSet {
  std::vector<RotatingWaveBranch> branches;
  double cpu_s = kNaN;  // the least of `repeats` runs
  WhirlLimit up, down;
  BranchReading q1;
};

BranchSet ComputeBranchSet(const RubStructure& structure, FrictionLawKind law,
                           const RotatingWaveBranchOptions& options, double q1_speed, int repeats) {
  BranchSet set;
  for (int i = 0; i < repeats; ++i) {
    const double start = ProcessCpuSeconds();
    set.branches = ComputeRotatingWaveBranches(structure, law, options);
    const double cpu = ProcessCpuSeconds() - start;
    if (!(cpu >= set.cpu_s)) set.cpu_s = cpu;
  }
  set.up = FindWhirlLimit(set.branches, +1, options.search.speed_min);
  set.down = FindWhirlLimit(set.branches, -1, options.search.speed_max);
  set.q1 = PrecessionBeyond(set.branches, set.up, q1_speed);
  return set;
}

void AddLimitRow(std::vector<Row>& rows, const std::string& question, const std::string& method,
                 const std::string& setting, const WhirlLimit& limit, double cpu) {
  Row r;
  r.question = question;
  r.level = "L1";
  r.method = method;
  r.setting = setting;
  r.cpu_s = cpu;
  if (limit.found) {
    r.value = RadPerSecondToRpm(limit.speed);
    r.note = fmt::format("{} at {:.4f} Hz", limit.point, limit.precession_hz);
    if (!limit.converged) r.note += " (not located: the bracketing point)";
  } else {
    r.status = "no_answer";
    r.note = limit.reason;
  }
  rows.push_back(r);
}

void AddBranchRows(std::vector<Row>& rows, const std::string& method, const std::string& setting,
                   const BranchSet& set) {
  AddLimitRow(rows, "q2", method, setting, set.up, set.cpu_s);
  AddLimitRow(rows, "q3", method, setting, set.down, set.cpu_s);
  Row r;
  r.question = "q1";
  r.level = "L1";
  r.method = method;
  r.setting = setting;
  r.cpu_s = set.cpu_s;
  if (set.q1.found) {
    r.value = set.q1.value;
    r.note = "the circular whip beyond the speed-up limit";
  } else {
    r.status = "no_answer";
    r.note = set.q1.reason;
  }
  rows.push_back(r);
}

// ------------------------------------------------------------------------------------------------
// L3: sweeps.

struct SweepSetting {
  std::string name;
  double step_rpm = 1.0;
  double dwell = 0.75;
  double window = 0.25;
  double analysis = 0.5;
  double tolerance = 1e-6;
};

std::string Describe(const SweepSetting& s, bool with_step) {
  return (with_step ? fmt::format("step {:g} rpm, ", s.step_rpm) : std::string()) +
         fmt::format("dwell {:g} s, window {:g} s, rtol {:g}", s.dwell, s.window, s.tolerance);
}

// CVODES BDF whatever the scene's integrator: the questions' speeds (40–70 rpm) are continuous
// contact on stable rotating waves, where BDF is right and the cheapest
// (docs/studies/sweep_integrators.md), and `tolerance` is its rtol = atol.
SweepOptions OptionsFor(const Scene& scene, SweepDirection direction, const SweepSetting& s,
                        const std::vector<double>& rpm) {
  Scene bdf = scene;
  bdf.analysis.sweep.integrator = SweepIntegrator::kBdf;
  SweepOptions o = SweepOptionsOf(bdf, direction);
  o.parameters.clear();
  for (double v : rpm) o.parameters.push_back(RpmToRadPerSecond(v));
  o.dwell = s.dwell;
  o.window = s.window;
  o.analysis_length = s.analysis;
  o.integrator.relative_tolerance = o.integrator.absolute_tolerance = s.tolerance;
  return o;
}

// The fixed-frame state of the rotating wave with unknowns u at speed ω.
Vector FixedFrameState(const RubStructure& structure, const Vector& u, double omega) {
  const Index nc = structure.Coordinates();
  RubRotatingFrame frame(structure, u(2 * nc), omega);
  Vector x = Vector::Zero(4 * nc);
  x.head(2 * nc) = u.head(2 * nc);
  return frame.ToFixedFrame(0.0, x);
}

// A jump window: from the whirl at its first speed, stopped at the first whirl → whip jump.
Row RunJumpWindow(const Scene& scene, SweepDirection direction, const SweepSetting& s,
                  double reference_rpm, const std::vector<RotatingWaveBranch>& branches,
                  const WhirlLimit& limit) {
  Row r;
  r.question = direction == SweepDirection::kUp ? "q2" : "q3";
  r.level = "L3";
  r.method = "sweep";
  r.setting = s.name + ": " + Describe(s, true);
  const double start = ProcessCpuSeconds();
  const double anchor = direction == SweepDirection::kUp ? std::floor(reference_rpm) : std::ceil(reference_rpm);
  const double sign = direction == SweepDirection::kUp ? 1.0 : -1.0;
  const std::vector<double> rpm = SpeedSchedule(anchor - 4 * sign, anchor + 4 * sign, s.step_rpm);
  const RubStructure structure = TwoPointStructure(scene.two_point);
  const Vector whirl = WhirlStateAt(branches, limit, RpmToRadPerSecond(rpm.front()));
  if (whirl.size() == 0) {
    r.status = "no_answer";
    r.note = fmt::format("no stable whirl at {:g} rpm to start from", rpm.front());
    return r;
  }
  RubSweepOptions options = RubSweepOptionsOf(scene, direction);
  options.sweep = OptionsFor(scene, direction, s, rpm);
  SweepRun run(SweepStructureOf(scene), options, {},
               FixedFrameState(structure, whirl, RpmToRadPerSecond(rpm.front())));
  const RubSweepJump* jump = nullptr;
  RubSweepRegimes regimes;
  while (!run.stepper().Done() && !run.stepper().Failed() && jump == nullptr) {
    run.stepper().Step();
    regimes = run.Regimes();
    for (const RubSweepJump& j : regimes.jumps) {
      if (j.kind == RubJumpKind::kWhirlToWhip) {
        jump = &j;
        break;
      }
    }
  }
  r.cpu_s = ProcessCpuSeconds() - start;
  const auto& points = run.stepper().points();
  double simulated = 0.0;
  int unsettled = 0;
  for (const SweepPoint& p : points) {
    simulated += p.simulated_time;
    unsettled += p.status == SweepPointStatus::kNotSettled ? 1 : 0;
  }
  r.note = fmt::format("{} speeds {:g} → {:g} rpm, {} not settled, {:.2f} s simulated",
                       points.size(), rpm.front(), RadPerSecondToRpm(points.back().parameter),
                       unsettled, simulated);
  if (run.stepper().Failed()) {
    r.status = "failed";
    r.note += "; integration failure: " + points.back().message;
    return r;
  }
  if (jump == nullptr) {
    r.status = "no_answer";
    r.note += "; no whirl → whip jump in the window";
    return r;
  }
  r.value = 0.5 * (jump->speed_from_rpm + jump->speed_to_rpm);
  r.error_estimate = 0.5 * std::abs(jump->speed_to_rpm - jump->speed_from_rpm);
  r.note += fmt::format("; jump between {:g} and {:g} rpm, BP {:.2f} → {:.2f} Hz",
                        jump->speed_from_rpm, jump->speed_to_rpm, jump->precession_from_hz,
                        jump->precession_to_hz);
  if (!jump->settled) r.status = "not_settled";
  return r;
}

struct PrecessionRun {
  Row row;
  Vector state;        // where the run ended (fixed frame)
  double bp_hz = kNaN;
};

// q1 by a sweep at the q1 speed alone, from rest plus the scene's impulse.
PrecessionRun RunPrecession(const Scene& scene, const SweepSetting& s, double q1_rpm) {
  PrecessionRun out;
  Row& r = out.row;
  r.question = "q1";
  r.level = "L3";
  r.method = "sweep";
  r.setting = s.name + ": " + Describe(s, false);
  const double start = ProcessCpuSeconds();
  RubSweepOptions options = RubSweepOptionsOf(scene, SweepDirection::kUp);
  options.sweep = OptionsFor(scene, SweepDirection::kUp, s, {q1_rpm});
  SweepRun run(SweepStructureOf(scene), options);
  run.stepper().Step();
  r.cpu_s = ProcessCpuSeconds() - start;
  const SweepPoint& p = run.stepper().points().back();
  if (run.stepper().Failed()) {
    r.status = "failed";
    r.note = "integration failure: " + p.message;
    return out;
  }
  const RubSweepRegimes regimes = run.Regimes();
  out.bp_hz = regimes.precession_hz[0].back();
  out.state = run.stepper().state();
  r.value = out.bp_hz;
  // The refined peak of a single tone is exact to O(N⁻²); sidebands leak into it. The spectral
  // resolution 1/analysis is what the sweep itself can vouch for.
  r.error_estimate = 0.5 / s.analysis;
  r.note = fmt::format("{} ({} windows, {:.2f} s simulated, {} steps), regime {}", ToString(p.status),
                       p.windows, p.simulated_time, p.statistics.steps,
                       ToString(regimes.regime[0].back()));
  if (p.status != SweepPointStatus::kSettled) r.status = "not_settled";
  return out;
}

// ------------------------------------------------------------------------------------------------
// L2: the modulated whip.

struct ShootingSetting {
  int segments = 1;
  double tolerance = 1e-7;
  long collocation_intervals = 0;  // per period: Gauss collocation (order 8); 0: CVODES BDF
};

Row SolveL2(const Scene& scene, const ShootingSetting& s, double q1_speed, const PrecessionRun& start) {
  Row r;
  r.question = "q1";
  r.level = "L2";
  const bool gauss = s.collocation_intervals > 0;
  r.method = gauss ? "shooting, Gauss collocation"
                   : (s.segments == 1 ? "single shooting" : "multiple shooting");
  r.setting = gauss ? fmt::format("{} segments, {} intervals", s.segments, s.collocation_intervals)
                    : fmt::format("{} segment{}, rtol {:g}", s.segments, s.segments == 1 ? "" : "s",
                                  s.tolerance);
  if (start.state.size() == 0 || !std::isfinite(start.bp_hz)) {
    r.status = "no_answer";
    r.note = "no transient to start from: " + start.row.note;
    return r;
  }
  // The orbits stage's shooting (apps/stage_options.h) at this setting.
  Scene shot = scene;
  shot.analysis.orbits.segments = s.segments;
  shot.analysis.orbits.tolerance = s.tolerance;
  shot.analysis.orbits.integrator = gauss ? OrbitIntegrator::kGauss : OrbitIntegrator::kBdf;
  if (gauss) shot.analysis.orbits.collocation_intervals = static_cast<int>(s.collocation_intervals);
  ModulatedOrbitOptions o;
  o.shooting = RubShootingOptionsOf(shot);
  o.newton.residual_tolerance = o.newton.step_tolerance = 100 * s.tolerance;
  o.newton.max_iterations = 10;
  const double cpu = ProcessCpuSeconds();
  const ModulatedOrbit orbit = SolveModulatedOrbit(TwoPointStructure(scene.two_point), q1_speed,
                                                   HzToRadPerSecond(start.bp_hz), start.state, o);
  r.cpu_s = ProcessCpuSeconds() - cpu + start.row.cpu_s;
  r.note = orbit.message + fmt::format("; {} integrator steps; includes the L3 start ({:.2f} s)",
                                       orbit.work.steps, start.row.cpu_s);
  if (!orbit.converged) {
    r.status = "failed";
    return r;
  }
  r.value = orbit.dominant_hz;
  return r;
}

// ------------------------------------------------------------------------------------------------

struct Reference {
  double value = kNaN;
  double next = kNaN;  // the next tightest setting's value
  std::string source, next_source;
};

int Main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: work_precision_bench SCENE OUTDIR [--q1-speed RPM] [--quick]\n");
    return 2;
  }
  Scene scene = LoadScene(argv[1]);
  // The sweeps read a jump where the BP leaves the rolling line, as a waterfall does: a slip
  // tolerance of 99.9 % of ωR lets the frequency check alone decide whirl or whip. That is the
  // jump in the motion, at the whirl's loss of stability (the reference). The scenes' slip rule
  // (sweeps/rub_sweep.h) asks whether the contact rolls, which the tanh law gives up at its knee,
  // 0.72 rpm before the Hopf point in A(a) (both tend to the exact law's event as ε → 0).
  scene.analysis.sweep.rolling_slip_tolerance = 0.999;
  const std::filesystem::path out_dir = argv[2];
  double q1_rpm = 60.0;
  bool quick = false;
  for (int i = 3; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--q1-speed" && i + 1 < argc) q1_rpm = std::atof(argv[++i]);
    else if (a == "--quick") quick = true;
    else {
      std::fprintf(stderr, "work_precision_bench: unknown argument %s\n", argv[i]);
      return 2;
    }
  }
  std::filesystem::create_directories(out_dir);
  const double q1_speed = RpmToRadPerSecond(q1_rpm);
  const TwoPointParams& params = scene.two_point;
  RubStructure structure = TwoPointStructure(params);
  const RotatingWaveBranchOptions branch_options = BranchOptionsOf(scene);
  const double epsilon = structure.law.velocity_scale;
  std::vector<Row> rows;
  std::ostringstream summary;
  auto progress = [](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); };

  // L0.
  const L0Answers l0 = AnswerL0(params, branch_options.search.speed_min,
                                branch_options.search.speed_max, q1_speed);
  rows.insert(rows.end(), {l0.q1, l0.q2, l0.q3});
  progress(fmt::format("L0: q2 {:.4f} rpm, q3 {:.4f} rpm, q1 {:.4f} Hz", l0.q2.value, l0.q3.value, l0.q1.value));

  // L1: exact law; tanh over ε; tanh at the scene's ε over the location tolerance.
  const int repeats = quick ? 1 : 3;
  {
    const BranchSet exact = ComputeBranchSet(structure, FrictionLawKind::kExact, branch_options,
                                             q1_speed, repeats);
    AddBranchRows(rows, "exact friction", "default location", exact);
  }
  const std::vector<double> epsilons =
      quick ? std::vector<double>{1e-1, 1e-2, 1e-3, 1e-4} : std::vector<double>{1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6};
  std::vector<BranchSet> by_epsilon;
  for (double e : epsilons) {
    RubStructure s = structure;
    s.law.velocity_scale = e;
    by_epsilon.push_back(ComputeBranchSet(s, FrictionLawKind::kTanh, branch_options, q1_speed, repeats));
    progress(fmt::format("L1 tanh ε = {:g}: q2 {:.6f}, q3 {:.6f} rpm, q1 {:.4f} Hz, {:.3f} s", e,
                         RadPerSecondToRpm(by_epsilon.back().up.speed),
                         RadPerSecondToRpm(by_epsilon.back().down.speed), by_epsilon.back().q1.value,
                         by_epsilon.back().cpu_s));
  }
  // The bias flag: the shift to ε/10 above 0.01 rpm.
  const double bias_tolerance = RpmToRadPerSecond(0.01);
  for (std::size_t i = 0; i + 1 < epsilons.size(); ++i) {
    const std::size_t first = rows.size();
    AddBranchRows(rows, "rotating waves, tanh", fmt::format("ε = {:g} m/s", epsilons[i]), by_epsilon[i]);
    for (std::size_t k = first; k < rows.size(); ++k) {
      Row& r = rows[k];
      if (r.question == "q1") {
        r.error_estimate = std::abs(by_epsilon[i].q1.value - by_epsilon[i + 1].q1.value);
        continue;
      }
      const bool up = r.question == "q2";
      const RegularizationBias bias = CompareRegularization(
          up ? by_epsilon[i].up : by_epsilon[i].down, up ? by_epsilon[i + 1].up : by_epsilon[i + 1].down,
          epsilons[i], bias_tolerance);
      r.error_estimate = std::abs(RadPerSecondToRpm(bias.shift));
      if (bias.flagged && r.status == "ok") r.status = "bias_flagged";
      r.note += "; " + bias.message;
    }
  }
  const std::size_t scene_epsilon =
      static_cast<std::size_t>(std::find(epsilons.begin(), epsilons.end(), epsilon) - epsilons.begin());
  if (scene_epsilon == epsilons.size()) {
    std::fprintf(stderr, "work_precision_bench: the scene's ε = %g is not in the ε list\n", epsilon);
    return 2;
  }
  // Location tolerances at the scene's ε (the default, 1e-10, is the ε row above).
  struct Location {
    std::string name;
    bool locate = true;
    double tolerance = 1e-10;
  };
  std::vector<Location> locations = {{"not located (the bracketing point)", false, 0.0},
                                     {"location 1e-2", true, 1e-2}, {"location 1e-4", true, 1e-4},
                                     {"location 1e-6", true, 1e-6}, {"location 1e-8", true, 1e-8},
                                     {"location 1e-10", true, 1e-10}, {"location 1e-12", true, 1e-12}};
  if (quick) locations = {locations[0], locations[2], locations[5], locations[6]};
  std::vector<BranchSet> by_location;
  for (const Location& l : locations) {
    RotatingWaveBranchOptions o = branch_options;
    o.continuation.detect.locate = l.locate;
    if (l.locate) o.continuation.location.step_tolerance = l.tolerance;
    by_location.push_back(ComputeBranchSet(structure, FrictionLawKind::kTanh, o, q1_speed, repeats));
    AddBranchRows(rows, fmt::format("rotating waves, tanh ε = {:g}", epsilon), l.name, by_location.back());
    progress(fmt::format("L1 {}: q2 {:.9f}, q3 {:.9f} rpm, {:.3f} s {}{}", l.name,
                         RadPerSecondToRpm(by_location.back().up.speed),
                         RadPerSecondToRpm(by_location.back().down.speed), by_location.back().cpu_s,
                         by_location.back().up.reason, by_location.back().down.reason));
  }
  const BranchSet& tightest = by_location.back();
  const BranchSet& next_tightest = by_location[by_location.size() - 2];
  Reference ref_q2{RadPerSecondToRpm(tightest.up.speed), RadPerSecondToRpm(next_tightest.up.speed),
                   "L1 tanh, " + locations.back().name, locations[locations.size() - 2].name};
  Reference ref_q3{RadPerSecondToRpm(tightest.down.speed), RadPerSecondToRpm(next_tightest.down.speed),
                   "L1 tanh, " + locations.back().name, locations[locations.size() - 2].name};

  // L3 jump windows.
  std::vector<SweepSetting> jump_settings = {
      {"step", 4.0}, {"step", 2.0}, {"step", 1.0}, {"step", 0.5}, {"step", 0.25}, {"step", 0.125},
      {"short windows", 1.0, 0.375, 0.125, 0.25}, {"long dwell", 1.0, 1.5},
      {"loose", 1.0, 0.75, 0.25, 0.5, 1e-5}, {"tight", 1.0, 0.75, 0.25, 0.5, 1e-7}};
  if (quick) jump_settings = {jump_settings[0], jump_settings[2], jump_settings[6]};
  for (SweepDirection direction : {SweepDirection::kUp, SweepDirection::kDown}) {
    const bool up = direction == SweepDirection::kUp;
    const Reference& ref = up ? ref_q2 : ref_q3;
    if (!std::isfinite(ref.value)) {
      Row r;
      r.question = up ? "q2" : "q3";
      r.level = "L3";
      r.method = "sweep";
      r.status = "no_answer";
      r.note = "no reference limit to place the window: " + (up ? tightest.up : tightest.down).reason;
      rows.push_back(r);
      continue;
    }
    for (const SweepSetting& s : jump_settings) {
      rows.push_back(RunJumpWindow(scene, direction, s, ref.value, tightest.branches,
                                   up ? tightest.up : tightest.down));
      progress(fmt::format("L3 {} {}: {:.3f} rpm ({}), {:.1f} s; {}", rows.back().question,
                           rows.back().setting, rows.back().value, rows.back().status,
                           rows.back().cpu_s, rows.back().note));
    }
  }

  // L3 at the q1 speed. L2 starts from the end of the run `l2_start` (3 s at most, settled by
  // 0.5 s windows: the modulated whip takes more than the scene's 0.75 s to settle from rest).
  std::vector<SweepSetting> precession_settings = {
      {"dwell", 0.0, 0.75, 0.25, 0.5, 1e-6}, {"dwell", 0.0, 1.5, 0.25, 0.5, 1e-6},
      {"dwell", 0.0, 3.0, 0.25, 0.5, 1e-6},  {"long windows", 0.0, 3.0, 0.5, 1.0, 1e-6},
      {"loose", 0.0, 3.0, 0.5, 1.0, 1e-5},   {"tight", 0.0, 3.0, 0.5, 1.0, 1e-7},
      {"longest windows", 0.0, 6.0, 1.0, 2.0, 1e-7}, {"longest windows", 0.0, 6.0, 1.0, 2.0, 1e-8}};
  std::size_t l2_start_index = 3;
  if (quick) {
    precession_settings = {precession_settings[0], precession_settings[3], precession_settings[6],
                           precession_settings[7]};
    l2_start_index = 1;
  }
  PrecessionRun l2_start;
  for (std::size_t i = 0; i < precession_settings.size(); ++i) {
    PrecessionRun run = RunPrecession(scene, precession_settings[i], q1_rpm);
    rows.push_back(run.row);
    progress(fmt::format("L3 q1 {}: {:.4f} Hz ({}), {:.1f} s; {}", run.row.setting, run.row.value,
                         run.row.status, run.row.cpu_s, run.row.note));
    if (i == l2_start_index) l2_start = run;
  }

  // L2.
  // BDF first (the tightest two are q1's reference), then Gauss collocation on 4 segments.
  std::vector<ShootingSetting> shooting_settings = {{1, 1e-6}, {4, 1e-7}, {1, 1e-7}, {1, 1e-8},
                                                    {1, 1e-9}};
  const std::size_t bdf_settings = shooting_settings.size();
  for (long intervals : {100L, 200L, 400L}) shooting_settings.push_back({4, 1e-7, intervals});
  if (quick) shooting_settings = {{1, 1e-6}, {1, 1e-7}, {4, 1e-7, 200}};
  std::vector<Row> l2_rows;
  for (const ShootingSetting& s : shooting_settings) {
    l2_rows.push_back(SolveL2(scene, s, q1_speed, l2_start));
    progress(fmt::format("L2 {}: {:.6f} Hz ({}), {:.1f} s; {}", l2_rows.back().setting,
                         l2_rows.back().value, l2_rows.back().status, l2_rows.back().cpu_s,
                         l2_rows.back().note));
  }
  // The change to the next tolerance (BDF) or the next finer mesh (Gauss) is the estimate.
  const auto finer = [](const ShootingSetting& a, const ShootingSetting& b) {
    if (a.segments != b.segments || (a.collocation_intervals > 0) != (b.collocation_intervals > 0)) {
      return false;
    }
    return a.collocation_intervals > 0 ? b.collocation_intervals > a.collocation_intervals
                                       : b.tolerance < a.tolerance;
  };
  for (std::size_t i = 0; i < l2_rows.size(); ++i) {
    for (std::size_t k = i + 1; k < l2_rows.size(); ++k) {
      if (finer(shooting_settings[i], shooting_settings[k])) {
        l2_rows[i].error_estimate = std::abs(l2_rows[i].value - l2_rows[k].value);
        break;
      }
    }
  }
  rows.insert(rows.end(), l2_rows.begin(), l2_rows.end());
  // q1's reference: the two tightest BDF shooting settings; where shooting did not converge (a
  // modulation that is not a relative periodic orbit), the two tightest sweeps (the last two).
  const std::size_t n3 = rows.size() - l2_rows.size();  // the L3 q1 rows end here
  const std::size_t tightest_bdf = quick ? 1 : bdf_settings - 1;
  Reference ref_q1 = l2_rows[tightest_bdf].status == "ok" && l2_rows[tightest_bdf - 1].status == "ok"
      ? Reference{l2_rows[tightest_bdf].value, l2_rows[tightest_bdf - 1].value,
                  "L2 " + l2_rows[tightest_bdf].method + ", " + l2_rows[tightest_bdf].setting,
                  l2_rows[tightest_bdf - 1].setting}
      : Reference{rows[n3 - 1].value, rows[n3 - 2].value, "L3 sweep, " + rows[n3 - 1].setting,
                  rows[n3 - 2].setting};
  for (const char* q : {"q2", "q3"}) {
    Row r;
    r.question = q;
    r.level = "L2";
    r.method = "single shooting";
    r.status = "not_applicable";
    r.note = "L2 shoots the modulated whip at one speed; the jump speeds are stability limits of "
             "the circular whirl (L1)";
    rows.push_back(r);
  }

  // Errors against the references.
  auto reference_of = [&](const std::string& q) -> const Reference& {
    return q == "q1" ? ref_q1 : q == "q2" ? ref_q2 : ref_q3;
  };
  for (Row& r : rows) r.error = std::abs(r.value - reference_of(r.question).value);

  // The CSV.
  {
    std::ofstream csv(out_dir / "work_precision.csv");
    csv << "question,level,method,setting,value,error,error_estimate,cpu_s,status,note\n";
    for (const Row& r : rows) {
      csv << r.question << ',' << r.level << ',' << Quoted(r.method) << ',' << Quoted(r.setting)
          << ',' << fmt::format("{:.12g},{:.6g},{:.6g},{:.6g}", r.value, r.error, r.error_estimate,
                                r.cpu_s)
          << ',' << r.status << ',' << Quoted(r.note) << '\n';
    }
  }

  // The summary: references with their convergence, then the ratios.
  summary << fmt::format("work_precision_bench: scene {} (ε = {:g} m/s), q1 at {:g} rpm\n",
                         scene.name, epsilon, q1_rpm);
  summary << fmt::format("L1 tanh rows flag a regularization bias (status bias_flagged) when the "
                         "limit moves by more than {:g} rpm from ε to ε/10\n",
                         RadPerSecondToRpm(bias_tolerance));
  const char* units[] = {"Hz", "rpm", "rpm"};
  const char* questions[] = {"q1", "q2", "q3"};
  for (int i = 0; i < 3; ++i) {
    const Reference& ref = reference_of(questions[i]);
    summary << fmt::format("reference {}: {:.9f} {} ({}); {}: {:.9f}, difference {:.2g} {}\n",
                           questions[i], ref.value, units[i], ref.source, ref.next_source, ref.next,
                           std::abs(ref.value - ref.next), units[i]);
  }
  // Continuation against sweep at equal or better accuracy. A sweep's accuracy is the larger of
  // its error and its bracket's half width (a bracket that happens to centre on the reference
  // does not make a step accurate); the most accurate sweep is set against the cheapest tanh-law
  // branch set at the scene's ε whose error is at most that.
  auto valid = [](const Row& r) { return r.status != "no_answer" && r.status != "failed" &&
                                         r.status != "not_applicable" && std::isfinite(r.error); };
  auto sweep_accuracy = [](const Row& r) { return std::max(r.error, r.error_estimate); };
  for (const char* q : {"q2", "q3"}) {
    const Row* sweep = nullptr;
    for (const Row& r : rows) {
      if (r.question == q && r.level == "L3" && valid(r) &&
          (!sweep || sweep_accuracy(r) < sweep_accuracy(*sweep))) {
        sweep = &r;
      }
    }
    const Row* branches = nullptr;
    for (const Row& r : rows) {
      if (r.question == q && r.level == "L1" && r.method.rfind("rotating waves, tanh ε", 0) == 0 &&
          valid(r) && sweep && r.error <= sweep_accuracy(*sweep) &&
          (!branches || r.cpu_s < branches->cpu_s)) {
        branches = &r;
      }
    }
    if (sweep && branches) {
      summary << fmt::format(
          "{}: most accurate sweep ({}) error {:.3g} rpm, bracket ±{:g} rpm, in {:.2f} s CPU; the "
          "cheapest branch set at least as accurate ({}) error {:.3g} rpm in {:.3f} s: sweep / "
          "continuation = {:.0f}\n",
          q, sweep->setting, sweep->error, sweep->error_estimate, sweep->cpu_s, branches->setting,
          branches->error, branches->cpu_s, sweep->cpu_s / branches->cpu_s);
    } else {
      summary << fmt::format("{}: no ratio (no valid sweep or branch-set answer)\n", q);
    }
  }
  // q1: rotating waves (the tanh law at the scene's ε, default location) against shooting, and
  // the sweep that is at least as accurate as the cheapest shooting.
  {
    const std::string scene_setting = fmt::format("ε = {:g} m/s", epsilon);
    const Row* waves = nullptr;
    const Row* shooting = nullptr;
    for (const Row& r : rows) {
      if (r.question != "q1" || !valid(r)) continue;
      if (r.level == "L1" && r.method == "rotating waves, tanh" && r.setting == scene_setting) waves = &r;
      if (r.level == "L2" && (!shooting || r.cpu_s < shooting->cpu_s)) shooting = &r;
    }
    if (waves && shooting) {
      summary << fmt::format(
          "q1: rotating waves ({}) error {:.3g} Hz in {:.3f} s CPU; the cheapest rotating-frame "
          "shooting ({}, {}) error {:.3g} Hz in {:.2f} s: shooting / rotating waves = {:.0f}\n",
          waves->setting, waves->error, waves->cpu_s, shooting->method, shooting->setting,
          shooting->error, shooting->cpu_s, shooting->cpu_s / waves->cpu_s);
    } else {
      summary << "q1: no shooting ratio (no valid rotating-wave or shooting answer)\n";
    }
    const Row* sweep = nullptr;
    const Row* cheap_sweep = nullptr;  // the cheapest at least as accurate as the rotating waves
    for (const Row& r : rows) {
      if (r.question != "q1" || r.level != "L3" || !valid(r)) continue;
      if (!sweep || r.error < sweep->error) sweep = &r;
      if (waves && r.error <= waves->error && (!cheap_sweep || r.cpu_s < cheap_sweep->cpu_s)) {
        cheap_sweep = &r;
      }
    }
    if (waves && cheap_sweep) {
      summary << fmt::format("q1: the cheapest sweep at least as accurate as the rotating waves ({}) "
                             "error {:.3g} Hz in {:.2f} s CPU: sweep / rotating waves = {:.0f}\n",
                             cheap_sweep->setting, cheap_sweep->error, cheap_sweep->cpu_s,
                             cheap_sweep->cpu_s / waves->cpu_s);
    }
    if (sweep && shooting) {
      summary << fmt::format("q1: most accurate sweep ({}) error {:.3g} Hz in {:.2f} s CPU: "
                             "sweep / shooting = {:.2f}\n", sweep->setting, sweep->error,
                             sweep->cpu_s, sweep->cpu_s / shooting->cpu_s);
    }
  }
  std::cout << summary.str();
  std::ofstream(out_dir / "summary.txt") << summary.str();
  return 0;
}

}  // namespace
}  // namespace rubcont

int main(int argc, char** argv) {
  return rubcont::RunBenchmark("work_precision_bench", [&] { return rubcont::Main(argc, argv); });
}
