// `rubcont attractor`, run as a user runs it: the verdict on a whirl, the file, bad input.
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
using testing::WhirlScene;

TEST_CASE("rubcont attractor: the whirl is a rotating wave, one zero exponent, its section a "
          "single force", "[attractor_cli]") {
  TempDir dir;
  const fs::path scene = WhirlScene(dir.path);
  const fs::path h5 = dir.path / "whirl.h5";
  const Outcome o = testing::RubcontNoPython(
      "attractor " + scene.string() + " --from 48 --duration 0.2 --discard 0.05 --interval 0.01 "
      "--exponents 3 --quiet --out " + h5.string());
  INFO(o.out << o.err);
  REQUIRE(o.exit_code == 0);
  CHECK_THAT(o.out, Contains("from the up sweep 40 → 44 rpm"));
  CHECK_THAT(o.out, Contains("48.0 rpm: rotating wave: λ = "));
  ResultReader r(h5);
  CHECK(r.ReadStringAttribute("/", "level") == "L3");
  CHECK(r.ReadDoubles("/attractor/speed_rpm") == std::vector<double>{48.0});
  CHECK(r.ReadStrings("/attractor/motion") == std::vector<std::string>{"rotating wave"});
  CHECK(r.ReadStrings("/attractor/untrusted") == std::vector<std::string>{""});
  CHECK(r.ReadInts("/attractor/zero_exponents") == std::vector<int>{1});
  // The exponents' values are tests/studies/attractor_study_test.cpp's; here their shape.
  CHECK(r.ReadMatrix("/attractor/exponents").cols() == 3);
  CHECK(r.ReadMatrix("/attractor/standard_errors").cols() == 3);
  CHECK(r.ReadDoubles("/attractor/counted_s").at(0) == Approx(0.2));
  CHECK(r.ReadMatrix("/attractor/running/0").cols() == 20);
  // Rolling in full contact, still settling 0.05 s after the step to 48 rpm (the exponents'
  // −10.8/s): the normal force drifts slowly, and the section keeps the maxima of that drift
  // and of the integrator's noise on it (measured 11 maxima, 1320–1352 N, after 2026-11-26; none
  // before, with the right-hand side's sums in another order). Whatever their number, they lie
  // within the drift (a bounce would range from 0 N), and the symmetric rotor's two contacts
  // carry the same force at the same instants.
  const std::vector<double> left = r.ReadDoubles("/attractor/section_normal_force_left");
  const std::vector<double> right = r.ReadDoubles("/attractor/section_normal_force_right");
  REQUIRE(left.size() == right.size());
  for (std::size_t i = 0; i < left.size(); ++i) {
    CHECK(left[i] == Approx(left.front()).epsilon(0.05));
    CHECK(right[i] == Approx(left[i]).epsilon(1e-6));
  }
}

TEST_CASE("rubcont attractor: --approach up with --direction down steps back down from where the "
          "speed-up sweep arrived", "[attractor_cli]") {
  TempDir dir;
  const fs::path scene = WhirlScene(dir.path);
  const fs::path h5 = dir.path / "back.h5";
  const Outcome o = testing::RubcontNoPython(
      "attractor " + scene.string() + " --from 48 --to 44 --direction down --approach up "
      "--duration 0.1 --discard 0.02 --interval 0.01 --exponents 2 --quiet --out " + h5.string());
  INFO(o.out << o.err);
  REQUIRE(o.exit_code == 0);
  CHECK_THAT(o.out, Contains("from the up sweep 40 → 44 rpm"));
  ResultReader r(h5);
  CHECK(r.ReadStringAttribute("/attractor", "direction") == "down");
  CHECK(r.ReadStringAttribute("/attractor", "approach") == "up");
  CHECK(r.ReadDoubles("/attractor/speed_rpm") == std::vector<double>{48.0, 44.0});
  CHECK(r.ReadStrings("/attractor/motion").at(0) == "rotating wave");
}

TEST_CASE("rubcont attractor: bad options are exit code 2 naming the option", "[attractor_cli]") {
  TempDir dir;
  const fs::path scene = WhirlScene(dir.path);
  auto bad = [&](const std::string& args, const std::string& message) {
    const Outcome o = testing::RubcontNoPython("attractor " + scene.string() + " " + args +
                                               " --quiet --out " + (dir.path / "x.h5").string());
    CHECK(o.exit_code == 2);
    CHECK_THAT(o.err, Contains(message));
    CHECK_FALSE(fs::exists(dir.path / "x.h5"));
  };
  bad("--from 48 --to 40", "--to = 40: must lie beyond --from in the direction of the schedule");
  bad("--from 48 --direction sideways", "--direction = sideways: must be up or down");
  bad("--from 48 --approach across", "--approach = across: must be up or down");
  bad("--from 48 --duration 0.1 --interval 0.05", "--interval = 0.05: must be positive and at most a tenth");
  bad("--from 48 --sample 0.01", "--sample = 0.01: must be positive and at most --interval");
  bad("--from 48 --exponents 99", "--exponents = 99: must be at most the model's");
  bad("--from 48 --tolerance 2", "--tolerance = 2: must lie in (0, 1)");
}

}  // namespace
}  // namespace rubcont
