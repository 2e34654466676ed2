// The plan check and the unit-mistake warnings (apps/plan_check.h, issue 50): the sweep over
// [20, 1e9] rpm refused before any work, --force past it, every committed scene silent, and the
// scene written in mm, the 1000 km radius and the masses in g each warned of by its key.
#include <filesystem>
#include <fstream>
#include <string>

#include <catch2/catch.hpp>

#include "apps/models.h"
#include "apps/plan_check.h"
#include "apps/scene.h"
#include "apps/stage_options.h"
#include "cli_support.h"

namespace rubcont {
namespace {

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using testing::RubcontNoPython;
using testing::TempDir;

// Case A(a) with `analysis` added to its [analysis] table and its speed-up range replaced by
// `sweep`.
fs::path WideScene(const fs::path& dir, const std::string& analysis, const std::string& sweep) {
  std::string text = testing::Slurp("scenes/thesis_A_a.toml");
  text.insert(text.find("[analysis.sweep]"), analysis + "\n");
  text.replace(text.find("up_range_rpm = [20.0, 256.0]"), 28, sweep);
  const fs::path file = dir / "wide.toml";
  std::ofstream(file) << text;
  return file;
}

TEST_CASE("Plan check: a sweep over [20, 1e9] rpm is refused (exit 2) before any work, --force passes",
          "[plan_check]") {
  TempDir dir;
  const fs::path scene =
      WideScene(dir.path, "speed_range_rpm = [20.0, 1e9]", "up_range_rpm = [20.0, 1e9]");
  const fs::path out = dir.path / "wide.h5";
  const testing::Outcome refused =
      RubcontNoPython("sweep " + scene.string() + " --out " + out.string() + " -q");
  CHECK(refused.exit_code == 2);
  // The key, its value, the estimate against the limit, and the way past it.
  CHECK_THAT(refused.err, Contains("analysis.sweep.up_range_rpm = [20, 1e+09] in steps of 4 rpm plans "
                                   "2.5e+08 speeds of the speed-up sweep, 1.87e+08 s simulated"));
  CHECK_THAT(refused.err, Contains("years of CPU"));
  CHECK_THAT(refused.err, Contains("over the limit of 1e+06 speeds"));
  CHECK_THAT(refused.err, Contains("--force to run it anyway"));
  // The branches' range is no work (at most 1000 steps a branch) but no rotor turns that fast.
  CHECK_THAT(refused.err, Contains("warning: analysis.speed_range_rpm = [20, 1000000000] rpm: the surface "
                                   "speed R·ω reaches 3.99e+06 m/s"));
  CHECK_FALSE(fs::exists(out));

  // With --force the check passes with a warning: the command goes on to its output, which this
  // test makes unwritable (a directory under a plain file), so it stops there with exit 1.
  std::ofstream(dir.path / "plain") << "x";
  const testing::Outcome forced = RubcontNoPython(
      "sweep " + scene.string() + " --out " + (dir.path / "plain" / "wide.h5").string() + " -q --force");
  CHECK(forced.exit_code == 1);
  CHECK_THAT(forced.err, Contains("warning: analysis.sweep.up_range_rpm = [20, 1e+09]"));
  CHECK_THAT(forced.err, Contains("running it anyway (--force)"));
}

TEST_CASE("Plan check: ensemble, lifetime, attractor and loop refuse their own absurd plans",
          "[plan_check]") {
  TempDir dir;
  const std::string aa = "scenes/thesis_A_a.toml --out " + (dir.path / "x.h5").string() + " -q ";
  const struct {
    std::string args, named;
  } cases[] = {
      {"ensemble " + aa + "--speed 176 --copies 100000 --duration 1e6",
       "--copies × --duration = 100000 × 1e+06 s plans 1e+05 copies, 1e+11 s simulated"},
      {"lifetime " + aa + "--from 170 --to 180 --duration 1e5",
       "--copies × --duration = 16 × 100000 s at 11 speeds plans 176 copy runs"},
      {"attractor " + aa + "--from 100 --to 110 --duration 1e6 --interval 1",
       "--discard + --duration = 0.5 + 1e+06 s at 3 speeds plans 3 speeds, 3e+06 s simulated"},
      {"loop " + aa + "--budget 1e9",
       "--budget = 1e+09 G work units plans 1 loop, ≈ 2.54e+03 years of CPU: over the limit of 7 days of CPU "
       "(CPU estimated at 80 s per G work units)"},
  };
  for (const auto& c : cases) {
    INFO(c.args);
    const testing::Outcome o = RubcontNoPython(c.args);
    CHECK(o.exit_code == 2);
    CHECK_THAT(o.err, Contains(c.named));
    CHECK_THAT(o.err, Contains("--force to run it anyway"));
  }
  CHECK_FALSE(fs::exists(dir.path / "x.h5"));
}

TEST_CASE("Plan check: every committed scene passes, without a warning", "[plan_check]") {
  int scenes = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator("scenes")) {
    if (entry.path().extension() != ".toml") continue;
    const Scene scene = LoadScene(entry.path());
    INFO(entry.path().string());
    CHECK(UnitMistakes(scene).empty());
    CHECK(ExcessiveWork(StagePlanOf(scene, scene.analysis.stages)).empty());
    if (ModelOf(scene).Has(Stage::kSweep)) CHECK(ExcessiveWork(StagePlanOf(scene, {Stage::kLoop})).empty());
    ++scenes;
  }
  CHECK(scenes >= 30);
}

TEST_CASE("Unit mistakes: a scene in mm, a 1000 km radius, masses in g: each named by its key",
          "[plan_check]") {
  const Scene aa = LoadScene("scenes/thesis_A_a.toml");
  // Every length in mm: the first length key is named, the others counted.
  Scene mm = aa;
  for (double* length : {&mm.two_point.contact_span, &mm.two_point.rotor_mass_center, &mm.two_point.stator_span,
                         &mm.two_point.stator_mass_center, &mm.two_point.clearance[0], &mm.two_point.clearance[1],
                         &mm.two_point.radius[0], &mm.two_point.radius[1]}) {
    *length *= 1000.0;
  }
  std::vector<std::string> mistakes = UnitMistakes(mm);
  REQUIRE(mistakes.size() == 1);
  CHECK_THAT(mistakes[0], Contains("rotor.contact_span = 290 m: larger than any rotor (20 m): a length in mm "
                                   "written as m? (4 more length keys outside the rotor lengths)"));
  // A contact radius of 1000 km.
  Scene far = aa;
  far.two_point.radius = {1e6, 1e6};
  mistakes = UnitMistakes(far);
  REQUIRE(mistakes.size() == 1);
  CHECK_THAT(mistakes[0], Contains("contact.radius = [1000000, 1000000] m: larger than any rotor"));
  // Masses in g: the knee (C/R)·ω_n falls 31.6-fold, to 1.65 rpm, below the range [20, 260] rpm.
  Scene grams = aa;
  grams.two_point.rotor_mass *= 1000.0;
  grams.two_point.stator_mass *= 1000.0;
  mistakes = UnitMistakes(grams);
  REQUIRE(mistakes.size() == 1);
  CHECK_THAT(mistakes[0], Contains("analysis.speed_range_rpm = [20, 260] rpm: the range lies more than 10 "
                                   "times above the speed 1.65"));
}

TEST_CASE("Unit mistakes: a scene in mm warns at the command line and still runs (exit 0)",
          "[plan_check]") {
  TempDir dir;
  std::string text = testing::Slurp("scenes/thesis_A_a.toml");
  text.replace(text.find("contact_span = 0.29"), 19, "contact_span = 290.0");
  const fs::path scene = dir.path / "mm.toml";
  std::ofstream(scene) << text;
  const testing::Outcome outcome =
      RubcontNoPython("analytic " + scene.string() + " --out " + (dir.path / "mm.h5").string() + " -q");
  CHECK(outcome.exit_code == 0);
  CHECK_THAT(outcome.err, Contains("warning: rotor.contact_span = 290 m: larger than any rotor"));
  CHECK(fs::exists(dir.path / "mm.h5"));
}

}  // namespace
}  // namespace rubcont
