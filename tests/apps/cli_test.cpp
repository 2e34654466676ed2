// The rubcont executable, run as a user runs it: exit codes, messages, files written.
#include <algorithm>
#include <cmath>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "cli_support.h"
#include <sys/wait.h>
#include <unistd.h>

#include "apps/hdf5_file.h"
#include "apps/scene.h"

namespace rubcont {
namespace {

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using Catch::Matchers::StartsWith;

using testing::Outcome;
using testing::Slurp;
using testing::TempDir;
using testing::kNoPython;
using testing::Rubcont;

TEST_CASE("CLI: scene check accepts a valid scene and prints resolved values (exit 0)", "[cli]") {
  const Outcome o = Rubcont("scene check scenes/thesis_B_b.toml");
  CHECK(o.exit_code == 0);
  CHECK_THAT(o.out, Contains("valid scene \"thesis_B_b\""));
  CHECK_THAT(o.out, Contains("rotor.mass_center                      = 0.22 m"));
  CHECK_THAT(o.out, Contains("RCI_R = R_R/C_R = 125"));
}

TEST_CASE("CLI: a bad scene is exit code 2 with key, value and rule", "[cli]") {
  TempDir dir;
  std::string text = Slurp("scenes/thesis_A_a.toml");
  text.replace(text.find("mass = 9.99"), 11, "mass = -1  ");
  std::ofstream(dir.path / "bad.toml") << text;
  const Outcome o = Rubcont("scene check " + (dir.path / "bad.toml").string());
  CHECK(o.exit_code == 2);
  CHECK_THAT(o.err, Contains("bad.toml:6:8: rotor.mass = -1: must be positive (kg)"));
  CHECK(Rubcont("run " + (dir.path / "bad.toml").string() + " --out " + dir.path.string()).exit_code == 2);
  CHECK(Rubcont("analytic " + (dir.path / "bad.toml").string()).exit_code == 2);
  CHECK_FALSE(fs::exists(dir.path / "bad"));  // nothing written

  std::ofstream(dir.path / "syntax.toml") << "[rotor\nmass = 1\n";
  const Outcome syntax = Rubcont("scene check " + (dir.path / "syntax.toml").string());
  CHECK(syntax.exit_code == 2);
  CHECK_THAT(syntax.err, Contains("syntax.toml:1:"));
  CHECK(Rubcont("scene check " + (dir.path / "missing.toml").string()).exit_code == 2);
  const Outcome directory = Rubcont("scene check " + dir.path.string());
  CHECK(directory.exit_code == 2);
  CHECK_THAT(directory.err, Contains("is a directory, not a scene file"));
}

TEST_CASE("CLI: a temporary file left by an interrupted run is removed, and said so", "[cli]") {
  TempDir dir;
  const fs::path h5 = dir.path / "a.h5";
  std::ofstream(dir.path / "a.h5.tmp.12345.0badcafe") << "half a file";
  fs::last_write_time(dir.path / "a.h5.tmp.12345.0badcafe",
                      fs::file_time_type::clock::now() - std::chrono::minutes(1));
  const Outcome o = testing::RubcontNoPython("analytic scenes/thesis_A_a.toml --quiet --out " + h5.string());
  CHECK(o.exit_code == 0);
  CHECK_THAT(o.err, Contains("a.h5.tmp.12345.0badcafe was left by an interrupted run; it is removed"));
  CHECK(fs::exists(h5));
  CHECK_FALSE(fs::exists(dir.path / "a.h5.tmp.12345.0badcafe"));
  const Outcome again = testing::RubcontNoPython("analytic scenes/thesis_A_a.toml --quiet --out " + h5.string());
  CHECK_THAT(again.err, !Contains("interrupted run"));
}

TEST_CASE("CLI: bad arguments are exit code 2, help is 0", "[cli]") {
  CHECK(Rubcont("").exit_code == 2);
  CHECK(Rubcont("frobnicate").exit_code == 2);
  CHECK(Rubcont("run --bogus").exit_code == 2);
  CHECK(Rubcont("analytic").exit_code == 2);  // SCENE is required
  CHECK(Rubcont("scene").exit_code == 2);
  CHECK(Rubcont("--help").exit_code == 0);
  const Outcome version = Rubcont("--version");
  CHECK(version.exit_code == 0);
  CHECK_THAT(version.out, Contains("rubcont 0."));
  CHECK_THAT(version.out, Contains("(git "));
  CHECK_THAT(version.out, Contains("BSD-3-Clause"));
}

// Random scene 37 of seed 1 (bench/random_scene_campaign --print 37), tanh law, branches only.
constexpr const char* kRandomScene37 =
    "description = \"random scene 37 of seed 1\"\n"
    "[rotor]\n"
    "mass = 6.5905127474272263\n"
    "inertia = 0.10015794025288097\n"
    "contact_span = 0.56134747393181883\n"
    "mass_center = 0.72360286455522049\n"
    "[stator]\n"
    "mass = 7.8311748919552802\n"
    "inertia = 0.21070294710748436\n"
    "span = 0.56433817571551792\n"
    "mass_center = 0.33415234469973842\n"
    "stiffness = [22742513.568590853, 540635.3890830694]\n"
    "damping = [427.38839224466307, 89.002074189427972]\n"
    "[contact]\n"
    "clearance = [0.00053993568261835557, 0.000409229770905801]\n"
    "radius = [0.068014053200672692, 0.036041097979320806]\n"
    "friction = 0.50458484435021755\n"
    "stiffness = 234860849558.96933\n"
    "stiffness2 = 0.0\n"
    "damping = 631610.5081770831\n"
    "[contact.friction_law]\n"
    "kind = \"tanh\"\n"
    "velocity_scale = 0.0013212719867768863\n"
    "[center_damper]\n"
    "damping = 0\n"
    "[analysis]\n"
    "stages = [\"branches\"]\n"
    "precession_range_hz = [1.0, 1541.1573912029467]\n"
    "speed_range_rpm = [3.6370079732847231, 1259.9366153478861]\n";

// Runs an inline scene as <dir>/<name>.toml with `rubcont run` (no figures): every special point
// located, exit code 0; the result file for the caller to read.
fs::path RunLocatingEverything(const TempDir& dir, const std::string& name, const char* toml) {
  const fs::path scene = dir.path / (name + ".toml");
  std::ofstream(scene) << toml;
  const Outcome o = Rubcont("run " + scene.string() + " --quiet --out " + dir.path.string(),
                            kNoPython);
  INFO(o.out << o.err);
  REQUIRE(o.exit_code == 0);
  CHECK_THAT(o.out, !Contains("not located"));
  return dir.path / name / (name + ".h5");
}

TEST_CASE("CLI: a step that jumps to another branch is taken again shorter (random scene 37)",
          "[cli]") {
  // Its one-contact whirl (branch3) becomes a full-slip whip whose state hardly changes with
  // speed; a 30 rpm step from 383.6 rpm landed on a branch with the right contact open: "right
  // contact loss, not located" (the margin's trial points between the step's ends could not be
  // corrected), and the branch ended there. Taken again shorter, it goes on to the speed bound
  // through the knees and Hopf points at 387–388 rpm it had jumped over.
  TempDir dir;
  const ResultReader r(RunLocatingEverything(dir, "random37", kRandomScene37));
  CHECK(r.ReadStringAttribute("/branches/branch3", "message") ==
        "backward: reached λ min = 0.3808665843; forward: reached λ max = 131.9402538");
}

// Random scene 61 of seed 1, tanh law, branches only (the analytic stage dropped).
constexpr const char* kRandomScene61 =
    "description = \"random scene 61 of seed 1\"\n"
    "[rotor]\n"
    "mass = 42.29085169782784\n"
    "inertia = 0.2888558066557958\n"
    "contact_span = 0.15502570568852575\n"
    "mass_center = 0.13469642918360214\n"
    "[stator]\n"
    "mass = 6.6400759790367303\n"
    "inertia = 0.12645757677179068\n"
    "span = 0.17903595911713252\n"
    "mass_center = 0.13128349033035028\n"
    "stiffness = [3562888.4273699634, 7305115.8669763906]\n"
    "damping = [5.3164640147888944, 49.086617334381778]\n"
    "[contact]\n"
    "clearance = [0.00095691347416691861, 0.00048625461398360277]\n"
    "radius = [0.061322634851795274, 0.027600073041162996]\n"
    "friction = 1.1029946968975168\n"
    "stiffness = 2995843772.4934807\n"
    "stiffness2 = 0.0\n"
    "damping = 24676.526041832847\n"
    "[contact.friction_law]\n"
    "kind = \"tanh\"\n"
    "velocity_scale = 0.00011803063348014272\n"
    "[center_damper]\n"
    "damping = 27.96149710992707\n"
    "[analysis]\n"
    "stages = [\"branches\"]\n"
    "precession_range_hz = [1.0, 511.55820016568958]\n"
    "speed_range_rpm = [13.04175953634644, 648.90489616504055]\n";

TEST_CASE("CLI: a tanh whip is followed through the rolling line's boundary layer (random scene 61)",
          "[cli]") {
  // Its Mode 2 start (branch1) is a whip touching the right contact only, the same state at
  // every speed down to 130.8 rpm, where the slip velocity falls to the tanh law's scale (1.2e-4
  // m/s) and the state changes within 0.1 rpm. Four halvings of a 1 rad/s step left a step that
  // still jumped: "right contact loss, not located", and the branch ended where the switch point
  // did not solve the contact-free piece. Ten halvings follow the layer into the one-contact
  // whirl, to the speed bound.
  TempDir dir;
  const ResultReader r(RunLocatingEverything(dir, "random61", kRandomScene61));
  CHECK_THAT(r.ReadStringAttribute("/branches/branch1", "message"),
             StartsWith("backward: reached λ max = 67.95316182"));
  const std::vector<double> slip = r.ReadDoubles("/branches/branch1/slip_velocity_right");
  CHECK(std::count_if(slip.begin(), slip.end(),
                      [](double v) { return std::abs(v) < 1e-3; }) >= 5);
}

TEST_CASE("CLI: run without a scene runs the built-in default into <out>/default/", "[cli]") {
  TempDir dir;
  const Outcome o = Rubcont("run --out " + dir.path.string(), kNoPython);
  CHECK(o.exit_code == 0);
  const fs::path h5 = dir.path / "default" / "default.h5";
  REQUIRE(fs::exists(h5));
  CHECK_FALSE(fs::exists(dir.path / "default" / "default.h5.tmp"));
  CHECK_THAT(o.out, Contains("84.4780 Hz  both   μ_req rises through μ"));
  CHECK_THAT(o.err, Contains("[analytic]"));  // progress
  CHECK_THAT(o.err, Contains("warning: figures not made: Python interpreter /nonexistent/python3 not found"));
  const ResultReader reader(h5);
  CHECK(reader.ReadStringAttribute("/", "level") == "L1");  // analytic, then branches
  CHECK_FALSE(reader.ReadStringAttribute("/", "rubcont_version").empty());
  CHECK_THAT(o.out, Contains("[branches] L1 rotating waves, exact friction"));
  CHECK_THAT(o.out, Contains("event: left stick to slip+"));
  CHECK(reader.ReadStringAttribute("/branches/branch1", "kind") == "rotating_wave");
  // The stored scene reproduces the run.
  const Scene stored = ParseScene(reader.ReadStringAttribute("/", "scene_toml"), "stored", "x");
  const auto body = [](const std::string& toml) { return toml.substr(toml.find('\n') + 1); };
  CHECK(body(ResolvedSceneToml(stored)) == body(ResolvedSceneToml(DefaultScene())));
  CHECK(reader.ReadDoubles("/analytic/mode1/precession_hz").size() == 4000);

  const Outcome quiet = Rubcont("run --quiet --out " + dir.path.string(), kNoPython);
  CHECK(quiet.exit_code == 0);
  CHECK(quiet.err.find("[analytic]") == std::string::npos);  // progress silenced ...
  CHECK_THAT(quiet.err, Contains("warning: figures not made"));  // ... warnings are not
}

TEST_CASE("CLI: analytic writes the HDF5 file and the two figures", "[cli]") {
  TempDir dir;
  const fs::path h5 = dir.path / "sub" / "c_a.h5";
  const Outcome o = Rubcont("analytic scenes/thesis_C_a.toml --quiet --out " + h5.string());
  CHECK(o.exit_code == 0);
  CHECK(o.err.empty());
  CHECK(fs::exists(h5));
  CHECK(fs::file_size(dir.path / "sub" / "analytic_mode1.png") > 10000);
  CHECK(fs::file_size(dir.path / "sub" / "analytic_mode2.png") > 10000);
}

TEST_CASE("CLI: --format svg and pdf write the figures in that format, another is exit 2", "[cli]") {
  TempDir dir;
  const Outcome svg = Rubcont("analytic scenes/thesis_C_a.toml -q --format svg --out " +
                              (dir.path / "c_a.h5").string());
  CHECK(svg.exit_code == 0);
  CHECK(svg.err.empty());
  CHECK_THAT(Slurp(dir.path / "analytic_mode1.svg"), Contains("<svg"));
  CHECK_FALSE(fs::exists(dir.path / "analytic_mode1.png"));
  const Outcome pdf = Rubcont("analytic scenes/thesis_C_a.toml -q --format pdf --out " +
                              (dir.path / "c_a.h5").string());
  CHECK(pdf.exit_code == 0);
  CHECK(Slurp(dir.path / "analytic_mode2.pdf").rfind("%PDF-", 0) == 0);
  const Outcome jpg = Rubcont("analytic scenes/thesis_C_a.toml -q --format jpg --out " +
                              (dir.path / "c_a.h5").string());
  CHECK(jpg.exit_code == 2);
  CHECK_THAT(jpg.err, Contains("--format"));
}

TEST_CASE("CLI: branches of an imbalanced scene leave the imbalance out and say so", "[cli]") {
  TempDir dir;
  const fs::path h5 = dir.path / "imbalance.h5";
  const Outcome o =
      Rubcont("branches scenes/thesis_A_a_imbalance.toml -q --out " + h5.string(), kNoPython);
  INFO(o.err);
  CHECK(o.exit_code == 0);
  CHECK_THAT(o.out, Contains("[branches] note: the imbalance (3.43e-05 kg·m) is left out"));
  CHECK_THAT(o.out, Contains("event: left stick to slip+"));
  const ResultReader reader(h5);
  CHECK_THAT(reader.ReadStringAttribute("/branches", "note"), Contains("not stationary"));
}

TEST_CASE("CLI: a missing plotting module keeps the HDF5 file (exit 0, warning)", "[cli]") {
  TempDir dir;
  const Outcome o = Rubcont("analytic scenes/thesis_A_b.toml -q --out " + (dir.path / "a.h5").string(),
                            "RUBCONT_PYTHON_DIR=" + dir.path.string());
  CHECK(o.exit_code == 0);
  CHECK_THAT(o.err, Contains("plotting module " + (dir.path / "rubcont/plots/analytic.py").string()));
  CHECK_THAT(o.err, Contains("the HDF5 result is complete"));
  CHECK(fs::exists(dir.path / "a.h5"));
}

TEST_CASE("CLI: a numerical failure is exit code 1 with the reason, and the data is kept", "[cli]") {
  TempDir dir;
  std::string text = Slurp("scenes/thesis_A_a.toml");
  // A rotor so light (but positive) that M_r⁻¹ overflows: the closed form is not finite.
  text.replace(text.find("mass = 9.99"), 11, "mass = 1e-320");
  std::ofstream(dir.path / "light.toml") << text;
  const Outcome o = Rubcont("analytic " + (dir.path / "light.toml").string() + " -q --out " +
                            (dir.path / "light.h5").string(), kNoPython);
  CHECK(o.exit_code == 1);
  CHECK_THAT(o.err, Contains("numerical failure: [analytic] mode1: contact force not finite at 1 Hz"));
  REQUIRE(fs::exists(dir.path / "light.h5"));
  CHECK(ResultReader(dir.path / "light.h5").ReadStringAttribute("/", "status") == "failure");
}

TEST_CASE("CLI: scene keys prints the schema's key reference", "[cli]") {
  const Outcome o = Rubcont("scene keys");
  CHECK(o.exit_code == 0);
  CHECK(o.out == SceneKeysMarkdown());
}

}  // namespace
}  // namespace rubcont
