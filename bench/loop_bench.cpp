// The loop of a scene (studies/loop.h): what it answers and what it costs, against the fixed design
// of speeds × copies it replaces, and checked by independent run-ups.
//
//   loop_bench SCENE STEP_RPM DWELL_S BUDGET_CPU_S [RUN_UPS [LIFETIME.h5]]
//
// 1. `rubcont loop`'s study on the scene with that schedule and budget: every decision, the
//    corners, the CPU seconds.
// 2. With LIFETIME.h5 (a committed `rubcont lifetime` file of the same scene's speed-up whip, made
//    with a fixed grid of speeds × copies): its ensembles refitted (FitCrisis) and the leave
//    distribution it predicts for the same schedule, with the median's interval by the same rule
//    (MedianInterval), beside its CPU seconds — the fixed design's answer and cost against the
//    loop's.
// 3. RUN_UPS independent run-ups of that schedule (RunCheckSweeps: perturbed copies of the tracker's
//    state on the whip escape_reach_rpm below the whip's end), each until it leaves: where they
//    leave, against the loop's predicted 5–95 % range and median.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "apps/hdf5_file.h"
#include "apps/scene.h"
#include "apps/stage_options.h"
#include "bench/bench_main.h"
#include "models/units.h"
#include "solvers/constants.h"
#include "solvers/parallel.h"
#include "solvers/stopwatch.h"
#include "studies/lifetime_study.h"
#include "studies/loop.h"

namespace {

using namespace rubcont;

// The ensembles of a `rubcont lifetime` file (apps/lifetime_output.h) as escape observations.
std::vector<EscapeObservations> ReadEnsembles(const std::string& file, double& cpu_seconds, std::string& target) {
  const ResultReader r(file);
  const std::vector<double> speed = r.ReadDoubles("/lifetime/speed_rpm");
  const std::vector<int> stayed = r.ReadInts("/lifetime/stayed");
  const Matrix arrival = r.ReadMatrix("/lifetime/arrival_time_s");
  const double stretch = r.ReadDoubleAttribute("/lifetime", "stretch");
  const double duration = r.ReadDoubleAttribute("/lifetime", "duration");
  cpu_seconds = r.ReadDoubleAttribute("/lifetime", "cpu_seconds");
  target = r.ReadStringAttribute("/lifetime", "until");
  std::vector<EscapeObservations> out;
  for (std::size_t i = 0; i < speed.size(); ++i) {
    EscapeObservations o;
    o.parameter = speed[i];
    o.stretch = stretch;
    o.duration = duration;
    o.stayed = stayed[i];
    for (Index c = 0; c < arrival.cols(); ++c) {
      const double t = arrival(static_cast<Index>(i), c);
      if (std::isfinite(t)) o.escape_stretch.push_back(std::max(1, static_cast<int>(std::lround(t / stretch))));
    }
    out.push_back(o);
  }
  return out;
}

}  // namespace

static int Run(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr, "usage: loop_bench SCENE STEP_RPM DWELL_S BUDGET_CPU_S [RUN_UPS [LIFETIME.h5]]\n");
    return 2;
  }
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // lines as they come: the bench runs for minutes
  const Scene scene = LoadScene(argv[1]);
  LoopOptions options = LoopOptionsOf(scene);
  options.step_rpm = std::atof(argv[2]);
  options.dwell = std::atof(argv[3]);
  options.budget = std::atof(argv[4]);
  const int run_ups = argc >= 6 ? std::atoi(argv[5]) : 0;
  const RubStructure structure = StructureOf(scene);
  fmt::print("loop_bench: {} with {:g} rpm steps, {:g} s per speed, budget {:g} s CPU, 2 threads\n", scene.name,
             options.step_rpm, options.dwell, options.budget);

  LoopProgress progress;
  progress.note = [](const std::string& line) { fmt::print("  {}\n", line); };
  const double cpu_start = ProcessCpuSeconds();
  const LoopResult r = ComputeLoop(structure, options, ThreadJobs(2), progress);
  const double loop_cpu = ProcessCpuSeconds() - cpu_start;
  fmt::print("{}\n", r.BriefReport());
  const LoopCorner* end = nullptr;
  for (const LoopCorner& c : r.corners) {
    fmt::print("  {:4} {:15} {:12} {:8.2f} [{:.2f}, {:.2f}] {} ({}); {:.1f} s CPU\n", c.direction, c.kind, c.contact,
               c.speed_rpm, c.lower_rpm, c.upper_rpm, c.cause, c.level, c.cpu_seconds);
    if (c.direction == "up" && c.level == "L3" && end == nullptr) end = &c;
  }
  fmt::print("the whole loop: {:.1f} s CPU, {:.1f} s wall\n", loop_cpu, r.wall_seconds);
  if (end == nullptr) {
    fmt::print("no run-up corner decided at L3: nothing to compare\n");
    return 0;
  }
  const EscapeDesign& design = r.escape_designs.at(static_cast<std::size_t>(end->escape_design)).design;
  fmt::print("the whip's end (loop): median {:g} rpm, 5–95 % {:g} … {:g}, the median's 95 % {:g} … {:g}; {} ensembles, "
             "{:.1f} s CPU of copies\n", design.leave.median, design.leave.low, design.leave.high, design.median_lower,
             design.median_upper, design.observations.size(), design.cost);

  if (argc >= 7) {
    double fixed_cpu = 0.0;
    std::string target;
    const std::vector<EscapeObservations> fixed = ReadEnsembles(argv[6], fixed_cpu, target);
    CrisisOptions crisis;
    const CrisisFit fit = FitCrisis(fixed, crisis);
    const std::vector<double>& schedule = r.up.schedule_rpm;
    const LeaveDistribution leave = PredictLeave(fit, CrisisSide::kAbove, schedule, options.dwell);
    const LeaveMedianInterval interval = MedianInterval(fixed, fit, CrisisSide::kAbove, schedule, options.dwell);
    int copies = 0;
    for (const EscapeObservations& o : fixed) copies += static_cast<int>(o.escape_stretch.size()) + o.stayed;
    fmt::print("the whip's end (fixed design, {}: {} speeds, {} copies, until {}): median {:g} rpm, 5–95 % {:g} … {:g}, "
               "the median's 95 % {:g} … {:g}{}; {:.0f} s CPU\n", argv[6], fixed.size(), copies, target, leave.median,
               leave.low, leave.high, interval.lower, interval.upper, interval.open.empty() ? "" : " (" + interval.open + ")",
               fixed_cpu);
    fmt::print("cost ratio fixed / loop (the whole loop): {:.1f}; (the copies alone): {:.1f}\n", fixed_cpu / loop_cpu,
               fixed_cpu / design.cost);
  }

  if (run_ups > 0) {
    // Independent run-ups from the tracker's whip escape_reach_rpm below the end.
    const LoopRun& up = r.up;
    std::size_t start = 0;
    for (std::size_t k = 0; k < up.points.size(); ++k) {
      if (RadPerSecondToRpm(up.points[k].parameter) <= end->seen_from_rpm - options.escape_reach_rpm + 1e-9) start = k;
    }
    const double start_rpm = RadPerSecondToRpm(up.points[start].parameter);
    // Through the schedule to three steps past the predicted 95 % point (a run-up that has not
    // left by then counts as staying).
    std::vector<double> speeds;
    for (double p : up.schedule_rpm)
      if (p > start_rpm + 1e-9 && p <= design.leave.high + 3.0 * options.step_rpm + 1e-9) speeds.push_back(p);
    ArrivalTarget target;
    target.regime = RubRegime::kWhirl;
    EnsembleOptions ensemble;
    ensemble.copies = run_ups;
    ensemble.seed = 424242;
    ensemble.threads = 2;
    RubSweepOptions sweep = options.up;
    const double run_cpu = ProcessCpuSeconds();
    const CheckSweeps checks = RunCheckSweeps(structure, sweep, up.states[start], speeds, options.dwell, options.window,
                                              ensemble, target);
    int inside = 0, left = 0;
    std::vector<double> where;
    for (double s : checks.leave_speed_rpm) {
      if (std::isnan(s)) continue;
      ++left;
      where.push_back(s);
      if (s >= design.leave.low - 1e-9 && s <= design.leave.high + 1e-9) ++inside;
    }
    std::sort(where.begin(), where.end());
    fmt::print("run-ups ({} from the tracker's whip at {:g} rpm, {:g} s per speed, until whirl on every contact): left at",
               run_ups, start_rpm, checks.dwell);
    for (double s : checks.leave_speed_rpm) fmt::print(" {}", std::isnan(s) ? std::string("(stayed)") : fmt::format("{:g}", s));
    fmt::print(" rpm; {} of {} inside the predicted 5–95 % ({:g} … {:g}); their median {:g} rpm against the predicted {:g}; "
               "{} failed; {:.1f} s CPU\n", inside, left, design.leave.low, design.leave.high,
               where.empty() ? kNaN : where[where.size() / 2], design.leave.median, checks.failures.size(),
               ProcessCpuSeconds() - run_cpu);
  }
  return 0;
}

int main(int argc, char** argv) {
  return rubcont::RunBenchmark("loop_bench", [&] { return Run(argc, argv); });
}
