// The skeleton the loop's L2 reports (studies/loop.h, RideFamily and SkeletonEnd), on the cycle with
// a Moebius band (tests/shooting/moebius_band.h): its orbits are stable up to a supercritical
// period doubling at λ = 0, and the doubled orbits (|w|² = λ, stable) touch |w| = 0.3 at λ = 0.09.
// A run going up from λ = −0.5 rides the cycle to the doubling, then the doubled orbits to that
// grazing: the end of its stable state is the grazing, not the doubling. And the speeds the loop's
// escape design tries (EscapeCandidatesFor).
#include "studies/loop.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <catch2/catch.hpp>

#include "models/units.h"
#include "tests/shooting/moebius_band.h"

namespace rubcont {
namespace {

struct MoebiusRide {
  CycleWithMoebiusBand system;
  PeriodicOrbitBranchOptions options = MoebiusBandOptions();
  PeriodicOrbitBranch family;
  MoebiusRide() {
    options.test_functions = {Grazing([](ConstVectorRef x) { return x(2) * x(2) + x(3) * x(3) - 0.09; },
                                      GrazingSide::kTouchdown, "touchdown")};
    options.stop_at_grazing = true;
    family = ContinuePeriodicOrbits(system, OrbitKind::kAutonomous, MoebiusCycleStart(), options);
  }
  DoublingFollower Follower(int& calls) {
    return [this, &calls](std::size_t k) {
      ++calls;
      return ContinueOrbitsFromPeriodDoubling(system, family, k, options);
    };
  }
};

TEST_CASE("loop L2: past a period doubling the run rides the doubled orbits to their grazing", "[loop][skeleton]") {
  MoebiusRide m;
  INFO(m.family.branch.BriefReport());
  REQUIRE(m.family.branch.Count(SpecialPointType::kPeriodDoubling) == 1);
  std::vector<OrbitPeriodDoubling> doublings;
  int calls = 0;
  const OrbitRide ride = RideFamily(m.family, -0.5, +1, 0.5, doublings, m.Follower(calls));
  INFO(ride.text);
  REQUIRE(ride.rides);
  CHECK(ride.from == Approx(-0.5).margin(1e-12));
  CHECK(calls == 1);
  REQUIRE(doublings.size() == 1);
  REQUIRE(doublings[0].ok);
  CHECK(m.family.branch.special_points[doublings[0].special_point].type == SpecialPointType::kPeriodDoubling);
  REQUIRE(ride.end.found);
  CHECK(ride.end.doubled);
  CHECK(ride.end.type == SpecialPointType::kGrazing);
  CHECK(ride.end.lambda == Approx(0.09).epsilon(0).margin(1e-6));
  CHECK(ride.end.doubling_lambda == Approx(0.0).epsilon(0).margin(1e-8));
  CHECK_THAT(ride.text, Catch::Contains("stable from") && Catch::Contains("touchdown"));
}

TEST_CASE("loop L2: a doubling not followed, or beyond the jump, is itself the end", "[loop][skeleton]") {
  MoebiusRide m;
  std::vector<OrbitPeriodDoubling> doublings;
  int calls = 0;
  // No follower: the doubling ends the state, and says its doubled orbits were not followed.
  const OrbitRide alone = RideFamily(m.family, -0.5, +1, 0.5, doublings, DoublingFollower());
  INFO(alone.text);
  REQUIRE(alone.end.found);
  CHECK_FALSE(alone.end.doubled);
  CHECK(alone.end.type == SpecialPointType::kPeriodDoubling);
  CHECK(alone.end.lambda == Approx(0.0).epsilon(0).margin(1e-8));
  CHECK_THAT(alone.text, Catch::Contains("not followed: no budget left, or doubled_steps = 0"));
  // A doubling past the landing (`far` before it) is not followed.
  const OrbitRide short_run = RideFamily(m.family, -0.5, +1, -0.1, doublings, m.Follower(calls));
  CHECK(calls == 0);
  CHECK(doublings.empty());
  CHECK(short_run.end.type == SpecialPointType::kPeriodDoubling);
  CHECK_THAT(short_run.text, Catch::Contains("not followed: past the landing"));
  // From an unstable orbit (λ = 0.3, past the doubling) the ride starts at the last stable orbit
  // before it, and meets the doubling behind that orbit.
  const OrbitRide back = RideFamily(m.family, 0.3, +1, 0.5, doublings, m.Follower(calls));
  INFO(back.text);
  CHECK(back.from < 0.0);
  CHECK(calls == 1);
  CHECK(back.end.doubled);
  CHECK(back.end.lambda == Approx(0.09).epsilon(0).margin(1e-6));
}

TEST_CASE("loop L2: doubled orbits unstable at the doubling's speed are read as no state to move on "
          "to only where their family ended of itself",
          "[loop][skeleton]") {
  // The doubled family as followed, its orbits marked unstable: ended of itself (the λ bound) the
  // run has no periodic state to move on to; cut short (the budget's callback) it may yet turn back
  // stable over the doubling's speed (A(a)'s does past its fold), so the reading is "not decided".
  MoebiusRide m;
  for (const BranchStatus status : {BranchStatus::kReachedLambdaBound, BranchStatus::kStoppedByCaller}) {
    std::vector<OrbitPeriodDoubling> doublings;
    DoublingFollower unstable = [&m, status](std::size_t k) {
      OrbitPeriodDoubling d = ContinueOrbitsFromPeriodDoubling(m.system, m.family, k, m.options);
      for (BranchPoint& q : d.branch.branch.points) q.num_unstable = 1;
      d.branch.branch.status = status;
      return d;
    };
    const OrbitRide ride = RideFamily(m.family, -0.5, +1, 0.5, doublings, unstable);
    CAPTURE(ToString(status));
    INFO(ride.text);
    REQUIRE(ride.end.found);
    CHECK_FALSE(ride.end.doubled);
    CHECK(ride.end.type == SpecialPointType::kPeriodDoubling);
    if (status == BranchStatus::kReachedLambdaBound) {
      CHECK_THAT(ride.text, Catch::Contains("unstable there") && Catch::Contains("no periodic state to move on to"));
    } else {
      CHECK_THAT(ride.text, Catch::Contains("as far as their family went") && Catch::Contains("not decided"));
      CHECK_THAT(ride.text, !Catch::Contains("no periodic state to move on to"));
    }
  }
}

// A run's speeds come back from rad/s with their last bit changed; the design's first speed must
// be one of its candidates (EscapeDesignOptions' rule) all the same.
TEST_CASE("the escape design starts at the schedule's speed nearest the landing, which the run "
          "carries through rad/s",
          "[loop]") {
  std::vector<double> schedule;
  for (double p = 100.0; p <= 140.0; p += 2.0) schedule.push_back(p);
  const double landed_up = RadPerSecondToRpm(RpmToRadPerSecond(126.0));
  REQUIRE(landed_up != 126.0);  // the case that ended C(c)'s loop
  const EscapeCandidates up = EscapeCandidatesFor(schedule, 1, 124.0, 110.0, landed_up, 10.0, 2.0);
  CHECK(up.speeds == std::vector<double>{114, 116, 118, 120, 122, 124, 126, 128, 130});
  CHECK(up.first == 126.0);
  // Downwards: from 10 rpm above the departure, not above where the run was first seen on its
  // state, to two steps below the landing.
  const double landed_down = RadPerSecondToRpm(RpmToRadPerSecond(118.0));
  const EscapeCandidates down =
      EscapeCandidatesFor(schedule, -1, 120.0, 128.0, landed_down, 10.0, 2.0);
  CHECK(down.speeds == std::vector<double>{114, 116, 118, 120, 122, 124, 126, 128});
  CHECK(down.first == 118.0);
  CHECK(std::find(down.speeds.begin(), down.speeds.end(), down.first) != down.speeds.end());
}

}  // namespace
}  // namespace rubcont
