#include "studies/work_plan.h"

#include <array>

#include <catch2/catch.hpp>

#include "sweeps/rub_sweep.h"

namespace rubcont {
namespace {

using Catch::Matchers::Contains;

TEST_CASE("Work plan: a sweep counts SpeedSchedule's speeds without making them", "[work_plan]") {
  for (auto [from, to, step] : {std::array<double, 3>{20.0, 258.0, 2.0}, {252.0, 20.0, 4.0},
                                {20.0, 20.3, 0.1}, {50.0, 50.0, 2.0}}) {
    CHECK(SpeedCount(from, to, step) == static_cast<double>(SpeedSchedule(from, to, step).size()));
  }
  const PlannedWork up = SweepWork("analysis.sweep.up_range_rpm", "speeds", 20.0, 256.0, 4.0, 0.75, 1000.0);
  CHECK(up.items == 60.0);
  CHECK(up.simulated_seconds == Approx(45.0));
  CHECK(up.cpu_seconds == Approx(45.0 * kCpuSecondsPerSimulatedSecond));
  CHECK(up.memory_bytes == Approx(60.0 * (1000.0 + 16.0)));
  CHECK(up.value == "[20, 256] in steps of 4 rpm");
  // A(a)'s sweep keeps 11 158 bytes a speed in its file; the estimate 10 640.
  CHECK(SweepSpeedBytes(2, 600.0, 0.5) == Approx(10640.0));
  // 16 copies of 5 s in stretches of 0.1 s: 50 stretches each.
  const PlannedWork copies = CopiesWork("--copies × --duration", "16 × 5 s", "copies", 16.0, 5.0, 0.05, 100.0);
  CHECK(copies.simulated_seconds == Approx(80.0));
  CHECK(copies.memory_bytes == Approx(16.0 * 50.0 * 100.0));
  // The default scene's friction map: 41 branch sets, 41 × 481 cells of five ints.
  const PlannedWork map = MapWork("--eta-points × --speed-points", "41 × 481", 41, 481);
  CHECK(map.items == 41.0);
  CHECK(map.memory_bytes == Approx(20.0 * 41 * 481));
  CHECK(map.cpu_seconds == 0.0);
}

TEST_CASE("Work plan: the first item over a limit is named with its estimate", "[work_plan]") {
  const PlannedWork normal = SweepWork("analysis.sweep.up_range_rpm", "speeds", 20.0, 256.0, 4.0, 0.75, 1e4);
  CHECK(ExcessiveWork({normal}).empty());
  // The sweep of issue 50: 2.5e8 speeds, over every limit; the count is named first.
  const PlannedWork wide = SweepWork("analysis.sweep.up_range_rpm", "speeds", 20.0, 1e9, 4.0, 0.75, 1e4);
  const std::string excess = ExcessiveWork({normal, wide});
  CHECK_THAT(excess, Contains("analysis.sweep.up_range_rpm = [20, 1e+09] in steps of 4 rpm plans 2.5e+08 speeds"));
  CHECK_THAT(excess, Contains("years of CPU"));
  // CPU alone: 10 speeds of 1e6 s; memory alone: 1000 speeds of 1e7 bytes.
  const PlannedWork slow = SweepWork("analysis.sweep.dwell", "speeds", 20.0, 38.0, 2.0, 1e6, 1e4);
  CHECK_THAT(ExcessiveWork({slow}), Contains("over the limit of 7 days of CPU"));
  const PlannedWork big = SweepWork("analysis.sweep.spectrum_max_hz", "speeds", 20.0, 2018.0, 2.0, 0.75, 1e7);
  CHECK_THAT(ExcessiveWork({big}), Contains("over the limit of 4 GB of memory"));
  // Items within the limits that add up beyond them: the largest contributor is named.
  const PlannedWork half = SweepWork("analysis.sweep.dwell", "speeds", 20.0, 38.0, 2.0, 4e3, 1e4);
  const PlannedWork third = SweepWork("analysis.sweep.up_range_rpm", "speeds", 20.0, 38.0, 2.0, 3e3, 1e4);
  CHECK(ExcessiveWork({half}).empty());
  CHECK_THAT(ExcessiveWork({third, half}), Contains("analysis.sweep.dwell = [20, 38] in steps of 2 rpm plans 10 speeds"));
  CHECK_THAT(ExcessiveWork({third, half}), Contains("and the plan ≈ 8.1 days of CPU in all: over the limit of 7 days of CPU"));
  WorkLimits none;
  none.max_items = 0.0;
  CHECK_THROWS_WITH(ExcessiveWork({normal}, none), Contains("WorkLimits.max_items = 0"));
}

}  // namespace
}  // namespace rubcont
