#include "apps/attractor_command.h"

#include <cmath>
#include <filesystem>
#include <ostream>
#include <stdexcept>

#include <fmt/format.h>

#include "apps/atomic_file.h"
#include "apps/attractor_output.h"
#include "apps/commands.h"
#include "apps/figures.h"
#include "apps/guarded.h"
#include "apps/plan_check.h"
#include "apps/scene.h"
#include "apps/stage_options.h"
#include "apps/sweep_output.h"
#include "solvers/stopwatch.h"
#include "studies/attractor_study.h"

namespace rubcont {
namespace {

void CheckAttractorRequest(const AttractorRequest& r) {
  auto fail = [](const char* option, const auto& value, const char* rule) {
    throw std::invalid_argument(fmt::format("--{} = {}: {}", option, value, rule));
  };
  auto positive = [&](const char* option, double value) {
    if (!(value > 0.0) || !std::isfinite(value)) fail(option, value, "must be positive");
  };
  positive("from", r.from_rpm);
  if (r.to_rpm) positive("to", *r.to_rpm);
  positive("step", r.step_rpm);
  ParseDirection("direction", r.direction);
  if (r.approach) ParseDirection("approach", *r.approach);
  if (r.to_rpm && (r.direction == "up" ? *r.to_rpm < r.from_rpm : *r.to_rpm > r.from_rpm)) {
    fail("to", *r.to_rpm, "must lie beyond --from in the direction of the schedule");
  }
  positive("duration", r.duration);
  if (!(r.discard >= 0.0) || !std::isfinite(r.discard)) fail("discard", r.discard, "must be finite and ≥ 0");
  if (!(r.interval > 0.0) || !(r.interval <= r.duration / 10.0)) {
    fail("interval", r.interval, "must be positive and at most a tenth of --duration");
  }
  if (r.exponents < 1) fail("exponents", r.exponents, "must be at least 1");
  if (!(r.sample_interval > 0.0) || !(r.sample_interval <= r.interval)) {
    fail("sample", r.sample_interval, "must be positive and at most --interval");
  }
  if (r.tolerance && !(*r.tolerance > 0.0 && *r.tolerance < 1.0)) {
    fail("tolerance", *r.tolerance, "must lie in (0, 1)");
  }
}

}  // namespace

int AttractorCommand(const AttractorRequest& request, std::ostream& out, std::ostream& err) {
  return Guarded(err, [&] {
    CheckAttractorRequest(request);
    const Scene scene = AttractorSceneOf(LoadScene(request.scene_file));
    const RubStructure structure = SweepStructureOf(scene);
    WarnUnitMistakes(scene, err);
    std::vector<PlannedWork> plan = SweepPlanOf(scene);  // the approach's schedule
    // Each speed integrates its discard and duration with `exponents` tangents beside the state:
    // 1 + exponents times the cost of a simulated second.
    const double speeds = SpeedCount(request.from_rpm, request.to_rpm.value_or(request.from_rpm), request.step_rpm);
    plan.push_back(MarchingWork("--discard + --duration",
                                fmt::format("{:g} + {:g} s at {:g} speeds", request.discard, request.duration, speeds),
                                "speeds", speeds, request.discard + request.duration, 0.0,
                                1.0 + request.exponents));
    CheckPlan(plan, request.force, err);
    AttractorStudyOptions options = AttractorStudyOptionsOf(
        scene, ParseDirection("approach", request.approach.value_or(request.direction)));
    options.direction = ParseDirection("direction", request.direction);
    options.from_rpm = request.from_rpm;
    options.to_rpm = request.to_rpm.value_or(request.from_rpm);
    options.step_rpm = request.step_rpm;
    options.attractor.duration = request.duration;
    options.attractor.discard = request.discard;
    options.attractor.interval = request.interval;
    options.attractor.exponents = request.exponents;
    if (request.tolerance) {
      options.attractor.integrator.relative_tolerance = *request.tolerance;
      options.attractor.integrator.absolute_tolerance = *request.tolerance;
    }
    options.sample_interval = request.sample_interval;
    if (options.attractor.exponents > structure.States()) {
      throw std::invalid_argument(fmt::format("--exponents = {}: must be at most the model's {} states",
                                              options.attractor.exponents, structure.States()));
    }

    const std::filesystem::path file = request.out_file
                                           ? std::filesystem::path(*request.out_file)
                                           : std::filesystem::path("results") / scene.name / "attractor.h5";
    PrepareToWrite(file);  // before the work
    const AttractorStudyResult result = RunAttractorStudy(
        structure, options, request.quiet ? AttractorStudyProgress{} : PrintAttractorProgress(err, SteadyClock::now()));
    if (result.status == AttractorStudyStatus::kApproachFailed) throw std::runtime_error(result.message);

    WriteAttractorResult(file, scene, structure, result);
    PrintAttractorSummary(out, err, scene, structure, result, file);
    DrawFigures("attractor", file, request.figure_format, out, err);
    return result.status == AttractorStudyStatus::kMeasured ? kExitSuccess : kExitFailure;
  });
}

}  // namespace rubcont
