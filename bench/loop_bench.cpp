// The loop of a scene (studies/loop.h) and what it cost: `loop_bench SCENE [STEP_RPM DWELL_S]
// [BUDGET_CPU_S] [THREADS]`. Prints every decision as it is made, then the corners.
#include <cstdio>
#include <cstdlib>
#include <string>

#include <fmt/format.h>

#include "apps/scene.h"
#include "apps/stage_options.h"
#include "solvers/parallel.h"
#include "studies/loop.h"

int main(int argc, char** argv) {
  using namespace rubcont;
  if (argc < 2) {
    std::fprintf(stderr, "usage: loop_bench SCENE [STEP_RPM DWELL_S] [BUDGET_CPU_S] [THREADS]\n");
    return 2;
  }
  const Scene scene = LoadScene(argv[1]);
  LoopOptions options = LoopOptionsOf(scene);
  if (argc >= 4) {
    options.step_rpm = std::atof(argv[2]);
    options.dwell = std::atof(argv[3]);
  }
  if (argc >= 5) options.budget = std::atof(argv[4]);
  const int threads = argc >= 6 ? std::atoi(argv[5]) : 2;
  LoopProgress progress;
  progress.note = [](const std::string& line) { fmt::print(stderr, "{}\n", line); };
  const LoopResult r = ComputeLoop(StructureOf(scene), options, ThreadJobs(threads), progress);
  fmt::print("{}\n", r.BriefReport());
  for (const LoopCorner& c : r.corners) {
    fmt::print("{:4} {:15} {:12} {:8.2f} [{:.2f}, {:.2f}] {} | {} | {} | crisis [{:.2f}, {:.2f}] | {:.1f} s | {}\n",
               c.direction, c.kind, c.contact, c.speed_rpm, c.lower_rpm, c.upper_rpm, c.cause, c.level, c.interval,
               c.crisis_lower_rpm, c.crisis_upper_rpm, c.cpu_seconds, c.note);
  }
  for (const LoopRun* run : {&r.up, &r.down}) {
    for (const LoopSkip& s : run->skips) {
      fmt::print("skip {}: {:g} → {:g} rpm on {} ({})\n", ToString(run->direction), s.from_rpm, s.to_rpm, s.branch, s.limit);
    }
  }
  return 0;
}
