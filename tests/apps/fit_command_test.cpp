// `rubcont fit`, run as a user runs it: exit codes, messages, the HDF5 layout of apps/fit_command.h.
#include "apps/fit_command.h"

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

namespace rubcont {
namespace {

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

using testing::Outcome;
using testing::Slurp;
using testing::TempDir;

std::string DefaultSceneWithRange(const std::string& range) {
  std::ifstream in("scenes/default.toml");
  std::string text((std::istreambuf_iterator<char>(in)), {});
  const std::string section = "[analysis]\n";
  const std::size_t at = text.find(section);
  REQUIRE(at != std::string::npos);
  REQUIRE(text.find("speed_range_rpm") == std::string::npos);
  return text.substr(0, at + section.size()) + "speed_range_rpm = " + range + "\n" +
         text.substr(at + section.size());
}

TEST_CASE("rubcont fit recovers friction from a jump speed and writes /fit", "[cli][fit]") {
  TempDir dir;
  const fs::path scene = dir.path / "narrow.toml";
  std::ofstream(scene) << DefaultSceneWithRange("[20.0, 100.0]");
  const fs::path targets = dir.path / "targets.toml";
  // 50.689 rpm is the scene's own Mode 1 stick → slip speed (μ = 0.5): the fit must return 0.5.
  std::ofstream(targets) << "[[parameter]]\nname = \"friction\"\nrange = [0.3, 0.7]\n"
                            "[[target]]\nfamily = \"mode1\"\nevent = \"stick to slip+\"\n"
                            "quantity = \"speed_rpm\"\nvalue = 50.688718793\nuncertainty = 0.001\n"
                            "[fit]\nglobal_evaluations = 15\nlocal_evaluations = 60\n";
  const fs::path file = dir.path / "fit.h5";
  const Outcome o = testing::RubcontNoPython("fit " + scene.string() + " --targets " + targets.string() + " -q --out " +
                            file.string());
  INFO(o.out << o.err);
  REQUIRE(o.exit_code == 0);
  CHECK_THAT(o.out, Contains("[fit] fitted"));
  ResultReader reader(file);
  CHECK(reader.ReadStringAttribute("/fit", "status") == "fitted");
  const std::vector<double> values = reader.ReadDoubles("/fit/values");
  REQUIRE(values.size() == 1);
  CHECK(values[0] == Approx(0.5).epsilon(1e-5));
  CHECK(reader.ReadStrings("/fit/parameter_names") == std::vector<std::string>{"friction"});
  CHECK(reader.ReadDoubles("/fit/residuals").size() == 1);
}

TEST_CASE("rubcont fit rejects bad targets files naming key, value and rule", "[cli][fit][failure]") {
  TempDir dir;
  const fs::path targets = dir.path / "t.toml";
  std::ofstream(targets) << "[[parameter]]\nname = \"mu\"\nrange = [0.3, 0.7]\n"
                            "[[parameter]]\nname = \"stator_damping\"\nrange = [-5.0, 700.0]\n"
                            "[[target]]\nfamily = \"mode3\"\nevent = \"stick to slip+\"\n"
                            "quantity = \"rpm\"\nvalue = 50.0\nuncertainty = 0.0\ncolour = 1\n"
                            "[fit]\nglobal = \"genetic\"\nlocal_starts = 0\n";
  const Outcome o = testing::RubcontNoPython("fit scenes/default.toml --targets " + targets.string() + " -q --out " +
                            (dir.path / "f.h5").string());
  CHECK(o.exit_code == 2);
  CHECK_THAT(o.err, Contains("parameter[0].name = \"mu\": must be one of friction"));
  CHECK_THAT(o.err, Contains("parameter[1].range = [ -5.0, 700.0 ]: lower must lie in the physical range"));
  CHECK_THAT(o.err, Contains("target[0].family = \"mode3\": must be mode1"));
  CHECK_THAT(o.err, Contains("target[0].quantity = \"rpm\": must be speed_rpm or precession_hz"));
  CHECK_THAT(o.err, Contains("target[0].uncertainty = 0.0: must be positive"));
  CHECK_THAT(o.err, Contains("target[0].colour: unknown key"));
  CHECK_THAT(o.err, Contains("fit.global = \"genetic\": must be direct_l, crs2 or multistart"));
  CHECK_THAT(o.err, Contains("fit.local_starts = 0: must be an integer in 1 … 100000"));
  CHECK(!fs::exists(dir.path / "f.h5"));
  const Outcome missing = testing::RubcontNoPython("fit scenes/default.toml --targets " + (dir.path / "none.toml").string());
  CHECK(missing.exit_code == 2);
  CHECK_THAT(missing.err, Contains("cannot read the targets file"));
  const Outcome threads = testing::RubcontNoPython(
      "fit scenes/default.toml --targets tests/apps/fit_multistart.toml --threads 2000");
  CHECK(threads.exit_code == 2);
  CHECK_THAT(threads.err, Contains("--threads = 2000: must be in 0 … 1024"));
}

}  // namespace
}  // namespace rubcont
