#include "apps/loop_command.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "apps/hdf5_file.h"
#include "cli_support.h"

namespace rubcont {
namespace {

using Catch::Matchers::Contains;
using testing::RubcontNoPython;
using testing::Slurp;
using testing::TempDir;

// Case A(a) run up from 40 to 120 rpm and down from 120 to 40 rpm, 4 rpm and 0.75 s per speed (the
// committed sweep's schedule): its loop in that range has the whirl's knee going up and down and
// the whirl's Hopf point going down; the run-up does not reach the whip's end (about 180 rpm).
std::filesystem::path WindowScene(const std::filesystem::path& dir) {
  std::string text = Slurp("scenes/thesis_A_a.toml");
  text = text.substr(0, text.find("[analysis.sweep]")) +
         "[analysis.sweep]\nup_range_rpm = [40.0, 120.0]\ndown_range_rpm = [40.0, 120.0]\n"
         "speed_step_rpm = 4.0\ndwell = 0.75\n";
  const std::filesystem::path file = dir / "thesis_A_a.toml";
  std::ofstream(file) << text;
  return file;
}

// Case A(a) with the thesis's imbalance, run up and down over 44–60 rpm (4 rpm, 0.75 s per speed):
// the rotating frame has no imbalance, so the runs are integrated at every speed (no skip along a
// wave, which used to end the loop with exit 2 when the run-down moved onto a wave); the balanced
// rotor's knee still explains the run-up's whirl → whip.
TEST_CASE("rubcont loop: an imbalanced rotor's runs are integrated at every speed, its jumps explained by the balanced waves",
          "[loop][cli]") {
  TempDir dir;
  std::string text = Slurp("scenes/thesis_A_a_imbalance.toml");
  text = text.substr(0, text.find("[analysis.sweep]")) +
         "[analysis.sweep]\nup_range_rpm = [44.0, 60.0]\ndown_range_rpm = [44.0, 60.0]\n"
         "speed_step_rpm = 4.0\ndwell = 0.75\n";
  const std::filesystem::path scene = dir.path / "imbalanced.toml";
  std::ofstream(scene) << text;
  const std::string file = (dir.path / "loop.h5").string();
  const auto r = RubcontNoPython("loop " + scene.string() + " --quiet --out " + file);
  INFO(r.out << r.err);
  REQUIRE(r.exit_code == 0);
  const ResultReader loop(file);
  for (const char* direction : {"up", "down"}) {
    const std::string run = std::string("/loop/runs/") + direction;
    CHECK(loop.ReadDoubles(run + "/skips/from_rpm").empty());
    CHECK(loop.ReadDoubles(run + "/speed_rpm").size() == loop.ReadDoubles(run + "/schedule_rpm").size());
  }
  const std::vector<std::string> decisions = loop.ReadStrings("/loop/decisions");
  CHECK(std::any_of(decisions.begin(), decisions.end(),
                    [](const std::string& d) { return d.find("the waves are the balanced rotor's") != std::string::npos; }));
  const std::vector<std::string> direction = loop.ReadStrings("/loop/corners/direction");
  const std::vector<std::string> kind = loop.ReadStrings("/loop/corners/kind");
  const std::vector<std::string> cause = loop.ReadStrings("/loop/corners/cause");
  bool knee_up = false;
  for (std::size_t i = 0; i < kind.size(); ++i) {
    knee_up = knee_up || (direction[i] == "up" && kind[i] == "whirl_to_whip" && cause[i] == "knee");
  }
  CHECK(knee_up);
}

TEST_CASE("rubcont loop: the L1 corners are the committed jump table's, and a run-up that ends on the whip says so",
          "[loop][cli]") {
  TempDir dir;
  const std::string file = (dir.path / "loop.h5").string();
  const auto r = RubcontNoPython("loop " + WindowScene(dir.path).string() + " --quiet --out " + file);
  INFO(r.out << r.err);
  REQUIRE(r.exit_code == 0);
  // The summary opens with the table.
  CHECK(r.out.find("the hysteresis loop of a run with 4 rpm steps and 0.75 s per speed") < r.out.find("knee"));
  CHECK_THAT(r.out, Contains("the run-up ends in left whip, right whip at 120 rpm"));

  const ResultReader loop(file);
  const std::vector<std::string> direction = loop.ReadStrings("/loop/corners/direction");
  const std::vector<std::string> kind = loop.ReadStrings("/loop/corners/kind");
  const std::vector<std::string> cause = loop.ReadStrings("/loop/corners/cause");
  const std::vector<std::string> level = loop.ReadStrings("/loop/corners/level");
  const std::vector<std::string> evidence = loop.ReadStrings("/loop/corners/evidence");
  const std::vector<double> speed = loop.ReadDoubles("/loop/corners/speed_rpm");
  const std::vector<double> lower = loop.ReadDoubles("/loop/corners/lower_rpm");
  const std::vector<double> upper = loop.ReadDoubles("/loop/corners/upper_rpm");
  REQUIRE(direction.size() == 3);
  for (const char* column : {"contact", "interval", "note", "cpu_seconds", "crisis_lower_rpm", "crisis_upper_rpm"}) {
    CHECK(loop.Exists(std::string("/loop/corners/") + column));
  }
  // The committed sweep's jump table (results/thesis_A_a/sweep.h5: the full range, the same
  // schedule and waves): every corner here is a row of it with the same bifurcation.
  const ResultReader sweep("results/thesis_A_a/sweep.h5");
  const std::vector<std::string> t_direction = sweep.ReadStrings("/sweeps/jump_table/direction");
  const std::vector<std::string> t_kind = sweep.ReadStrings("/sweeps/jump_table/kind");
  const std::vector<std::string> t_bifurcation = sweep.ReadStrings("/sweeps/jump_table/bifurcation");
  const std::vector<double> t_speed = sweep.ReadDoubles("/sweeps/jump_table/bifurcation_speed_rpm");
  for (std::size_t i = 0; i < direction.size(); ++i) {
    INFO(direction[i] << " " << kind[i] << " " << cause[i] << " at " << speed[i]);
    CHECK(level[i] == "L1");
    CHECK(loop.Exists(evidence[i]));
    CHECK(lower[i] <= speed[i]);
    CHECK(upper[i] >= speed[i]);
    bool found = false;
    for (std::size_t k = 0; k < t_direction.size(); ++k) {
      if (t_direction[k] == direction[i] && t_kind[k] == kind[i] && t_bifurcation[k].find(cause[i]) != std::string::npos &&
          std::abs(t_speed[k] - speed[i]) < 1e-6) {
        found = true;
      }
    }
    CHECK(found);
  }
  CHECK(std::set<std::string>(cause.begin(), cause.end()) == std::set<std::string>{"knee", "Hopf"});
  // The tracker moved along the stable waves: far fewer speeds integrated than scheduled.
  CHECK(loop.ReadDoubles("/loop/runs/down/speed_rpm").size() < loop.ReadDoubles("/loop/runs/down/schedule_rpm").size() / 2);
  CHECK(loop.ReadStringAttribute("/loop/runs/up", "end") == "left whip, right whip at 120 rpm");
}

TEST_CASE("rubcont loop: the default scene's loop, every jump with a cause or said to be undecided", "[loop][cli]") {
  TempDir dir;
  const std::string file = (dir.path / "loop.h5").string();
  // 0.75 G work units: the run, L1, L2 at the whip's end and one try of its route, and the whip's end
  // said undecided (0.92 G in 75 s of CPU beside another loop, 2026-11-30): the same on any machine.
  const auto r = RubcontNoPython("loop scenes/default.toml --schedule 4 0.75 --budget 0.75 --quiet --out " + file);
  INFO(r.out << r.err);
  REQUIRE(r.exit_code == 0);
  const ResultReader loop(file);
  const std::vector<std::string> kind = loop.ReadStrings("/loop/corners/kind");
  const std::vector<std::string> cause = loop.ReadStrings("/loop/corners/cause");
  const std::vector<std::string> note = loop.ReadStrings("/loop/corners/note");
  const std::vector<std::string> evidence = loop.ReadStrings("/loop/corners/evidence");
  REQUIRE(kind.size() >= 4);
  for (const std::string& path : evidence) CHECK(loop.Exists(path));
  for (std::size_t i = 0; i < kind.size(); ++i) {
    INFO(kind[i] << ": " << cause[i] << "; " << note[i]);
    CHECK(!cause[i].empty());
    if (cause[i] == "not explained") CHECK(!note[i].empty());
  }
  CHECK(loop.Exists("/loop/branches"));
  CHECK(loop.Exists("/loop/runs/up/skips/from_rpm"));
  CHECK(loop.ReadStrings("/loop/decisions").size() >= 3);
  // The budget counts work: what it stopped is said with the units used.
  CHECK(loop.ReadDoubleAttribute("/loop", "budget_g_work_units") == 0.75);
  CHECK(loop.ReadDoubleAttribute("/loop", "g_work_units") >= 0.75);
  bool said = false;
  for (const std::string& n : note) said = said || n.find("G work units") != std::string::npos;
  CHECK(said);
}

TEST_CASE("rubcont loop: bad input names the option, with exit code 2", "[loop][cli]") {
  const auto budget = RubcontNoPython("loop scenes/default.toml --budget 0");
  CHECK(budget.exit_code == 2);
  CHECK_THAT(budget.err, Contains("--budget = 0") && Contains("positive"));
  const auto dwell = RubcontNoPython("loop scenes/default.toml --schedule 2 0");
  CHECK(dwell.exit_code == 2);
  CHECK_THAT(dwell.err, Contains("--schedule = 2 0") && Contains("time per speed"));
  const auto step = RubcontNoPython("loop scenes/default.toml --schedule -1 1.5");
  CHECK(step.exit_code == 2);
  CHECK_THAT(step.err, Contains("--schedule") && Contains("speed step"));
  TempDir dir;
  std::string text = Slurp("scenes/default.toml");
  text = text.substr(0, text.find("[contact]")) + text.substr(text.find("[contact.friction_law]"));
  std::ofstream(dir.path / "no_contact.toml") << text;
  const auto no_contact = RubcontNoPython("loop " + (dir.path / "no_contact.toml").string());
  CHECK(no_contact.exit_code == 2);
  CHECK_THAT(no_contact.err, Contains("contact."));
  const auto jeffcott = RubcontNoPython("loop scenes/jeffcott.toml");
  CHECK(jeffcott.exit_code == 2);
  CHECK_THAT(jeffcott.err, Contains("sweep"));
}

}  // namespace
}  // namespace rubcont
