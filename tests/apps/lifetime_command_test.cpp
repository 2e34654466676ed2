// `rubcont lifetime`, run as a user runs it: the approach, the ensembles per speed, the crisis
// fit's status, the check sweeps, the file, bad input.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "apps/hdf5_file.h"
#include "apps/lifetime_output.h"
#include "apps/scene.h"
#include "solvers/constants.h"
#include "cli_support.h"

namespace rubcont {
namespace {

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using testing::Outcome;
using testing::TempDir;
using testing::WhirlScene;

TEST_CASE("rubcont lifetime: the whirl never ends in a whip and is whirl at once, with statuses",
          "[lifetime_cli]") {
  TempDir dir;
  const fs::path scene = WhirlScene(dir.path);
  auto run = [&](const std::string& until, const fs::path& h5) {
    const Outcome o = testing::RubcontNoPython(
        "lifetime " + scene.string() + " --from 48 --to 48.5 --step 0.5 --copies 2 --duration 0.2 --check-copies 2 "
        "--check-dwell 0.1 --until " + until + " --quiet --out " + h5.string());
    INFO(o.out << o.err);
    REQUIRE(o.exit_code == 0);
    return o;
  };
  // The approach runs 40 and 44 rpm (whirl); at 48 and 48.5 rpm every copy rolls in its first
  // stretch: "left the state" (reached whirl) at once, κ only bounded below, no crisis law.
  const Outcome whirl = run("whirl", dir.path / "whirl.h5");
  CHECK_THAT(whirl.out, Contains("from the up sweep's state at 44 rpm (left whirl, right whirl)"));
  CHECK_THAT(whirl.out, Contains("48 rpm:   2 of 2 left, all in the first stretch: κ >"));
  CHECK_THAT(whirl.out, Contains("crisis law: too few speeds (2 parameter values with escapes (0 with a finite rate)"));
  CHECK_THAT(whirl.out, Contains("check: 2 sweeps 48 → 48.5 rpm in 0.5 rpm steps"));
  CHECK_THAT(whirl.out, Contains("left at: 48 48 rpm"));
  {
    ResultReader r(dir.path / "whirl.h5");
    CHECK(r.ReadStringAttribute("/", "level") == "L3");
    CHECK(r.ReadDoubles("/lifetime/speed_rpm") == std::vector<double>{48.0, 48.5});
    CHECK(r.ReadInts("/lifetime/escapes") == std::vector<int>{2, 2});
    CHECK(std::isinf(r.ReadDoubles("/lifetime/escape_rate")[0]));
    CHECK(r.ReadStrings("/lifetime/rate_status")[1] == "all in the first stretch");
    CHECK(r.ReadStringAttribute("/lifetime/crisis", "status") == "too few speeds");
    CHECK(r.ReadDoubles("/lifetime/check/speed_rpm") == std::vector<double>{48.0, 48.5});
    CHECK(r.ReadDoubles("/lifetime/check/jump_speed_rpm") == std::vector<double>{48.0, 48.0});
    // A stretch is two windows of round(0.05 s × 4096 Hz) = 205 samples.
    CHECK(r.ReadDoubleAttribute("/lifetime", "stretch") == Approx(410.0 / 4096.0).epsilon(1e-12));
    const Matrix arrival = r.ReadMatrix("/lifetime/arrival_time_s");
    CHECK(arrival == Matrix::Constant(2, 2, 410.0 / 4096.0));
  }
  // Until the whip: no copy leaves the whirl in 0.2 s, κ bounded above by 1.92 / (2 × 0.2 s).
  const Outcome whip = run("whip", dir.path / "whip.h5");
  CHECK_THAT(whip.out, Contains("48 rpm:   0 of 2 left, κ < 4.8 /s"));
  CHECK_THAT(whip.out, Contains("left at: (stayed) (stayed) rpm"));
  CHECK_THAT(whip.out, !Contains("untrusted"));
  {
    ResultReader r(dir.path / "whip.h5");
    CHECK(r.ReadDoubles("/lifetime/escape_rate") == std::vector<double>{0.0, 0.0});
    CHECK(r.ReadInts("/lifetime/stayed") == std::vector<int>{2, 2});
    CHECK(r.ReadInts("/lifetime/untrusted") == std::vector<int>{0, 0});
  }
  // The whirl penetrates about 8e-9 m (2e-5 of the clearance): beyond a limit of 1e-6 of it,
  // every copy is untrusted, and counted all the same.
  std::ofstream(scene, std::ios::app) << "max_penetration = 1e-6\n";
  const Outcome strict = run("whip", dir.path / "strict.h5");
  CHECK_THAT(strict.out, Contains("48 rpm:   0 of 2 left, κ < 4.8 /s (mean lifetime > 0.208 s); 2 untrusted"));
  CHECK_THAT(strict.out, Contains("untrusted copies (counted all the same") &&
                             Contains("contact penetrates"));
  ResultReader r(dir.path / "strict.h5");
  CHECK(r.ReadInts("/lifetime/untrusted") == std::vector<int>{2, 2});
  CHECK(r.ReadInts("/lifetime/stayed") == std::vector<int>{2, 2});
}

TEST_CASE("rubcont lifetime: bad input names the option, the value and the rule, with exit code 2",
          "[lifetime_cli]") {
  TempDir dir;
  const fs::path scene = WhirlScene(dir.path);
  auto bad = [&](const std::string& args) {
    const Outcome o = testing::RubcontNoPython("lifetime " + scene.string() + " " + args + " --quiet --out " +
                                               (dir.path / "x.h5").string());
    CHECK(o.exit_code == 2);
    CHECK_FALSE(fs::exists(dir.path / "x.h5"));
    return o.err;
  };
  CHECK_THAT(bad("--from 48 --to 46"), Contains("--to = 46: must be above --from (direction up)"));
  CHECK_THAT(bad("--from 48 --to 50 --direction down"), Contains("--to = 50: must be below --from (direction down)"));
  CHECK_THAT(bad("--from 48 --to 50 --check-step 0"), Contains("--check-step = 0: must be positive"));
  CHECK_THAT(bad("--from 48 --to 50 --until spin"), Contains("--until = spin: must be whirl, whip"));
  CHECK_THAT(bad("--from 48 --to 50 --check-dwell 0.01"), Contains("--check-dwell = 0.01: must be at least two windows"));
  CHECK_THAT(bad("--from 48 --to 50 --step 0.0001"), Contains("--step = 0.0001: gives more than 1000 speeds"));
  CHECK_THAT(bad("--from 48 --to 50 --resume --fresh"), Contains("--resume and --fresh: give one of them"));
}

TEST_CASE("rubcont lifetime: a checkpoint reads back as written, is refused without --resume or --fresh and "
          "from other options, and is kept", "[lifetime_cli]") {
  TempDir dir;
  const fs::path scene_file = WhirlScene(dir.path);
  const Scene scene = LoadScene(scene_file.string());
  SweepApproach approach;
  approach.state = Vector::LinSpaced(16, -1.0, 1.0);
  approach.speeds = {4.2, 4.6};
  approach.regimes = {RubRegime::kWhirl, RubRegime::kIntermittent};
  std::vector<SpeedEscapes> escapes(2);
  for (int i = 0; i < 2; ++i) {
    SpeedEscapes& e = escapes[static_cast<std::size_t>(i)];
    e.observations = {48.0 + 0.5 * i, 0.1, 0.4, {1, 3}, 1};
    e.arrival_time = {0.1, kNaN, 0.3};
    e.failed = i;
    if (i == 1) e.failures.push_back({2, "too many steps"});
    e.untrusted = 1;
    e.first_untrusted_copy = 0;
    e.first_untrusted = "penetrated 2e-6 m";
    e.wall_seconds = 0.25;
  }
  const fs::path out = dir.path / "study.h5";
  const fs::path checkpoint = LifetimeCheckpointPath(out);
  CHECK(checkpoint.filename() == "study.checkpoint.h5");
  WriteLifetimeCheckpoint(checkpoint, scene, "the request", approach, escapes);
  const std::optional<LifetimeStudyStart> back = ReadLifetimeCheckpoint(checkpoint, scene, "the request");
  REQUIRE(back);
  CHECK(back->approach.state == approach.state);
  CHECK(back->approach.speeds == approach.speeds);
  CHECK(back->approach.regimes == approach.regimes);
  REQUIRE(back->escapes.size() == 2);
  for (std::size_t i = 0; i < 2; ++i) {
    const SpeedEscapes& a = escapes[i];
    const SpeedEscapes& b = back->escapes[i];
    CHECK(b.observations.parameter == a.observations.parameter);
    CHECK(b.observations.escape_stretch == a.observations.escape_stretch);
    CHECK(b.observations.stayed == 1);
    CHECK(b.arrival_time[0] == 0.1);
    CHECK(std::isnan(b.arrival_time[1]));
    CHECK(b.failed == a.failed);
    CHECK(b.failures.size() == a.failures.size());
    CHECK(b.first_untrusted == a.first_untrusted);
  }
  CHECK(back->escapes[1].failures[0].message == "too many steps");
  CHECK_THROWS_WITH(ReadLifetimeCheckpoint(checkpoint, scene, "another request"),
                    Contains("was written for another scene or other options"));
  CHECK_FALSE(ReadLifetimeCheckpoint(dir.path / "none.h5", scene, "the request"));

  const std::string command = "lifetime " + scene_file.string() + " --from 48 --to 48.5 --step 0.5 --copies 2 "
                              "--duration 0.2 --quiet --out " + out.string();
  const Outcome refused = testing::RubcontNoPython(command);
  CHECK(refused.exit_code == 2);
  CHECK_THAT(refused.err, Contains("holds the finished speeds of an interrupted lifetime study: --resume continues "
                                   "from it, --fresh starts again"));
  const Outcome other = testing::RubcontNoPython(command + " --resume");
  CHECK(other.exit_code == 2);
  CHECK_THAT(other.err, Contains("was written for another scene or other options") && Contains("the request"));
  CHECK(fs::exists(checkpoint));
  CHECK_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace rubcont
