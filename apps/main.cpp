// The rubcont executable: argument parsing only (CLI11 stays in this translation unit); the
// commands live in the rubcont_io library (apps/commands.h).
#include <csignal>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "apps/commands.h"
#include "apps/attractor_command.h"
#include "apps/batch_command.h"
#include "apps/ensemble_command.h"
#include "apps/lifetime_command.h"
#include "apps/loop_command.h"
#include "apps/figures.h"
#include "apps/fit_command.h"
#include "apps/flexible_command.h"
#include "apps/map_command.h"
#include "apps/ross_import.h"
#include "apps/version.h"

namespace {

// --format of a command with figures.
void AddFigureFormat(CLI::App* command, std::string& format) {
  std::vector<std::string> formats(rubcont::kFigureFormats.begin(), rubcont::kFigureFormats.end());
  command->add_option("--format", format, "file format of the figures: png, pdf or svg")
      ->check(CLI::IsMember(formats))
      ->capture_default_str();
}

}  // namespace

int main(int argc, char** argv) {
  // Past a file-size limit (ulimit -f) a write fails with EFBIG, which the writer reports with the
  // file's name, instead of SIGXFSZ ending the process without a word.
  std::signal(SIGXFSZ, SIG_IGN);
  CLI::App app{"rubcont: continuation and bifurcation toolkit for rotor–stator rub "
               "(dry-friction backward whirl and whip).\n"
               "Exit codes: 0 success, 1 numerical failure or I/O error, 2 bad scene or arguments."};
  app.set_version_flag("--version", std::string("rubcont ") + rubcont::Version() + " (git " +
                                        rubcont::GitDescribe() + "), BSD-3-Clause licence");
  app.require_subcommand(1);

  rubcont::RunRequest run_request;
  std::string run_scene;
  CLI::App* run = app.add_subcommand("run", "run every stage the scene asks for; results go to "
                                            "<out>/<scene name>/ (HDF5 + figures)");
  run->add_option("SCENE", run_scene, "scene file (TOML); default: the built-in default scene "
                                      "(scenes/default.toml)");
  run->add_option("--out", run_request.out_dir, "output directory")->capture_default_str();
  run->add_flag("-q,--quiet", run_request.quiet, "no progress on stderr");
  AddFigureFormat(run, run_request.figure_format);
  run->add_flag("--resume", run_request.resume,
                "sweeps continue from the checkpoints of an interrupted run");
  run->add_flag("--fresh", run_request.fresh,
                "sweeps start again and overwrite the checkpoints of an interrupted run (without "
                "--resume or --fresh, a checkpoint is refused: exit 2)");
  run->add_flag("--force", run_request.force, "run work the plan check refuses (more than 1e6 speeds or copy runs, a week of estimated CPU, 4 GB of memory)");
  run->add_flag("!--no-figures", run_request.figures,
                "write the HDF5 file and the summary only (scripts/check_results.sh)");

  rubcont::AnalyticRequest analytic_request;
  std::string analytic_out;
  CLI::App* analytic = app.add_subcommand(
      "analytic", "level L0: closed-form Mode 1 / Mode 2 contact forces, μ_req and transitions");
  analytic->add_option("SCENE", analytic_request.scene_file, "scene file (TOML)")->required();
  analytic->add_option("--out", analytic_out,
                       "HDF5 file to write (figures go next to it); default "
                       "results/<scene name>/analytic.h5");
  analytic->add_flag("-q,--quiet", analytic_request.quiet, "no progress on stderr");
  AddFigureFormat(analytic, analytic_request.figure_format);

  rubcont::SweepRequest sweep_request;
  std::string sweep_out;
  CLI::App* sweep = app.add_subcommand(
      "sweep", "level L3: time-marching speed-up / speed-down sweeps of [analysis.sweep] (BP "
               "frequency, slip velocity, waterfall spectra, jumps), checkpointed per speed");
  sweep->add_option("SCENE", sweep_request.scene_file, "scene file (TOML)")->required();
  sweep->add_option("--direction", sweep_request.direction, "up, down or both (up first)")
      ->check(CLI::IsMember({"up", "down", "both"}))
      ->capture_default_str();
  sweep->add_option("--out", sweep_out,
                    "HDF5 file to write (figures and checkpoints go next to it); default "
                    "results/<scene name>/sweep.h5");
  sweep->add_flag("-q,--quiet", sweep_request.quiet, "no progress on stderr");
  AddFigureFormat(sweep, sweep_request.figure_format);
  sweep->add_flag("--resume", sweep_request.resume,
                  "continue from the checkpoints of an interrupted sweep (<out>.<direction>."
                  "checkpoint.h5) instead of starting again");
  sweep->add_flag("--fresh", sweep_request.fresh,
                  "start again and overwrite the checkpoints of an interrupted sweep (without "
                  "--resume or --fresh, a checkpoint is refused: exit 2)");
  sweep->add_flag("--force", sweep_request.force, "run work the plan check refuses (more than 1e6 speeds or copy runs, a week of estimated CPU, 4 GB of memory)");
  sweep->add_flag("!--no-figures", sweep_request.figures,
                  "write the HDF5 file and the summary only (scripts/check_results.sh)");
  rubcont::AnalyticRequest branches_request;
  std::string branches_out;
  CLI::App* branches = app.add_subcommand(
      "branches", "level L1: whirl and whip rotating waves continued in running speed, with "
                  "stability and special points (runs the analytic stage too)");
  branches->add_option("SCENE", branches_request.scene_file, "scene file (TOML)")->required();
  branches->add_option("--out", branches_out,
                       "HDF5 file to write (figures go next to it); default "
                       "results/<scene name>/branches.h5");
  branches->add_flag("-q,--quiet", branches_request.quiet, "no progress on stderr");
  AddFigureFormat(branches, branches_request.figure_format);

  rubcont::MapRequest map_request;
  std::vector<double> map_range;
  CLI::App* map = app.add_subcommand(
      "map", "hysteresis map in (running speed, design parameter): regions with one, two or no "
             "stable circular state, and the jump curves (HDF5 /maps/<parameter> + figure)");
  map->add_option("SCENE", map_request.scene_file, "scene file (TOML), model two_point")->required();
  map->add_option("--parameter", map_request.parameter,
                  "friction | stator_damping | support_stiffness | center_damping | rci_ratio | "
                  "contact_stiffness")->required();
  map->add_option("--range", map_range, "LO HI: the parameter's range (default: ±50 % of the "
                                        "scene's value; rci_ratio 0.75–1.35 of it)")->expected(2);
  map->add_option("--eta-points", map_request.eta_points, "grid values of the parameter")
      ->capture_default_str();
  map->add_option("--speed-points", map_request.speed_points, "grid speeds")->capture_default_str();
  map->add_option("--threads", map_request.threads,
                  "threads for the grid (0: one per core); under mpirun the grid is also shared "
                  "out over the ranks")->capture_default_str();
  map->add_option("--out", map_request.out_file,
                  "HDF5 file (figure next to it); default results/<scene>/map_<parameter>.h5");
  map->add_flag("-q,--quiet", map_request.quiet, "no progress on stderr");
  AddFigureFormat(map, map_request.figure_format);
  map->add_flag("!--no-figures", map_request.figures, "write the HDF5 file and the summary only");
  map->add_flag("--force", map_request.force, "run work the plan check refuses (more than 1e6 speeds or copy runs, a week of estimated CPU, 4 GB of memory)");

  rubcont::FitRequest fit_request;
  CLI::App* fit = app.add_subcommand(
      "fit", "identification: fit design parameters to target jump speeds and whip frequencies "
             "(NLopt global then local search; HDF5 /fit)");
  fit->add_option("SCENE", fit_request.scene_file, "scene file (TOML), model two_point")->required();
  fit->add_option("--targets", fit_request.targets_file,
                  "targets file (TOML): [[parameter]], [[target]], [fit] (apps/fit_command.h)")
      ->required();
  fit->add_option("--out", fit_request.out_file, "HDF5 file; default results/<scene>/fit.h5");
  fit->add_flag("-q,--quiet", fit_request.quiet, "no progress on stderr");
  fit->add_option("--threads", fit_request.threads,
                  "threads for the batches of evaluations (0: one per core); under mpirun they are "
                  "also shared over the ranks")->capture_default_str();

  rubcont::BatchRequest batch_request;
  CLI::App* batch = app.add_subcommand(
      "batch", "many independent jobs (sweeps, maps, fits, branch sets) from a jobs file, shared "
               "out over the ranks of `mpirun -n N rubcont batch JOBS.toml`; a re-run does only "
               "what is missing (apps/batch_command.h)");
  batch->add_option("JOBS", batch_request.jobs_file, "jobs file (TOML): out, [[job]] tables")
      ->required();
  batch->add_option("--out", batch_request.out_dir,
                    "output directory (default: the file's `out`, else results/batch/<stem>)");
  batch->add_flag("-q,--quiet", batch_request.quiet, "no progress on stderr");
  batch->add_flag("--list", batch_request.list,
                  "print the jobs numbered as --job-index counts them, and run none");
  batch->add_option("--job-index", batch_request.job_index,
                    "run only job N, numbered from 1 as in the summary (a Slurm array: "
                    "--array=1-<jobs>); default: $SLURM_ARRAY_TASK_ID when set, else every job");
  batch->add_option("--stale-after", batch_request.claims.stale_after_s,
                    "seconds after its last heartbeat at which another run's claim on a job is "
                    "taken over (a claim of a process gone from this host is taken at once)")
      ->capture_default_str();

  rubcont::EnsembleRequest ensemble_request;
  std::string ensemble_out;
  CLI::App* ensemble = app.add_subcommand(
      "ensemble", "level L3: how long the state a sweep reaches lasts at the next speed: perturbed "
                  "copies run in parallel until every contact is in one regime");
  ensemble->add_option("SCENE", ensemble_request.scene_file, "scene file (TOML)")->required();
  ensemble->add_option("--speed", ensemble_request.speed_rpm,
                       "running speed of the copies [rpm]; the scene's sweep reaches the state "
                       "at the speed before it")->required();
  ensemble->add_option("--direction", ensemble_request.direction, "the sweep that reaches it: up or down")
      ->capture_default_str();
  ensemble->add_option("--copies", ensemble_request.copies, "number of copies")->capture_default_str();
  ensemble->add_option("--duration", ensemble_request.duration, "simulated time per copy [s]")
      ->capture_default_str();
  ensemble->add_option("--window", ensemble_request.window,
                       "window [s]; each stretch of two is classified as a sweep speed")
      ->capture_default_str();
  ensemble->add_option("--perturbation", ensemble_request.perturbation,
                       "normal perturbation of the start, in units of each state's scale")
      ->capture_default_str();
  ensemble->add_option("--seed", ensemble_request.seed, "seed of copy 0 (copy i: seed + i)")
      ->capture_default_str();
  ensemble->add_option("--threads", ensemble_request.threads, "threads (0: one per core)")
      ->capture_default_str();
  ensemble->add_option("--until", ensemble_request.until,
                       "the regime every contact must reach: whirl, whip, intermittent, no_contact")
      ->capture_default_str();
  ensemble->add_option("--until-above", ensemble_request.until_above_hz,
                       "> 0: arrive when the backward precession exceeds this [Hz] instead of --until "
                       "(a whip that lands on a faster slipping state)")
      ->capture_default_str();
  ensemble->add_option("--until-contacts", ensemble_request.until_contacts,
                       "every, any, or a contact's name (left, right): the contacts that must arrive "
                       "(any: a rotor with unequal clearances lands with one contact rolling)")
      ->capture_default_str();
  ensemble->add_option("--out", ensemble_out,
                       "HDF5 file; default results/<scene>/ensemble_<speed>rpm.h5");
  ensemble->add_flag("-q,--quiet", ensemble_request.quiet, "no progress on stderr");
  AddFigureFormat(ensemble, ensemble_request.figure_format);
  ensemble->add_flag("--force", ensemble_request.force, "run work the plan check refuses (more than 1e6 speeds or copy runs, a week of estimated CPU, 4 GB of memory)");

  rubcont::LifetimeRequest lifetime_request;
  std::string lifetime_out;
  CLI::App* lifetime = app.add_subcommand(
      "lifetime", "level L3: where a state a sweep reaches ceases to exist: escape rates of perturbed copies at "
                  "each speed, the crisis law fitted to them, and long-dwell sweeps against its prediction");
  lifetime->add_option("SCENE", lifetime_request.scene_file, "scene file (TOML)")->required();
  lifetime->add_option("--from", lifetime_request.from_rpm,
                       "first speed [rpm]; the scene's sweep reaches the state at the speed before it")->required();
  lifetime->add_option("--to", lifetime_request.to_rpm, "last speed [rpm]")->required();
  lifetime->add_option("--step", lifetime_request.step_rpm, "speed step of the ensembles [rpm]")->capture_default_str();
  lifetime->add_option("--direction", lifetime_request.direction,
                       "up or down: the sweep that reaches the state, and the side on which it ends")
      ->capture_default_str();
  lifetime->add_option("--copies", lifetime_request.copies, "copies per speed")->capture_default_str();
  lifetime->add_option("--duration", lifetime_request.duration, "simulated time per copy [s]")->capture_default_str();
  lifetime->add_option("--window", lifetime_request.window, "window [s]; each stretch of two is classified as a sweep speed")
      ->capture_default_str();
  lifetime->add_option("--perturbation", lifetime_request.perturbation,
                       "normal perturbation of the start, in units of each state's scale")->capture_default_str();
  lifetime->add_option("--seed", lifetime_request.seed, "seed of the first copy at the first speed")->capture_default_str();
  lifetime->add_option("--threads", lifetime_request.threads, "threads (0: one per core)")->capture_default_str();
  lifetime->add_option("--until", lifetime_request.until,
                       "the regime every contact must reach: whirl, whip, intermittent, no_contact")
      ->capture_default_str();
  lifetime->add_option("--until-above", lifetime_request.until_above_hz,
                       "> 0: arrive when the backward precession exceeds this [Hz] instead of --until "
                       "(a whip that lands on a faster slipping state)")
      ->capture_default_str();
  lifetime->add_option("--until-contacts", lifetime_request.until_contacts,
                       "every, any, or a contact's name (left, right): the contacts that must arrive "
                       "(any: a rotor with unequal clearances lands with one contact rolling)")
      ->capture_default_str();
  lifetime->add_option("--check-copies", lifetime_request.check_copies,
                       "perturbed sweeps through the speeds against the fitted law (0: none)")->capture_default_str();
  lifetime->add_option("--check-step", lifetime_request.check_step_rpm, "speed step of the check sweeps [rpm]")
      ->capture_default_str();
  lifetime->add_option("--check-dwell", lifetime_request.check_dwell, "simulated time per speed of the check sweeps [s]")
      ->capture_default_str();
  lifetime->add_option("--out", lifetime_out, "HDF5 file; default results/<scene>/lifetime.h5");
  lifetime->add_flag("--resume", lifetime_request.resume,
                     "continue from <out stem>.checkpoint.h5 (written after the approach and after every speed)");
  lifetime->add_flag("--fresh", lifetime_request.fresh,
                     "start again although a checkpoint exists (it is overwritten; with neither --resume nor "
                     "--fresh, a checkpoint is refused: exit 2)");
  lifetime->add_flag("-q,--quiet", lifetime_request.quiet, "no progress on stderr");
  AddFigureFormat(lifetime, lifetime_request.figure_format);
  lifetime->add_flag("--force", lifetime_request.force, "run work the plan check refuses (more than 1e6 speeds or copy runs, a week of estimated CPU, 4 GB of memory)");

  rubcont::LoopRequest loop_request;
  std::vector<double> loop_schedule;
  double loop_budget = 0.0;
  std::string loop_out;
  CLI::App* loop = app.add_subcommand(
      "loop", "the hysteresis loop of the scene's rotor, explained: every jump of a run-up and a run-down, its "
              "cause (L1 rotating waves; L3 escape rates for a whip that ends by chance), how sure, and the level");
  loop->add_option("SCENE", loop_request.scene_file, "scene file (TOML), model two_point")->required();
  loop->add_option("--schedule", loop_schedule,
                   "STEP_RPM DWELL_S: the run's speed step and time per speed; default the scene's "
                   "[analysis.sweep] speed_step_rpm and dwell")
      ->expected(2);
  loop->add_option("--budget", loop_budget,
                   "G work units for the whole loop (a unit: one explicit step of one state; the same "
                   "on every machine, about 80 s of CPU per G here); default the scene's, 4");
  loop->add_option("--threads", loop_request.threads, "threads (0: one per core)")->capture_default_str();
  loop->add_option("--out", loop_out, "HDF5 file; default results/<scene>/loop.h5");
  loop->add_flag("!--no-figures", loop_request.figures, "write the HDF5 file and the summary only");
  loop->add_flag("-q,--quiet", loop_request.quiet, "no progress on stderr");
  AddFigureFormat(loop, loop_request.figure_format);
  loop->add_flag("--force", loop_request.force, "run work the plan check refuses (more than 1e6 speeds or copy runs, a week of estimated CPU, 4 GB of memory)");

  rubcont::FlexibleRequest flexible_request;
  std::string flexible_out;
  int flexible_modes = 4;
  bool flexible_no_gyroscopic = false;
  CLI::App* flexible = app.add_subcommand(
      "flexible", "level L4: the scene's rotor and stator as Timoshenko shafts (sections fitted to the "
                  "thesis's Tables 2–3), reduced by Craig–Bampton; its rotating waves against the rigid model's");
  flexible->add_option("SCENE", flexible_request.scene_file, "scene file (TOML), model two_point")->required();
  flexible->add_option("--modes", flexible_modes,
                       "fixed-interface modes kept; default the scene's [flexible] modes, or 4");
  flexible->add_flag("--no-gyroscopic", flexible_no_gyroscopic, "leave out the polar inertias (as the rigid model)");
  flexible->add_option("--out", flexible_out, "HDF5 file; default results/<scene>/flexible.h5");
  flexible->add_flag("-q,--quiet", flexible_request.quiet, "no progress on stderr");

  rubcont::AttractorRequest attractor_request;
  std::string attractor_out, attractor_approach;
  double attractor_to = 0.0, attractor_tolerance = 0.0;
  CLI::App* attractor = app.add_subcommand(
      "attractor", "level L3: what the motion is at each speed: Lyapunov exponents (variational "
                   "equations) and Poincaré sections of long transients");
  attractor->add_option("SCENE", attractor_request.scene_file, "scene file (TOML)")->required();
  attractor->add_option("--from", attractor_request.from_rpm,
                        "first speed [rpm]; the scene's sweep reaches the state at the speed before it")
      ->required();
  attractor->add_option("--to", attractor_to, "last speed [rpm]; default: --from alone");
  attractor->add_option("--step", attractor_request.step_rpm, "speed step [rpm]")->capture_default_str();
  attractor->add_option("--direction", attractor_request.direction,
                        "up or down: the order of the speeds (and the approach sweep)")
      ->capture_default_str();
  attractor->add_option("--approach", attractor_approach,
                        "up or down: the sweep that reaches the first speed; default --direction "
                        "(the other one steps back from the branch a sweep reached: hysteresis)");
  attractor->add_option("--duration", attractor_request.duration, "counted time per speed [s]")
      ->capture_default_str();
  attractor->add_option("--discard", attractor_request.discard, "uncounted time first, per speed [s]")
      ->capture_default_str();
  attractor->add_option("--interval", attractor_request.interval,
                        "re-orthonormalization interval of the tangents [s]")
      ->capture_default_str();
  attractor->add_option("--sample", attractor_request.sample_interval,
                        "sampling interval of the section (penetration maxima) [s]")
      ->capture_default_str();
  attractor->add_option("--exponents", attractor_request.exponents, "number of Lyapunov exponents")
      ->capture_default_str();
  attractor->add_option("--tolerance", attractor_tolerance,
                        "relative = absolute tolerance; default: the scene's sweep integrator's");
  attractor->add_option("--out", attractor_out, "HDF5 file; default results/<scene>/attractor.h5");
  attractor->add_flag("-q,--quiet", attractor_request.quiet, "no progress on stderr");
  AddFigureFormat(attractor, attractor_request.figure_format);
  attractor->add_flag("--force", attractor_request.force, "run work the plan check refuses (more than 1e6 speeds or copy runs, a week of estimated CPU, 4 GB of memory)");

  CLI::App* scene = app.add_subcommand("scene", "scene files");
  scene->require_subcommand(1);
  std::string check_file;
  CLI::App* check = scene->add_subcommand("check", "validate a scene and print its resolved values");
  check->add_option("FILE", check_file, "scene file (TOML)")->required();
  CLI::App* keys = scene->add_subcommand("keys", "print the scene key reference (markdown)");
  std::string matrices_file, matrices_out;
  CLI::App* matrices = scene->add_subcommand(
      "matrices", "write the full M, C, K, G of a flexible scene's structure and print the "
                  "[flexible.matrices] section that reads them");
  matrices->add_option("FILE", matrices_file, "scene file (TOML) with [flexible]")->required();
  matrices->add_option("--out", matrices_out, "FILE.h5 (HDF5) or a directory (MatrixMarket .mtx)")
      ->required();

  rubcont::ImportRossRequest ross_request;
  std::vector<int> ross_stations;
  std::string ross_out;
  CLI::App* import_ross = scene->add_subcommand(
      "import-ross", "a ROSS rotor file (ross.Rotor.save's TOML) as the listed rotor of a scene: "
                     "prints the scene (or writes --out)");
  import_ross->add_option("ROSS", ross_request.ross_file, "ROSS rotor file (TOML)")->required();
  import_ross->add_option("--base", ross_request.base_scene,
                          "two_point scene whose stator, contacts and analysis are kept (its rotor "
                          "is replaced)")->required();
  import_ross->add_option("--contact-stations", ross_stations,
                          "L R: the ROSS nodes of the left and right contacts")
      ->expected(2)->required();
  import_ross->add_option("--out", ross_out, "scene file to write (TOML); default: print it");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);  // prints help / version / the error
    return code == 0 ? rubcont::kExitSuccess : rubcont::kExitBadInput;
  }

  if (*run) {
    if (!run_scene.empty()) run_request.scene_file = run_scene;
    return rubcont::RunCommand(run_request, std::cout, std::cerr);
  }
  if (*analytic) {
    if (!analytic_out.empty()) analytic_request.out_file = analytic_out;
    return rubcont::AnalyticCommand(analytic_request, std::cout, std::cerr);
  }
  if (*sweep) {
    if (!sweep_out.empty()) sweep_request.out_file = sweep_out;
    return rubcont::SweepCommand(sweep_request, std::cout, std::cerr);
  }
  if (*branches) {
    if (!branches_out.empty()) branches_request.out_file = branches_out;
    return rubcont::BranchesCommand(branches_request, std::cout, std::cerr);
  }
  if (*map) {
    if (map_range.size() == 2) {
      map_request.eta_min = map_range[0];
      map_request.eta_max = map_range[1];
    }
    return rubcont::MapCommand(map_request, std::cout, std::cerr);
  }
  if (*fit) return rubcont::FitCommand(fit_request, std::cout, std::cerr);
  if (*batch) return rubcont::BatchCommand(batch_request, std::cout, std::cerr);
  if (*ensemble) {
    if (!ensemble_out.empty()) ensemble_request.out_file = ensemble_out;
    return rubcont::EnsembleCommand(ensemble_request, std::cout, std::cerr);
  }
  if (*lifetime) {
    if (!lifetime_out.empty()) lifetime_request.out_file = lifetime_out;
    return rubcont::LifetimeCommand(lifetime_request, std::cout, std::cerr);
  }
  if (*loop) {
    if (loop_schedule.size() == 2) {
      loop_request.step_rpm = loop_schedule[0];
      loop_request.dwell = loop_schedule[1];
    }
    if (loop->count("--budget") > 0) loop_request.budget = loop_budget;
    if (!loop_out.empty()) loop_request.out_file = loop_out;
    return rubcont::LoopCommand(loop_request, std::cout, std::cerr);
  }
  if (*attractor) {
    if (!attractor_out.empty()) attractor_request.out_file = attractor_out;
    if (attractor->count("--to") > 0) attractor_request.to_rpm = attractor_to;
    if (attractor->count("--tolerance") > 0) attractor_request.tolerance = attractor_tolerance;
    if (attractor->count("--approach") > 0) attractor_request.approach = attractor_approach;
    return rubcont::AttractorCommand(attractor_request, std::cout, std::cerr);
  }
  if (*flexible) {
    if (!flexible_out.empty()) flexible_request.out_file = flexible_out;
    if (flexible->count("--modes") > 0) flexible_request.modes = flexible_modes;
    if (flexible_no_gyroscopic) flexible_request.gyroscopic = false;
    return rubcont::FlexibleCommand(flexible_request, std::cout, std::cerr);
  }
  if (*check) return rubcont::SceneCheckCommand(check_file, std::cout, std::cerr);
  if (*keys) return rubcont::SceneKeysCommand(std::cout);
  if (*import_ross) {
    ross_request.contact_stations = {ross_stations[0], ross_stations[1]};
    if (!ross_out.empty()) ross_request.out_file = ross_out;
    return rubcont::ImportRossCommand(ross_request, std::cout, std::cerr);
  }
  if (*matrices) return rubcont::SceneMatricesCommand(matrices_file, matrices_out, std::cout, std::cerr);
  return rubcont::kExitBadInput;
}
