#include "apps/commands.h"

#include <cmath>
#include <exception>
#include <filesystem>
#include <memory>
#include <optional>
#include <ostream>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>

#include "apps/atomic_file.h"
#include "apps/branch_output.h"
#include "apps/figures.h"
#include "apps/guarded.h"
#include "apps/hdf5_file.h"
#include "apps/loop_output.h"
#include "apps/models.h"
#include "apps/plan_check.h"
#include "apps/scene.h"
#include "apps/scene_schema.h"
#include "apps/stage_options.h"
#include "apps/structure_file.h"
#include "apps/sweep_output.h"
#include "apps/tori_stage.h"
#include "models/units.h"
#include "solvers/stopwatch.h"
#include "waves/rotating_wave_branches.h"

namespace rubcont {
namespace {

// Progress lines on stderr, silenced by --quiet.
class Progress {
 public:
  Progress(bool quiet, std::ostream& err) : quiet_(quiet), err_(err) {}
  template <class... Args>
  void operator()(fmt::format_string<Args...> format, Args&&... args) {
    if (quiet_) return;
    fmt::print(err_, "rubcont: {}\n", fmt::format(format, std::forward<Args>(args)...));
    err_.flush();
  }

 private:
  bool quiet_;
  std::ostream& err_;
};

struct ExecuteOptions {
  bool quiet = false;
  bool resume = false;  // sweeps continue from their checkpoints
  bool fresh = false;   // sweeps start again over their checkpoints (neither: a checkpoint is refused)
  bool figures = true;  // draw the figures after the file is complete
  std::string figure_format = "png";  // png, pdf or svg (kFigureFormats)
  bool force = false;   // run a plan the plan check refuses, with a warning
  std::vector<SweepDirection> directions{SweepDirection::kUp, SweepDirection::kDown};
};

std::string Duration(double seconds) {
  if (!(seconds < 1e9)) return "?";
  if (seconds < 60.0) return fmt::format("{:.0f} s", seconds);
  if (seconds < 3600.0) return fmt::format("{:.0f} min {:02.0f} s", std::floor(seconds / 60.0),
                                           std::fmod(seconds, 60.0));
  return fmt::format("{:.0f} h {:02.0f} min", std::floor(seconds / 3600.0),
                     std::fmod(seconds, 3600.0) / 60.0);
}

std::string Hz(double value) { return std::isnan(value) ? "  –  " : fmt::format("{:.2f}", value); }

// The sweep stage: each direction from its checkpoint (with resume) or from the impulse, a
// checkpoint after every finished speed, progress with ETA. Writes /sweeps into `writer`.
void SweepStage(const Scene& scene, const ExecuteOptions& options, const std::filesystem::path& h5_file,
                ResultWriter& writer, Progress& progress, std::ostream& out, std::ostream& err,
                std::vector<std::string>& failures, std::vector<std::filesystem::path>& checkpoints) {
  // Runs first (resumed or new), so the ETA can count every speed still to do. A direction not
  // asked for is carried over from an earlier result file of this scene, when there is one.
  const RubStructure structure = SweepStructureOf(scene);
  std::vector<std::unique_ptr<SweepRun>> runs;
  std::vector<bool> carried;
  std::size_t remaining = 0;
  for (SweepDirection direction : {SweepDirection::kUp, SweepDirection::kDown}) {
    const bool asked = std::find(options.directions.begin(), options.directions.end(), direction) !=
                       options.directions.end();
    if (!asked) {
      if (std::optional<std::vector<SweepPoint>> earlier = ReadFinishedSweep(h5_file, scene, direction)) {
        progress("[sweep {}] kept from {}: {} speeds", ToString(direction), h5_file.string(),
                 earlier->size());
        runs.push_back(std::make_unique<SweepRun>(structure, RubSweepOptionsOf(scene, direction),
                                                  std::move(*earlier), Vector::Zero(structure.States())));
        carried.push_back(true);
      }
      continue;
    }
    const std::filesystem::path checkpoint = CheckpointPath(h5_file, direction);
    std::optional<SweepCheckpoint> saved;
    if (options.resume) {
      saved = ReadSweepCheckpoint(checkpoint, scene, direction);
    } else if (std::filesystem::exists(checkpoint)) {
      fmt::print(err, "rubcont: note: starting the {} sweep afresh (--fresh); {} will be overwritten\n",
                 ToString(direction), checkpoint.string());
    }
    std::optional<std::vector<SweepPoint>> finished;
    if (options.resume && !saved) {
      // No checkpoint: a direction already complete in the result file is not run again.
      finished = ReadFinishedSweep(h5_file, scene, direction);
      const std::size_t planned = SweepOptionsOf(scene, direction).parameters.size();
      if (finished && (finished->size() != planned ||
                       finished->back().status == SweepPointStatus::kIntegrationFailure)) {
        finished.reset();
      }
    }
    if (saved) {
      progress("[sweep {}] resuming from {}: {} speeds done", ToString(direction),
               checkpoint.string(), saved->points.size());
      runs.push_back(std::make_unique<SweepRun>(structure, RubSweepOptionsOf(scene, direction),
                                                std::move(saved->points), saved->state));
    } else if (finished) {
      progress("[sweep {}] complete in {}: not run again", ToString(direction), h5_file.string());
      runs.push_back(std::make_unique<SweepRun>(structure, RubSweepOptionsOf(scene, direction),
                                                std::move(*finished), Vector::Zero(structure.States())));
    } else {
      runs.push_back(std::make_unique<SweepRun>(structure, RubSweepOptionsOf(scene, direction)));
    }
    carried.push_back(false);
    const SweepRun& run = *runs.back();
    remaining += run.stepper().options().parameters.size() - run.stepper().next_index();
  }
  const SweepSettings& w = scene.analysis.sweep;
  const SweepOptions& used = runs.front()->stepper().options();
  auto describe = [](const IntegratorOptions& o) {
    return o.method == IntegrationMethod::kExplicitRungeKutta
               ? fmt::format("{} order {}, rtol = atol {:g}", ToString(o.method), o.explicit_order,
                             o.relative_tolerance)
           : o.method == IntegrationMethod::kDormandPrince
               ? fmt::format("{} 5(4), rtol = atol {:g}", ToString(o.method), o.relative_tolerance)
               : fmt::format("{} order ≤ {}, rtol {:g}, atol {:g}", ToString(o.method), o.max_order,
                             o.relative_tolerance, o.absolute_tolerance);
  };
  std::string integrators = describe(used.integrator);
  if (used.intermittent_integrator) {
    integrators += fmt::format(" ({} after a window with intermittent contact)",
                               describe(*used.intermittent_integrator));
  }
  fmt::print(out, "[sweep] L3 time marching (Kumar 2010 §3.5): {}; "
                  "{:g} rpm steps, dwell ≤ {:g} s, settled when {} successive {:g} s windows agree "
                  "(spectra to {:g}, BP to {:g} Hz); impulse {:g} N·s\n",
             integrators, w.speed_step_rpm, w.dwell, w.settle_windows + 1, w.settle_window, w.spectrum_tolerance,
             w.frequency_tolerance_hz, w.impulse);

  const SteadyClock::time_point start = SteadyClock::now();
  std::size_t done = 0;
  for (std::size_t r = 0; r < runs.size(); ++r) {
    SweepRun& run = *runs[r];
    if (carried[r]) {
      WriteSweep(writer, scene, run);
      continue;
    }
    SweepStepper& stepper = run.stepper();
    const std::string label = fmt::format("[sweep {}]", ToString(run.direction()));
    const std::filesystem::path checkpoint = CheckpointPath(h5_file, run.direction());
    const std::size_t total = stepper.options().parameters.size();
    checkpoints.push_back(checkpoint);
    while (!stepper.Done() && !stepper.Failed()) {
      const SweepStepOutcome outcome = stepper.Step();
      const SweepPoint& p = stepper.points().back();
      ++done;
      if (outcome == SweepStepOutcome::kFailed) {
        progress("{} {}/{} {:.1f} rpm: integration failure: {}", label, stepper.points().size(), total,
                 RadPerSecondToRpm(p.parameter), p.message);
        break;
      }
      WriteSweepCheckpoint(checkpoint, scene, run);
      const RubSweepRegimes regimes = run.Regimes();
      const std::size_t i = stepper.points().size() - 1;
      const double elapsed = SecondsSince(start);
      progress("{} {}/{} {:.1f} rpm: BP {}/{} Hz ({}/{}), V {:.4f}/{:.4f} m/s, {} after {:g} s "
               "({:.1f} s); ETA {}",
               label, stepper.points().size(), total, RadPerSecondToRpm(p.parameter),
               Hz(regimes.precession_hz[0][i]), Hz(regimes.precession_hz[1][i]),
               ToString(regimes.regime[0][i]), ToString(regimes.regime[1][i]),
               p.channels[0].measures[kSlipVelocityMeasure].mean,
               p.channels[1].measures[kSlipVelocityMeasure].mean, ToString(p.status),
               p.simulated_time, p.wall_seconds,
               Duration(elapsed / static_cast<double>(done) * static_cast<double>(remaining - done)));
      if (!regimes.untrusted[i].empty()) progress("{} {:.1f} rpm: untrusted: {}", label, RadPerSecondToRpm(p.parameter), regimes.untrusted[i]);
    }
    WriteSweep(writer, scene, run);

    // Summary on stdout.
    const std::vector<SweepPoint>& points = stepper.points();
    int settled = 0, unsettled = 0;
    double simulated = 0.0, wall = 0.0;
    long steps = 0;
    for (const SweepPoint& p : points) {
      settled += p.status == SweepPointStatus::kSettled ? 1 : 0;
      unsettled += p.status == SweepPointStatus::kNotSettled ? 1 : 0;
      simulated += p.simulated_time;
      wall += p.wall_seconds;
      steps += p.statistics.steps;
    }
    fmt::print(out, "  {}: {} of {} speeds, {:g} → {:g} rpm; {} settled, {} not settled within {:g} s; "
                    "{:.1f} s simulated, {} steps, {:.1f} s wall\n",
               ToString(run.direction()), points.size(), total,
               RadPerSecondToRpm(stepper.options().parameters.front()),
               RadPerSecondToRpm(stepper.options().parameters.back()), settled, unsettled, w.dwell,
               simulated, steps, wall);
    const RubSweepRegimes regimes = run.Regimes();
    for (const RubSweepJump& j : regimes.jumps) {
      fmt::print(out, "    {:<5}  {:<16}  {:6.1f} → {:6.1f} rpm   BP {} → {} Hz{}{}\n",
                 run.structure().contacts[static_cast<std::size_t>(j.contact)].name, ToString(j.kind),
                 j.speed_from_rpm, j.speed_to_rpm, Hz(j.precession_from_hz), Hz(j.precession_to_hz),
                 j.settled ? "" : "  (not settled: a speed ran to its dwell)",
                 j.trusted ? "" : "  (untrusted: see below)");
    }
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (regimes.untrusted[i].empty()) continue;
      fmt::print(out, "    untrusted at {:.1f} rpm: {}\n", RadPerSecondToRpm(points[i].parameter), regimes.untrusted[i]);
    }
    if (stepper.Failed()) {
      failures.push_back(fmt::format("[sweep {}] at {:.1f} rpm: {}", ToString(run.direction()),
                                     RadPerSecondToRpm(points.back().parameter), points.back().message));
    }
  }

  // The jump table: each jump next to the bifurcation of the L1 branches that predicts it. The
  // branches are those of the law the sweeps integrate (tanh, ε = velocity_scale): with exact
  // friction two contacts of an asymmetric rotor cannot both roll (docs/studies/rotating_waves.md),
  // with tanh they can, and the sweeps do.
  const SteadyClock::time_point branches_start = SteadyClock::now();
  const std::vector<RotatingWaveBranch> branches =
      ComputeRotatingWaveBranches(structure, FrictionLawKind::kTanh, BranchOptionsOf(scene));
  WriteRotatingWaveBranches(writer, branches, FrictionLawKind::kTanh,
                            scene.analysis.speed_range_rpm, "/sweeps/branches");
  std::vector<PredictedJump> table;
  for (const auto& run : runs) {
    const std::vector<PredictedJump> rows =
        PredictJumps(ToString(run->direction()), structure, run->stepper().points(), run->Regimes(),
                     branches);
    table.insert(table.end(), rows.begin(), rows.end());
  }
  // One truth: a jump the waves leave open takes the cause the scene's loop gave it at L3 (a
  // chaotic whip's end: loop.h5 beside this file, made for the same structure), predicted for this
  // sweep's own schedule.
  const std::filesystem::path loop_file = h5_file.parent_path() / "loop.h5";
  const std::vector<LoopCrisis> crises = ReadLoopCrises(loop_file, scene);
  if (!crises.empty()) {
    auto rpm = [&](SweepDirection d) {
      std::vector<double> speeds;
      for (double omega : SweepOptionsOf(scene, d).parameters) speeds.push_back(RadPerSecondToRpm(omega));
      return speeds;
    };
    SweepJumpsByLoop(table, crises, rpm(SweepDirection::kUp), rpm(SweepDirection::kDown), w.dwell,
                     LoopOptionsOf(scene).escape_reach_rpm, loop_file.filename().string());
  }
  WriteJumpTable(writer, table);
  fmt::print(out, "  jump table (L1 branches, tanh friction ε = {:g} m/s: {} in {:.3f} s):\n",
             structure.law.velocity_scale, branches.size(), SecondsSince(branches_start));
  for (const PredictedJump& row : table) {
    const RubSweepJump& j = row.jump;
    fmt::print(out, "    {:<4} {:<5} {:<16} {:6.1f} → {:6.1f} rpm  BP {} → {} Hz  ", row.direction,
               row.contact, ToString(j.kind), j.speed_from_rpm, j.speed_to_rpm,
               Hz(j.precession_from_hz), Hz(j.precession_to_hz));
    if (!j.trusted) fmt::print(out, "[untrusted: a speed penetrates beyond max_penetration] ");
    // A cause that is no point of a wave (no precession: the crisis the loop located at L3) is
    // printed with the median it predicts, not with the branch its states were matched to.
    if (!row.bifurcation.empty() && (row.branch.empty() || std::isnan(row.bifurcation_precession_hz))) {
      fmt::print(out, "{}; jump − median {:+.2f} rpm\n", row.bifurcation, row.difference_rpm);
    } else if (row.bifurcation.empty()) {
      if (row.branch.empty()) {
        fmt::print(out, "not predicted: neither state is a rotating wave\n");
      } else {
        fmt::print(out, "not predicted: {} state on {} ({}), no special point within 10 rpm\n",
                   row.matched_side, row.branch,
                   row.branch_stable == 1 ? "stable" : row.branch_stable == 0 ? "unstable" : "?");
      }
    } else {
      fmt::print(out, "{} on {} ({}, {}): {:.2f} rpm, {:.2f} Hz; jump − bifurcation {:+.2f} rpm\n",
                 row.bifurcation, row.branch, row.matched_side,
                 row.branch_stable == 1 ? "stable" : row.branch_stable == 0 ? "unstable" : "?",
                 row.bifurcation_speed_rpm, row.bifurcation_precession_hz, row.difference_rpm);
    }
  }
}

// Level L1: every rotating-wave family of the scene continued over its speed range.
void RunBranches(const Scene& scene, ResultWriter& writer, Progress& progress, std::ostream& out,
                 std::vector<std::string>& failures) {
  const SteadyClock::time_point start = SteadyClock::now();
  const FrictionLawKind law = FrictionLawOf(scene);
  // The imbalance is left out of the rotating waves (note below).
  const std::vector<RotatingWaveBranch> branches = ComputeRotatingWaveBranches(
      StructureOf(scene), law, BranchOptionsOf(scene), [&](int done, int tried, int starts) {
        progress("[branches] {} branches from {} of {} starts ({:.1f} s)", done, tried, starts,
                 SecondsSince(start));
      });
  const double compute_s = SecondsSince(start);
  WriteRotatingWaveBranches(writer, branches, law, scene.analysis.speed_range_rpm);
  const double imbalance = StructureOf(scene).imbalance;
  if (imbalance != 0.0) {
    // A rotating wave is an equilibrium of the frame precessing backward at Ω; the imbalance
    // turns forward at ω, so it is not stationary there: the branches are those of the balanced
    // rotor, and the imbalance response is a periodic orbit (shooting).
    const std::string note = fmt::format(
        "the imbalance ({} kg·m) is left out of the rotating waves: it is not stationary in the "
        "backward-precessing frame", imbalance);
    writer.SetAttribute("/branches", "note", note);
    fmt::print(out, "[branches] note: {}\n", note);
  }
  fmt::print(out, "[branches] L1 rotating waves, {} friction, {}–{} rpm: {} branches in {:.3f} s\n",
             law == FrictionLawKind::kExact ? "exact" : "tanh", scene.analysis.speed_range_rpm[0],
             scene.analysis.speed_range_rpm[1], branches.size(), compute_s);
  for (const RotatingWaveBranch& b : branches) {
    fmt::print(out, "  {} ({}, {}): {}\n", b.name, PatternName(b.normals), b.family,
               b.branch.BriefReport());
    for (std::size_t i = 0; i < b.branch.special_points.size(); ++i) {
      const SpecialPoint& p = b.branch.special_points[i];
      fmt::print(out, "    {:<36} {:9.3f} rpm {:9.3f} Hz{}{}\n", p.Name(),
                 RadPerSecondToRpm(p.lambda), b.SpecialPrecessionHz(i), LyapunovText(p),
                 p.converged ? "" : "  (not located" + (p.note.empty() ? "" : ": " + p.note) + ")");
    }
    if (IsFailure(b.branch.status)) {
      failures.push_back(fmt::format("[branches] {}: {}", b.name, b.branch.message));
    }
  }
}

// Runs the stages, writes the HDF5 file atomically, then the figures. Returns the exit code.
int Execute(const Scene& scene, const std::vector<Stage>& stages, const std::filesystem::path& h5_file,
            const ExecuteOptions& options, std::ostream& out, std::ostream& err) {
  const bool quiet = options.quiet;
  Progress progress(quiet, err);
  const ModelEntry& model = ModelOf(scene);
  for (Stage stage : stages) {
    if (!model.Has(stage)) {
      throw std::invalid_argument(fmt::format("stage \"{}\" does not apply to model \"{}\"",
                                              ToString(stage), ToString(scene.model)));
    }
  }
  if (options.resume && options.fresh) {
    throw std::invalid_argument("--resume and --fresh: give one of them");
  }
  WarnUnitMistakes(scene, err);
  CheckPlan(StagePlanOf(scene, stages), options.force, err);
  if (std::find(stages.begin(), stages.end(), Stage::kSweep) != stages.end() && !options.resume &&
      !options.fresh) {
    for (SweepDirection direction : options.directions) {
      RefuseUnaskedCheckpoint(CheckpointPath(h5_file, direction), fmt::format("{} sweep", ToString(direction)),
                              options.resume, options.fresh);
    }
  }
  const std::filesystem::path out_dir = h5_file.parent_path().empty() ? "." : h5_file.parent_path();
  PrepareToWrite(h5_file);

  ResultWriter writer(h5_file);
  for (const std::filesystem::path& leftover : writer.removed_leftovers()) {
    fmt::print(err, "rubcont: note: {} was left by an interrupted run; it is removed\n",
               leftover.string());
  }
  WriteSceneAttributes(writer, scene);
  std::vector<std::string> failures;
  std::vector<std::string> scripts;
  std::vector<std::filesystem::path> checkpoints;

  fmt::print(out, "scene {} (model {}) from {}\n", scene.name, model.name, scene.source);
  StageContext context{writer, [&](const std::string& line) { progress("{}", line); }, out,
                       failures};
  for (Stage stage : stages) {
    switch (stage) {
      case Stage::kAnalytic: {
        if (model.analytic_skipped && !model.analytic_skipped(scene).empty()) {
          fmt::print(out, "[analytic] L0 closed form not computed: {}\n", model.analytic_skipped(scene));
          break;
        }
        model.analytic(scene, context);
        scripts.push_back("analytic");
        break;
      }
      case Stage::kSweep: {
        SweepStage(scene, options, h5_file, writer, progress, out, err, failures, checkpoints);
        scripts.push_back("sweep");
        break;
      }
      case Stage::kBranches: {
        RunBranches(scene, writer, progress, out, failures);
        scripts.push_back("branches");
        break;
      }
      case Stage::kOrbits: {
        model.orbits(scene, context);
        scripts.push_back(model.orbits_figure);
        break;
      }
      case Stage::kTori: {
        RunRubTori(scene, context);
        scripts.push_back("rub_tori");
        break;
      }
      case Stage::kLoop: {
        RunLoopStage(scene, context);
        scripts.push_back("loop");
        break;
      }
    }
  }
  writer.SetAttribute("/", "level", ToString(ResultLevel(scene, HighestLevel(stages))));
  writer.SetAttribute("/", "status", failures.empty() ? "success" : "failure");
  writer.Commit();
  fmt::print(out, "wrote {}\n", h5_file.string());
  // The result holds every finished speed now: the checkpoints are no longer needed.
  for (const std::filesystem::path& checkpoint : checkpoints) {
    std::error_code ignored;
    std::filesystem::remove(checkpoint, ignored);
  }

  if (!options.figures) scripts.clear();
  for (const std::string& module : scripts) {
    const SteadyClock::time_point start = SteadyClock::now();
    progress("figures: {} -m rubcont.plots.{} (from {}) ...", PythonInterpreter(), module,
             PythonPackageDirectory().string());
    const FigureOutcome figures = MakeFigures(module, h5_file, out_dir, options.figure_format);
    if (figures.made) {
      progress("figures: done in {:.1f} s", SecondsSince(start));
      fmt::print(out, "wrote figures ({}) in {}\n", module, out_dir.string());
    } else {
      fmt::print(err, "rubcont: warning: {}\n", figures.warning);
    }
  }
  for (const std::string& failure : failures) fmt::print(err, "rubcont: numerical failure: {}\n", failure);
  return failures.empty() ? kExitSuccess : kExitFailure;
}

}  // namespace

int RunCommand(const RunRequest& request, std::ostream& out, std::ostream& err) {
  return Guarded(err, [&] {
    const Scene scene = request.scene_file ? LoadScene(*request.scene_file) : DefaultScene();
    const std::filesystem::path dir = std::filesystem::path(request.out_dir) / scene.name;
    ExecuteOptions options;
    options.quiet = request.quiet;
    options.resume = request.resume;
    options.fresh = request.fresh;
    options.figures = request.figures;
    options.figure_format = request.figure_format;
    options.force = request.force;
    return Execute(scene, scene.analysis.stages, dir / (scene.name + ".h5"), options, out, err);
  });
}

int AnalyticCommand(const AnalyticRequest& request, std::ostream& out, std::ostream& err) {
  return Guarded(err, [&] {
    const Scene scene = LoadScene(request.scene_file);
    const std::filesystem::path file =
        request.out_file ? std::filesystem::path(*request.out_file)
                         : std::filesystem::path("results") / scene.name / "analytic.h5";
    ExecuteOptions options;
    options.quiet = request.quiet;
    options.figures = request.figures;
    options.figure_format = request.figure_format;
    return Execute(scene, {Stage::kAnalytic}, file, options, out, err);
  });
}

int SweepCommand(const SweepRequest& request, std::ostream& out, std::ostream& err) {
  return Guarded(err, [&] {
    ExecuteOptions options;
    options.quiet = request.quiet;
    options.resume = request.resume;
    options.fresh = request.fresh;
    options.figures = request.figures;
    options.figure_format = request.figure_format;
    options.force = request.force;
    if (request.direction == "up") {
      options.directions = {SweepDirection::kUp};
    } else if (request.direction == "down") {
      options.directions = {SweepDirection::kDown};
    } else if (request.direction != "both") {
      throw std::invalid_argument("--direction " + request.direction + ": must be up, down or both");
    }
    const Scene scene = LoadScene(request.scene_file);
    const std::filesystem::path file =
        request.out_file ? std::filesystem::path(*request.out_file)
                         : std::filesystem::path("results") / scene.name / "sweep.h5";
    // The branches go into the same file: the figures draw the sweeps over them.
    return Execute(scene, {Stage::kBranches, Stage::kSweep}, file, options, out, err);
  });
}

int BranchesCommand(const AnalyticRequest& request, std::ostream& out, std::ostream& err) {
  return Guarded(err, [&] {
    const Scene scene = LoadScene(request.scene_file);
    const std::filesystem::path file =
        request.out_file ? std::filesystem::path(*request.out_file)
                         : std::filesystem::path("results") / scene.name / "branches.h5";
    ExecuteOptions options;
    options.quiet = request.quiet;
    options.figures = request.figures;
    options.figure_format = request.figure_format;
    return Execute(scene, {Stage::kAnalytic, Stage::kBranches}, file, options, out, err);
  });
}

int SceneCheckCommand(const std::string& file, std::ostream& out, std::ostream& err) {
  return Guarded(err, [&] {
    const Scene scene = LoadScene(file);
    fmt::print(out, "{}: valid scene \"{}\" (model {})\n{}", file, scene.name, ToString(scene.model),
               DescribeScene(scene));
    // What `run` would refuse or warn of, as warnings.
    WarnUnitMistakes(scene, err);
    const std::string excess = ExcessiveWork(StagePlanOf(scene, scene.analysis.stages));
    if (!excess.empty()) fmt::print(err, "rubcont: warning: {}; `rubcont run` refuses it without --force\n", excess);
    return kExitSuccess;
  });
}

int SceneMatricesCommand(const std::string& file, const std::string& out_path, std::ostream& out,
                         std::ostream& err) {
  return Guarded(err, [&] {
    const Scene scene = LoadScene(file);
    if (!scene.flexible.enabled) {
      throw std::invalid_argument(fmt::format(
          "scene {} has no [flexible] section: its rigid model has no structural matrices to "
          "write (level L4 scenes only)", file));
    }
    const MatrixRubModel model = FlexibleMatricesOf(scene);
    WriteStructuralMatrices(out_path, model.full);
    // The section that loads them back: the same structure, so the same results.
    fmt::print(out, "# {}: the {} × {} matrices of scene {}'s flexible structure\n"
                    "[flexible.matrices]\nfile = {}\nrotor_contact_coordinates = [{}, {}]\n"
                    "stator_contact_coordinates = [{}, {}]\nimbalance_coordinate = {}\n",
               out_path, model.full.Coordinates(), model.full.Coordinates(), scene.name,
               schema::Quote(std::filesystem::absolute(out_path).lexically_normal().string()),
               model.contacts[0].rotor, model.contacts[1].rotor, model.contacts[0].stator,
               model.contacts[1].stator, model.imbalance_coordinate);
    return kExitSuccess;
  });
}

void RefuseUnaskedCheckpoint(const std::filesystem::path& checkpoint, const std::string& what, bool resume,
                             bool fresh) {
  if (resume || fresh || !std::filesystem::exists(checkpoint)) return;
  throw std::invalid_argument(fmt::format("{} holds the finished speeds of an interrupted {}: --resume continues "
                                          "from it, --fresh starts again and overwrites it",
                                          checkpoint.string(), what));
}

int SceneKeysCommand(std::ostream& out) {
  out << SceneKeysMarkdown();
  return kExitSuccess;
}

}  // namespace rubcont
