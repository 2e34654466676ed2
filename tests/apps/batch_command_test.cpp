// rubcont batch (apps/batch_command.h): jobs files, their errors, outcomes, re-runs. The same
// command under mpirun is tested by ctest (tests/CMakeLists.txt, "batch over MPI ranks").
#include "apps/batch_command.h"

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include <catch2/catch.hpp>
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include "apps/claims.h"
#include "apps/commands.h"
#include "apps/hdf5_file.h"
#include "cli_support.h"

namespace rubcont {
namespace {

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using testing::Slurp;
using testing::TempDir;

struct Ran {
  int exit_code = -1;
  std::string out;
  std::string err;
};

Ran Batch(const fs::path& dir, const std::string& jobs, BatchRequest request = {}) {
  const fs::path file = dir / "jobs.toml";
  std::ofstream(file) << jobs;
  request.jobs_file = file.string();
  request.out_dir = (dir / "out").string();
  request.quiet = true;
  std::ostringstream out, err;
  Ran ran;
  ran.exit_code = BatchCommand(request, out, err);
  ran.out = out.str();
  ran.err = err.str();
  return ran;
}

TEST_CASE("batch: a bad jobs file is exit code 2 naming key, value and rule", "[batch]") {
  TempDir dir;
  const auto refused = [&](const std::string& jobs, const std::string& message) {
    const Ran ran = Batch(dir.path, jobs);
    INFO(jobs);
    CHECK(ran.exit_code == kExitBadInput);
    CHECK_THAT(ran.err, Contains(message));
  };
  refused("[[job]]\ncommand = \"frobnicate\"\nscene = \"x.toml\"\n",
          "job 1: command = \"frobnicate\": must be one of run, analytic, branches, sweep, map, fit");
  refused("[[job]]\ncommand = \"sweep\"\n", "job 1: scene: missing; required for command \"sweep\"");
  refused("[[job]]\ncommand = \"sweep\"\nscene = \"a.toml\"\ndirection = \"sideways\"\n",
          "direction = \"sideways\": must be up, down or both");
  refused("[[job]]\ncommand = \"map\"\nscene = \"a.toml\"\n",
          "parameter: missing; required for command \"map\"");
  refused("[[job]]\ncommand = \"map\"\nscene = \"a.toml\"\nparameter = \"friction\"\neta_points = 1\n",
          "eta_points = 1: must be an integer in 2 … 2000");
  refused("[[job]]\ncommand = \"branches\"\nscene = \"a.toml\"\nspeed = 3\n", "speed: unknown key");
  refused("[[job]]\ncommand = \"branches\"\nvary = { scene = \"a.toml\" }\n",
          "vary.scene = \"a.toml\": must be a non-empty list");
  refused("[[job]]\ncommand = \"branches\"\nscene = \"dir1/a.toml\"\n"
          "[[job]]\ncommand = \"branches\"\nscene = \"dir2/a.toml\"\n",
          "job 2: name = \"a_branches\": another job has the same name");
  refused("outt = 3\n", "outt: unknown key");
  refused("", "job: missing; at least one [[job]] table");
  refused("[[job]\n", "jobs.toml:1:");
}

TEST_CASE("batch: jobs run once, a re-run does only what is missing", "[batch]") {
  TempDir dir;
  const std::string jobs =
      "[[job]]\n"
      "command = \"branches\"\n"
      "vary = { scene = [\"scenes/thesis_A_a.toml\", \"scenes/thesis_B_a.toml\"] }\n"
      "[[job]]\n"
      "name = \"A_a_analytic\"\n"
      "command = \"analytic\"\n"
      "scene = \"scenes/thesis_A_a.toml\"\n";
  const Ran first = Batch(dir.path, jobs);
  INFO(first.out << first.err);
  REQUIRE(first.exit_code == kExitSuccess);
  CHECK_THAT(first.out, Contains("batch of 3 jobs"));
  CHECK_THAT(first.out, Contains("(one process; 3 run now"));  // no MPI without mpirun
  CHECK_THAT(first.out, Contains("3 done, 0 failed or not finished"));
  const fs::path out = dir.path / "out";
  for (const char* name : {"thesis_A_a_branches", "thesis_B_a_branches", "A_a_analytic"}) {
    CHECK(fs::exists(out / name / (std::string(name) + ".h5")));
    CHECK_THAT(Slurp(out / (std::string(name) + ".outcome")), Contains("exit_code = 0"));
    CHECK_FALSE(fs::exists(out / (std::string(name) + ".claim")));
  }
  // The result is the command's: the A(a) whirl's speed-up event where `rubcont branches` has it.
  const ResultReader reader(out / "thesis_A_a_branches" / "thesis_A_a_branches.h5");
  CHECK(reader.ReadStringAttribute("/", "status") == "success");
  CHECK(Slurp(out / "summary.txt") == first.out);

  const Ran again = Batch(dir.path, jobs);
  CHECK(again.exit_code == kExitSuccess);
  CHECK_THAT(again.out, Contains("0 run now"));

  fs::remove(out / "thesis_B_a_branches" / "thesis_B_a_branches.h5");
  std::ofstream(out / "A_a_analytic.claim.0");  // on a done job: it does not matter
  const Ran missing = Batch(dir.path, jobs);
  CHECK(missing.exit_code == kExitSuccess);
  CHECK_THAT(missing.out, Contains("1 run now"));
  CHECK(fs::exists(out / "thesis_B_a_branches" / "thesis_B_a_branches.h5"));
}

TEST_CASE("batch: a job's numerical failure is reported and the others are kept", "[batch]") {
  TempDir dir;
  const Ran ran = Batch(dir.path,
                        "[[job]]\n"
                        "command = \"map\"\n"
                        "scene = \"scenes/thesis_A_a_tanh.toml\"\n"
                        "parameter = \"friction\"\n"
                        "range = [0.45, 0.55]\n"
                        "eta_points = 3\n"
                        "speed_points = 41\n"
                        "[[job]]\n"
                        "command = \"analytic\"\n"
                        "scene = \"scenes/thesis_A_a.toml\"\n"
                        "[[job]]\n"
                        "command = \"branches\"\n"
                        "scene = \"scenes/no_such_scene.toml\"\n");
  INFO(ran.out << ran.err);
  CHECK(ran.exit_code == kExitFailure);
  CHECK_THAT(ran.out, Contains("thesis_A_a_tanh_map_friction     map       failure"));
  CHECK_THAT(ran.out, Contains("thesis_A_a_analytic              analytic  success"));
  CHECK_THAT(ran.out, Contains("no_such_scene_branches           branches  bad input"));
  CHECK_THAT(ran.out, Contains("1 done, 2 failed or not finished"));
  const fs::path out = dir.path / "out";
  CHECK_THAT(Slurp(out / "thesis_A_a_tanh_map_friction.log"), Contains("numerical failure: curve"));
  CHECK_THAT(Slurp(out / "no_such_scene_branches.log"), Contains("no_such_scene.toml"));
  // The failed map's file is a result (its status says failure): a re-run keeps it; the job with
  // bad input has none and is tried again.
  const Ran again = Batch(dir.path, Slurp(dir.path / "jobs.toml"));
  CHECK_THAT(again.out, Contains("1 run now"));
}

TEST_CASE("batch: a sweep job re-run after a kill continues from its checkpoint", "[batch]") {
  // Without --resume a re-run would now refuse the checkpoint (exit 2); batch jobs resume.
  TempDir dir;
  const fs::path scene = testing::WhirlScene(dir.path);  // 40, 44, 48 rpm
  const fs::path result = dir.path / "out" / "s" / "s.h5";
  const fs::path checkpoint = dir.path / "out" / "s" / "s.up.checkpoint.h5";
  fs::create_directories(result.parent_path());
  const char* binary_dir = std::getenv("RUBCONT_BINARY_DIR");
  const std::string binary = std::string(binary_dir ? binary_dir : "build") + "/rubcont";
  const pid_t pid = fork();
  REQUIRE(pid >= 0);
  if (pid == 0) {  // the job as batch runs it, killed after its first speed
    const int null = open("/dev/null", O_WRONLY);
    dup2(null, 1);
    dup2(null, 2);
    execl(binary.c_str(), "rubcont", "sweep", scene.c_str(), "--direction", "up", "--quiet", "--out",
          result.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  for (int i = 0; i < 6000 && !fs::exists(checkpoint); ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  kill(pid, SIGKILL);
  waitpid(pid, nullptr, 0);
  REQUIRE(fs::exists(checkpoint));
  REQUIRE_FALSE(fs::exists(result));
  const std::vector<double> saved = ResultReader(checkpoint).ReadDoubles("/sweeps/up/wall_seconds");
  REQUIRE(saved.size() == 1);

  const Ran ran = Batch(dir.path, "[[job]]\nname = \"s\"\ncommand = \"sweep\"\ndirection = \"up\"\n"
                                  "scene = \"" + scene.string() + "\"\n");
  INFO(ran.out << ran.err << Slurp(dir.path / "out" / "s.log"));
  CHECK(ran.exit_code == kExitSuccess);
  const std::vector<double> wall = ResultReader(result).ReadDoubles("/sweeps/up/wall_seconds");
  REQUIRE(wall.size() == 3);
  CHECK(wall[0] == saved[0]);  // the speed from the checkpoint, not integrated again
  CHECK_FALSE(fs::exists(checkpoint));
}

TEST_CASE("batch: a job whose outcome cannot be written fails alone, the rank goes on", "[batch]") {
  // Under mpirun the rank must reach the final gather whatever happens to one job.
  TempDir dir;
  fs::create_directories(dir.path / "out" / "first.outcome" / "inside");  // where the outcome goes
  const Ran ran = Batch(dir.path,
                        "[[job]]\nname = \"first\"\ncommand = \"analytic\"\n"
                        "scene = \"scenes/thesis_A_a.toml\"\n"
                        "[[job]]\nname = \"second\"\ncommand = \"analytic\"\n"
                        "scene = \"scenes/thesis_A_a.toml\"\n");
  INFO(ran.out << ran.err);
  CHECK(ran.exit_code == kExitFailure);
  CHECK_THAT(ran.out, Contains("first                            analytic  not finished"));
  CHECK_THAT(ran.out, Contains("second                           analytic  success"));
  CHECK_THAT(ran.out, Contains("1 done, 1 failed or not finished"));
}

// Two tiny jobs, a and b.
const std::string kTwoJobs =
    "[[job]]\nname = \"a\"\ncommand = \"analytic\"\nscene = \"scenes/thesis_A_a.toml\"\n"
    "[[job]]\nname = \"b\"\ncommand = \"analytic\"\nscene = \"scenes/thesis_B_a.toml\"\n";

BatchRequest StaleAfter(double seconds) {
  BatchRequest request;
  request.claims.stale_after_s = seconds;
  return request;
}

TEST_CASE("batch: a job a live owner runs is left to it, a stale or dead claim is taken over", "[batch]") {
  // Before, every run first deleted the claims of unfinished jobs: a second allocation on the same
  // output ran again the jobs the first was running.
  TempDir dir;
  const fs::path out = dir.path / "out";
  fs::create_directories(out);
  {  // a live owner (this process, its heartbeat beating) holds b
    const ClaimOptions options = StaleAfter(0.5).claims;
    const ClaimAttempt live =
        TryClaim(out / "b.claim", ThisProcess(0, options.HeartbeatSeconds()), options);
    REQUIRE(live.held);
    const Ran second = Batch(dir.path, kTwoJobs, StaleAfter(0.5));
    INFO(second.out << second.err);
    CHECK(second.exit_code == kExitFailure);
    CHECK_THAT(second.out, Contains("1 run now"));
    CHECK_THAT(second.out, Contains("b                                analytic  running elsewhere: pid " +
                                    std::to_string(getpid())));
    CHECK_THAT(second.out, Contains("1 done, 1 failed or not finished (1 running elsewhere)"));
    CHECK_FALSE(fs::exists(out / "b.outcome"));
    CHECK(fs::exists(out / "b.claim.0"));
  }
  // b's owner stopped 5 s ago on another host: its claim is stale after 1 s and taken over.
  std::ofstream(out / "b.claim.0") << "host = \"node-elsewhere\"\npid = 4242\n";
  fs::last_write_time(out / "b.claim.0", fs::file_time_type::clock::now() - std::chrono::seconds(5));
  const Ran stale = Batch(dir.path, kTwoJobs, StaleAfter(1.0));
  INFO(stale.out << stale.err);
  CHECK(stale.exit_code == kExitSuccess);
  CHECK_THAT(stale.err, Contains("b: took over"));
  CHECK_THAT(stale.err, Contains("its heartbeat is 5 s old (stale after 1 s); owner pid 4242 on node-elsewhere"));
  CHECK_THAT(stale.out, Contains("1 run now"));
  CHECK_FALSE(fs::exists(out / "b.claim.0"));  // let go with the new generation
  CHECK_FALSE(fs::exists(out / "b.claim.1"));

  // A process of this host that is gone: taken over at once, its heartbeat however fresh.
  fs::remove(out / "a.outcome");
  const pid_t child = fork();
  if (child == 0) _exit(0);
  waitpid(child, nullptr, 0);
  ClaimOwner gone = ThisProcess(0, 30.0);
  std::ofstream(out / "a.claim.0") << "host = \"" << gone.host << "\"\nboot_id = \"" << gone.boot_id
                                   << "\"\npid = " << child << "\n";
  const Ran dead = Batch(dir.path, kTwoJobs);  // stale only after the default 300 s
  INFO(dead.out << dead.err);
  CHECK(dead.exit_code == kExitSuccess);
  CHECK_THAT(dead.err, Contains("a: took over"));
  CHECK_THAT(dead.err, Contains("is gone"));
}

TEST_CASE("batch: --job-index or SLURM_ARRAY_TASK_ID runs one job, numbered from 1", "[batch]") {
  TempDir dir;
  const fs::path out = dir.path / "out";
  BatchRequest list;
  list.list = true;
  const Ran listed = Batch(dir.path, kTwoJobs, list);
  CHECK(listed.exit_code == kExitSuccess);
  CHECK_THAT(listed.out, Contains("2 jobs, numbered for --job-index and SLURM_ARRAY_TASK_ID (a Slurm "
                                  "array: --array=1-2)"));
  CHECK_THAT(listed.out, Contains("    2  b                                analytic  scenes/thesis_B_a.toml"));
  CHECK_FALSE(fs::exists(out));  // nothing run, nothing made
  BatchRequest second;
  second.job_index = 2;
  const Ran ran = Batch(dir.path, kTwoJobs, second);
  INFO(ran.out << ran.err);
  CHECK(ran.exit_code == kExitSuccess);
  CHECK_THAT(ran.out, Contains("job 2 of 2 only"));
  CHECK_THAT(ran.out, Contains("1 done, 0 failed"));
  CHECK(fs::exists(out / "b.outcome"));
  CHECK_FALSE(fs::exists(out / "a.outcome"));
  CHECK_FALSE(fs::exists(out / "summary.txt"));  // the whole batch's: left to a run without index

  ::setenv("SLURM_ARRAY_TASK_ID", "1", 1);
  const Ran array = Batch(dir.path, kTwoJobs);
  ::setenv("SLURM_ARRAY_TASK_ID", "3", 1);
  const Ran beyond = Batch(dir.path, kTwoJobs);
  ::unsetenv("SLURM_ARRAY_TASK_ID");
  CHECK(array.exit_code == kExitSuccess);
  CHECK_THAT(array.out, Contains("job 1 of 2 only"));
  CHECK(fs::exists(out / "a.outcome"));
  CHECK(beyond.exit_code == kExitBadInput);
  CHECK_THAT(beyond.err, Contains("SLURM_ARRAY_TASK_ID=3 (the job index, as --job-index is not "
                                  "given): out of range: the jobs file has 2 job(s), numbered from "
                                  "1 to 2"));
  BatchRequest zero;
  zero.job_index = 0;  // a 0-based array
  const Ran refused = Batch(dir.path, kTwoJobs, zero);
  CHECK(refused.exit_code == kExitBadInput);
  CHECK_THAT(refused.err, Contains("--job-index 0: out of range: the jobs file has 2 job(s), numbered "
                                   "from 1 to 2 (for a Slurm array: #SBATCH --array=1-2)"));
}

}  // namespace
}  // namespace rubcont
