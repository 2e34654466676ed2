// `rubcont ensemble`, run as a user runs it: the approach, the copies, the file, bad input.
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <fmt/core.h>

#include "apps/hdf5_file.h"
#include "cli_support.h"

namespace rubcont {
namespace {

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using testing::Outcome;
using testing::Slurp;
using testing::TempDir;
using testing::WhirlScene;

// The study's numbers (arrivals, quantiles, threads) are tests/studies/ensemble_study_test.cpp's;
// here the command: options, summary, file.
TEST_CASE("rubcont ensemble: copies of the whirl reached by the sweep stay in it or arrive at "
          "once", "[ensemble_cli]") {
  TempDir dir;
  const fs::path scene = WhirlScene(dir.path);
  auto run = [&](const std::string& until, int threads, const fs::path& h5) {
    const Outcome o = testing::RubcontNoPython(
        "ensemble " + scene.string() + " --speed 48 --copies 3 --duration 0.3 --until " + until +
        " --threads " + std::to_string(threads) + " --quiet --out " + h5.string());
    INFO(o.out << o.err);
    REQUIRE(o.exit_code == 0);
    return o;
  };
  // The approach runs 40 and 44 rpm; at 48 rpm the whirl rolls on: every copy is in the whirl
  // in its first stretch (2 × 0.05 s), none reaches the whip in 0.3 s.
  const Outcome whirl = run("whirl", 2, dir.path / "whirl.h5");
  CHECK_THAT(whirl.out, Contains("from the up sweep 40 → 44 rpm (left whirl, right whirl)"));
  CHECK_THAT(whirl.out, Contains("3 of 3 reached whirl on every contact, after 0.10 s (min)"));
  const Outcome whip = run("whip", 2, dir.path / "whip.h5");
  CHECK_THAT(whip.out, Contains("0 of 3 reached whip"));
  {
    ResultReader r(dir.path / "whirl.h5");
    CHECK(r.ReadStringAttribute("/", "level") == "L3");
    CHECK(r.ReadDoubleAttribute("/ensemble", "speed_rpm") == 48.0);
    CHECK(r.ReadDoubleAttribute("/ensemble", "approach_to_rpm") == Approx(44.0));
    CHECK(r.ReadStringAttribute("/ensemble", "approach_regime_left") == "whirl");
    // A stretch is two windows of round(0.05 s × 4096 Hz) = 205 samples: 0.1000977 s.
    const std::vector<double> time = r.ReadDoubles("/ensemble/time_s");
    REQUIRE(time.size() == 3);
    CHECK(time[0] == Approx(410.0 / 4096.0).epsilon(1e-12));
    CHECK(time[2] == Approx(3.0 * 410.0 / 4096.0).epsilon(1e-12));
    CHECK(r.ReadDoubles("/ensemble/arrival_time_s") == std::vector<double>(3, time[0]));
    CHECK(r.ReadInts("/ensemble/reached") == std::vector<int>{1, 1, 1});
    // Rolling at RCI 100: BP = 100 × 48 / 60 Hz in every stretch of every copy.
    const Matrix bp = r.ReadMatrix("/ensemble/precession_hz_left");
    REQUIRE(bp.rows() == 3);
    REQUIRE(bp.cols() == 3);
    CHECK((bp.array() - 80.0).abs().maxCoeff() < 0.8);
    CHECK(r.ReadMatrix("/ensemble/regime_left") == Matrix::Constant(3, 3, 3.0));  // whirl
  }
  {
    ResultReader r(dir.path / "whip.h5");
    CHECK(r.ReadInts("/ensemble/reached") == std::vector<int>{0, 0, 0});
    for (double t : r.ReadDoubles("/ensemble/simulated_s")) CHECK(t == Approx(3.0 * 410.0 / 4096.0).epsilon(1e-12));
    CHECK(r.ReadStrings("/ensemble/untrusted") == std::vector<std::string>(3, ""));
  }
  CHECK_THAT(whip.out, !Contains("untrusted"));
  // The whirl penetrates about 8e-9 m (2e-5 of the clearance): beyond a limit of 1e-6 of it,
  // every copy is untrusted, and counted all the same.
  std::ofstream(scene, std::ios::app) << "max_penetration = 1e-6\n";
  const Outcome strict = run("whip", 2, dir.path / "strict.h5");
  CHECK_THAT(strict.out, Contains("0 of 3 reached whip"));
  CHECK_THAT(strict.out, Contains("3 untrusted (counted all the same") &&
                             Contains("× its clearance (limit 1e-06)"));
  ResultReader r(dir.path / "strict.h5");
  for (const std::string& why : r.ReadStrings("/ensemble/untrusted")) {
    CHECK_THAT(why, Contains("contact penetrates"));
  }
}

TEST_CASE("rubcont ensemble: with unequal clearances one contact rolls, and --until-contacts any "
          "or the contact's name counts it, by regime or by precession", "[ensemble_cli]") {
  // Case B(c) (RCI 125/100) from the impulse through 20 and 24 rpm: the right contact (RCI 100)
  // rolls and the left slips (as the committed sweep, 20–48 rpm). At 28 rpm no copy has every
  // contact rolling; with `any` or `right` every copy arrives in its first stretch, with `left`
  // none. The rolling right contact precesses at RCI·f = 100 × 28/60 = 46.7 Hz: above 40 Hz, not
  // above 60.
  TempDir dir;
  std::string text = Slurp("scenes/thesis_B_c.toml");
  text = text.substr(0, text.find("[analysis.sweep]")) +
         "[analysis.sweep]\nup_range_rpm = [20.0, 24.0]\nspeed_step_rpm = 4.0\ndwell = 0.75\n";
  const fs::path scene = dir.path / "thesis_B_c.toml";
  std::ofstream(scene) << text;
  int runs = 0;
  auto run = [&](const std::string& until) {
    const fs::path h5 = dir.path / fmt::format("run{}.h5", runs++);
    const Outcome o = testing::RubcontNoPython("ensemble " + scene.string() + " --speed 28 --copies 2 --duration 0.3 " +
                                               until + " --quiet --out " + h5.string());
    INFO(o.out << o.err);
    REQUIRE(o.exit_code == 0);
    return o.out;
  };
  const std::string every = run("--until-contacts every");
  CHECK_THAT(every, Contains("(left whip, right whirl)"));
  CHECK_THAT(every, Contains("0 of 2 reached whirl on every contact"));
  CHECK_THAT(run("--until-contacts any"), Contains("2 of 2 reached whirl on any contact, after 0.10 s (min)"));
  ResultReader r(dir.path / "run1.h5");
  CHECK(r.ReadStringAttribute("/ensemble", "until_contacts") == "any");
  CHECK_THAT(run("--until-contacts right"), Contains("2 of 2 reached whirl on the right contact, after 0.10 s (min)"));
  CHECK_THAT(run("--until-contacts left"), Contains("0 of 2 reached whirl on the left contact"));
  CHECK_THAT(run("--until-contacts right --until-above 40"),
             Contains("2 of 2 reached precession above 40 Hz on the right contact, after 0.10 s (min)"));
  CHECK_THAT(run("--until-contacts right --until-above 60"), Contains("0 of 2 reached precession above 60 Hz"));
  ResultReader above(dir.path / "run5.h5");
  CHECK(above.ReadDoubleAttribute("/ensemble", "until_above_hz") == 60.0);
  CHECK(above.ReadStringAttribute("/ensemble", "arrival") == "precession above 60 Hz on the right contact");
}

TEST_CASE("rubcont ensemble: bad input names the option, the value and the rule, with exit code 2",
          "[ensemble_cli]") {
  TempDir dir;
  const fs::path scene = WhirlScene(dir.path);
  auto bad = [&](const std::string& args) {
    const Outcome o = testing::RubcontNoPython("ensemble " + scene.string() + " " + args +
                                               " --quiet --out " + (dir.path / "x.h5").string());
    CHECK(o.exit_code == 2);
    CHECK_FALSE(fs::exists(dir.path / "x.h5"));
    return o.err;
  };
  CHECK_THAT(bad("--speed 48 --copies 0"), Contains("--copies = 0: must be in 1 … 100000"));
  CHECK_THAT(bad("--speed 48 --until spin"), Contains("--until = spin: must be whirl, whip"));
  CHECK_THAT(bad("--speed 48 --duration 0.05"), Contains("--duration = 0.05: must be at least two windows"));
  CHECK_THAT(bad("--speed -3"), Contains("--speed = -3: must be positive"));
  CHECK_THAT(bad("--speed 48 --direction sideways"), Contains("--direction = sideways"));
  CHECK_THAT(bad("--speed 48 --until-contacts some"),
             Contains("--until-contacts = some: must be every, any, left, right"));
  CHECK_THAT(bad("--speed 48 --until-above -5"), Contains("--until-above = -5: must be a precession in Hz"));
}

}  // namespace
}  // namespace rubcont
