#include "studies/lifetime_study.h"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <catch2/catch.hpp>

#include "../sweeps/whirl_sweep.h"
#include "solvers/constants.h"

namespace rubcont {
namespace {

using Catch::Matchers::Contains;
using testing::kStretch;
using testing::WhirlStructure;
using testing::WhirlSweep;

constexpr double kDrop = 1.920729410347062;  // χ²₁(0.95)/2: the likelihood-ratio 95 % limit

// Two copies at 48 and 48.5 rpm for 0.2 s (two stretches) from the approach through 40 and
// 44 rpm; two check sweeps of one stretch per speed.
LifetimeStudyOptions WhirlLifetime(RubRegime until) {
  LifetimeStudyOptions o;
  o.sweep = WhirlSweep();
  o.from_rpm = 48.0;
  o.to_rpm = 48.5;
  o.step_rpm = 0.5;
  o.sampling.ensemble.copies = 2;
  o.sampling.ensemble.threads = 2;
  o.sampling.duration = 0.2;
  o.sampling.window = 0.05;
  o.target.regime = until;
  o.check_copies = 2;
  o.check_step_rpm = 0.5;
  o.check_dwell = 0.1;
  return o;
}

TEST_CASE("Lifetime study: the rolling whirl never leaves for the whip, and is whirl at once",
          "[lifetime_study]") {
  const RubStructure structure = WhirlStructure();
  // Until the whip: no copy leaves in 2 × 0.2 s, so κ is bounded above only, where the
  // likelihood exp(−κ·E) of the exposure E = 2 copies × 2 stretches has dropped by 1.92.
  const LifetimeStudyResult stay = RunLifetimeStudy(structure, WhirlLifetime(RubRegime::kWhip));
  INFO(stay.BriefReport());
  REQUIRE(stay.status == LifetimeStatus::kComplete);
  CHECK(stay.approach.regimes == std::vector<RubRegime>(2, RubRegime::kWhirl));
  CHECK(stay.speeds_rpm == std::vector<double>{48.0, 48.5});
  REQUIRE(stay.rates.size() == 2);
  for (std::size_t i = 0; i < 2; ++i) {
    const SpeedEscapes& e = stay.escapes[i];
    CHECK(e.observations.parameter == stay.speeds_rpm[i]);
    CHECK(e.observations.stretch == Approx(kStretch).epsilon(1e-12));
    CHECK(e.observations.duration == Approx(2.0 * kStretch).epsilon(1e-12));
    CHECK(e.observations.stayed == 2);
    CHECK(e.observations.escape_stretch.empty());
    CHECK(e.failed == 0);
    CHECK(e.untrusted == 0);
    CHECK(std::isnan(e.arrival_time[0]));
    CHECK(stay.rates[i].status == EscapeRateStatus::kNoEscape);
    CHECK(stay.rates[i].rate == 0.0);
    CHECK(stay.rates[i].upper == Approx(kDrop / (2 * 2 * kStretch)).epsilon(1e-9));
  }
  CHECK(stay.crisis.status == CrisisStatus::kTooFewSpeeds);
  CHECK(stay.check.speeds_rpm == std::vector<double>{48.0, 48.5});
  CHECK(stay.check.dwell == Approx(kStretch).epsilon(1e-12));
  REQUIRE(stay.check.leave_speed_rpm.size() == 2);
  CHECK(std::isnan(stay.check.leave_speed_rpm[0]));
  CHECK(std::isnan(stay.check.leave_time[1]));
  CHECK(stay.predicted.probability.empty());
  CHECK(stay.Failures() == 0);
  CHECK_THAT(stay.BriefReport(), Contains("0 of 4 copies reached whip on every contact") && Contains("too few speeds"));

  // Until the whirl: every copy is there in its first stretch: κ bounded below only.
  const LifetimeStudyResult at_once = RunLifetimeStudy(structure, WhirlLifetime(RubRegime::kWhirl));
  REQUIRE(at_once.status == LifetimeStatus::kComplete);
  for (std::size_t i = 0; i < 2; ++i) {
    CHECK(at_once.escapes[i].observations.escape_stretch == std::vector<int>{1, 1});
    CHECK(at_once.escapes[i].arrival_time == std::vector<double>(2, at_once.escapes[i].observations.stretch));
    CHECK(at_once.rates[i].status == EscapeRateStatus::kAllImmediate);
    CHECK(std::isinf(at_once.rates[i].rate));
  }
  CHECK(at_once.check.leave_speed_rpm == std::vector<double>{48.0, 48.0});
  CHECK(at_once.check.leave_time == std::vector<double>(2, at_once.check.dwell));
}

TEST_CASE("Lifetime study's blocks: escapes the same on one thread and on two, untrusted copies "
          "counted, a check sweep leaves where the whirl ends",
          "[lifetime_study]") {
  const RubStructure structure = WhirlStructure();
  const RubSweepOptions sweep = WhirlSweep();
  const SweepApproach approach = ApproachState(structure, sweep, 48.0);
  REQUIRE(approach.status == ApproachStatus::kReached);
  CHECK(approach.speeds.size() == 2);
  EscapeSampling sampling;
  sampling.ensemble.copies = 3;
  sampling.ensemble.seed = 7;
  sampling.duration = 0.2;
  ArrivalTarget whip;
  whip.regime = RubRegime::kWhip;
  sampling.ensemble.threads = 1;
  const SpeedEscapes serial = ObserveEscapes(structure, sweep, approach.state, 48.0, sampling, whip);
  sampling.ensemble.threads = 2;
  const SpeedEscapes parallel = ObserveEscapes(structure, sweep, approach.state, 48.0, sampling, whip);
  CHECK(serial.observations.stayed == 3);
  CHECK(parallel.observations.stayed == serial.observations.stayed);
  CHECK(parallel.observations.stretch == serial.observations.stretch);
  CHECK(parallel.observations.duration == serial.observations.duration);
  CHECK(parallel.failed == serial.failed);
  CHECK(serial.Observed());
  // The whirl penetrates about 8e-9 m (2e-5 of the clearance): beyond a limit of 1e-6 of it every
  // copy is untrusted, and still counted as stayed.
  RubSweepOptions strict = sweep;
  strict.regimes.max_penetration = 1e-6;
  const SpeedEscapes untrusted = ObserveEscapes(structure, strict, approach.state, 48.0, sampling, whip);
  CHECK(untrusted.untrusted == 3);
  CHECK(untrusted.first_untrusted_copy == 0);
  CHECK_THAT(untrusted.first_untrusted, Contains("contact penetrates"));
  CHECK(untrusted.observations.stayed == 3);
  // A check sweep 48 → 52 rpm, two stretches per speed: the whirl rolls on at 48 rpm and slips at
  // 52 rpm (above the tanh law's knee at 50.96 rpm) in the first stretch there, the third of the
  // sweep: it left at 52 rpm after three stretches.
  EnsembleOptions check;
  check.copies = 1;
  const CheckSweeps sweeps = RunCheckSweeps(structure, sweep, approach.state, {48.0, 52.0}, 0.2, 0.05, check, whip);
  CHECK(sweeps.dwell == Approx(2.0 * kStretch).epsilon(1e-12));
  CHECK(sweeps.leave_speed_rpm == std::vector<double>{52.0});
  REQUIRE(sweeps.leave_time.size() == 1);
  CHECK(sweeps.leave_time[0] == Approx(3.0 * kStretch).epsilon(1e-12));
  CHECK(sweeps.failures.empty());
}

TEST_CASE("Lifetime study: a failed approach and copies that all fail are statuses with the reason",
          "[lifetime_study]") {
  const RubStructure structure = WhirlStructure();
  LifetimeStudyOptions o = WhirlLifetime(RubRegime::kWhirl);
  o.sweep.sweep.integrator.max_steps = 10;
  const LifetimeStudyResult approach = RunLifetimeStudy(structure, o);
  CHECK(approach.status == LifetimeStatus::kApproachFailed);
  CHECK_THAT(approach.message, Contains("the approach sweep failed"));
  CHECK(approach.escapes.empty());
  // From 40 rpm there is no approach: the copies start from the impulse and each fails.
  o.from_rpm = 40.0;
  o.to_rpm = 41.0;
  o.step_rpm = 1.0;
  const LifetimeStudyResult copies = RunLifetimeStudy(structure, o);
  CHECK(copies.status == LifetimeStatus::kNoEstimate);
  CHECK(copies.message == "every copy failed at 40 rpm: nothing to estimate");
  REQUIRE(copies.escapes.size() == 1);
  CHECK(copies.escapes[0].failed == 2);
  REQUIRE(copies.escapes[0].failures.size() == 2);
  CHECK(copies.escapes[0].failures[1].copy == 1);
  CHECK_THAT(copies.escapes[0].failures[0].message, Contains("10 steps"));
  CHECK(copies.Failures() == 2);
  CHECK_THAT(copies.BriefReport(), Contains("no estimate"));
}

TEST_CASE("Lifetime study: interrupted after its first speed and resumed from what it had finished, it "
          "gives the uninterrupted study's numbers without running the approach or that speed again",
          "[lifetime_study]") {
  const RubStructure structure = WhirlStructure();
  const LifetimeStudyOptions o = WhirlLifetime(RubRegime::kWhirl);
  const LifetimeStudyResult whole = RunLifetimeStudy(structure, o);
  REQUIRE(whole.status == LifetimeStatus::kComplete);

  // The checkpoints the study hands out: after the approach (no speed), after 48 rpm; then it is
  // "killed" (an exception from the checkpoint writer).
  struct Interrupted {};
  std::vector<LifetimeStudyStart> checkpoints;
  LifetimeStudyProgress interrupt;
  interrupt.finished = [&](const SweepApproach& approach, const std::vector<SpeedEscapes>& escapes) {
    checkpoints.push_back({approach, escapes});
    if (escapes.size() == 1) throw Interrupted{};
  };
  CHECK_THROWS_AS(RunLifetimeStudy(structure, o, interrupt), Interrupted);
  REQUIRE(checkpoints.size() == 2);
  CHECK(checkpoints[0].escapes.empty());
  CHECK(checkpoints[0].approach.state == whole.approach.state);

  std::vector<double> ran;  // the speeds whose copies ran again
  bool approached = false;
  LifetimeStudyProgress watch;
  watch.approach = [&](const SweepRun&) { approached = true; };
  watch.copies = [&](double speed_rpm, int, int) {
    if (ran.empty() || !(ran.back() == speed_rpm || (std::isnan(speed_rpm) && std::isnan(ran.back())))) {
      ran.push_back(speed_rpm);
    }
  };
  const LifetimeStudyResult resumed = RunLifetimeStudy(structure, o, watch, &checkpoints[1]);
  REQUIRE(resumed.status == LifetimeStatus::kComplete);
  CHECK_FALSE(approached);
  REQUIRE(ran.size() == 2);  // 48.5 rpm and the check sweeps
  CHECK(ran[0] == 48.5);
  CHECK(std::isnan(ran[1]));
  REQUIRE(resumed.escapes.size() == whole.escapes.size());
  for (std::size_t i = 0; i < whole.escapes.size(); ++i) {
    CHECK(resumed.escapes[i].observations.escape_stretch == whole.escapes[i].observations.escape_stretch);
    CHECK(resumed.escapes[i].arrival_time == whole.escapes[i].arrival_time);
    CHECK(resumed.rates[i].rate == whole.rates[i].rate);
  }
  CHECK(resumed.check.leave_speed_rpm == whole.check.leave_speed_rpm);

  // A start that is not this study's: another schedule, another number of copies.
  LifetimeStudyOptions other = o;
  other.from_rpm = 47.5;
  CHECK_THROWS_WITH(RunLifetimeStudy(structure, other, {}, &checkpoints[1]),
                    Contains("must be the schedule's speed 47.5 rpm"));
  other = o;
  other.sampling.ensemble.copies = 3;
  CHECK_THROWS_WITH(RunLifetimeStudy(structure, other, {}, &checkpoints[1]), Contains("must be the study's 3 copies"));
}

TEST_CASE("Lifetime study: bad options are rejected naming the field, the value and the rule",
          "[lifetime_study]") {
  const RubStructure structure = WhirlStructure();
  auto rejected = [&](auto change) { return testing::Rejection(WhirlLifetime(RubRegime::kWhirl), structure, change); };
  CHECK(rejected([](LifetimeStudyOptions&) {}) == "accepted");
  CHECK_THAT(rejected([](LifetimeStudyOptions& o) { o.from_rpm = -1.0; }),
             Contains("LifetimeStudyOptions.from_rpm = -1: must be positive"));
  CHECK_THAT(rejected([](LifetimeStudyOptions& o) { o.to_rpm = 46.0; }),
             Contains("LifetimeStudyOptions.to_rpm = 46: must be above from_rpm (direction up)"));
  CHECK_THAT(rejected([](LifetimeStudyOptions& o) { o.sweep.direction = SweepDirection::kDown; }),
             Contains("to_rpm = 48.5: must be below from_rpm (direction down)"));
  CHECK_THAT(rejected([](LifetimeStudyOptions& o) { o.step_rpm = 1e-4; }),
             Contains("LifetimeStudyOptions.step_rpm = 0.0001: gives more than 1000 speeds"));
  CHECK_THAT(rejected([](LifetimeStudyOptions& o) { o.sampling.duration = 0.05; }),
             Contains("LifetimeStudyOptions.sampling.duration = 0.05: must be at least two windows"));
  CHECK_THAT(rejected([](LifetimeStudyOptions& o) { o.sampling.ensemble.copies = 0; }),
             Contains("LifetimeStudyOptions.sampling.ensemble.copies = 0"));
  CHECK_THAT(rejected([](LifetimeStudyOptions& o) { o.check_copies = -1; }),
             Contains("LifetimeStudyOptions.check_copies = -1"));
  CHECK_THAT(rejected([](LifetimeStudyOptions& o) { o.check_dwell = 0.01; }),
             Contains("LifetimeStudyOptions.check_dwell = 0.01: must be at least two windows"));
  CHECK_THAT(rejected([](LifetimeStudyOptions& o) {
               o.target.contacts = ArrivalContacts::kOne;
               o.target.contact = 3;
             }),
             Contains("LifetimeStudyOptions.target.contact = 3"));
  CHECK_THAT(rejected([](LifetimeStudyOptions& o) { o.sweep.impulse = kNaN; }),
             Contains("RubSweepOptions.impulse = nan"));
  LifetimeStudyOptions bad = WhirlLifetime(RubRegime::kWhirl);
  bad.from_rpm = 0.0;
  CHECK_THROWS_AS(RunLifetimeStudy(structure, bad), std::invalid_argument);
}

}  // namespace
}  // namespace rubcont
