// Level L4 against the rigid model (issue 18): the reduced flexible model's size and cost, measured
// in one run. For each thesis case with a flexible scene (scenes/thesis_<case>_flexible.toml beside
// scenes/thesis_<case>.toml), interleaved, `repetitions` times:
//   - the L1 branch set of the scene's friction law over its speed range (process CPU time);
//   - a short speed-up sweep through the whip, 52 → 60 rpm in 4 rpm steps from the impulse, with
//     the scene's sweep settings (process CPU time; one thread);
// and the median over the repetitions of each flexible / rigid ratio.
//
//   build/bench/flexible_bench [repetitions]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "apps/scene.h"
#include "apps/stage_options.h"
#include "bench/bench_main.h"
#include "solvers/stopwatch.h"
#include "waves/rotating_wave_branches.h"

namespace rubcont {
namespace {

double Median(std::vector<double> x) {
  std::sort(x.begin(), x.end());
  return x[x.size() / 2];
}

double BranchCpuSeconds(const Scene& scene) {
  const double start = ProcessCpuSeconds();
  ComputeRotatingWaveBranches(StructureOf(scene), FrictionLawOf(scene), BranchOptionsOf(scene));
  return ProcessCpuSeconds() - start;
}

double SweepCpuSeconds(Scene scene, std::string& last) {
  scene.analysis.sweep.up_range_rpm = {52.0, 60.0};
  scene.analysis.sweep.speed_step_rpm = 4.0;
  const double start = ProcessCpuSeconds();
  SweepRun run(SweepStructureOf(scene), RubSweepOptionsOf(scene, SweepDirection::kUp));
  while (!run.stepper().Done() && !run.stepper().Failed()) run.stepper().Step();
  const double seconds = ProcessCpuSeconds() - start;
  const RubSweepRegimes regimes = run.Regimes();
  const std::size_t i = run.stepper().points().size() - 1;
  char text[96];
  std::snprintf(text, sizeof text, "%s at %.0f rpm, BP %.2f Hz", ToString(regimes.regime[0][i]),
                RadPerSecondToRpm(run.stepper().points().back().parameter),
                regimes.precession_hz[0][i]);
  last = text;
  return seconds;
}

}  // namespace
}  // namespace rubcont

static int Run(int argc, char** argv) {
  using namespace rubcont;
  const int repetitions = argc > 1 ? std::max(1, std::atoi(argv[1])) : 3;
  std::printf("flexible_bench: %d repetitions, interleaved; medians of the per-repetition ratios\n",
              repetitions);
  for (const std::string c : {"A_a", "B_a", "C_a"}) {
    const Scene rigid = LoadScene("scenes/thesis_" + c + ".toml");
    const Scene flexible = LoadScene("scenes/thesis_" + c + "_flexible.toml");
    std::vector<double> l1_rigid, l1_flexible, l1_ratio, l3_rigid, l3_flexible, l3_ratio;
    std::string rigid_last, flexible_last;
    for (int r = 0; r < repetitions; ++r) {
      l1_rigid.push_back(BranchCpuSeconds(rigid));
      l1_flexible.push_back(BranchCpuSeconds(flexible));
      l1_ratio.push_back(l1_flexible.back() / l1_rigid.back());
      l3_rigid.push_back(SweepCpuSeconds(rigid, rigid_last));
      l3_flexible.push_back(SweepCpuSeconds(flexible, flexible_last));
      l3_ratio.push_back(l3_flexible.back() / l3_rigid.back());
    }
    std::printf("thesis_%s: rigid %ld coordinates (%ld states), flexible %ld (%ld)\n", c.c_str(),
                static_cast<long>(StructureOf(rigid).Coordinates()),
                static_cast<long>(StructureOf(rigid).States()),
                static_cast<long>(StructureOf(flexible).Coordinates()),
                static_cast<long>(StructureOf(flexible).States()));
    std::printf("  L1 branch set: rigid %.3f s CPU, flexible %.3f s CPU (medians), ratio %.2f×\n",
                Median(l1_rigid), Median(l1_flexible), Median(l1_ratio));
    std::printf("  L3 sweep 52 → 60 rpm: rigid %.2f s CPU, flexible %.2f s CPU (medians), ratio "
                "%.2f×; last speed: rigid %s, flexible %s\n",
                Median(l3_rigid), Median(l3_flexible), Median(l3_ratio), rigid_last.c_str(),
                flexible_last.c_str());
    std::fflush(stdout);
  }
  return 0;
}

int main(int argc, char** argv) {
  return rubcont::RunBenchmark("flexible_bench", [&] { return Run(argc, argv); });
}
