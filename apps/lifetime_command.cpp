#include "apps/lifetime_command.h"

#include <cmath>
#include <filesystem>
#include <optional>
#include <ostream>
#include <stdexcept>

#include <fmt/format.h>

#include "apps/atomic_file.h"
#include "apps/commands.h"
#include "apps/figures.h"
#include "apps/guarded.h"
#include "apps/lifetime_output.h"
#include "apps/plan_check.h"
#include "apps/scene.h"
#include "apps/stage_options.h"
#include "apps/sweep_output.h"
#include "solvers/stopwatch.h"
#include "studies/lifetime_study.h"

namespace rubcont {
namespace {

void CheckLifetimeRequest(const LifetimeRequest& r) {
  auto fail = [](const char* option, const auto& value, const char* rule) {
    throw std::invalid_argument(fmt::format("--{} = {}: {}", option, value, rule));
  };
  ParseDirection("direction", r.direction);
  if (!(r.from_rpm > 0.0) || !std::isfinite(r.from_rpm)) fail("from", r.from_rpm, "must be positive");
  if (!(r.to_rpm > 0.0) || !std::isfinite(r.to_rpm)) fail("to", r.to_rpm, "must be positive");
  const double sign = r.direction == "up" ? 1.0 : -1.0;
  if (!(sign * (r.to_rpm - r.from_rpm) > 0.0)) {
    fail("to", r.to_rpm, r.direction == "up" ? "must be above --from (direction up)"
                                             : "must be below --from (direction down)");
  }
  if (!(r.step_rpm > 0.0) || !std::isfinite(r.step_rpm)) fail("step", r.step_rpm, "must be positive");
  if (std::abs(r.to_rpm - r.from_rpm) / r.step_rpm > 1000.0) fail("step", r.step_rpm, "gives more than 1000 speeds");
  CheckCopyOptions(r.copies, r.window, r.duration, r.perturbation, r.threads);
  if (r.check_copies < 0 || r.check_copies > 100000) fail("check-copies", r.check_copies, "must be in 0 … 100000");
  if (!(r.check_step_rpm > 0.0) || !std::isfinite(r.check_step_rpm)) {
    fail("check-step", r.check_step_rpm, "must be positive");
  }
  if (std::abs(r.to_rpm - r.from_rpm) / r.check_step_rpm > 1000.0) {
    fail("check-step", r.check_step_rpm, "gives more than 1000 speeds");
  }
  if (!(r.check_dwell >= 2.0 * r.window) || !std::isfinite(r.check_dwell)) {
    fail("check-dwell", r.check_dwell, "must be at least two windows");
  }
}

// The options that decide a study's numbers, as text (a checkpoint belongs to a study with the same):
// all but the threads (the numbers do not depend on them), the output and the check sweeps (run
// after the last checkpoint).
std::string RequestText(const LifetimeRequest& r) {
  return fmt::format("--from {:.17g} --to {:.17g} --step {:.17g} --direction {} --copies {} --duration {:.17g} "
                     "--window {:.17g} --perturbation {:.17g} --seed {} --until {} --until-above {:.17g} "
                     "--until-contacts {}",
                     r.from_rpm, r.to_rpm, r.step_rpm, r.direction, r.copies, r.duration, r.window, r.perturbation,
                     r.seed, r.until, r.until_above_hz, r.until_contacts);
}

}  // namespace

int LifetimeCommand(const LifetimeRequest& request, std::ostream& out, std::ostream& err) {
  return Guarded(err, [&] {
    CheckLifetimeRequest(request);
    const Scene scene = LoadScene(request.scene_file);
    const RubStructure structure = SweepStructureOf(scene);
    WarnUnitMistakes(scene, err);
    std::vector<PlannedWork> plan = SweepPlanOf(scene);  // the approach's schedule
    const double speeds = SpeedCount(request.from_rpm, request.to_rpm, request.step_rpm);
    plan.push_back(CopiesWorkOf(scene, "--copies × --duration",
                                fmt::format("{} × {:g} s at {:g} speeds", request.copies, request.duration, speeds),
                                "copy runs", request.copies * speeds, request.duration, request.window));
    const double check_speeds = SpeedCount(request.from_rpm, request.to_rpm, request.check_step_rpm);
    plan.push_back(CopiesWorkOf(scene, "--check-copies × --check-dwell",
                                fmt::format("{} × {:g} s at {:g} speeds", request.check_copies, request.check_dwell,
                                            check_speeds),
                                "check-sweep speeds", request.check_copies * check_speeds, request.check_dwell,
                                request.window));
    CheckPlan(plan, request.force, err);
    LifetimeStudyOptions options;
    options.target = ParseUntil(structure, request.until, request.until_above_hz, request.until_contacts);
    options.sweep = RubSweepOptionsOf(scene, ParseDirection("direction", request.direction));
    options.from_rpm = request.from_rpm;
    options.to_rpm = request.to_rpm;
    options.step_rpm = request.step_rpm;
    options.sampling.ensemble.copies = request.copies;
    options.sampling.ensemble.perturbation = request.perturbation;
    options.sampling.ensemble.seed = request.seed;
    options.sampling.ensemble.threads = request.threads;
    options.sampling.duration = request.duration;
    options.sampling.window = request.window;
    options.check_copies = request.check_copies;
    options.check_step_rpm = request.check_step_rpm;
    options.check_dwell = request.check_dwell;

    const std::filesystem::path file = request.out_file ? std::filesystem::path(*request.out_file)
                                                        : std::filesystem::path("results") / scene.name / "lifetime.h5";
    const std::filesystem::path checkpoint = LifetimeCheckpointPath(file);
    const std::string request_text = RequestText(request);
    if (request.resume && request.fresh) throw std::invalid_argument("--resume and --fresh: give one of them");
    RefuseUnaskedCheckpoint(checkpoint, "lifetime study", request.resume, request.fresh);
    const std::optional<LifetimeStudyStart> start =
        request.resume ? ReadLifetimeCheckpoint(checkpoint, scene, request_text) : std::nullopt;
    PrepareToWrite(file);  // before the work
    LifetimeStudyProgress progress =
        request.quiet ? LifetimeStudyProgress{} : PrintLifetimeProgress(err, SteadyClock::now());
    progress.finished = [&](const SweepApproach& approach, const std::vector<SpeedEscapes>& escapes) {
      WriteLifetimeCheckpoint(checkpoint, scene, request_text, approach, escapes);
    };
    if (start && !request.quiet) {
      fmt::print(err, "rubcont: [lifetime] resuming from {}: the approach and {} speed(s) done\n",
                 checkpoint.string(), start->escapes.size());
    }
    const LifetimeStudyResult result = RunLifetimeStudy(structure, options, progress, start ? &*start : nullptr);
    PrintLifetimeFailures(err, result);
    if (result.status == LifetimeStatus::kApproachFailed || result.status == LifetimeStatus::kNoEstimate) {
      throw std::runtime_error(result.message);
    }

    WriteLifetimeResult(file, scene, structure, result);
    std::error_code ignored;
    std::filesystem::remove(checkpoint, ignored);  // its speeds are in the result now
    PrintLifetimeSummary(out, scene, structure, result, file);
    DrawFigures("lifetime", file, request.figure_format, out, err);
    return result.status == LifetimeStatus::kComplete ? kExitSuccess : kExitFailure;
  });
}

}  // namespace rubcont
