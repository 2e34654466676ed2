#include "studies/ensemble_study.h"

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

// Three copies at 48 rpm for 0.3 s (three stretches) from the approach through 40 and 44 rpm.
EnsembleStudyOptions WhirlEnsemble(RubRegime until, int threads) {
  EnsembleStudyOptions o;
  o.sweep = WhirlSweep();
  o.speed_rpm = 48.0;
  o.duration = 0.3;
  o.window = 0.05;
  o.ensemble.copies = 3;
  o.ensemble.threads = threads;
  o.target.regime = until;
  return o;
}

TEST_CASE("Ensemble study: copies of the rolling whirl arrive at whirl at once, never at whip, the "
          "same on one thread and on two", "[ensemble_study]") {
  const RubStructure structure = WhirlStructure();
  const EnsembleStudyResult whirl = RunEnsembleStudy(structure, WhirlEnsemble(RubRegime::kWhirl, 2));
  INFO(whirl.BriefReport());
  REQUIRE(whirl.status == EnsembleStudyStatus::kComplete);
  CHECK(whirl.arrival == "whirl on every contact");
  REQUIRE(whirl.approach.speeds.size() == 2);
  CHECK(RadPerSecondToRpm(whirl.approach.speeds.back()) == Approx(44.0).epsilon(1e-14));
  CHECK(whirl.approach.regimes == std::vector<RubRegime>(2, RubRegime::kWhirl));
  CHECK(whirl.stretches == 3);
  REQUIRE(whirl.stretch_end.size() == 3);
  CHECK(whirl.stretch_end[0] == Approx(kStretch).epsilon(1e-12));
  CHECK(whirl.stretch_end[2] == Approx(3.0 * kStretch).epsilon(1e-12));
  CHECK(whirl.reached == 3);
  CHECK(whirl.failed == 0);
  CHECK(whirl.untrusted == 0);
  // Every copy arrives at the end of its first stretch: all quantiles are that time.
  for (double t : {whirl.arrival_min, whirl.arrival_lower_quartile, whirl.arrival_median,
                   whirl.arrival_upper_quartile, whirl.arrival_max}) {
    CHECK(t == whirl.stretch_end[0]);
  }
  // Rolling at RCI 100: BP = 100 × 48 / 60 Hz = 80 Hz in every stretch of every copy.
  for (const RubArrival& a : whirl.run.arrivals) {
    for (double bp : a.regimes.precession_hz[0]) CHECK(bp == Approx(80.0).margin(0.8));
  }
  CHECK_THAT(whirl.BriefReport(), Contains("3 of 3 reached whirl on every contact"));

  // The copies share nothing: one thread gives the same numbers to the last bit.
  const EnsembleStudyResult serial = RunEnsembleStudy(structure, WhirlEnsemble(RubRegime::kWhirl, 1));
  REQUIRE(serial.run.copies.size() == 3);
  for (std::size_t c = 0; c < 3; ++c) {
    CHECK(serial.run.copies[c].start == whirl.run.copies[c].start);
    for (int k = 0; k < 2; ++k) {
      CHECK(serial.run.arrivals[c].regimes.precession_hz[k] == whirl.run.arrivals[c].regimes.precession_hz[k]);
    }
    REQUIRE(serial.run.copies[c].points.size() == 3);
    for (std::size_t i = 0; i < 3; ++i) {
      CHECK(serial.run.copies[c].points[i].channels[1].spectrum ==
            whirl.run.copies[c].points[i].channels[1].spectrum);
    }
  }
  // Different seeds perturb the copies differently.
  CHECK_FALSE(whirl.run.copies[0].start == whirl.run.copies[1].start);

  const EnsembleStudyResult whip = RunEnsembleStudy(structure, WhirlEnsemble(RubRegime::kWhip, 2));
  CHECK(whip.reached == 0);
  CHECK(std::isnan(whip.arrival_median));
  for (const RubArrival& a : whip.run.arrivals) CHECK(a.simulated == Approx(3.0 * kStretch).epsilon(1e-12));
  CHECK(whip.median_cpu_seconds > 0.0);
}

TEST_CASE("Ensemble study: a penetration limit below the whirl's marks every copy untrusted",
          "[ensemble_study]") {
  EnsembleStudyOptions o = WhirlEnsemble(RubRegime::kWhip, 2);
  o.sweep.regimes.max_penetration = 1e-6;  // the whirl penetrates 2e-5 of the clearance
  o.sweep.sweep.parameters = {RpmToRadPerSecond(40.0)};  // the approach: 40 rpm only
  o.duration = 0.1;
  o.ensemble.copies = 2;
  const EnsembleStudyResult result = RunEnsembleStudy(WhirlStructure(), o);
  CHECK(result.approach.speeds.size() == 1);
  CHECK(result.untrusted == 2);
  CHECK(result.first_untrusted_copy == 0);
  CHECK_THAT(result.first_untrusted, Contains("contact penetrates"));
}

TEST_CASE("Ensemble study: a failed approach or copy is a status, bad options name the field",
          "[ensemble_study]") {
  const RubStructure structure = WhirlStructure();
  EnsembleStudyOptions o = WhirlEnsemble(RubRegime::kWhirl, 2);
  o.sweep.sweep.integrator.max_steps = 10;
  const EnsembleStudyResult approach = RunEnsembleStudy(structure, o);
  CHECK(approach.status == EnsembleStudyStatus::kApproachFailed);
  CHECK_THAT(approach.BriefReport(), Contains("the approach sweep failed"));
  CHECK(approach.run.copies.empty());
  o.speed_rpm = 40.0;  // no approach: the copies fail
  const EnsembleStudyResult copies = RunEnsembleStudy(structure, o);
  CHECK(copies.status == EnsembleStudyStatus::kCopiesFailed);
  CHECK(copies.failed == 3);
  CHECK(copies.message == "3 of 3 copies failed to integrate");
  CHECK(copies.stretch_end.empty());

  auto rejected = [&](auto change) {
    return testing::Rejection(WhirlEnsemble(RubRegime::kWhirl, 2), structure, change);
  };
  CHECK(rejected([](EnsembleStudyOptions&) {}) == "accepted");
  CHECK_THAT(rejected([](EnsembleStudyOptions& b) { b.speed_rpm = -3.0; }),
             Contains("EnsembleStudyOptions.speed_rpm = -3: must be positive"));
  CHECK_THAT(rejected([](EnsembleStudyOptions& b) { b.duration = 0.05; }),
             Contains("EnsembleStudyOptions.duration = 0.05: must be at least two windows"));
  CHECK_THAT(rejected([](EnsembleStudyOptions& b) { b.ensemble.copies = 0; }),
             Contains("EnsembleStudyOptions.ensemble.copies = 0: must be in 1 … 100000"));
  CHECK_THAT(rejected([](EnsembleStudyOptions& b) { b.ensemble.perturbation = -1.0; }),
             Contains("EnsembleOptions.perturbation = -1"));
  CHECK_THAT(rejected([](EnsembleStudyOptions& b) { b.target.precession_above_hz = 0.0; }),
             Contains("EnsembleStudyOptions.target.precession_above_hz = 0"));
}

TEST_CASE("SortedQuantile interpolates linearly between ranks", "[ensemble_study]") {
  CHECK(std::isnan(SortedQuantile({}, 0.5)));
  CHECK(SortedQuantile({2.0}, 0.25) == 2.0);
  CHECK(SortedQuantile({1.0, 2.0, 4.0}, 0.5) == 2.0);
  CHECK(SortedQuantile({1.0, 2.0, 4.0}, 0.75) == 3.0);
  CHECK(SortedQuantile({1.0, 2.0, 4.0, 8.0}, 0.5) == 3.0);
  CHECK(SortedQuantile({1.0, 2.0, 4.0, 8.0}, 1.0) == 8.0);
}

}  // namespace
}  // namespace rubcont
