// The loop's file keeps L2's families: /loop/orbits/<k> (period T) and /loop/orbits/<k>_pd1 (the
// doubled family the run met), written from a LoopResult that holds them (the Moebius band's cycle
// and its doubled orbits, tests/shooting/moebius_band.h, stand in for a modulated whip: the writer
// takes any periodic-orbit family).
#include "apps/loop_output.h"

#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "apps/hdf5_file.h"
#include "apps/stage_options.h"
#include "cli_support.h"
#include "models/units.h"
#include "tests/shooting/moebius_band.h"

namespace rubcont {
namespace {

using testing::TempDir;

TEST_CASE("loop file: L2's family and the doubled family beside it are written with their special points",
          "[loop][output]") {
  CycleWithMoebiusBand system;
  PeriodicOrbitBranchOptions options = MoebiusBandOptions();
  options.test_functions = {Grazing([](ConstVectorRef x) { return x(2) * x(2) + x(3) * x(3) - 0.09; },
                                    GrazingSide::kTouchdown, "touchdown")};
  options.stop_at_grazing = true;
  LoopOrbits asked;
  asked.direction = "up";
  asked.seen_from_rpm = 4.0;
  asked.seen_to_rpm = 6.0;
  asked.orbit_rpm = 2.0;
  asked.route = true;
  asked.tries = "2 rpm an orbit";
  asked.orbits.start.converged = true;
  asked.orbits.family.orbits = ContinuePeriodicOrbits(system, OrbitKind::kAutonomous, MoebiusCycleStart(), options);
  std::vector<OrbitPeriodDoubling>& doublings = asked.orbits.family.doublings;
  const OrbitRide ride = RideFamily(asked.orbits.family.orbits, -0.5, +1, 0.5, doublings, [&](std::size_t k) {
    return ContinueOrbitsFromPeriodDoubling(system, asked.orbits.family.orbits, k, options);
  });
  asked.skeleton = ride.text;
  REQUIRE(doublings.size() == 1);
  REQUIRE(doublings[0].ok);

  const Scene scene = LoadScene("scenes/thesis_A_a.toml");
  const RubStructure structure = SweepStructureOf(scene);
  LoopResult result;
  for (LoopRun* run : {&result.up, &result.down}) {
    run->regimes.regime.assign(structure.contacts.size(), {});
    run->regimes.precession_hz.assign(structure.contacts.size(), {});
  }
  result.orbits.push_back(asked);
  TempDir dir;
  const std::filesystem::path file = dir.path / "loop.h5";
  WriteLoopResult(file, scene, structure, LoopOptionsOf(scene), result);

  const ResultReader r(file);
  REQUIRE(r.Exists("/loop/orbits/0/speed_rpm"));
  REQUIRE(r.Exists("/loop/orbits/0_pd1/speed_rpm"));
  CHECK(r.ReadDoubleAttribute("/loop/orbits/0", "orbit_rpm") == 2.0);
  CHECK(r.ReadDoubleAttribute("/loop/orbits/0", "route") == 1.0);
  CHECK(r.ReadStringAttribute("/loop/orbits/0", "skeleton") == ride.text);
  CHECK(r.ReadDoubleAttribute("/loop/orbits/0_pd1", "doubling_rpm") == Approx(0.0).margin(1e-6));
  const std::vector<std::string> types = r.ReadStrings("/loop/orbits/0_pd1/special_points/type");
  const std::vector<double> at = r.ReadDoubles("/loop/orbits/0_pd1/special_points/speed_rpm");
  REQUIRE(types.size() == at.size());
  bool grazing = false;
  for (std::size_t i = 0; i < types.size(); ++i) {
    if (types[i] == "grazing") grazing = at[i] == Approx(RadPerSecondToRpm(0.09)).epsilon(1e-5);
  }
  CHECK(grazing);
  CHECK(r.ReadDoubles("/loop/orbits/0_pd1/speed_rpm").size() == doublings[0].branch.branch.points.size());
  CHECK(r.ReadInts("/loop/orbits/0/stable").size() == asked.orbits.family.orbits.branch.points.size());
}

TEST_CASE("loop options: a negative route_tries or doubled_steps is refused by name", "[loop][output]") {
  const LoopOptions options = LoopOptionsOf(LoadScene("scenes/thesis_A_a.toml"));
  LoopOptions bad = options;
  bad.route_tries = -1;
  CHECK_THROWS_WITH(Validate(bad), Catch::Contains("LoopOptions.route_tries = -1"));
  bad = options;
  bad.doubled_steps = -2;
  CHECK_THROWS_WITH(Validate(bad), Catch::Contains("LoopOptions.doubled_steps = -2"));
  bad.doubled_steps = 0;  // not followed: allowed
  CHECK_NOTHROW(Validate(bad));
}

}  // namespace
}  // namespace rubcont
