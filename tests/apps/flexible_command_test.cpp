// `rubcont flexible`, run as a user runs it: the L4 file and summary, bad input.
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "apps/hdf5_file.h"
#include "cli_support.h"

namespace rubcont {
namespace {

namespace fs = std::filesystem;
using Catch::Matchers::Contains;
using testing::Outcome;
using testing::TempDir;

TEST_CASE("rubcont flexible: the thesis's Table 2 and A(a)'s branch points rigid → flexible",
          "[flexible_cli]") {
  TempDir dir;
  const fs::path file = dir.path / "flexible.h5";
  const Outcome o = testing::RubcontNoPython("flexible scenes/thesis_A_a.toml --quiet --out " +
                                             file.string());
  INFO(o.err);
  REQUIRE(o.exit_code == 0);
  CHECK_THAT(o.out, Contains("[flexible] L4: rotor"));
  CHECK_THAT(o.out, Contains("A pinned"));
  CHECK_THAT(o.out, Contains("mode1      left stick to slip+"));
  CHECK(o.err.empty());
  ResultReader reader(file);
  CHECK(reader.ReadStringAttribute("/", "level") == "L4");
  CHECK(reader.ReadDoubleAttribute("/flexible", "coordinates") == 8.0);
  const Matrix hz = reader.ReadMatrix("/flexible/table_hz");
  const Matrix thesis = reader.ReadMatrix("/flexible/thesis_hz");
  REQUIRE(hz.rows() == 4);
  CHECK(thesis(0, 2) == 595.1);
  CHECK(std::abs(hz(0, 0) / thesis(0, 0) - 1) < 0.04);
  const std::vector<std::string> label = reader.ReadStrings("/flexible/label");
  const std::vector<double> rigid = reader.ReadDoubles("/flexible/rigid_rpm");
  const std::vector<double> flexible = reader.ReadDoubles("/flexible/flexible_rpm");
  REQUIRE(label.size() == rigid.size());
  REQUIRE(label.size() == flexible.size());
  for (std::size_t i = 0; i < label.size(); ++i) CHECK(std::isfinite(flexible[i]));
}

TEST_CASE("a scene with [flexible]: branches at level L4, its own geometry in rubcont flexible",
          "[flexible_cli]") {
  TempDir dir;
  const fs::path branches = dir.path / "branches.h5";
  Outcome o = testing::RubcontNoPython("branches scenes/thesis_A_a_flexible.toml --quiet --out " +
                                       branches.string());
  INFO(o.err);
  REQUIRE(o.exit_code == 0);
  CHECK(ResultReader(branches).ReadStringAttribute("/", "level") == "L4");
  // The flexible Mode 1 whirl's end, as `rubcont flexible` found it with the fitted geometry.
  CHECK_THAT(o.out, Contains("50.412 rpm    84.017 Hz"));
  const fs::path file = dir.path / "flexible.h5";
  o = testing::RubcontNoPython("flexible scenes/thesis_A_a_flexible.toml --quiet --out " +
                               file.string());
  REQUIRE(o.exit_code == 0);
  CHECK_THAT(o.out, Contains("(the scene's [flexible])"));
  CHECK_THAT(o.out, Contains("50.689 rpm   84.478 Hz →   50.412 rpm"));
  // Maps and fits vary the rigid model's parameters: refused, not silently rigid.
  o = testing::RubcontNoPython("map scenes/thesis_A_a_flexible.toml --parameter friction --quiet --out " +
                               (dir.path / "map.h5").string());
  CHECK(o.exit_code == 2);
  CHECK_THAT(o.err, Contains("[flexible] in scene thesis_A_a_flexible: rubcont map varies the rigid "
                             "model's parameters"));
}

TEST_CASE("a scene that lists its shafts: branches at level L4, the uniform scene's corner",
          "[flexible_cli]") {
  // scenes/thesis_A_a_flexible_listed.toml is thesis_A_a_flexible.toml spelt out by station with
  // its disks rounded to 5 digits: the Mode 1 whirl's end moves by less than 0.001 rpm.
  TempDir dir;
  const fs::path branches = dir.path / "branches.h5";
  Outcome o = testing::RubcontNoPython("branches scenes/thesis_A_a_flexible_listed.toml --quiet --out " +
                                       branches.string());
  INFO(o.err);
  REQUIRE(o.exit_code == 0);
  CHECK(ResultReader(branches).ReadStringAttribute("/", "level") == "L4");
  CHECK_THAT(o.out, Contains("50.412 rpm    84.017 Hz"));
  // rubcont flexible evaluates uniform sections on the thesis's tables: it says so and stops.
  o = testing::RubcontNoPython("flexible scenes/thesis_A_a_flexible_listed.toml --quiet --out " +
                               (dir.path / "flexible.h5").string());
  CHECK(o.exit_code == 2);
  CHECK_THAT(o.err, Contains("[flexible] in scene thesis_A_a_flexible_listed lists its shafts: "
                             "rubcont flexible fits and evaluates uniform sections"));
  CHECK_FALSE(fs::exists(dir.path / "flexible.h5"));
}

TEST_CASE("rubcont flexible: bad input is exit code 2 naming it", "[flexible_cli]") {
  TempDir dir;
  const fs::path file = dir.path / "x.h5";
  Outcome o = testing::RubcontNoPython("flexible scenes/thesis_A_a.toml --modes 99 --quiet --out " +
                                       file.string());
  CHECK(o.exit_code == 2);
  CHECK_THAT(o.err, Contains("--modes = 99: must be 1 … 40"));
  CHECK_FALSE(fs::exists(file));
  o = testing::RubcontNoPython("flexible scenes/jeffcott.toml --quiet --out " + file.string());
  CHECK(o.exit_code == 2);
  CHECK_THAT(o.err, Contains("rubcont flexible"));
  CHECK_FALSE(fs::exists(file));
}

}  // namespace
}  // namespace rubcont
