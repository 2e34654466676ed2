#include "studies/attractor_study.h"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <catch2/catch.hpp>

#include "../sweeps/whirl_sweep.h"

namespace rubcont {
namespace {

using Catch::Matchers::Contains;
using testing::WhirlStructure;
using testing::WhirlSweep;

// 48 rpm after the approach through 40 and 44 rpm (CVODES BDF throughout): 0.05 s discarded,
// 0.2 s counted, 3 exponents re-orthonormalized every 0.01 s.
AttractorStudyOptions WhirlAttractor() {
  AttractorStudyOptions o;
  o.approach = WhirlSweep(true);
  o.from_rpm = o.to_rpm = 48.0;
  o.attractor.duration = 0.2;
  o.attractor.discard = 0.05;
  o.attractor.interval = 0.01;
  o.attractor.exponents = 3;
  o.attractor.integrator = o.approach.sweep.integrator;
  o.attractor.integrator.sensitivity_error_control = false;
  return o;
}

TEST_CASE("Attractor study: the rolling whirl is a rotating wave, its rotation the one neutral "
          "direction, its two contacts equally loaded", "[attractor_study]") {
  const RubStructure structure = WhirlStructure();
  int speeds_reported = 0;
  AttractorStudyProgress progress;
  progress.speed = [&](const AttractorSpeed&) { ++speeds_reported; };
  const AttractorStudyResult result = RunAttractorStudy(structure, WhirlAttractor(), progress);
  INFO(result.BriefReport());
  REQUIRE(result.status == AttractorStudyStatus::kMeasured);
  CHECK(speeds_reported == 1);
  REQUIRE(result.approach.speeds.size() == 2);
  REQUIRE(result.speeds.size() == 1);
  const AttractorSpeed& s = result.speeds[0];
  CHECK(s.speed_rpm == 48.0);
  CHECK(s.motion == "rotating wave");
  CHECK(s.untrusted.empty());
  CHECK(s.result.extrema.empty());  // kept as the section only
  CHECK(s.result.zero == 1);
  CHECK(s.result.counted_time == Approx(0.2));
  CHECK(s.result.running.cols() == 20);
  // The rotation (= the time shift) is neutral, zero within its error; the next ones decay.
  CHECK(std::abs(s.result.exponents(0)) <= 3.0 * s.result.standard_errors(0));
  CHECK(s.result.exponents(1) < -3.0 * s.result.standard_errors(1));
  // Whatever the number of section points (the normal force drifts slowly while the whirl
  // settles), the symmetric rotor's contacts carry the same force at the same instants.
  std::vector<double> left, right;
  for (const RubSectionPoint& p : s.section) (p.contact == 0 ? left : right).push_back(p.normal_force);
  REQUIRE(left.size() == right.size());
  for (std::size_t i = 0; i < left.size(); ++i) CHECK(right[i] == Approx(left[i]).epsilon(1e-6));
  CHECK(result.BriefReport() == "attractor: 1 speed(s) 48 → 48 rpm: rotating wave");
}

TEST_CASE("Attractor study: a failed speed ends the schedule with a status, a failed approach "
          "measures nothing", "[attractor_study]") {
  const RubStructure structure = WhirlStructure();
  AttractorStudyOptions o = WhirlAttractor();
  o.to_rpm = 52.0;
  o.approach.sweep.parameters = {RpmToRadPerSecond(48.0)};  // no approach
  o.attractor.integrator.max_steps = 10;
  const AttractorStudyResult failed = RunAttractorStudy(structure, o);
  CHECK(failed.status == AttractorStudyStatus::kIntegrationFailure);
  CHECK(failed.approach.speeds.empty());
  REQUIRE(failed.speeds.size() == 1);
  CHECK(failed.speeds[0].result.status == AttractorStatus::kIntegrationFailure);
  CHECK_THAT(failed.message, Contains("48.0 rpm"));

  o = WhirlAttractor();
  o.approach.sweep.integrator.max_steps = 10;
  const AttractorStudyResult approach = RunAttractorStudy(structure, o);
  CHECK(approach.status == AttractorStudyStatus::kApproachFailed);
  CHECK(approach.speeds.empty());
  CHECK_THAT(approach.BriefReport(), Contains("the approach sweep failed"));
}

TEST_CASE("Attractor study: bad options are rejected naming the field", "[attractor_study]") {
  const RubStructure structure = WhirlStructure();
  auto rejected = [&](auto change) { return testing::Rejection(WhirlAttractor(), structure, change); };
  CHECK(rejected([](AttractorStudyOptions&) {}) == "accepted");
  CHECK_THAT(rejected([](AttractorStudyOptions& o) { o.attractor.exponents = 99; }),
             Contains("AttractorStudyOptions.attractor.exponents = 99: must be at most the model's 16 states"));
  CHECK_THAT(rejected([](AttractorStudyOptions& o) { o.to_rpm = 40.0; }),
             Contains("AttractorStudyOptions.to_rpm = 40: must lie at from_rpm or beyond it"));
  CHECK_THAT(rejected([](AttractorStudyOptions& o) { o.sample_interval = 0.02; }),
             Contains("AttractorStudyOptions.sample_interval = 0.02"));
  CHECK_THAT(rejected([](AttractorStudyOptions& o) { o.step_rpm = 0.0; }),
             Contains("AttractorStudyOptions.step_rpm = 0: must be positive"));
  CHECK_THAT(rejected([](AttractorStudyOptions& o) { o.attractor.interval = 0.1; }),
             Contains("AttractorOptions.interval"));
}

}  // namespace
}  // namespace rubcont
