// The loop's file keeps L2's families: /loop/orbits/<k> (period T) and /loop/orbits/<k>_pd1 (the
// doubled family the run met), written from a LoopResult that holds them (the Moebius band's cycle
// and its doubled orbits, tests/shooting/moebius_band.h, stand in for a modulated whip: the writer
// takes any periodic-orbit family).
#include "apps/loop_output.h"

#include <cmath>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "apps/hdf5_file.h"
#include "apps/stage_options.h"
#include "cli_support.h"
#include "models/units.h"
#include "solvers/constants.h"
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

// Ensembles that follow the crisis law κ(p) = (p − 118 rpm)/s exactly: at each speed, 16 copies
// whose escape times are the law's exponential quantiles, counted in stretches of 0.5 s over 10 s.
LoopCrisis CrisisAt118() {
  LoopCrisis c{"up", ToString(RubJumpKind::kFrequencyJump), "left, right", 120.0, 122.0, {}};
  for (double p = 120.0; p <= 128.0; p += 2.0) {
    EscapeObservations o;
    o.parameter = p;
    o.duration = 10.0;
    o.stretch = 0.5;
    for (int i = 0; i < 16; ++i) {
      const double t = -std::log(1.0 - (i + 0.5) / 16.0) / (p - 118.0);
      if (t > o.duration) {
        ++o.stayed;
      } else {
        o.escape_stretch.push_back(static_cast<int>(std::ceil(t / o.stretch)));
      }
    }
    c.observations.push_back(o);
  }
  return c;
}

TEST_CASE("a sweep's jump takes the loop's crisis only where the sweep's schedule leaves the state",
          "[loop][output]") {
  std::vector<double> up;
  for (double p = 90.0; p <= 140.0; p += 2.0) up.push_back(p);
  const std::vector<double> down(up.rbegin(), up.rend());
  auto jump = [](double from, double to) {
    PredictedJump row;
    row.direction = "up";
    row.contact = "left";
    row.jump.kind = RubJumpKind::kFrequencyJump;
    row.jump.speed_from_rpm = from;
    row.jump.speed_to_rpm = to;
    row.bifurcation_speed_rpm = row.difference_rpm = kNaN;
    return row;
  };
  // Both within the 20 rpm the crisis's corner reaches: the first lies far below the range where
  // the run leaves (the law's own: 78 % of runs by 120 rpm at 1.5 s per speed, 99 % by 122; the
  // refitted law, whose p_c the ensembles above it bound only from above, says 114 … 120), the
  // second in it.
  std::vector<PredictedJump> table = {jump(100.0, 104.0), jump(118.0, 120.0)};
  SweepJumpsByLoop(table, {CrisisAt118()}, up, down, 1.5, 20.0, "loop.h5");
  CHECK(table[0].bifurcation.empty());
  CHECK(std::isnan(table[0].difference_rpm));
  CHECK_THAT(table[1].bifurcation, Catch::Contains("crisis of a chaotic whip"));
  CHECK(table[1].bifurcation_speed_rpm >= 114.0);
  CHECK(table[1].bifurcation_speed_rpm <= 120.0);
}

}  // namespace
}  // namespace rubcont
