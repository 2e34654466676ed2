// `rubcont map`, run as a user runs it: exit codes, messages, the HDF5 layout of apps/map_command.h.
#include "apps/map_command.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <catch2/catch.hpp>
#include <sys/wait.h>
#include <unistd.h>

#include "apps/hdf5_file.h"

namespace rubcont {
namespace {

namespace fs = std::filesystem;
using Catch::Matchers::Contains;

struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("rubcont_map_test_" + std::to_string(getpid()) + "_" +
                                        std::to_string(counter++));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() { fs::remove_all(path); }
  static inline int counter = 0;
};

std::string Slurp(const fs::path& file) {
  std::ifstream in(file);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

struct Outcome {
  int exit_code = -1;
  std::string out;
  std::string err;
};

Outcome Rubcont(const std::string& args) {
  const char* binary_dir = std::getenv("RUBCONT_BINARY_DIR");
  const std::string binary = std::string(binary_dir ? binary_dir : "build") + "/rubcont";
  TempDir capture;
  const fs::path out = capture.path / "out", err = capture.path / "err";
  // No Python: figures are skipped with a warning, and the test stays fast.
  const std::string command = "RUBCONT_PYTHON=/nonexistent/python3 " + binary + " " + args + " >" +
                              out.string() + " 2>" + err.string();
  const int status = std::system(command.c_str());
  Outcome outcome;
  outcome.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  outcome.out = Slurp(out);
  outcome.err = Slurp(err);
  return outcome;
}

TEST_CASE("rubcont map writes /maps/<parameter> with grid, points and curves", "[cli][map]") {
  TempDir dir;
  const fs::path file = dir.path / "map.h5";
  const Outcome o = Rubcont("map scenes/default.toml --parameter stator_damping --range 250 400 "
                            "--eta-points 3 --speed-points 101 -q --out " + file.string());
  INFO(o.out << o.err);
  REQUIRE(o.exit_code == 0);
  CHECK_THAT(o.out, Contains("map of stator_damping over [250, 400]"));
  REQUIRE(fs::exists(file));
  CHECK(!fs::exists(file.string() + ".tmp"));
  ResultReader reader(file);
  const std::string g = "/maps/stator_damping";
  CHECK(reader.ReadStringAttribute(g, "unit") == "N·s/m");
  CHECK(reader.ReadDoubleAttribute(g, "base_value") == Approx(324.9));
  CHECK(reader.ReadDoubles(g + "/eta").size() == 3);
  CHECK(reader.ReadDoubles(g + "/speed_rpm").size() == 101);
  const Matrix count = reader.ReadMatrix(g + "/stable_count");
  CHECK(count.rows() == 3);
  CHECK(count.cols() == 101);
  CHECK(reader.Exists(g + "/by_pattern/mode1/stable_count"));
  CHECK(reader.Exists(g + "/points/speed_rpm"));
  const std::vector<std::string> curves = reader.Children(g + "/curves");
  REQUIRE(!curves.empty());
  CHECK(reader.ReadStringAttribute(g + "/curves/" + curves[0], "kind") == "event");
  CHECK(!reader.ReadDoubles(g + "/curves/" + curves[0] + "/eta").empty());
  CHECK(reader.ReadStringAttribute("/", "level") == "L1");
}

TEST_CASE("rubcont map rejects bad parameters and ranges with exit code 2", "[cli][map][failure]") {
  TempDir dir;
  const std::string out = " -q --out " + (dir.path / "m.h5").string();
  Outcome o = Rubcont("map scenes/default.toml --parameter mu" + out);
  CHECK(o.exit_code == 2);
  CHECK_THAT(o.err, Contains("--parameter = \"mu\": must be one of friction"));
  o = Rubcont("map scenes/default.toml --parameter friction --range -0.2 0.5" + out);
  CHECK(o.exit_code == 2);
  CHECK_THAT(o.err, Contains("--eta-min = -0.2: must lie in the physical range of friction"));
  o = Rubcont("map scenes/default.toml --parameter friction --range 0.6 0.4" + out);
  CHECK(o.exit_code == 2);
  CHECK_THAT(o.err, Contains("--eta-max = 0.4: must be finite and exceed --eta-min = 0.6"));
  o = Rubcont("map scenes/default.toml --parameter friction --eta-points 1" + out);
  CHECK(o.exit_code == 2);
  CHECK_THAT(o.err, Contains("--eta-points = 1: must be in 2"));
  o = Rubcont("map scenes/jeffcott.toml --parameter friction" + out);
  CHECK(o.exit_code == 2);
  CHECK_THAT(o.err, Contains("rubcont map needs the two_point model"));
  CHECK(!fs::exists(dir.path / "m.h5"));
}

}  // namespace
}  // namespace rubcont

// `rubcont fit` (apps/fit_command.h) lives here too: same helpers, same kind of checks.
#include "apps/fit_command.h"

namespace rubcont {
namespace {

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
  const Outcome o = Rubcont("fit " + scene.string() + " --targets " + targets.string() + " -q --out " +
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
                            "quantity = \"rpm\"\nvalue = 50.0\nuncertainty = 0.0\ncolour = 1\n";
  const Outcome o = Rubcont("fit scenes/default.toml --targets " + targets.string() + " -q --out " +
                            (dir.path / "f.h5").string());
  CHECK(o.exit_code == 2);
  CHECK_THAT(o.err, Contains("parameter[0].name = \"mu\": must be one of friction"));
  CHECK_THAT(o.err, Contains("parameter[1].range = [ -5.0, 700.0 ]: lower must lie in the physical range"));
  CHECK_THAT(o.err, Contains("target[0].family = \"mode3\": must be mode1"));
  CHECK_THAT(o.err, Contains("target[0].quantity = \"rpm\": must be speed_rpm or precession_hz"));
  CHECK_THAT(o.err, Contains("target[0].uncertainty = 0.0: must be positive"));
  CHECK_THAT(o.err, Contains("target[0].colour: unknown key"));
  CHECK(!fs::exists(dir.path / "f.h5"));
  const Outcome missing = Rubcont("fit scenes/default.toml --targets " + (dir.path / "none.toml").string());
  CHECK(missing.exit_code == 2);
  CHECK_THAT(missing.err, Contains("cannot read the targets file"));
}

}  // namespace
}  // namespace rubcont
