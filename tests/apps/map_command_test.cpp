// `rubcont map`, run as a user runs it: exit codes, messages, the HDF5 layout of apps/map_command.h.
#include "apps/map_command.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <catch2/catch.hpp>

#include "cli_support.h"
#include "describe_support.h"
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

TEST_CASE("rubcont map writes /maps/<parameter> with grid, points and curves", "[cli][map]") {
  TempDir dir;
  const fs::path file = dir.path / "map.h5";
  const Outcome o = testing::RubcontNoPython("map scenes/default.toml --parameter stator_damping --range 250 400 "
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
  // Self-described (apps/hdf5_file.h): η in the parameter's unit wherever it is written, the
  // counts a field over (eta, speed_rpm), the regions coded.
  const H5::H5File h5(file.string(), H5F_ACC_RDONLY);
  CHECK(testing::StringAttribute(h5.openDataSet(g + "/eta"), "units") == "N s/m");
  CHECK(testing::StringAttribute(h5.openDataSet(g + "/points/eta"), "units") == "N s/m");
  CHECK(testing::StringAttribute(h5.openDataSet(g + "/curves/" + curves[0] + "/eta"), "units") ==
        "N s/m");
  CHECK(testing::ScaleOf(h5, g + "/stable_count", 0) == "eta");
  CHECK(testing::ScaleOf(h5, g + "/stable_count", 1) == "speed_rpm");
  CHECK(testing::ScaleOf(h5, g + "/speed_rpm", 0).empty());
  CHECK(testing::StringAttribute(h5.openDataSet(g + "/region"), "flag_meanings") ==
        "not_computed no_stable_circular_state one_stable_circular_state "
        "coexisting_stable_circular_states");
}

TEST_CASE("rubcont map rejects bad parameters and ranges with exit code 2", "[cli][map][failure]") {
  TempDir dir;
  const std::string out = " -q --out " + (dir.path / "m.h5").string();
  Outcome o = testing::RubcontNoPython("map scenes/default.toml --parameter mu" + out);
  CHECK(o.exit_code == 2);
  CHECK_THAT(o.err, Contains("--parameter = \"mu\": must be one of friction"));
  o = testing::RubcontNoPython("map scenes/default.toml --parameter friction --range -0.2 0.5" + out);
  CHECK(o.exit_code == 2);
  CHECK_THAT(o.err, Contains("--eta-min = -0.2: must lie in the physical range of friction"));
  o = testing::RubcontNoPython("map scenes/default.toml --parameter friction --range 0.6 0.4" + out);
  CHECK(o.exit_code == 2);
  CHECK_THAT(o.err, Contains("--eta-max = 0.4: must be finite and exceed --eta-min = 0.6"));
  o = testing::RubcontNoPython("map scenes/default.toml --parameter friction --eta-points 1" + out);
  CHECK(o.exit_code == 2);
  CHECK_THAT(o.err, Contains("--eta-points = 1: must be in 2"));
  o = testing::RubcontNoPython("map scenes/jeffcott.toml --parameter friction" + out);
  CHECK(o.exit_code == 2);
  CHECK_THAT(o.err, Contains("rubcont map needs the two_point model"));
  CHECK(!fs::exists(dir.path / "m.h5"));
}

TEST_CASE("rubcont map outside the scene's value maps the grid and says why there are no curves",
          "[cli][map]") {
  TempDir dir;
  const fs::path file = dir.path / "map.h5";
  const Outcome o = testing::RubcontNoPython("map scenes/default.toml --parameter friction --range 0.6 0.9 "
                            "--eta-points 2 --speed-points 21 -q --out " + file.string());
  INFO(o.out << o.err);
  CHECK(o.exit_code == 0);
  CHECK_THAT(o.out, Contains("no curves: the scene's friction = 0.5 lies outside the range [0.6, 0.9]"));
  ResultReader reader(file);
  CHECK(reader.Children("/maps/friction/curves").empty());
  CHECK_THAT(reader.ReadStringAttribute("/maps/friction", "note"), Contains("outside the range"));
}

}  // namespace
}  // namespace rubcont
