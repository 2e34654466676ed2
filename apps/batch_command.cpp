#include "apps/batch_command.h"

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <toml++/toml.h>

#include "apps/atomic_file.h"
#include "apps/claims.h"
#include "apps/commands.h"
#include "apps/fit_command.h"
#include "apps/guarded.h"
#include "apps/map_command.h"
#include "apps/ranks.h"
#include "solvers/stopwatch.h"

namespace rubcont {
namespace {

namespace fs = std::filesystem;

const std::set<std::string> kCommands{"run", "analytic", "branches", "sweep", "map", "fit"};
const std::set<std::string> kKeys{"name",       "command",      "scene",   "direction",
                                  "parameter",  "range",        "eta_points", "speed_points",
                                  "targets",    "figures",      "vary"};

struct Job {
  std::string name;
  std::string command;
  std::optional<std::string> scene;
  std::string direction = "both";
  std::string parameter;
  std::optional<std::pair<double, double>> range;
  int eta_points = 31;
  int speed_points = 481;
  std::string targets;
  bool figures = false;
};

std::string Where(const fs::path& file, int index) {
  return fmt::format("{}: job {}", file.string(), index + 1);
}

std::string NodeText(const toml::node& node) {
  if (node.is_string()) return "\"" + node.value<std::string>().value() + "\"";
  std::ostringstream s;
  s << toml::node_view<const toml::node>(node);
  return s.str();
}

// The job a table describes (its `vary` already applied); throws invalid_argument naming the key,
// value and rule.
Job JobOf(const toml::table& table, const std::string& where) {
  Job job;
  for (const auto& [key, node] : table) {
    if (!kKeys.count(std::string(key))) {
      throw std::invalid_argument(fmt::format("{}: {}: unknown key (one of command, scene, name, "
                                              "direction, parameter, range, eta_points, "
                                              "speed_points, targets, figures, vary)",
                                              where, key.str()));
    }
  }
  auto text = [&](const char* key) -> std::optional<std::string> {
    const toml::node* node = table.get(key);
    if (node == nullptr) return std::nullopt;
    if (!node->is_string()) {
      throw std::invalid_argument(
          fmt::format("{}: {} = {}: must be a string", where, key, NodeText(*node)));
    }
    return node->value<std::string>();
  };
  auto integer = [&](const char* key, int fallback, int lo, int hi) {
    const toml::node* node = table.get(key);
    if (node == nullptr) return fallback;
    const std::optional<int64_t> v = node->is_integer() ? node->value<int64_t>() : std::nullopt;
    if (!v || *v < lo || *v > hi) {
      throw std::invalid_argument(
          fmt::format("{}: {} = {}: must be an integer in {} … {}", where, key, NodeText(*node), lo, hi));
    }
    return static_cast<int>(*v);
  };
  const std::optional<std::string> command = text("command");
  if (!command || !kCommands.count(*command)) {
    throw std::invalid_argument(fmt::format(
        "{}: command = {}: must be one of run, analytic, branches, sweep, map, fit", where,
        command ? "\"" + *command + "\"" : std::string("(missing)")));
  }
  job.command = *command;
  job.scene = text("scene");
  if (!job.scene && job.command != "run") {
    throw std::invalid_argument(fmt::format("{}: scene: missing; required for command \"{}\"",
                                            where, job.command));
  }
  if (const auto direction = text("direction")) {
    if (*direction != "up" && *direction != "down" && *direction != "both") {
      throw std::invalid_argument(fmt::format("{}: direction = \"{}\": must be up, down or both",
                                              where, *direction));
    }
    job.direction = *direction;
  }
  job.parameter = text("parameter").value_or("");
  if (job.command == "map" && job.parameter.empty()) {
    throw std::invalid_argument(fmt::format("{}: parameter: missing; required for command \"map\"", where));
  }
  if (const toml::node* node = table.get("range")) {
    const toml::array* a = node->as_array();
    if (a == nullptr || a->size() != 2 || !(*a)[0].is_number() || !(*a)[1].is_number()) {
      throw std::invalid_argument(
          fmt::format("{}: range = {}: must be two numbers [lo, hi]", where, NodeText(*node)));
    }
    job.range = std::make_pair((*a)[0].value<double>().value(), (*a)[1].value<double>().value());
  }
  job.eta_points = integer("eta_points", job.eta_points, 2, 2000);
  job.speed_points = integer("speed_points", job.speed_points, 2, 100000);
  job.targets = text("targets").value_or("");
  if (job.command == "fit" && job.targets.empty()) {
    throw std::invalid_argument(fmt::format("{}: targets: missing; required for command \"fit\"", where));
  }
  if (const toml::node* node = table.get("figures")) {
    if (!node->is_boolean()) {
      throw std::invalid_argument(
          fmt::format("{}: figures = {}: must be true or false", where, NodeText(*node)));
    }
    job.figures = node->value<bool>().value();
  }
  if (const auto name = text("name")) {
    job.name = *name;
  } else {
    job.name = (job.scene ? fs::path(*job.scene).stem().string() : std::string("default")) + "_" +
               job.command;
    if (job.command == "sweep") job.name += "_" + job.direction;
    if (job.command == "map") job.name += "_" + job.parameter;
  }
  if (job.name.empty() || job.name.find('/') != std::string::npos) {
    throw std::invalid_argument(
        fmt::format("{}: name = \"{}\": must be a non-empty file name without '/'", where, job.name));
  }
  return job;
}

// The jobs of one [[job]] table: itself, or one per combination of its `vary` lists (the name,
// when given, gets each varied value appended: a path's stem).
std::vector<Job> Expand(const toml::table& table, const std::string& where) {
  const toml::node* vary_node = table.get("vary");
  if (vary_node == nullptr) return {JobOf(table, where)};
  const toml::table* vary = vary_node->as_table();
  if (vary == nullptr || vary->empty()) {
    throw std::invalid_argument(fmt::format(
        "{}: vary = {}: must be a table of lists, e.g. {{ direction = [\"up\", \"down\"] }}", where,
        NodeText(*vary_node)));
  }
  std::vector<toml::table> combinations{table};
  combinations.front().erase("vary");
  std::vector<std::vector<std::string>> suffixes{{}};
  for (const auto& [key, node] : *vary) {
    const toml::array* values = node.as_array();
    if (values == nullptr || values->empty()) {
      throw std::invalid_argument(fmt::format("{}: vary.{} = {}: must be a non-empty list", where,
                                              key.str(), NodeText(node)));
    }
    std::vector<toml::table> next;
    std::vector<std::vector<std::string>> next_suffixes;
    for (size_t c = 0; c < combinations.size(); ++c) {
      for (const toml::node& value : *values) {
        toml::table t = combinations[c];
        t.insert_or_assign(key, value);
        next.push_back(std::move(t));
        std::vector<std::string> s = suffixes[c];
        const std::string shown = value.is_string() ? value.value<std::string>().value() : NodeText(value);
        s.push_back(key.str() == "scene" ? fs::path(shown).stem().string() : shown);
        next_suffixes.push_back(std::move(s));
      }
    }
    combinations = std::move(next);
    suffixes = std::move(next_suffixes);
  }
  std::vector<Job> jobs;
  for (size_t c = 0; c < combinations.size(); ++c) {
    Job job = JobOf(combinations[c], where);
    if (table.get("name") != nullptr) {
      for (const std::string& s : suffixes[c]) job.name += "_" + s;
    }
    jobs.push_back(std::move(job));
  }
  return jobs;
}

struct JobsFile {
  fs::path out;
  std::vector<Job> jobs;
};

JobsFile ReadJobs(const fs::path& file, const std::optional<std::string>& out_dir) {
  if (fs::is_directory(file)) {
    throw std::invalid_argument(fmt::format("{}: is a directory, not a jobs file", file.string()));
  }
  toml::table root;
  try {
    root = toml::parse_file(file.string());
  } catch (const toml::parse_error& e) {
    throw std::invalid_argument(fmt::format("{}:{}:{}: {}", file.string(), e.source().begin.line,
                                            e.source().begin.column, e.description()));
  }
  JobsFile jobs;
  jobs.out = fs::path("results") / "batch" / file.stem();
  for (const auto& [key, node] : root) {
    if (key.str() != "out" && key.str() != "job") {
      throw std::invalid_argument(
          fmt::format("{}: {}: unknown key (the file holds `out` and [[job]] tables)", file.string(), key.str()));
    }
  }
  if (const toml::node* node = root.get("out")) {
    if (!node->is_string()) {
      throw std::invalid_argument(fmt::format("{}: out = {}: must be a string", file.string(), NodeText(*node)));
    }
    jobs.out = node->value<std::string>().value();
  }
  if (out_dir) jobs.out = *out_dir;
  const toml::array* list = root.get_as<toml::array>("job");
  if (list == nullptr || list->empty()) {
    throw std::invalid_argument(fmt::format("{}: job: missing; at least one [[job]] table", file.string()));
  }
  std::set<std::string> names;
  for (size_t i = 0; i < list->size(); ++i) {
    const toml::table* table = (*list)[i].as_table();
    const std::string where = Where(file, static_cast<int>(i));
    if (table == nullptr) throw std::invalid_argument(where + ": must be a [[job]] table");
    for (Job& job : Expand(*table, where)) {
      if (!names.insert(job.name).second) {
        throw std::invalid_argument(fmt::format(
            "{}: name = \"{}\": another job has the same name (give each job a `name`)", where, job.name));
      }
      jobs.jobs.push_back(std::move(job));
    }
  }
  return jobs;
}

// Each job's files (result, figures) in a folder of its own: <out>/<name>/<name>.h5 (run:
// <out>/<name>/<scene name>/<scene name>.h5, the path the command prints).
fs::path ResultOf(const Job& job, const fs::path& out) { return out / job.name / (job.name + ".h5"); }

struct Outcome {
  bool present = false;
  int exit_code = -1;
  std::string status;
  int rank = -1;
  double wall_seconds = 0.0;
  double cpu_seconds = 0.0;
  std::string result;
};

Outcome ReadOutcome(const fs::path& file) {
  Outcome o;
  if (!fs::is_regular_file(file)) return o;  // none yet, or a directory in its place
  try {
    const toml::table t = toml::parse_file(file.string());
    o.exit_code = static_cast<int>(t["exit_code"].value_or(int64_t{-1}));
    o.status = t["status"].value_or(std::string());
    o.rank = static_cast<int>(t["rank"].value_or(int64_t{-1}));
    o.wall_seconds = t["wall_seconds"].value_or(0.0);
    o.cpu_seconds = t["cpu_seconds"].value_or(0.0);
    o.result = t["result"].value_or(std::string());
    o.present = true;
  } catch (const toml::parse_error&) {
  }
  return o;
}

bool Done(const Outcome& o) {
  return o.present && (o.exit_code == 0 || o.exit_code == 1) && fs::exists(o.result);
}

fs::path OutcomeFile(const fs::path& out, const Job& job) { return out / (job.name + ".outcome"); }
// The stem of the job's claim files <out>/<name>.claim.<generation> (apps/claims.h).
fs::path ClaimStem(const fs::path& out, const Job& job) { return out / (job.name + ".claim"); }

// Nothing left to do for this run: the job is done, or its outcome was written since `run_start_ns`
// (a rank of this run, or another run, tried it: a bad input is not tried again by every rank).
bool Settled(const fs::path& out, const Job& job, int64_t run_start_ns) {
  const fs::path file = OutcomeFile(out, job);
  return Done(ReadOutcome(file)) || ModifiedNs(file) > run_start_ns;
}

// The one job of --job-index or SLURM_ARRAY_TASK_ID (numbered from 1), as an index from 0; none
// when neither is given. Throws invalid_argument naming the option, its value and the jobs' number.
std::optional<size_t> JobIndex(const BatchRequest& request, size_t jobs) {
  std::string given;
  long long index = 0;
  if (request.job_index) {
    given = fmt::format("--job-index {}", *request.job_index);
    index = *request.job_index;
  } else if (const char* task = std::getenv("SLURM_ARRAY_TASK_ID"); task != nullptr && *task != '\0') {
    given = fmt::format("SLURM_ARRAY_TASK_ID={} (the job index, as --job-index is not given)", task);
    char* end = nullptr;
    errno = 0;
    index = std::strtoll(task, &end, 10);
    if (*end != '\0' || errno != 0) {
      throw std::invalid_argument(given + ": must be an integer");
    }
  } else {
    return std::nullopt;
  }
  if (index < 1 || index > static_cast<long long>(jobs)) {
    throw std::invalid_argument(fmt::format(
        "{}: out of range: the jobs file has {} job(s), numbered from 1 to {} (for a Slurm array: "
        "#SBATCH --array=1-{})", given, jobs, jobs, jobs));
  }
  return static_cast<size_t>(index - 1);
}

// Runs one job through its command; its stdout and stderr go to the log.
Outcome RunJob(const Job& job, const fs::path& out, const ClaimOwner& me) {
  std::ostringstream log;
  const SteadyClock::time_point start = SteadyClock::now();
  const double cpu_start = ProcessCpuSeconds();
  int code = kExitFailure;
  fs::path result = ResultOf(job, out);
  PrepareToWrite(result);
  if (job.command == "run") {
    RunRequest r;
    r.scene_file = job.scene;
    r.out_dir = result.parent_path().string();
    r.resume = true;  // a job re-run after a kill continues its sweeps' checkpoints
    r.quiet = true;
    r.figures = job.figures;
    std::ostringstream printed;
    code = RunCommand(r, printed, log);
    log << printed.str();
    std::istringstream lines(printed.str());
    for (std::string line; std::getline(lines, line);) {
      if (line.rfind("wrote ", 0) == 0 && line.size() > 9 && line.substr(line.size() - 3) == ".h5") {
        result = line.substr(6);
      }
    }
  } else if (job.command == "analytic" || job.command == "branches") {
    AnalyticRequest r;
    r.scene_file = *job.scene;
    r.out_file = result.string();
    r.quiet = true;
    r.figures = job.figures;
    code = job.command == "analytic" ? AnalyticCommand(r, log, log) : BranchesCommand(r, log, log);
  } else if (job.command == "sweep") {
    SweepRequest r;
    r.scene_file = *job.scene;
    r.out_file = result.string();
    r.direction = job.direction;
    r.resume = true;
    r.figures = job.figures;
    r.quiet = true;
    code = SweepCommand(r, log, log);
  } else if (job.command == "map") {
    MapRequest r;
    r.scene_file = *job.scene;
    r.out_file = result.string();
    r.parameter = job.parameter;
    if (job.range) {
      r.eta_min = job.range->first;
      r.eta_max = job.range->second;
    }
    r.eta_points = job.eta_points;
    r.speed_points = job.speed_points;
    r.quiet = true;
    r.figures = job.figures;
    r.over_ranks = false;  // the other ranks run other jobs
    code = MapCommand(r, log, log);
  } else {
    FitRequest r;
    r.scene_file = *job.scene;
    r.targets_file = job.targets;
    r.out_file = result.string();
    r.quiet = true;
    r.over_ranks = false;  // the other ranks run other jobs
    code = FitCommand(r, log, log);
  }
  Outcome o;
  o.present = true;
  o.exit_code = code;
  o.status = code == kExitSuccess ? "success" : code == kExitFailure ? "failure" : "bad input";
  o.rank = me.rank;
  o.wall_seconds = SecondsSince(start);
  o.cpu_seconds = CpuSecondsSince(cpu_start);
  o.result = result.string();
  WriteFileAtomically(out / (job.name + ".log"), log.str());
  WriteFileAtomically(OutcomeFile(out, job),
                      fmt::format("name = \"{}\"\ncommand = \"{}\"\nexit_code = {}\nstatus = \"{}\"\n"
                                  "rank = {}\nhost = \"{}\"\npid = {}\nallocation = \"{}\"\n"
                                  "wall_seconds = {:.3f}\ncpu_seconds = {:.3f}\nresult = \"{}\"\n",
                                  job.name, job.command, o.exit_code, o.status, o.rank, me.host,
                                  me.pid, me.allocation, o.wall_seconds, o.cpu_seconds, o.result));
  return o;
}

// The summary's text over the jobs `shown`, and how many of them failed, did not finish or run
// elsewhere (a claim left after every rank of this run has finished is another run's).
std::pair<std::string, int> Summary(const JobsFile& jobs, const std::vector<size_t>& shown,
                                    const Ranks& ranks, double elapsed, int run_here) {
  std::string text = fmt::format("batch of {} jobs into {} ({}; {} run now, the rest done before)\n",
                                 jobs.jobs.size(), jobs.out.string(), ranks.Describe(), run_here);
  if (shown.size() < jobs.jobs.size()) {
    text += fmt::format("job {} of {} only (--job-index or SLURM_ARRAY_TASK_ID)\n", shown.front() + 1,
                        jobs.jobs.size());
  }
  int done = 0, failed = 0, elsewhere = 0;
  double job_seconds = 0.0;
  for (const size_t i : shown) {
    const Job& job = jobs.jobs[i];
    const Outcome o = ReadOutcome(OutcomeFile(jobs.out, job));
    const ClaimState claim = LookAtClaim(ClaimStem(jobs.out, job));
    if (!Done(o) && claim.generation >= 0) {
      text += fmt::format("  {:<32} {:<9} running elsewhere: {}, heartbeat {:.0f} s ago\n", job.name,
                          job.command, claim.owner_known ? claim.owner.Describe() : claim.file.string(),
                          claim.heartbeat_age_s);
      ++failed;
      ++elsewhere;
      continue;
    }
    if (!o.present) {
      text += fmt::format("  {:<32} {:<9} not finished (no outcome: its rank stopped)\n", job.name,
                          job.command);
      ++failed;
      continue;
    }
    const bool ok = o.exit_code == kExitSuccess && Done(o);
    (ok ? done : failed) += 1;
    job_seconds += o.wall_seconds;
    text += fmt::format("  {:<32} {:<9} {:<9} rank {:<3} {:>9.1f} s wall {:>9.1f} s CPU  {}\n",
                        job.name, job.command, o.status, o.rank, o.wall_seconds, o.cpu_seconds,
                        o.result);
  }
  text += fmt::format("{} done, {} failed or not finished{}; jobs' wall time {:.1f} s, this run "
                      "{:.1f} s on {} rank(s)\n",
                      done, failed,
                      elsewhere > 0 ? fmt::format(" ({} running elsewhere)", elsewhere) : "",
                      job_seconds, elapsed, ranks.size());
  return {text, failed};
}

// This rank's share of the jobs `selected`: passes over them, running each that is free or whose
// claim is stale or dead, until none is left but those a live owner runs; returns how many it ran.
// A claim seen held is watched (its generation and heartbeat) until its heartbeat moves (live: left
// to its owner) or it goes stale (taken over by TryClaim). A job that cannot be claimed, or cannot
// write its log or outcome, fails alone: the rank goes on, so that every rank reaches the final
// gather; the summary lists the job as not finished.
int RunShare(const JobsFile& jobs, const std::vector<size_t>& selected, const BatchRequest& request,
             int64_t run_start_ns, const Ranks& ranks, std::ostream& err) {
  const ClaimOwner me = ThisProcess(ranks.rank(), request.claims.HeartbeatSeconds());
  // Polls every 0.05 s at first, doubling up to half a heartbeat (at most 5 s): a job another
  // rank of this run is finishing is seen done at once, a long one costs few looks.
  const double max_poll_s = std::clamp(request.claims.HeartbeatSeconds() / 2.0, 0.01, 5.0);
  double poll_s = std::min(0.05, max_poll_s);
  std::map<size_t, std::pair<int, int64_t>> watched;
  std::vector<size_t> pending = selected;
  int run_here = 0;
  while (!pending.empty()) {
    std::vector<size_t> held;
    for (const size_t i : pending) {
      const Job& job = jobs.jobs[i];
      if (Settled(jobs.out, job, run_start_ns)) continue;
      try {
        const ClaimAttempt attempt = TryClaim(ClaimStem(jobs.out, job), me, request.claims);
        if (!attempt.held) {
          const std::pair<int, int64_t> seen{attempt.seen.generation, attempt.seen.heartbeat_ns};
          const auto [watch, first] = watched.emplace(i, seen);
          if (first || watch->second == seen) held.push_back(i);
          continue;
        }
        if (!attempt.taken_over_because.empty()) {
          fmt::print(err, "rubcont: note: [batch] rank {}: {}: took over {}: {}\n", ranks.rank(),
                     job.name, attempt.seen.file.string(), attempt.taken_over_because);
        }
        // Another rank may have finished it (and let go of its claim) since the check above.
        if (Settled(jobs.out, job, run_start_ns)) continue;
        if (!request.quiet) {
          fmt::print(err, "rubcont: [batch] rank {}: job {} of {}: {} ({} {})\n", ranks.rank(),
                     i + 1, jobs.jobs.size(), job.name, job.command,
                     job.scene.value_or("default scene"));
        }
        ++run_here;
        const Outcome o = RunJob(job, jobs.out, me);
        if (!request.quiet) {
          fmt::print(err, "rubcont: [batch] rank {}: {}: {} in {:.1f} s\n", ranks.rank(),
                     job.name, o.status, o.wall_seconds);
        }
      } catch (const std::exception& e) {
        fmt::print(err, "rubcont: [batch] rank {}: {}: no outcome written: {}\n", ranks.rank(),
                   job.name, e.what());
      }
    }
    pending = std::move(held);
    if (pending.empty()) break;
    std::this_thread::sleep_for(std::chrono::duration<double>(poll_s));
    poll_s = std::min(2.0 * poll_s, max_poll_s);
  }
  return run_here;
}

void ListJobs(const JobsFile& jobs, std::ostream& out) {
  fmt::print(out, "{} jobs, numbered for --job-index and SLURM_ARRAY_TASK_ID (a Slurm array: "
                  "--array=1-{}); output into {}\n", jobs.jobs.size(), jobs.jobs.size(),
             jobs.out.string());
  for (size_t i = 0; i < jobs.jobs.size(); ++i) {
    const Job& job = jobs.jobs[i];
    fmt::print(out, "{:>5}  {:<32} {:<9} {}\n", i + 1, job.name, job.command,
               job.scene.value_or("default scene"));
  }
}

}  // namespace

int BatchCommand(const BatchRequest& request, std::ostream& out, std::ostream& err) {
  const Ranks& ranks = Ranks::World();
  return Guarded(err, [&] {
    const SteadyClock::time_point start = SteadyClock::now();
    request.claims.Validate();
    const JobsFile jobs = ReadJobs(request.jobs_file, request.out_dir);
    if (request.list) {
      if (ranks.rank() == 0) ListJobs(jobs, out);
      return kExitSuccess;
    }
    const std::optional<size_t> index = JobIndex(request, jobs.jobs.size());
    std::vector<size_t> selected;
    for (size_t i = 0; i < jobs.jobs.size(); ++i) {
      if (!index || i == *index) selected.push_back(i);
    }
    PrepareToWrite(jobs.out / "summary.txt");
    const int64_t run_start_ns = RealtimeNs();
    ranks.Barrier();  // every rank's start precedes every outcome of this run (Settled)
    const int run_here = RunShare(jobs, selected, request, run_start_ns, ranks, err);
    const std::vector<std::string> counts = ranks.GatherToRoot(std::to_string(run_here));
    if (ranks.rank() != 0) return kExitSuccess;
    int total_run = 0;
    for (const std::string& c : counts) total_run += std::stoi(c);
    const auto [summary, failed] = Summary(jobs, selected, ranks, SecondsSince(start), total_run);
    if (!index) WriteFileAtomically(jobs.out / "summary.txt", summary);
    out << summary;
    return failed == 0 ? kExitSuccess : kExitFailure;
  });
}

}  // namespace rubcont
