// Benchmark of the time-marching speed sweep (level L3) on a two-point rub scene: wall time of a
// full up + down sweep and its cost breakdown (steps per simulated second, Jacobian evaluations,
// Newton iterations = dense linear solves, LU factorizations), per direction and per regime; and,
// in the same run, the wall time of the continuation that predicts the same jumps
// (ComputeRotatingWaveBranches over the scene's speed_range_rpm with the sweeps' tanh law, as the
// sweep stage runs it for its jump table; best of 5) and the ratio sweep / continuation.
//
// Usage: sweep_bench [SCENE] [--from RPM --to RPM] [--step RPM] [--dwell S] [--rtol X] [--order K]
//                    [--method explicit|auto|bdf|adams|erk|dirk] [--direction up|down|both]
//                    [--verbose]
// --method explicit|auto|bdf is the scene's `integrator`; adams, erk and dirk replace BDF (ARKODE's
// ERK/DIRK). --order is the method's order (BDF/Adams: largest order; ERK/DIRK: the table's order).
// Default: scenes/thesis_A_a.toml with its [analysis.sweep] settings, both directions.
#include <chrono>
#include <ctime>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <string>
#include <vector>

#include "apps/scene.h"
#include "apps/stage_options.h"
#include "bench/bench_main.h"
#include "models/units.h"
#include "sweeps/rub_runs.h"
#include "sweeps/rub_sweep.h"

namespace {

using rubcont::SweepPoint;

struct Totals {
  long steps = 0, rhs = 0, jacobians = 0, setups = 0, newton = 0, error_tests = 0, convergence = 0;
  double simulated = 0.0, wall = 0.0;
  int points = 0, settled = 0;
  void Add(const SweepPoint& p) {
    steps += p.statistics.steps;
    rhs += p.statistics.rhs_evaluations;
    jacobians += p.statistics.jacobian_evaluations;
    setups += p.statistics.linear_solver_setups;
    newton += p.statistics.nonlinear_iterations;
    error_tests += p.statistics.error_test_failures;
    convergence += p.statistics.nonlinear_convergence_failures;
    simulated += p.simulated_time;
    wall += p.wall_seconds;
    ++points;
    settled += p.status == rubcont::SweepPointStatus::kSettled ? 1 : 0;
  }
  void Print(const char* label) const {
    if (points == 0) return;
    std::printf("  %-22s %4d speeds (%3d settled)  %7.2f s simulated  %8.2f s wall  "
                "%8.0f steps/s  %6.2f µs/step  per step: %.2f f, %.3f Jacobians, %.3f LU, "
                "%.2f Newton (linear solves); %.3f error-test and %.3f convergence failures\n",
                label, points, settled, simulated, wall, steps / simulated,
                1e6 * wall / std::max(1L, steps), double(rhs) / steps, double(jacobians) / steps,
                double(setups) / steps, double(newton) / steps, double(error_tests) / steps,
                double(convergence) / steps);
  }
};

}  // namespace

static int Run(int argc, char** argv) {
  std::string scene_file = "scenes/thesis_A_a.toml";
  std::string direction = "both";
  double from = -1, to = -1, step = -1, dwell = -1, rtol = -1;
  int order = -1;
  std::string method;
  bool verbose = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() { return i + 1 < argc ? std::atof(argv[++i]) : 0.0; };
    if (a == "--from") from = next();
    else if (a == "--to") to = next();
    else if (a == "--step") step = next();
    else if (a == "--dwell") dwell = next();
    else if (a == "--rtol") rtol = next();
    else if (a == "--order") order = static_cast<int>(next());
    else if (a == "--direction" && i + 1 < argc) direction = argv[++i];
    else if (a == "--method" && i + 1 < argc) method = argv[++i];
    else if (a == "--verbose") verbose = true;
    else scene_file = a;
  }
  rubcont::Scene scene = rubcont::LoadScene(scene_file);
  rubcont::SweepSettings& s = scene.analysis.sweep;
  if (step > 0) s.speed_step_rpm = step;
  if (dwell > 0) s.dwell = dwell;
  if (rtol > 0) s.relative_tolerance = s.absolute_tolerance = s.explicit_tolerance = rtol;
  if (method == "explicit") s.integrator = rubcont::SweepIntegrator::kExplicit;
  if (method == "auto") s.integrator = rubcont::SweepIntegrator::kAuto;
  if (method == "bdf" || method == "adams" || method == "erk" || method == "dirk")
    s.integrator = rubcont::SweepIntegrator::kBdf;
  if (from > 0 && to > 0) {
    s.up_range_rpm = {std::min(from, to), std::max(from, to)};
    s.down_range_rpm = s.up_range_rpm;
  }
  const rubcont::IntegratorOptions integrator =
      rubcont::SweepOptionsOf(scene, rubcont::SweepDirection::kUp).integrator;
  const int max_order = order >= 0 ? order : integrator.max_order;
  const std::string order_text = integrator.method == rubcont::IntegrationMethod::kBdf
                                     ? ", max order " + std::to_string(max_order)
                                     : std::string();
  std::printf("sweep_bench: scene %s, step %g rpm, dwell %g s, window %g s, integrator \"%s\" "
              "(%s, rtol %g, atol %g%s)\n",
              scene.name.c_str(), s.speed_step_rpm, s.dwell, s.settle_window,
              rubcont::ToString(s.integrator), rubcont::ToString(integrator.method),
              integrator.relative_tolerance, integrator.absolute_tolerance, order_text.c_str());
  std::vector<std::string> directions;
  if (direction == "both" || direction == "up") directions.push_back("up");
  if (direction == "both" || direction == "down") directions.push_back("down");

  Totals all;
  const auto start = std::chrono::steady_clock::now();
  for (const std::string& d : directions) {
    const rubcont::SweepDirection dir = d == "up" ? rubcont::SweepDirection::kUp : rubcont::SweepDirection::kDown;
    rubcont::SweepOptions options = rubcont::SweepOptionsOf(scene, dir);
    if (options.integrator.method == rubcont::IntegrationMethod::kBdf)
      options.integrator.max_order = max_order;
    if (method == "adams") options.integrator.method = rubcont::IntegrationMethod::kAdams;
    if (method == "erk" || method == "dirk") {
      options.integrator.method = method == "erk" ? rubcont::IntegrationMethod::kExplicitRungeKutta
                                                  : rubcont::IntegrationMethod::kDiagonallyImplicitRungeKutta;
      options.integrator.max_order = 0;
      if (order > 0) options.integrator.explicit_order = options.integrator.implicit_order = order;
    }
    rubcont::RubSweepOptions run_options = rubcont::RubSweepOptionsOf(scene, dir);
    run_options.sweep = options;
    rubcont::SweepRun run(rubcont::SweepStructureOf(scene), run_options);
    std::map<std::string, Totals> by_regime;
    Totals total;
    while (!run.stepper().Done() && !run.stepper().Failed()) {
      run.stepper().Step();
      const SweepPoint& p = run.stepper().points().back();
      total.Add(p);
      all.Add(p);
      const rubcont::RubSweepRegimes regimes = run.Regimes();
      const std::size_t i = run.stepper().points().size() - 1;
      const std::string label = std::string(ToString(regimes.regime[0][i])) + "/" +
                                ToString(regimes.regime[1][i]);
      by_regime[label].Add(p);
      if (verbose) {
        std::printf("  %s %6.1f rpm  BP %7.2f / %7.2f Hz  V %8.4f / %8.4f m/s  contact %.2f/%.2f  "
                    "%-11s %d win  Δspec %.3f Δf %.3f  %7ld steps  %6.2f s\n",
                    d.c_str(), rubcont::RadPerSecondToRpm(p.parameter), regimes.precession_hz[0][i],
                    regimes.precession_hz[1][i],
                    p.channels.empty() ? rubcont::kNaN : p.channels[0].measures[0].mean,
                    p.channels.empty() ? rubcont::kNaN : p.channels[1].measures[0].mean,
                    p.channels.empty() ? rubcont::kNaN : p.channels[0].active_fraction,
                    p.channels.empty() ? rubcont::kNaN : p.channels[1].active_fraction, ToString(p.status),
                    p.windows, p.spectrum_change, p.frequency_change, p.statistics.steps,
                    p.wall_seconds);
        std::fflush(stdout);
      }
    }
    std::printf("direction %s:\n", d.c_str());
    total.Print("all");
    for (const auto& [label, t] : by_regime) t.Print(label.c_str());
    for (const rubcont::RubSweepJump& j : run.Regimes().jumps) {
      std::printf("  jump %-6s %-16s %6.1f → %6.1f rpm  %7.2f → %7.2f Hz\n",
                  j.contact == 0 ? "left" : "right", ToString(j.kind), j.speed_from_rpm,
                  j.speed_to_rpm, j.precession_from_hz, j.precession_to_hz);
    }
    if (run.stepper().Failed()) std::printf("  FAILED: %s\n", run.stepper().points().back().message.c_str());
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::printf("total:\n");
  all.Print("up + down");
  std::printf("wall time of the sweeps: %.1f s\n", wall);

  // The continuation run (level L1) that predicts the jumps, timed the same way.
  double continuation = 1e300;
  std::size_t branches = 0;
  for (int repeat = 0; repeat < 5; ++repeat) {
    const auto c0 = std::chrono::steady_clock::now();
    const auto result = rubcont::ComputeRotatingWaveBranches(
        rubcont::StructureOf(scene), rubcont::FrictionLawKind::kTanh,
        rubcont::BranchOptionsOf(scene));
    continuation = std::min(continuation,
                            std::chrono::duration<double>(std::chrono::steady_clock::now() - c0).count());
    branches = result.size();
  }
  std::printf("continuation (L1, tanh, %zu branches, %g–%g rpm, best of 5): %.1f ms\n", branches,
              scene.analysis.speed_range_rpm[0], scene.analysis.speed_range_rpm[1], 1e3 * continuation);
  std::printf("ratio sweep / continuation: %.0f\n", wall / continuation);
  return 0;
}

int main(int argc, char** argv) {
  return rubcont::RunBenchmark("sweep_bench", [&] { return Run(argc, argv); });
}
