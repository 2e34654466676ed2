#include "apps/loop_command.h"

#include <cmath>
#include <filesystem>
#include <ostream>
#include <stdexcept>

#include <fmt/format.h>

#include "apps/atomic_file.h"
#include "apps/commands.h"
#include "apps/figures.h"
#include "apps/guarded.h"
#include "apps/loop_output.h"
#include "apps/plan_check.h"
#include "apps/ranks.h"
#include "apps/scene.h"
#include "apps/stage_options.h"
#include "studies/loop.h"

namespace rubcont {
namespace {

void CheckLoopRequest(const LoopRequest& r) {
  auto fail = [](const char* option, const auto& value, const char* rule) {
    throw std::invalid_argument(fmt::format("--{} = {}: {}", option, value, rule));
  };
  if (r.step_rpm && (!(*r.step_rpm > 0.0) || !std::isfinite(*r.step_rpm))) {
    fail("schedule", fmt::format("{} {}", *r.step_rpm, r.dwell.value_or(0.0)), "the speed step must be positive (rpm)");
  }
  if (r.dwell && (!(*r.dwell > 0.0) || !std::isfinite(*r.dwell))) {
    fail("schedule", fmt::format("{} {}", r.step_rpm.value_or(0.0), *r.dwell), "the time per speed must be positive (s)");
  }
  if (r.budget && (!(*r.budget > 0.0) || !std::isfinite(*r.budget))) fail("budget", *r.budget, "must be positive (G work units)");
}

}  // namespace

int LoopCommand(const LoopRequest& request, std::ostream& out, std::ostream& err) {
  return Guarded(err, [&] {
    CheckLoopRequest(request);
    const Scene scene = LoadScene(request.scene_file);
    const RubStructure structure = SweepStructureOf(scene);
    if (Ranks::World().rank() == 0) WarnUnitMistakes(scene, err);  // once under mpirun
    // The plan of the loop as the command line sets it: its schedule and budget over the scene's.
    Scene planned = scene;
    planned.analysis.sweep.speed_step_rpm = request.step_rpm.value_or(planned.analysis.sweep.speed_step_rpm);
    planned.analysis.sweep.dwell = request.dwell.value_or(planned.analysis.sweep.dwell);
    planned.analysis.loop.budget = request.budget.value_or(planned.analysis.loop.budget);
    std::vector<PlannedWork> plan = StagePlanOf(planned, {Stage::kLoop});
    for (PlannedWork& work : plan) {
      if (request.budget && work.key == "analysis.loop.budget") work.key = "--budget";
    }
    CheckPlan(plan, request.force, err);
    LoopOptions options = LoopOptionsOf(scene);
    if (request.step_rpm) options.step_rpm = *request.step_rpm;
    if (request.dwell) options.dwell = *request.dwell;
    if (request.budget) options.budget = *request.budget;
    const Ranks& ranks = Ranks::World();
    const bool talk = !request.quiet && ranks.rank() == 0;
    const std::filesystem::path file = request.out_file ? std::filesystem::path(*request.out_file)
                                                        : std::filesystem::path("results") / scene.name / "loop.h5";
    if (ranks.rank() == 0) PrepareToWrite(file);  // before the work
    const LoopResult result = ComputeLoop(structure, options, RankJobs(ranks, ThreadsOption(request.threads)),
                                          talk ? PrintLoopProgress(err, SteadyClock::now()) : LoopProgress{});
    if (ranks.rank() != 0) return kExitSuccess;  // rank 0 writes
    WriteLoopResult(file, scene, structure, options, result);
    PrintLoopSummary(out, scene, options, result);
    fmt::print(out, "wrote {}\n", file.string());
    if (request.figures) DrawFigures("loop", file, request.figure_format, out, err);
    return result.status == LoopStatus::kRunFailed ? kExitFailure : kExitSuccess;
  });
}

}  // namespace rubcont
