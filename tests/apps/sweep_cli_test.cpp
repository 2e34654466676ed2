// `rubcont sweep`, run as a user runs it: what the file holds, one direction after the other,
// --resume of a complete file, bad input.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "cli_support.h"
#include "describe_support.h"
#include <sys/wait.h>
#include <unistd.h>

#include <H5Cpp.h>

#include "apps/hdf5_file.h"
#include "apps/scene.h"
#include "models/units.h"

namespace rubcont {
namespace {

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

using testing::Outcome;
using testing::Slurp;
using testing::TempDir;

// Case A(a) with a two-speed sweep each way (40 and 44 rpm: whirl), written into `dir`.
fs::path ShortSweepScene(const fs::path& dir, const std::string& sweep_section) {
  std::string text = Slurp("scenes/thesis_A_a.toml");
  const auto at = text.find("[analysis.sweep]");
  REQUIRE(at != std::string::npos);
  text = text.substr(0, at) + sweep_section;
  const fs::path file = dir / "thesis_A_a.toml";
  std::ofstream(file) << text;
  return file;
}

const std::string kTwoSpeeds =
    "[analysis.sweep]\nup_range_rpm = [40.0, 44.0]\ndown_range_rpm = [40.0, 44.0]\n"
    "speed_step_rpm = 4.0\ndwell = 0.75\n";

// Sweeps `scene` up into `h5`, then removes `lines` (each a whole line of the resolved scene, with
// its newline) from the file's stored scene: a file as an earlier version, before those keys, wrote it.
void SweepUpAsWrittenWithout(const fs::path& scene, const fs::path& h5,
                             const std::vector<std::string>& lines) {
  const Outcome first =
      testing::RubcontNoPython("sweep " + scene.string() + " --direction up --quiet --out " + h5.string());
  INFO(first.out << first.err);
  REQUIRE(first.exit_code == 0);
  H5::H5File file(h5.string(), H5F_ACC_RDWR);
  const H5::StrType type(H5::PredType::C_S1, H5T_VARIABLE);
  std::string toml;
  {
    const H5::Attribute stored = file.openAttribute("scene_toml");
    stored.read(stored.getStrType(), toml);
  }
  for (const std::string& line : lines) {
    const auto at = toml.find(line);
    REQUIRE(at != std::string::npos);
    toml.erase(at, line.size());
  }
  file.removeAttr("scene_toml");
  file.createAttribute("scene_toml", type, H5::DataSpace(H5S_SCALAR)).write(type, toml);
}

TEST_CASE("rubcont sweep: one direction after the other gives one file with both, and the jump table",
          "[sweep_cli]") {
  TempDir dir;
  const fs::path scene = ShortSweepScene(dir.path, kTwoSpeeds);
  const fs::path h5 = dir.path / "sweep.h5";

  const Outcome up = testing::RubcontNoPython("sweep " + scene.string() + " --direction up --quiet --out " + h5.string());
  INFO(up.out << up.err);
  REQUIRE(up.exit_code == 0);
  CHECK_THAT(up.out, Contains("Odeint Dormand-Prince 5(4), rtol = atol 1e-08; 4 rpm steps"));
  CHECK_THAT(up.out, Contains("up: 2 of 2 speeds, 40 → 44 rpm"));
  CHECK_FALSE(fs::exists(dir.path / "sweep.up.checkpoint.h5"));  // removed once the file is written
  std::vector<double> up_bp;
  {
    ResultReader r(h5);
    CHECK(r.ReadStringAttribute("/", "level") == "L3");
    CHECK(r.ReadStringAttribute("/sweeps/up", "status") == "complete");
    CHECK_FALSE(r.Exists("/sweeps/down"));
    CHECK(r.Exists("/branches/branch1"));                 // the scene's law (exact)
    CHECK(r.ReadStringAttribute("/sweeps/branches", "friction_law") == "tanh");  // the sweeps' law
    CHECK(r.Exists("/sweeps/jump_table/difference_rpm"));
    // Every numeric [analysis.sweep] key is an attribute of the direction's group, from the one list.
    int scalars = 0;
    for (const auto& [key, value] : SweepKeyValues(LoadScene(scene))) {
      if (const auto* text = std::get_if<std::string>(&value)) {
        CHECK(r.ReadStringAttribute("/sweeps/up", key) == *text);
        continue;
      }
      const auto& values = std::get<std::vector<double>>(value);
      if (values.size() != 1) continue;
      CHECK(r.ReadDoubleAttribute("/sweeps/up", key) == values[0]);
      ++scalars;
    }
    CHECK(scalars == 18);
    CHECK(r.ReadStringAttribute("/sweeps/up", "integrator_method") == "Odeint Dormand-Prince");
    up_bp = r.ReadDoubles("/sweeps/up/precession_hz_left");
    REQUIRE(up_bp.size() == 2);
    // Rolling whirl at RCI 100: BP = 100 × speed / 60.
    CHECK(up_bp[0] == Approx(100.0 * RpmToHz(40.0)).epsilon(0.01));
    CHECK(up_bp[1] == Approx(100.0 * RpmToHz(44.0)).epsilon(0.01));
  }

  const Outcome down = testing::RubcontNoPython("sweep " + scene.string() + " --direction down --quiet --out " + h5.string());
  INFO(down.out << down.err);
  REQUIRE(down.exit_code == 0);
  {
    ResultReader r(h5);
    CHECK(r.ReadDoubles("/sweeps/up/precession_hz_left") == up_bp);  // kept, not recomputed
    const std::vector<double> speeds = r.ReadDoubles("/sweeps/down/speed_rpm");
    REQUIRE(speeds.size() == 2);
    CHECK(speeds[0] == Approx(44.0).epsilon(1e-12));
    CHECK(speeds[1] == Approx(40.0).epsilon(1e-12));
  }
  {
    // Both directions describe themselves (apps/hdf5_file.h), the one rewritten from the file too:
    // speed labels every per-speed column, the spectrum's bins its second axis.
    const H5::H5File file(h5.string(), H5F_ACC_RDONLY);
    for (const std::string g : {"/sweeps/up", "/sweeps/down"}) {
      CHECK(testing::ScaleOf(file, g + "/precession_hz_left", 0) == "speed_rpm");
      CHECK(testing::ScaleOf(file, g + "/regime_left", 0) == "speed_rpm");
      CHECK(testing::ScaleOf(file, g + "/spectrum_magnitude_left", 0) == "speed_rpm");
      CHECK(testing::ScaleOf(file, g + "/spectrum_magnitude_left", 1) == "spectrum_frequency_hz");
      CHECK(testing::StringAttribute(file.openDataSet(g + "/speed_rpm"), "units") == "rpm");
      CHECK(testing::StringAttribute(file.openDataSet(g + "/spectrum_magnitude_left"), "units") == "m");
      CHECK(testing::StringAttribute(file.openDataSet(g + "/settled"), "flag_meanings") ==
            "not_settled settled");
    }
    CHECK(testing::CreationOrder(file, "/sweeps") ==
          std::vector<std::string>{"up", "down", "branches", "jump_table"});  // as written
  }

  // --resume with both directions complete in the file: nothing is integrated again.
  const Outcome again = testing::RubcontNoPython("sweep " + scene.string() + " --resume --out " + h5.string());
  INFO(again.out << again.err);
  REQUIRE(again.exit_code == 0);
  CHECK_THAT(again.err, Contains("[sweep up] complete in"));
  CHECK_THAT(again.err, Contains("[sweep down] complete in"));
  {
    ResultReader r(h5);
    CHECK(r.ReadDoubles("/sweeps/up/precession_hz_left") == up_bp);
    CHECK(r.ReadStrings("/sweeps/up/regime_left") == std::vector<std::string>{"whirl", "whirl"});
  }

  // Other rules for reading the finished speeds are not other sweeps: --resume classifies them
  // again without integrating. With rolling thresholds below the whirl's micro-slip (about
  // 2e-4 of ωR, 0.04ε at 40–44 rpm) the same speeds read as whip.
  ShortSweepScene(dir.path, kTwoSpeeds + "rolling_slip_tolerance = 1e-6\nrolling_micro_slip = 0.0\n");
  const Outcome reread = testing::RubcontNoPython("sweep " + scene.string() + " --resume --out " + h5.string());
  INFO(reread.out << reread.err);
  REQUIRE(reread.exit_code == 0);
  CHECK_THAT(reread.err, Contains("[sweep up] complete in"));
  CHECK_THAT(reread.err, Contains("[sweep down] complete in"));
  ResultReader r(h5);
  CHECK(r.ReadDoubles("/sweeps/up/precession_hz_left") == up_bp);
  CHECK(r.ReadStrings("/sweeps/up/regime_left") == std::vector<std::string>{"whip", "whip"});
  CHECK(r.ReadDoubleAttribute("/sweeps/up", "rolling_slip_tolerance") == 1e-6);
  const std::vector<double> ratio = r.ReadDoubles("/sweeps/up/slip_ratio_left");
  REQUIRE(ratio.size() == 2);
  CHECK(ratio[0] > 1e-6);
  CHECK(ratio[0] < 0.005);
}

TEST_CASE("rubcont sweep: --resume does not take a file from before a key existed for the same "
          "sweeps", "[sweep_cli]") {
  // A file written before [analysis.sweep] integrator existed (BDF was the default then): its
  // stored scene lacks the key, which today's default would fill in as "explicit". Such a file is
  // integrated again, not relabelled.
  TempDir dir;
  const fs::path scene = ShortSweepScene(dir.path, kTwoSpeeds);
  const fs::path h5 = dir.path / "sweep.h5";
  SweepUpAsWrittenWithout(scene, h5, {"integrator = \"explicit\"\n"});
  const Outcome again =
      testing::RubcontNoPython("sweep " + scene.string() + " --direction up --resume --out " + h5.string());
  INFO(again.out << again.err);
  REQUIRE(again.exit_code == 0);
  CHECK_THAT(again.err, !Contains("complete in"));
  ResultReader r(h5);
  CHECK_THAT(r.ReadStringAttribute("/", "scene_toml"), Contains("integrator = \"explicit\""));
  CHECK(r.ReadStringAttribute("/sweeps/up", "status") == "complete");
}

TEST_CASE("rubcont sweep: --resume takes a file from before a key added at its older behaviour",
          "[sweep_cli]") {
  // [analysis.orbits] at_grazing and predictor were added with defaults that keep what runs did
  // before them (AddedAtOlderBehaviour): a stored scene without them describes the same sweeps.
  TempDir dir;
  const fs::path scene = ShortSweepScene(dir.path, kTwoSpeeds);
  const fs::path h5 = dir.path / "sweep.h5";
  SweepUpAsWrittenWithout(scene, h5, {"at_grazing = \"continue\"\n", "predictor = \"tangent\"\n"});
  const Outcome again =
      testing::RubcontNoPython("sweep " + scene.string() + " --direction up --resume --out " + h5.string());
  INFO(again.out << again.err);
  REQUIRE(again.exit_code == 0);
  CHECK_THAT(again.err, Contains("[sweep up] complete in"));  // read, not integrated again
}

TEST_CASE("rubcont sweep: --resume takes a file whose scene differs in the loop's keys only", "[sweep_cli]") {
  // [analysis.loop] (its budget's unit and default changed on 2026-11-30) does not touch the sweeps.
  TempDir dir;
  const fs::path scene = ShortSweepScene(dir.path, kTwoSpeeds + "[analysis.loop]\nbudget = 2.0\n");
  const fs::path h5 = dir.path / "sweep.h5";
  const Outcome first =
      testing::RubcontNoPython("sweep " + scene.string() + " --direction up --no-figures --out " + h5.string());
  INFO(first.out << first.err);
  REQUIRE(first.exit_code == 0);
  ShortSweepScene(dir.path, kTwoSpeeds + "[analysis.loop]\nbudget = 9.0\n");
  const Outcome again = testing::RubcontNoPython("sweep " + scene.string() +
                                                 " --direction up --no-figures --resume --out " + h5.string());
  INFO(again.out << again.err);
  REQUIRE(again.exit_code == 0);
  CHECK_THAT(again.err, Contains("[sweep up] complete in"));  // read, not integrated again
}

TEST_CASE("rubcont sweep: the auto integrator takes Dormand-Prince where the contact bounces, and "
          "at a loose explicit tolerance would keep up a chatter that has died out",
          "[sweep_cli]") {
  // Case A(a) from the impulse at 20 rpm: the rotor bounces on the stator (contact 60 % of the
  // last 0.5 s by BDF and by Dormand–Prince at 1e-9), then whirls in full contact at 24 rpm.
  auto contact_at_24 = [](const std::string& explicit_tolerance) {
    TempDir dir;
    const fs::path scene = ShortSweepScene(
        dir.path, "[analysis.sweep]\nup_range_rpm = [20.0, 24.0]\ndown_range_rpm = [20.0, 24.0]\n"
                  "speed_step_rpm = 4.0\ndwell = 0.75\nintegrator = \"auto\"\n" + explicit_tolerance);
    const fs::path h5 = dir.path / "sweep.h5";
    const Outcome o = testing::RubcontNoPython("sweep " + scene.string() +
                                               " --direction up --no-figures --out " + h5.string());
    INFO(o.out << o.err);
    REQUIRE(o.exit_code == 0);
    CHECK_THAT(o.out, Contains("Odeint Dormand-Prince 5(4)"));
    ResultReader r(h5);
    CHECK(r.ReadStringAttribute("/sweeps/up", "integrator") == "auto");
    CHECK(r.ReadStringAttribute("/sweeps/up", "intermittent_integrator_method") == "Odeint Dormand-Prince");
    const std::vector<int> explicit_windows = r.ReadInts("/sweeps/up/intermittent_windows");
    REQUIRE(explicit_windows.size() == 2);
    CHECK(explicit_windows[0] >= 1);  // the bouncing after the impulse
    return r.ReadDoubles("/sweeps/up/contact_fraction_left").at(1);
  };
  // The default (1e-8): full contact at 24 rpm, as the tight references.
  CHECK(contact_at_24("") > 0.99);
  // 1e-5: Dormand–Prince at its stability limit keeps the contact chattering (measured 0.12;
  // Odeint's error test, a maximum over the scaled states, holds it from 1e-6 on, where ARKODE's
  // root-mean-square one chattered at 1e-6, 0.23, and 1e-7).
  CHECK(contact_at_24("explicit_tolerance = 1e-5\n") < 0.5);
}

TEST_CASE("rubcont sweep: an imbalanced rotor sweeps, its jump table uses the balanced branches",
          "[sweep_cli]") {
  TempDir dir;
  std::string text = Slurp("scenes/thesis_A_a_imbalance.toml");
  const auto at = text.find("[analysis.sweep]");
  REQUIRE(at != std::string::npos);
  text = text.substr(0, at) + kTwoSpeeds;
  const fs::path scene = dir.path / "thesis_A_a_imbalance.toml";
  std::ofstream(scene) << text;
  const fs::path h5 = dir.path / "sweep.h5";
  const Outcome up = testing::RubcontNoPython("sweep " + scene.string() + " --direction up --quiet --out " + h5.string());
  INFO(up.out << up.err);
  REQUIRE(up.exit_code == 0);
  ResultReader r(h5);
  CHECK(r.ReadStringAttribute("/sweeps/up", "status") == "complete");
  CHECK(r.Exists("/sweeps/branches/branch1"));
  // Rolling whirl at RCI 100 despite the imbalance (m e ω² = 6e-4 N at 40 rpm).
  const std::vector<double> bp = r.ReadDoubles("/sweeps/up/precession_hz_left");
  REQUIRE(bp.size() == 2);
  CHECK(bp[0] == Approx(100.0 * RpmToHz(40.0)).epsilon(0.01));
}

TEST_CASE("rubcont sweep: a speed beyond max_penetration is untrusted in the summary and the file",
          "[sweep_cli]") {
  // The whirl at 40 and 44 rpm penetrates the stiff thesis contact by ~1e-8 m: trusted under the
  // default limit (0.1 of the clearance, 3.8e-5 m), untrusted under 1e-6 of it (3.8e-10 m).
  TempDir dir;
  auto run = [&](const std::string& limit, const std::string& name) {
    const fs::path scene = ShortSweepScene(dir.path, kTwoSpeeds + limit);
    const fs::path h5 = dir.path / name;
    const Outcome o = testing::RubcontNoPython("sweep " + scene.string() + " --direction up --quiet --out " + h5.string());
    INFO(o.out << o.err);
    REQUIRE(o.exit_code == 0);
    return std::make_pair(o.out, h5);
  };
  const auto [trusted_out, trusted_h5] = run("", "trusted.h5");
  CHECK_THAT(trusted_out, !Contains("untrusted"));
  {
    ResultReader r(trusted_h5);
    CHECK(r.ReadStrings("/sweeps/up/untrusted") == std::vector<std::string>{"", ""});
    for (double depth : r.ReadDoubles("/sweeps/up/penetration_max_left")) {
      CHECK(depth > 0.0);
      CHECK(depth < 1e-4 * 3.81e-4);
    }
  }
  const auto [strict_out, strict_h5] = run("max_penetration = 1e-6\n", "strict.h5");
  CHECK_THAT(strict_out, Contains("untrusted at 40.0 rpm: the left contact penetrates"));
  CHECK_THAT(strict_out, Contains("× its clearance (limit 1e-06)"));
  ResultReader r(strict_h5);
  const std::vector<std::string> untrusted = r.ReadStrings("/sweeps/up/untrusted");
  REQUIRE(untrusted.size() == 2);
  CHECK_THAT(untrusted[1], Contains("contact penetrates"));
  CHECK(r.Exists("/sweeps/jump_table/trusted"));
}

TEST_CASE("rubcont sweep: a checkpoint is refused without --resume or --fresh (exit 2) and kept",
          "[sweep_cli]") {
  // It used to be overwritten with a warning: 28 of 41 finished speeds lost by a re-run (issue 50).
  TempDir dir;
  const fs::path scene = ShortSweepScene(dir.path, kTwoSpeeds);
  const fs::path h5 = dir.path / "sweep.h5";
  const fs::path checkpoint = dir.path / "sweep.up.checkpoint.h5";
  const std::string saved = "the finished speeds of an interrupted run";
  std::ofstream(checkpoint) << saved;
  const std::string run = "sweep " + scene.string() + " --direction up --quiet --out " + h5.string();

  const Outcome refused = testing::RubcontNoPython(run);
  CHECK(refused.exit_code == 2);
  CHECK(refused.err == "rubcont: " + checkpoint.string() +
                           " holds the finished speeds of an interrupted up sweep: --resume continues "
                           "from it, --fresh starts again and overwrites it\n");
  CHECK(Slurp(checkpoint) == saved);
  CHECK_FALSE(fs::exists(h5));
  const Outcome both = testing::RubcontNoPython(run + " --resume --fresh");
  CHECK(both.exit_code == 2);
  CHECK_THAT(both.err, Contains("--resume and --fresh: give one of them"));
  CHECK(Slurp(checkpoint) == saved);

  const Outcome fresh = testing::RubcontNoPython(run + " --fresh");
  INFO(fresh.err);
  CHECK(fresh.exit_code == 0);
  CHECK_THAT(fresh.err, Contains("starting the up sweep afresh (--fresh)"));
  CHECK(ResultReader(h5).ReadDoubles("/sweeps/up/speed_rpm").size() == 2);
  CHECK_FALSE(fs::exists(checkpoint));
}

TEST_CASE("rubcont sweep: bad input names the key, the value and the rule, with exit code 2",
          "[sweep_cli]") {
  TempDir dir;
  const fs::path scene = ShortSweepScene(dir.path, "[analysis.sweep]\ndwell = -1.0\n");
  const Outcome bad = testing::RubcontNoPython("sweep " + scene.string() + " --quiet --out " + (dir.path / "x.h5").string());
  CHECK(bad.exit_code == 2);
  CHECK_THAT(bad.err, Contains("analysis.sweep.dwell = -1"));
  CHECK_THAT(bad.err, Contains("must be positive"));
  CHECK_FALSE(fs::exists(dir.path / "x.h5"));
  const fs::path flat = ShortSweepScene(dir.path, kTwoSpeeds + "max_penetration = 0.0\n");
  const Outcome zero = testing::RubcontNoPython("sweep " + flat.string() + " --quiet --out " + (dir.path / "x.h5").string());
  CHECK(zero.exit_code == 2);
  CHECK_THAT(zero.err, Contains("analysis.sweep.max_penetration = 0"));

  const fs::path good = ShortSweepScene(dir.path, kTwoSpeeds);
  const Outcome sideways = testing::RubcontNoPython("sweep " + good.string() + " --direction sideways");
  CHECK(sideways.exit_code == 2);
  CHECK_THAT(sideways.err, Contains("--direction"));
}

}  // namespace
}  // namespace rubcont
