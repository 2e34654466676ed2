#include "solvers/constants.h"
#include "studies/jump_prediction.h"

#include <cmath>
#include <limits>

#include <catch2/catch.hpp>

#include "models/units.h"

namespace rubcont {
namespace {

// Case A(a) (the scene defaults are the thesis's): its L1 branches over 20–80 rpm.
struct CaseAa {
  RubStructure structure = TwoPointStructure(ThesisCaseAa());
  std::vector<RotatingWaveBranch> branches;
  CaseAa() {
    RotatingWaveBranchOptions o;
    o.search.speed_min = RpmToRadPerSecond(20.0);
    o.search.speed_max = RpmToRadPerSecond(80.0);
    o.search.precession_max = HzToRadPerSecond(200.0);
    branches = ComputeRotatingWaveBranches(structure, FrictionLawKind::kExact, o);
  }
};

// A sweep of case A(a) from the thesis's impulse at 48, 50, 52 rpm (scene defaults: BDF order ≤ 2,
// rtol 1e-6), each speed run for the minimum three settle windows.
struct ShortSweep {
  std::vector<SweepPoint> points;
  RubSweepRegimes regimes;
  explicit ShortSweep(const RubStructure& structure) {
    RubFixedFrame system(structure);
    RubSweepObservables observables(system);
    SweepOptions o;
    for (double rpm : {48.0, 50.0, 52.0}) o.parameters.push_back(RpmToRadPerSecond(rpm));
    o.dwell = 0.75;
    o.integrator.max_order = 2;
    o.integrator.relative_tolerance = o.integrator.absolute_tolerance = 1e-6;
    o.integrator.max_steps = 100000000;
    SweepStepper stepper(system, observables, o, RubImpulseIncrement(structure, 1.0));
    while (stepper.Step() == SweepStepOutcome::kContinue) {
    }
    REQUIRE(stepper.Done());
    points = stepper.points();
    regimes = ClassifySweep(structure, points);
  }
};

TEST_CASE("Jump table: the speed-up sweep leaves the Mode 1 whirl at its stick-slip event",
          "[jump_prediction]") {
  const CaseAa a;
  const ShortSweep sweep(a.structure);
  // Both contacts jump whirl → whip between 50 and 52 rpm; the Mode 1 whirl's contacts reach μ at
  // 50.6887 rpm, 84.478 Hz (the closed form's μ_req = μ crossing). The Mode 2 and one-contact
  // whirls roll at the same precession there: the normal forces and touching contacts tell them apart.
  const std::vector<PredictedJump> rows =
      PredictJumps("up", a.structure, sweep.points, sweep.regimes, a.branches);
  REQUIRE(rows.size() == 2);
  for (const PredictedJump& r : rows) {
    CAPTURE(r.contact, r.branch, r.bifurcation);
    CHECK(r.direction == "up");
    CHECK(r.jump.kind == RubJumpKind::kWhirlToWhip);
    CHECK(r.jump.speed_from_rpm == 50.0);
    CHECK(r.jump.speed_to_rpm == 52.0);
    CHECK(r.matched_side == "departure");
    CHECK(r.branch_stable == 1);
    CHECK_THAT(r.bifurcation, Catch::Matchers::Contains("stick to slip"));
    CHECK(r.bifurcation_speed_rpm == Approx(50.6887).epsilon(0).margin(1e-3));
    CHECK(r.bifurcation_precession_hz == Approx(84.478).epsilon(0).margin(1e-3));
    CHECK(r.difference_rpm == Approx(51.0 - r.bifurcation_speed_rpm).epsilon(0).margin(1e-12));
  }
  CHECK(rows[0].contact == "left");
  CHECK(rows[1].contact == "right");

  // With the law the sweep integrates (tanh, ε = 1e-3 m/s) the Mode 1 whirl has no event: the slip
  // sets in at its knee (50.96 rpm), and the circular whip it rounds into loses stability at a Hopf
  // point (51.68 rpm). Both lie in the jump's interval; the regime rule reads the slip, so the knee
  // predicts the whirl → whip change, while any other kind of jump there is left to the Hopf point.
  RotatingWaveBranchOptions o;
  o.search.speed_min = RpmToRadPerSecond(20.0);
  o.search.speed_max = RpmToRadPerSecond(80.0);
  o.search.precession_max = HzToRadPerSecond(200.0);
  const std::vector<RotatingWaveBranch> tanh_branches =
      ComputeRotatingWaveBranches(a.structure, FrictionLawKind::kTanh, o);
  const std::vector<PredictedJump> smooth =
      PredictJumps("up", a.structure, sweep.points, sweep.regimes, tanh_branches);
  REQUIRE(smooth.size() == 2);
  for (const PredictedJump& r : smooth) {
    CAPTURE(r.contact, r.branch, r.bifurcation);
    CHECK(r.branch_stable == 1);
    CHECK_THAT(r.bifurcation, Catch::Matchers::Contains(r.contact + " knee"));
    CHECK(r.bifurcation_speed_rpm == Approx(50.963).epsilon(0).margin(0.01));
  }
  RubSweepRegimes other = sweep.regimes;
  for (RubSweepJump& jump : other.jumps) jump.kind = RubJumpKind::kFrequencyJump;
  for (const PredictedJump& r : PredictJumps("up", a.structure, sweep.points, other, tanh_branches)) {
    CAPTURE(r.contact, r.branch, r.bifurcation);
    CHECK(r.bifurcation == "Hopf");
    CHECK(r.bifurcation_speed_rpm == Approx(51.685).epsilon(0).margin(0.01));
  }

  // The same whip left at 70 rpm (into a state on no branch): it lies on the circular Mode 1 whip,
  // whose only special point (50.69 rpm) is more than 10 rpm away to predict anything.
  std::vector<SweepPoint> far = {sweep.points[2], sweep.points[0]};
  far[0].parameter = RpmToRadPerSecond(70.0);
  far[1].parameter = RpmToRadPerSecond(74.0);
  RubSweepRegimes regimes;
  regimes.precession_hz = {{sweep.regimes.precession_hz[0][2], sweep.regimes.precession_hz[0][0]},
                           {sweep.regimes.precession_hz[1][2], sweep.regimes.precession_hz[1][0]}};
  RubSweepJump j = rows[0].jump;
  j.speed_from_rpm = 70.0;
  j.speed_to_rpm = 74.0;
  regimes.jumps = {j};
  const std::vector<PredictedJump> unexplained =
      PredictJumps("up", a.structure, far, regimes, a.branches);
  REQUIRE(unexplained.size() == 1);
  CHECK(unexplained[0].matched_side == "departure");
  CHECK(unexplained[0].branch == rows[0].branch);
  CHECK(unexplained[0].bifurcation.empty());
  CHECK(std::isnan(unexplained[0].difference_rpm));
}

TEST_CASE("Jump table: a state on no branch is reported as such, the landing state is tried next",
          "[jump_prediction]") {
  const CaseAa a;
  // Two speeds: a made-up state precessing at 40 Hz at 70 rpm with both contacts touching (on no
  // rotating wave), then the rotor free at 66 rpm; then regaining contact into rolling.
  auto point = [](double rpm, double fraction, double normal_force) {
    SweepPoint p;
    p.parameter = RpmToRadPerSecond(rpm);
    for (int k = 0; k < 2; ++k) {
      ChannelSummary c;
      c.active_fraction = fraction;
      c.measures.assign(2, MeasureSummary{});
      c.measures[kNormalForceMeasure].mean = normal_force;
      p.channels.push_back(c);
    }
    return p;
  };
  RubSweepRegimes regimes;
  regimes.precession_hz = {{40.0, kNaN}, {40.0, kNaN}};
  RubSweepJump j;
  j.kind = RubJumpKind::kContactLost;
  j.speed_from_rpm = 70.0;
  j.speed_to_rpm = 66.0;
  j.precession_from_hz = 40.0;
  j.precession_to_hz = kNaN;
  regimes.jumps = {j};
  std::vector<PredictedJump> rows = PredictJumps(
      "down", a.structure, {point(70.0, 1.0, 100.0), point(66.0, 0.0, kNaN)}, regimes, a.branches);
  REQUIRE(rows.size() == 1);
  CHECK(rows[0].matched_side == "none");
  CHECK(rows[0].bifurcation.empty());
  CHECK(std::isnan(rows[0].bifurcation_speed_rpm));
  CHECK(std::isnan(rows[0].difference_rpm));

  // The same sweep's first speed rolling at 50 Hz at 30 rpm instead, entered from no contact.
  const ShortSweep sweep(a.structure);  // its 48 rpm point: the stable Mode 1 whirl
  regimes.precession_hz = {{kNaN, sweep.regimes.precession_hz[0][0]},
                           {kNaN, sweep.regimes.precession_hz[1][0]}};
  j.kind = RubJumpKind::kContactRegained;
  j.speed_from_rpm = 46.0;
  j.speed_to_rpm = 48.0;
  j.precession_from_hz = kNaN;
  j.precession_to_hz = sweep.regimes.precession_hz[0][0];
  regimes.jumps = {j};
  rows = PredictJumps("up", a.structure, {point(46.0, 0.0, kNaN), sweep.points[0]}, regimes,
                      a.branches);
  REQUIRE(rows.size() == 1);
  CHECK(rows[0].matched_side == "landing");
  CHECK(rows[0].branch_stable == 1);
  CHECK_THAT(rows[0].bifurcation, Catch::Matchers::Contains("stick to slip"));
}

}  // namespace
}  // namespace rubcont
