#include "sweeps/rub_runs.h"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <catch2/catch.hpp>

#include "solvers/constants.h"
#include "whirl_sweep.h"

namespace rubcont {
namespace {

using Catch::Matchers::Contains;
using testing::kStretch;
using testing::WhirlStructure;
using testing::WhirlSweep;

TEST_CASE("StretchCount: the stretches of two windows that cover a time, to 1e-9", "[rub_runs]") {
  CHECK(StretchCount(0.2, 0.05) == 2);
  CHECK(StretchCount(0.2 + 1e-12, 0.05) == 2);  // rounding of a whole number of stretches
  CHECK(StretchCount(0.21, 0.05) == 3);
  CHECK(StretchCount(0.1, 0.05) == 1);
  CHECK(StretchCount(5.0, 0.05) == 50);
}

TEST_CASE("The approach sweeps the schedule strictly before the speed, in its direction",
          "[rub_runs]") {
  const RubStructure structure = WhirlStructure();
  RubSweepOptions options = WhirlSweep();
  // At or below the first speed: nothing to sweep; the state is the impulse's.
  for (double rpm : {40.0, 30.0}) {
    const SweepApproach none = ApproachSweep(structure, options, RpmToRadPerSecond(rpm));
    CHECK(none.status == ApproachStatus::kReached);
    CHECK(none.speeds.empty());
    CHECK(none.state == RubImpulseIncrement(structure, options.impulse));
    CHECK(none.regimes == std::vector<RubRegime>(2, RubRegime::kUnknown));
    CHECK(none.BriefReport() == "approach: none (rest and the impulse)");
  }
  // Before 44 rpm: 40 rpm only, where the impulse sets both contacts rolling.
  int calls = 0;
  const SweepApproach one =
      ApproachSweep(structure, options, RpmToRadPerSecond(44.0), [&](const SweepRun& run) {
        ++calls;
        CHECK(run.direction() == SweepDirection::kUp);
      });
  CHECK(calls == 1);
  REQUIRE(one.status == ApproachStatus::kReached);
  REQUIRE(one.speeds.size() == 1);
  CHECK(RadPerSecondToRpm(one.speeds[0]) == Approx(40.0).epsilon(1e-14));
  CHECK(one.regimes == std::vector<RubRegime>(2, RubRegime::kWhirl));
  CHECK(RegimeList(structure, one.regimes) == "left whirl, right whirl");
  CHECK(one.state.size() == structure.States());
  CHECK_FALSE(one.state.isApprox(RubImpulseIncrement(structure, options.impulse)));
  // Speed-down: the same schedule read from the top, so 44 rpm has 48 rpm before it. A failure is
  // a status with the integrator's reason, not an exception.
  options.direction = SweepDirection::kDown;
  options.sweep.parameters = {RpmToRadPerSecond(48.0), RpmToRadPerSecond(44.0), RpmToRadPerSecond(40.0)};
  options.sweep.integrator.max_steps = 10;
  const SweepApproach failed = ApproachSweep(structure, options, RpmToRadPerSecond(44.0));
  CHECK(failed.status == ApproachStatus::kFailed);
  CHECK(failed.speeds.size() == 1);
  CHECK_THAT(failed.message, Contains("the approach sweep failed") && Contains("10 steps"));
  CHECK_THAT(failed.BriefReport(), Contains("approach failed"));
}

TEST_CASE("Copies of the rolling whirl arrive at whirl in their first stretch and never at whip",
          "[rub_runs]") {
  const RubStructure structure = WhirlStructure();
  const RubSweepOptions options = WhirlSweep();
  const SweepApproach approach = ApproachSweep(structure, options, RpmToRadPerSecond(44.0));
  REQUIRE(approach.status == ApproachStatus::kReached);
  EnsembleOptions ensemble;
  ensemble.copies = 2;
  ensemble.threads = 1;
  const std::vector<double> speeds(2, RpmToRadPerSecond(44.0));
  ArrivalTarget whirl;
  const RubCopies arrived = RunRubCopies(structure, options, speeds, 0.05, approach.state, ensemble, whirl);
  CHECK(arrived.stretch_seconds == Approx(kStretch).epsilon(1e-12));
  REQUIRE(arrived.arrivals.size() == 2);
  for (const RubArrival& a : arrived.arrivals) {
    CHECK(a.reached);
    CHECK(a.point == 0);
    CHECK(a.time == Approx(kStretch).epsilon(1e-12));
    CHECK(a.simulated == Approx(2.0 * kStretch).epsilon(1e-12));
  }
  ArrivalTarget whip;
  whip.regime = RubRegime::kWhip;
  const RubCopies stayed = RunRubCopies(structure, options, speeds, 0.05, approach.state, ensemble, whip);
  for (const RubArrival& a : stayed.arrivals) {
    CHECK_FALSE(a.reached);
    CHECK_FALSE(a.failed);
    CHECK(std::isnan(a.time));
  }
}

TEST_CASE("Bad run options and targets are rejected naming the field", "[rub_runs]") {
  const RubStructure structure = WhirlStructure();
  RubSweepOptions options = WhirlSweep();
  options.impulse = -1.0;
  CHECK_THROWS_WITH(Validate(options), Contains("RubSweepOptions.impulse = -1"));
  CHECK_THROWS_AS(SweepRun(structure, options), std::invalid_argument);
  options = WhirlSweep();
  options.regimes.whirl_tolerance = 2.0;
  CHECK_THROWS_WITH(Validate(options), Contains("whirl_tolerance = 2"));
  ArrivalTarget target;
  target.contacts = ArrivalContacts::kOne;
  target.contact = 2;
  CHECK_THROWS_WITH(Validate(target, structure, "until"),
                    Contains("until.contact = 2: must index one of the structure's 2 contacts"));
  target.contact = 1;
  CHECK_NOTHROW(Validate(target, structure));
  target.precession_above_hz = -5.0;
  CHECK_THROWS_WITH(Validate(target, structure), Contains("target.precession_above_hz = -5"));
  target.precession_above_hz = kNaN;
  target.regime = RubRegime::kUnknown;
  CHECK_THROWS_WITH(Validate(target, structure), Contains("target.regime = unknown"));
}

}  // namespace
}  // namespace rubcont
