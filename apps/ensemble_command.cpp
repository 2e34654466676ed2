#include "apps/ensemble_command.h"

#include <cmath>
#include <filesystem>
#include <ostream>
#include <stdexcept>

#include <fmt/format.h>

#include "apps/atomic_file.h"
#include "apps/commands.h"
#include "apps/ensemble_output.h"
#include "apps/figures.h"
#include "apps/guarded.h"
#include "apps/plan_check.h"
#include "apps/scene.h"
#include "apps/stage_options.h"
#include "apps/sweep_output.h"
#include "solvers/stopwatch.h"
#include "studies/ensemble_study.h"

namespace rubcont {
namespace {

void CheckEnsembleRequest(const EnsembleRequest& r) {
  auto fail = [](const char* option, const auto& value, const char* rule) {
    throw std::invalid_argument(fmt::format("--{} = {}: {}", option, value, rule));
  };
  if (!(r.speed_rpm > 0.0) || !std::isfinite(r.speed_rpm)) fail("speed", r.speed_rpm, "must be positive");
  ParseDirection("direction", r.direction);
  CheckCopyOptions(r.copies, r.window, r.duration, r.perturbation, r.threads);
}

}  // namespace

int EnsembleCommand(const EnsembleRequest& request, std::ostream& out, std::ostream& err) {
  return Guarded(err, [&] {
    CheckEnsembleRequest(request);
    const Scene scene = LoadScene(request.scene_file);
    const RubStructure structure = SweepStructureOf(scene);
    WarnUnitMistakes(scene, err);
    std::vector<PlannedWork> plan = SweepPlanOf(scene);  // the approach's schedule
    plan.push_back(CopiesWorkOf(scene, "--copies × --duration",
                                fmt::format("{} × {:g} s", request.copies, request.duration), "copies",
                                request.copies, request.duration, request.window));
    CheckPlan(plan, request.force, err);
    EnsembleStudyOptions options;
    options.target = ParseUntil(structure, request.until, request.until_above_hz, request.until_contacts);
    options.sweep = RubSweepOptionsOf(scene, ParseDirection("direction", request.direction));
    options.speed_rpm = request.speed_rpm;
    options.duration = request.duration;
    options.window = request.window;
    options.ensemble.copies = request.copies;
    options.ensemble.perturbation = request.perturbation;
    options.ensemble.seed = request.seed;
    options.ensemble.threads = request.threads;

    const std::filesystem::path file =
        request.out_file ? std::filesystem::path(*request.out_file)
                         : std::filesystem::path("results") / scene.name /
                               fmt::format("ensemble_{:g}rpm.h5", request.speed_rpm);
    PrepareToWrite(file);  // before the work
    const EnsembleStudyResult result = RunEnsembleStudy(
        structure, options, request.quiet ? EnsembleStudyProgress{} : PrintEnsembleProgress(err, SteadyClock::now()));
    if (result.status == EnsembleStudyStatus::kApproachFailed) throw std::runtime_error(result.message);

    WriteEnsembleResult(file, scene, structure, result);
    PrintEnsembleSummary(out, scene, structure, result, file);
    DrawFigures("ensemble", file, request.figure_format, out, err);
    PrintEnsembleFailures(err, result);
    return result.status == EnsembleStudyStatus::kComplete ? kExitSuccess : kExitFailure;
  });
}

}  // namespace rubcont
