#include "solvers/constants.h"
#include "sweeps/rub_sweep.h"

#include <algorithm>
#include <cmath>
#include <tuple>
#include <complex>
#include <limits>
#include <optional>
#include <stdexcept>

#include <catch2/catch.hpp>

#include "models/analytic.h"
#include "models/units.h"
#include "waves/rotating_wave_branches.h"
#include "studies/whirl_limits.h"

namespace rubcont {
namespace {

using Catch::Matchers::Contains;

TEST_CASE("The impulse translates the rotor at J/m_r and leaves everything else at rest", "[rub_sweep]") {
  TwoPointParams p = ThesisCaseAa();
  for (double mass_center : {0.145, 0.22, 0.26, 0.35}) {
    CAPTURE(mass_center);
    p.rotor_mass_center = mass_center;
    const RubStructure s = TwoPointStructure(p);
    const Vector dx = RubImpulseIncrement(s, 2.0);
    REQUIRE(dx.size() == 16);
    CHECK(dx.head(8).isZero(0.0));
    // (vx, vy) of rotor L, rotor R, stator L, stator R.
    CHECK(dx(8) == Approx(2.0 / p.rotor_mass).epsilon(1e-12));
    CHECK(dx(10) == Approx(2.0 / p.rotor_mass).epsilon(1e-12));
    CHECK(dx(9) == 0.0);
    CHECK(dx(11) == 0.0);
    CHECK(std::abs(dx(12)) < 1e-15);
    CHECK(std::abs(dx(14)) < 1e-15);
    // Momentum: M Δv = b J.
    const Vector vx = (Vector(4) << dx(8), dx(10), dx(12), dx(14)).finished();
    CHECK((s.mass * vx - 2.0 * s.imbalance_weights).norm() < 1e-12);
  }
  CHECK_THROWS_WITH(RubImpulseIncrement(TwoPointStructure(p), -1.0), Contains("impulse = -1"));
}

TEST_CASE("Speed schedules: the thesis's 120 up and 117 down speeds", "[rub_sweep]") {
  const std::vector<double> up = SpeedSchedule(20.0, 258.0, 2.0);
  REQUIRE(up.size() == 120);
  CHECK(up.front() == 20.0);
  CHECK(up.back() == Approx(258.0).epsilon(1e-14));
  const std::vector<double> down = SpeedSchedule(252.0, 20.0, 2.0);
  REQUIRE(down.size() == 117);
  CHECK(down.front() == 252.0);
  CHECK(down[1] == 250.0);
  CHECK(down.back() == Approx(20.0).epsilon(1e-14));
  CHECK(SpeedSchedule(20.0, 25.0, 2.0) == std::vector<double>{20.0, 22.0, 24.0});
  CHECK(SpeedSchedule(20.0, 20.3, 0.1).size() == 4);  // 20.3 is on the grid despite rounding
  CHECK(SpeedSchedule(50.0, 50.0, 2.0) == std::vector<double>{50.0});
  CHECK_THROWS_WITH(SpeedSchedule(20.0, 258.0, 0.0), Contains("step = 0 rpm"));
  CHECK_THROWS_WITH(SpeedSchedule(-20.0, 258.0, 2.0), Contains("must be positive"));
  CHECK(RadPerSecondToRpm(RpmToRadPerSecond(60.0)) == Approx(60.0));
  CHECK(RpmToRadPerSecond(60.0) == Approx(kTwoPi));  // 1 rev/s, written by hand: the check of units.h
}

TEST_CASE("The observables are the contacts' relative motion, slip velocity, normal force and "
          "penetration", "[rub_sweep]") {
  const RubStructure s = TwoPointStructure(ThesisCaseAa());
  RubFixedFrame system(s, RpmToRadPerSecond(100.0));
  RubSweepObservables observables(system);
  REQUIRE(observables.Channels() == 2);
  CHECK(observables.ChannelName(0) == "left");
  CHECK(observables.ChannelName(1) == "right");
  CHECK(observables.MeasureName(kSlipVelocityMeasure) == "slip_velocity");
  CHECK(observables.MeasureName(kNormalForceMeasure) == "normal_force");
  CHECK(observables.MeasureName(kPenetrationMeasure) == "penetration");
  REQUIRE(observables.Measures() == 3);
  const double C = s.contacts[0].geometry.clearance;
  Vector x = Vector::Zero(16);
  x.head(8) << 1.001 * C, 0.0, 0.5 * C, 0.2 * C, 1e-7, -2e-7, 0.0, 0.0;  // left touches, right not
  x.tail(8) << 0.01, -0.2, 0.03, 0.04, 0.002, 0.001, 0.0, 0.0;
  SweepObservation o;
  o.signal.resize(2);
  o.active.assign(2, 0);
  o.measures.resize(2, observables.Measures());
  observables.Observe(0.0, x, o);
  const std::vector<ContactEvaluation> c = system.Contacts(x);
  CHECK(o.signal(0) == std::complex<double>(x(0) - x(4), x(1) - x(5)));
  CHECK(o.signal(1) == std::complex<double>(x(2) - x(6), x(3) - x(7)));
  CHECK(o.active[0] == 1);
  CHECK(o.active[1] == 0);
  CHECK(o.measures(0, kSlipVelocityMeasure) == c[0].slip_velocity);
  CHECK(o.measures(0, kNormalForceMeasure) == c[0].normal_force);
  CHECK(c[0].normal_force > 0.0);
  CHECK(o.measures(1, kNormalForceMeasure) == 0.0);
  CHECK(o.measures(0, kPenetrationMeasure) == c[0].penetration);
  CHECK(c[0].penetration == Approx(std::abs(o.signal(0)) - C).epsilon(1e-9));  // δ = |d| − C
  CHECK(o.measures(1, kPenetrationMeasure) < 0.0);  // a gap
}

// A synthetic sweep point at `rpm`: per contact its BP [Hz], mean slip velocity [m/s] and
// contact fraction.
struct ContactReading {
  double bp_hz;
  double slip_velocity;
  double contact_fraction = 1.0;
};
SweepPoint Point(double rpm, ContactReading left, ContactReading right) {
  SweepPoint p;
  p.parameter = RpmToRadPerSecond(rpm);
  for (const ContactReading& r : {left, right}) {
    ChannelSummary c;
    c.peak.found = !std::isnan(r.bp_hz);
    c.peak.frequency = -r.bp_hz;
    c.active_fraction = r.contact_fraction;
    c.measures.resize(2);
    c.measures[kSlipVelocityMeasure].mean = r.slip_velocity;
    p.channels.push_back(c);
  }
  return p;
}

// The same for a circular orbit: its slip velocity follows from the precession,
// V_k = ωR_k − 2π·BP·C_k (models/contact.h, penetration neglected).
SweepPoint CircularPoint(const RubStructure& s, double rpm, double bp_left, double bp_right,
                         double contact_left = 1.0, double contact_right = 1.0) {
  const auto slip = [&](int k, double bp) {
    const ContactGeometry& g = s.contacts[static_cast<std::size_t>(k)].geometry;
    return RpmToRadPerSecond(rpm) * g.radius - HzToRadPerSecond(bp) * g.clearance;
  };
  return Point(rpm, {bp_left, slip(0, bp_left), contact_left}, {bp_right, slip(1, bp_right), contact_right});
}

TEST_CASE("Regimes and jumps are read off the precession against rolling", "[rub_sweep]") {
  TwoPointParams params = ThesisCaseAa();
  params.clearance = {3.81e-4, 3.048e-4};  // RCI 100 / 125
  const RubStructure s = TwoPointStructure(params);
  // Rolling: 100·rpm/60 Hz at the left contact, 125·rpm/60 at the right.
  std::vector<SweepPoint> points = {
      CircularPoint(s, 48.0, 80.0, 83.0),            // left whirls, right whips (83 < 0.98·100)
      CircularPoint(s, 50.0, 83.33, 83.33),          // same trend: no jump
      CircularPoint(s, 52.0, 84.5, 84.5),            // left: whirl → whip
      CircularPoint(s, 54.0, 84.6, 84.6),
      CircularPoint(s, 56.0, 111.0, 84.7),           // left jumps to another whip frequency
      CircularPoint(s, 58.0, 111.2, 84.7, 0.0, 0.5), // left loses contact
      CircularPoint(s, 60.0, kNaN, 84.8, 0.5, 0.5),  // no peak: no contact either
      CircularPoint(s, 62.0, 103.3, 129.2),          // left regains contact in whirl; right whip → whirl
      CircularPoint(s, 64.0, 106.7, 133.3),
      CircularPoint(s, 66.0, 120.0, 137.5, 0.005),   // left touches 0.5 % of the time: intermittent
      CircularPoint(s, 68.0, 121.0, 141.7, 0.0),     // then not at all: still lost, no jump
  };
  points.insert(points.begin() + 8, SweepPoint{});  // a failed speed between 62 and 64 rpm
  points[8].parameter = RpmToRadPerSecond(63.0);
  points[8].status = SweepPointStatus::kIntegrationFailure;
  const RubSweepRegimes r = ClassifySweep(s, points);
  using R = RubRegime;
  CHECK(r.regime[0] == std::vector<R>{R::kWhirl, R::kWhirl, R::kWhip, R::kWhip, R::kWhip,
                                      R::kNoContact, R::kNoContact, R::kWhirl, R::kUnknown, R::kWhirl,
                                      R::kIntermittent, R::kNoContact});
  CHECK(r.regime[1] == std::vector<R>{R::kWhip, R::kWhip, R::kWhip, R::kWhip, R::kWhip, R::kWhip,
                                      R::kWhip, R::kWhirl, R::kUnknown, R::kWhirl, R::kWhirl,
                                      R::kWhirl});
  CHECK(r.precession_hz[0][2] == 84.5);
  CHECK(std::isnan(r.precession_hz[0][8]));
  // Intermittent contact keeps what was measured: its BP and its slip over the contact time.
  CHECK(r.precession_hz[0][10] == 120.0);
  CHECK(r.slip_ratio[0][10] ==
        Approx(std::abs(1.0 - 120.0 / (100.0 * RpmToHz(66.0)))).epsilon(1e-12));
  CHECK(std::isnan(r.slip_ratio[0][11]));
  REQUIRE(r.jumps.size() == 6);
  auto check = [&](std::size_t i, int contact, RubJumpKind kind, double from, double to) {
    CAPTURE(i);
    CHECK(r.jumps[i].contact == contact);
    CHECK(r.jumps[i].kind == kind);
    CHECK(r.jumps[i].speed_from_rpm == Approx(from));
    CHECK(r.jumps[i].speed_to_rpm == Approx(to));
  };
  check(0, 0, RubJumpKind::kWhirlToWhip, 50.0, 52.0);
  check(1, 0, RubJumpKind::kFrequencyJump, 54.0, 56.0);
  check(2, 0, RubJumpKind::kContactLost, 56.0, 58.0);
  check(3, 0, RubJumpKind::kContactRegained, 60.0, 62.0);
  check(4, 1, RubJumpKind::kWhipToWhirl, 60.0, 62.0);
  check(5, 0, RubJumpKind::kContactLost, 64.0, 66.0);  // whirl → intermittent, then nothing
  CHECK(r.jumps[5].precession_to_hz == 120.0);
  CHECK(r.jumps[0].precession_from_hz == 83.33);
  CHECK(r.jumps[0].precession_to_hz == 84.5);
  CHECK(std::isnan(r.jumps[2].precession_to_hz));
  // The failed speed 63 rpm is skipped: 62 → 64 is whirl → whirl on trend, no jump.

  RubRegimeOptions strict;
  strict.frequency_jump_hz = 0.05;  // now the whip's 0.1 Hz wander counts
  CHECK(ClassifySweep(s, points, strict).jumps.size() > 5);
  strict.whirl_tolerance = 1.5;
  CHECK_THROWS_WITH(ClassifySweep(s, points, strict), Contains("whirl_tolerance = 1.5"));
  // 111 Hz at 56 rpm (rolling 93.3 Hz) slips by 19 % of ωR: whip unless both rules let it roll.
  strict.whirl_tolerance = 0.2;
  CHECK(ClassifySweep(s, points, strict).regime[0][4] == RubRegime::kWhip);
  strict.rolling_slip_tolerance = 0.2;
  CHECK(ClassifySweep(s, points, strict).regime[0][4] == RubRegime::kWhirl);
  strict.rolling_slip_tolerance = 0.0;
  CHECK_THROWS_WITH(ClassifySweep(s, points, strict), Contains("rolling_slip_tolerance = 0"));

  // A point without the slip velocity cannot be classified.
  points[0].channels[1].measures.clear();
  CHECK_THROWS_WITH(ClassifySweep(s, points), Contains("slip velocity"));
}

TEST_CASE("Rolling is decided by the slip: case C(a)'s whip locked next to the rolling line is whip",
          "[rub_sweep]") {
  const RubStructure s = TwoPointStructure(ThesisCaseCa());
  // Readings of the C(a) speed-up sweep (results/thesis_C_a/sweep.h5, ε = 1e-3 m/s), left and
  // right: BP [Hz], mean slip velocity [m/s], contact fraction. Rolling is 100·rpm/60 Hz.
  const std::vector<SweepPoint> points = {
      Point(44.0, {73.254, 1.853e-4}, {73.238, 2.211e-4}),   // rolling whirl (slip 0.11–0.13 % of ωR)
      Point(48.0, {79.179, 1.992e-3}, {79.180, 1.972e-3}),   // whip: 1.0 % below rolling, slip 1.0 %
      Point(52.0, {79.266, 1.774e-2}, {79.262, 1.772e-2}),   // whip
      // The left contact 22 % in touch, precessing 0.25 % from rolling but slipping by 8.6 % of ωR;
      // then 2 % in touch, slipping by 0.24 % on average, precessing 13 % off the rolling line.
      Point(132.0, {219.442, 4.537e-2, 0.22}, {79.328, 3.306e-1, 0.84}),
      Point(196.0, {369.660, -1.872e-3, 0.0195}, {79.801, 4.821e-1, 0.10}),
  };
  const RubSweepRegimes r = ClassifySweep(s, points);
  using R = RubRegime;
  CHECK(r.regime[0] == std::vector<R>{R::kWhirl, R::kWhip, R::kWhip, R::kWhip, R::kWhip});
  CHECK(r.regime[1] == std::vector<R>{R::kWhirl, R::kWhip, R::kWhip, R::kWhip, R::kWhip});
  CHECK(r.slip_ratio[0][1] == Approx(1.992e-3 / (0.0381 * RpmToRadPerSecond(48.0))).epsilon(1e-12));
  // The speed-up jump lies between 44 and 48 rpm (the L1 Hopf point of the tanh Mode 1 whirl is
  // at 48.49 rpm); by the frequency alone (the former rule) 48 rpm was whirl and the jump one step
  // late.
  REQUIRE_FALSE(r.jumps.empty());
  CHECK(r.jumps[0].kind == RubJumpKind::kWhirlToWhip);
  CHECK(r.jumps[0].speed_from_rpm == Approx(44.0));
  CHECK(r.jumps[0].speed_to_rpm == Approx(48.0));
  RubRegimeOptions frequency_only;
  frequency_only.rolling_slip_tolerance = 0.999;
  const RubSweepRegimes f = ClassifySweep(s, points, frequency_only);
  CHECK(f.regime[0][1] == R::kWhirl);
  CHECK(f.regime[0][3] == R::kWhirl);
  CHECK(f.regime[0][4] == R::kWhip);  // the frequency check alone still calls this one whip

  // A rolling whirl close to its jump is still whirl: case A(a) at 48 rpm (speed-up sweep,
  // results/thesis_A_a/sweep.h5), 3.7 rpm below the Hopf point of its tanh Mode 1 whirl.
  const RubStructure a = TwoPointStructure(ThesisCaseAa());
  const RubSweepRegimes w =
      ClassifySweep(a, {Point(48.0, {79.878, 2.856e-4}, {79.878, 2.856e-4})});
  CHECK(w.regime[0][0] == R::kWhirl);
  CHECK(w.regime[1][0] == R::kWhirl);
  CHECK(w.slip_ratio[0][0] == Approx(0.00149).epsilon(0.01));
}

TEST_CASE("A tanh-law contact rolls with its micro-slip at low speed, below ε but above 0.5 % of ωR",
          "[rub_sweep]") {
  TwoPointParams params = ThesisCaseAa();  // case B(b): disk at ¾, RCI 100 / 125, ε = 1e-3 m/s
  params.rotor_inertia = 0.04;
  params.rotor_mass_center = 0.22;
  params.clearance = {3.81e-4, 3.048e-4};
  const RubStructure s = TwoPointStructure(params);
  // Its speed-down sweep at 20 rpm (results/thesis_B_b/sweep.h5): the right contact (RCI 125,
  // rolling at 41.67 Hz) precesses 0.6 % below its rolling line with V = 0.44 mm/s = 0.44ε,
  // 0.56 % of ωR; the left contact (rolling at 33.3 Hz) slips by 24 % of ωR.
  const std::vector<SweepPoint> points = {
      Point(20.0, {41.432, -1.9394e-2}, {41.432, 4.4464e-4})};
  const RubSweepRegimes r = ClassifySweep(s, points);
  CHECK(r.regime[0][0] == RubRegime::kWhip);
  CHECK(r.regime[1][0] == RubRegime::kWhirl);
  CHECK(r.slip_ratio[1][0] > 0.005);
  // By the surface speed alone it would whip.
  RubRegimeOptions surface_speed_only;
  surface_speed_only.rolling_micro_slip = 0.0;
  CHECK(ClassifySweep(s, points, surface_speed_only).regime[1][0] == RubRegime::kWhip);
  surface_speed_only.rolling_micro_slip = -1.0;
  CHECK_THROWS_WITH(ClassifySweep(s, points, surface_speed_only), Contains("rolling_micro_slip = -1"));
  // The allowance scales with the law's ε: at ε = 1e-4 m/s the same slip is 4.4ε.
  params.friction_law.velocity_scale = 1e-4;
  CHECK(ClassifySweep(TwoPointStructure(params), points).regime[1][0] == RubRegime::kWhip);
}

}  // namespace
}  // namespace rubcont

namespace rubcont {
namespace {

// The Mode 1 whirl of case A(a) at `rpm` (RCI 100) from the rigid-contact closed form, as a
// fixed-frame state.
Vector WhirlState(double rpm) {
  const RubStructure s = TwoPointStructure(ThesisCaseAa());
  const double precession = 100.0 * RpmToRadPerSecond(rpm);
  const RigidContactOrbit whirl = SolveRigidContactOrbit(s, precession, {1.0, 1.0});
  const Index nc = s.Coordinates();
  Vector x0(4 * nc);
  for (Index i = 0; i < nc; ++i) {
    const std::complex<double> u = whirl.amplitude[static_cast<std::size_t>(i)];
    const std::complex<double> v = std::complex<double>(0.0, -precession) * u;
    x0.segment(2 * i, 2) << u.real(), u.imag();
    x0.segment(2 * nc + 2 * i, 2) << v.real(), v.imag();
  }
  return x0;
}

struct SegmentResult {
  RubSweepRegimes regimes;
  std::vector<SweepPoint> points;
};

// A short speed-up segment of structure s, started by the 1 N·s impulse at its first speed, with
// at most 0.75 s per speed, integrated by `integrator` (and by `intermittent` after a window in
// which a contact touched only part of the time, when given: the sweeps' "auto").
SegmentResult Segment(const RubStructure& s, const std::vector<double>& rpm,
                      const IntegratorOptions& integrator,
                      const std::optional<IntegratorOptions>& intermittent = std::nullopt) {
  RubFixedFrame system(s);
  RubSweepObservables observables(system);
  SweepOptions o;
  for (double v : rpm) o.parameters.push_back(RpmToRadPerSecond(v));
  o.dwell = 0.75;
  o.integrator = integrator;
  o.intermittent_integrator = intermittent;
  SweepStepper stepper(system, observables, o, RubImpulseIncrement(s, 1.0));
  while (stepper.Step() == SweepStepOutcome::kContinue) {
  }
  REQUIRE(stepper.Done());
  return {ClassifySweep(s, stepper.points()), stepper.points()};
}

// CVODES BDF of maximum order `order` with relative and (scaled) absolute tolerance `tolerance`.
IntegratorOptions Bdf(int order, double tolerance) {
  IntegratorOptions o;
  o.max_order = order;
  o.relative_tolerance = o.absolute_tolerance = tolerance;
  o.max_steps = 100000000;
  return o;
}

// The same segment of case A(a) (the scene defaults are the thesis's) by BDF.
SegmentResult Segment(const std::vector<double>& rpm, int order, double tolerance) {
  return Segment(TwoPointStructure(ThesisCaseAa()), rpm, Bdf(order, tolerance));
}

TEST_CASE("Stiff contact: the sweep's BP frequencies do not change when the tolerances tighten",
          "[rub_sweep][tolerance]") {
  // 50 rpm rolls (whirl); 52, 54 rpm slip (whip at the analytic Mode 1 μ_req = μ frequency).
  // Loose: the scene default, BDF order ≤ 2 at 1e-6. Tight: 100× tighter and order ≤ 5, so that
  // the whip cannot be the numerical damping of the A-stable order-2 formula (orders 3–5 are not
  // A-stable and damp nothing at these step sizes: ~1e6 steps per simulated second).
  const std::vector<double> rpm = {50.0, 52.0, 54.0};
  const SegmentResult loose = Segment(rpm, 2, 1e-6);
  const SegmentResult tight = Segment(rpm, 5, 1e-8);
  const AnalyticCurve mode1 = ComputeAnalyticCurve(ThesisCaseAa(), CircularMode::kMode1);
  double whip_onset_hz = kNaN;
  for (const Transition& t : mode1.transitions)
    if (t.type == TransitionType::kMuCrossing && t.direction > 0) {
      whip_onset_hz = t.precession_hz;
      break;
    }
  REQUIRE(whip_onset_hz == Approx(84.478).epsilon(0).margin(0.01));
  for (std::size_t i = 0; i < rpm.size(); ++i) {
    for (int k = 0; k < 2; ++k) {
      CAPTURE(rpm[i], k);
      const double bp = loose.regimes.precession_hz[k][i];
      // Tolerances 100× tighter: the same BP to 0.01 Hz (the analysis bins are 2 Hz wide), the
      // same regime, the same slip velocity to 0.5 mm/s.
      CHECK(std::abs(bp - tight.regimes.precession_hz[k][i]) < 0.01);
      CHECK(loose.regimes.regime[k][i] == tight.regimes.regime[k][i]);
      const double v_loose = loose.points[i].channels[k].measures[kSlipVelocityMeasure].mean;
      const double v_tight = tight.points[i].channels[k].measures[kSlipVelocityMeasure].mean;
      CHECK(std::abs(v_loose - v_tight) < 5e-4);
      CHECK(loose.points[i].channels[k].active_fraction == 1.0);
      // And the physics: rolling at RCI·f below the transition, whip at the closed form's
      // μ_req = μ frequency above it (the sweep's whip is slightly modulated: within 0.1 Hz).
      if (rpm[i] <= 50.0) {
        CHECK(loose.regimes.regime[k][i] == RubRegime::kWhirl);
        CHECK(bp == Approx(100.0 * RpmToHz(rpm[i])).epsilon(0.005));
        CHECK(std::abs(v_loose) < 1e-3);
      } else {
        CHECK(loose.regimes.regime[k][i] == RubRegime::kWhip);
        CHECK(bp == Approx(whip_onset_hz).epsilon(0).margin(0.1));
        CHECK(v_loose > 1e-3);
      }
    }
  }
  // Cross-check with level L1: the whip at 54 rpm precesses at the circular Mode 1 whip's
  // frequency (exact slip) with its mean slip velocity (within 2 %), but it is not that circular
  // orbit, which L1 finds unstable (growth 262 s⁻¹ at 238 and 577 Hz in the rotating frame): the
  // slip velocity swings by more than its mean. The swing is the same in both runs (10 %): the
  // modulation is not an artefact of the order-2 formula's damping.
  RotatingWaveBranchOptions branch_options;
  branch_options.search.speed_min = RpmToRadPerSecond(40.0);
  branch_options.search.speed_max = RpmToRadPerSecond(60.0);
  branch_options.search.precession_max = HzToRadPerSecond(200.0);
  const std::vector<RotatingWaveBranch> branches = ComputeRotatingWaveBranches(
      TwoPointStructure(ThesisCaseAa()), FrictionLawKind::kExact, branch_options);
  double v_branch = kNaN;
  for (const RotatingWaveBranch& b : branches) {
    if (PatternName(b.normals) != "mode1") continue;
    const auto& names = b.branch.measure_names;
    const auto at = [&](const char* name) {
      return static_cast<Index>(std::find(names.begin(), names.end(), name) - names.begin());
    };
    const Index hz = at("precession_hz"), v = at("slip_velocity_left");
    const auto& p = b.branch.points;
    for (std::size_t i = 0; i + 1 < p.size(); ++i) {
      const double r0 = RadPerSecondToRpm(p[i].lambda), r1 = RadPerSecondToRpm(p[i + 1].lambda);
      if (54.0 < std::min(r0, r1) || 54.0 > std::max(r0, r1) || p[i].piece != p[i + 1].piece) continue;
      if (std::abs(p[i].measures(hz) - whip_onset_hz) > 0.1) continue;
      const double s = (54.0 - r0) / (r1 - r0);
      v_branch = (1.0 - s) * p[i].measures(v) + s * p[i + 1].measures(v);
    }
  }
  REQUIRE(v_branch > 1e-3);
  for (int k = 0; k < 2; ++k) {
    CAPTURE(k, v_branch);
    const MeasureSummary& a = loose.points[2].channels[k].measures[kSlipVelocityMeasure];
    const MeasureSummary& b = tight.points[2].channels[k].measures[kSlipVelocityMeasure];
    CAPTURE(a.min, a.max, b.min, b.max);
    CHECK(a.mean == Approx(v_branch).epsilon(0.02));
    CHECK(b.mean == Approx(v_branch).epsilon(0.02));
    CHECK(a.max - a.min > a.mean);
    CHECK((a.max - a.min) == Approx(b.max - b.min).epsilon(0.1));
  }

  // The tighter run does the work the tolerances ask for.
  long loose_steps = 0, tight_steps = 0;
  for (std::size_t i = 0; i < rpm.size(); ++i) {
    loose_steps += loose.points[i].statistics.steps;
    tight_steps += tight.points[i].statistics.steps;
  }
  CHECK(tight_steps > loose_steps);
}

TEST_CASE("BDF's damping holds cases B(b) and B(c) on unstable rotating waves, where the contacts "
          "chatter (Dormand-Prince, and BDF at 1e-9)", "[rub_sweep][tolerance]") {
  // Case B(b) (disk at ¾, RCI 100 / 125, tanh ε = 1e-3 m/s) at 20–28 rpm: the right contact rolls,
  // the left slips. L1 says that rotating wave is unstable (growth ~10³ s⁻¹). BDF of order ≤ 2 at
  // 1e-6 takes steps across the contact modes (36 and 85 kHz), whose growth its stability region
  // damps (it covers most of the right half-plane far from 0): it holds the rotor on the unstable
  // wave in full contact. Dormand–Prince at 1e-8 keeps both contacts touching only part of the
  // time — as Dormand–Prince at 1e-10 and BDF at 1e-9 do (measured 2026-11-27 from the same
  // impulse: contact fractions left/right at 28 rpm 0.45/0.64 and 0.48/0.66, against 1.00/1.00 by
  // BDF at 1e-6; BDF at 1e-9 costs 74–88 s per speed, too slow for a test).
  TwoPointParams params = ThesisCaseAa();
  params.rotor_inertia = 0.04;
  params.rotor_mass_center = 0.22;
  params.clearance = {3.81e-4, 3.048e-4};
  const RubStructure s = TwoPointStructure(params);
  const std::vector<double> rpm = {20.0, 24.0, 28.0};
  IntegratorOptions dormand_prince;
  dormand_prince.method = IntegrationMethod::kDormandPrince;
  dormand_prince.relative_tolerance = dormand_prince.absolute_tolerance = 1e-8;
  dormand_prince.max_steps = 100000000;
  const SegmentResult bdf = Segment(s, rpm, Bdf(2, 1e-6));
  const SegmentResult automatic = Segment(s, rpm, Bdf(2, 1e-6), dormand_prince);
  const SweepPoint& held = bdf.points.back();
  const SweepPoint& chatter = automatic.points.back();
  CHECK(held.channels[0].active_fraction == 1.0);
  CHECK(held.channels[1].active_fraction == 1.0);
  CHECK(chatter.channels[0].active_fraction < 0.8);
  CHECK(chatter.channels[1].active_fraction < 0.9);
  CHECK(chatter.intermittent_windows == chatter.windows);
  // The same slip (the left slips by 0.027 m/s, the right rolls): only the contact differs.
  for (int k = 0; k < 2; ++k) {
    CAPTURE(k);
    CHECK(bdf.regimes.regime[k].back() == automatic.regimes.regime[k].back());
    CHECK(std::abs(held.channels[k].measures[kSlipVelocityMeasure].mean -
                   chatter.channels[k].measures[kSlipVelocityMeasure].mean) < 5e-4);
  }
  CHECK(bdf.regimes.regime[1].back() == RubRegime::kWhirl);

  // L1: the tanh-law rotating wave with the right contact rolling at the BDF sweep's frequency at
  // 28 rpm is unstable, with a growth rate no 0.75 s run could miss.
  RotatingWaveBranchOptions options;
  options.search.speed_min = RpmToRadPerSecond(20.0);
  options.search.speed_max = RpmToRadPerSecond(260.0);
  options.search.precession_max = HzToRadPerSecond(200.0);
  params.friction_law.kind = FrictionLawKind::kTanh;
  const double held_hz = bdf.regimes.precession_hz[1].back();
  int matches = 0;
  for (const RotatingWaveBranch& b :
       ComputeRotatingWaveBranches(TwoPointStructure(params), FrictionLawKind::kTanh, options)) {
    const Index hz = b.branch.MeasureIndex("precession_hz");
    const std::vector<BranchPoint>& points = b.branch.points;
    for (std::size_t i = 0; i + 1 < points.size(); ++i) {
      const double r0 = RadPerSecondToRpm(points[i].lambda);
      const double r1 = RadPerSecondToRpm(points[i + 1].lambda);
      if (28.0 < std::min(r0, r1) || 28.0 > std::max(r0, r1)) continue;
      // The point of the pair nearer 28 rpm.
      const BranchPoint& p = std::abs(r0 - 28.0) < std::abs(r1 - 28.0) ? points[i] : points[i + 1];
      if (std::abs(p.measures(hz) - held_hz) > 1.0) continue;
      ++matches;
      CAPTURE(RadPerSecondToRpm(p.lambda), p.measures(hz));
      REQUIRE(p.spectrum.valid);
      CHECK(p.num_unstable > 0);
      CHECK(p.spectrum.values(0).real() > 100.0);
    }
  }
  CHECK(matches > 0);

  // Case B(c) (RCI 125 / 100): the impulse's bouncing ends within 20 rpm, so "auto" goes back to
  // BDF there, and BDF holds the rotor on the unstable right-rolling wave (growth 76–220 s⁻¹ at
  // 20–46 rpm) in full contact; Dormand–Prince throughout keeps the left contact chattering. Hence
  // the sweeps' default, "explicit".
  params.clearance = {3.048e-4, 3.81e-4};
  const RubStructure c = TwoPointStructure(params);
  const SweepPoint c_auto = Segment(c, rpm, Bdf(2, 1e-6), dormand_prince).points.back();
  const SweepPoint c_explicit = Segment(c, rpm, dormand_prince).points.back();
  CHECK(c_auto.intermittent_windows == 0);
  CHECK(c_auto.channels[0].active_fraction == 1.0);
  CHECK(c_explicit.channels[0].active_fraction < 0.9);
}

// The first whirl → whip jump of a classified segment at contact k (nullptr when there is none).
const RubSweepJump* FirstWhirlToWhip(const RubSweepRegimes& regimes, int k) {
  for (const RubSweepJump& j : regimes.jumps) {
    if (j.contact == k && j.kind == RubJumpKind::kWhirlToWhip) return &j;
  }
  return nullptr;
}

TEST_CASE("Sweeps: a jump is a bracket one speed step wide, and flagged when a speed at its ends "
          "ran to its dwell", "[rub_sweep][failure]") {
  // The stability limit the sweep looks for: where the tanh-law whirl it follows stops being
  // stable (studies/whirl_limits.h; measured: a Hopf point at 51.685 rpm).
  TwoPointParams params = ThesisCaseAa();
  params.friction_law.kind = FrictionLawKind::kTanh;
  RotatingWaveBranchOptions options;
  options.search.speed_min = RpmToRadPerSecond(20.0);
  options.search.speed_max = RpmToRadPerSecond(260.0);
  options.search.precession_max = HzToRadPerSecond(200.0);
  const WhirlLimit limit = FindWhirlLimit(
      ComputeRotatingWaveBranches(TwoPointStructure(params), FrictionLawKind::kTanh, options), +1,
      options.search.speed_min);
  REQUIRE(limit.found);
  const double hopf_rpm = RadPerSecondToRpm(limit.speed);
  REQUIRE(hopf_rpm == Approx(51.685).epsilon(0).margin(0.01));

  // 4 rpm steps: the jump lies between two speeds 4 rpm apart, and the whip at 55 rpm, just
  // entered, has not settled within its 0.75 s (measured): the jump is flagged.
  const SegmentResult coarse = Segment({47.0, 51.0, 55.0}, 2, 1e-6);
  // 0.5 rpm steps around the same point: a bracket of 0.5 rpm.
  const SegmentResult fine = Segment({51.0, 51.5, 52.0}, 2, 1e-6);
  // Read as a waterfall reads them, by the BP alone (a slip tolerance of 99.9 % of ωR lets the
  // frequency check decide, as bench/work_precision_bench does): the jump in the motion. The slip
  // rule reads the tanh knee instead, 0.72 rpm earlier (docs/studies/work_precision.md).
  RubRegimeOptions by_frequency;
  by_frequency.rolling_slip_tolerance = 0.999;
  const RubStructure structure = TwoPointStructure(ThesisCaseAa());
  const RubSweepRegimes coarse_regimes = ClassifySweep(structure, coarse.points, by_frequency);
  const RubSweepRegimes fine_regimes = ClassifySweep(structure, fine.points, by_frequency);
  for (int k = 0; k < 2; ++k) {
    CAPTURE(k);
    for (const auto& [regimes, segment, step] :
         {std::tuple{&coarse_regimes, &coarse, 4.0}, {&fine_regimes, &fine, 0.5}}) {
      const RubSweepJump* jump = FirstWhirlToWhip(*regimes, k);
      REQUIRE(jump != nullptr);
      CAPTURE(step, jump->speed_from_rpm, jump->speed_to_rpm);
      CHECK(jump->speed_to_rpm - jump->speed_from_rpm == Approx(step));
      CHECK(jump->speed_from_rpm <= hopf_rpm);
      CHECK(jump->speed_to_rpm >= hopf_rpm);
      // The flag is exactly "both speeds settled".
      const auto status_at = [&](double rpm) {
        for (const SweepPoint& p : segment->points)
          if (std::abs(RadPerSecondToRpm(p.parameter) - rpm) < 1e-9) return p.status;
        return SweepPointStatus::kIntegrationFailure;
      };
      CHECK(jump->settled == (status_at(jump->speed_from_rpm) == SweepPointStatus::kSettled &&
                              status_at(jump->speed_to_rpm) == SweepPointStatus::kSettled));
    }
    CHECK_FALSE(FirstWhirlToWhip(coarse_regimes, k)->settled);
  }
}

TEST_CASE("Explicit Runge-Kutta on the stiff contact: a loose tolerance lets the step outrun "
          "stability and the sweep stops with the reason, a tight one costs 3x the steps of BDF",
          "[rub_sweep][failure]") {
  const RubStructure s = TwoPointStructure(ThesisCaseAa());
  const double omega = RpmToRadPerSecond(40.0);
  const Vector x0 = WhirlState(40.0);
  RubFixedFrame system(s, omega);
  auto integrate = [&](IntegrationMethod method, double tolerance) {
    IntegratorOptions o;
    o.method = method;
    o.max_order = method == IntegrationMethod::kBdf ? 2 : 0;
    o.relative_tolerance = o.absolute_tolerance = tolerance;
    o.max_steps = 10000000;
    OdeIntegrator integrator(system, o);
    Vector x1(x0.size());
    return integrator.Integrate(0.0, x0, 0.05, x1);
  };
  // rtol 1e-6 (the sweeps'): both succeed; Dormand-Prince takes 25 484 steps (169 702 f
  // evaluations) where BDF order 2 takes 8086 (11 134) (measured).
  const IntegrationResult bdf = integrate(IntegrationMethod::kBdf, 1e-6);
  const IntegrationResult erk = integrate(IntegrationMethod::kExplicitRungeKutta, 1e-6);
  REQUIRE(bdf.Succeeded());
  REQUIRE(erk.Succeeded());
  CHECK(erk.statistics.steps > 3 * bdf.statistics.steps);
  CHECK(erk.statistics.rhs_evaluations > 10 * bdf.statistics.rhs_evaluations);
  // rtol 1e-2: the explicit method's step grows past its stability limit on the contact modes and
  // the state explodes within a few hundred steps; the state bound ends it with a status.
  const IntegrationResult loose = integrate(IntegrationMethod::kExplicitRungeKutta, 1e-2);
  INFO(loose.BriefReport());
  CHECK(loose.status == IntegrationStatus::kStateBound);
  CHECK(loose.statistics.steps < 1000);

  // In a sweep the same failure ends the sweep with the integrator's reason, and it stays stopped.
  RubSweepObservables observables(system);
  SweepOptions o;
  o.parameters = {omega, RpmToRadPerSecond(44.0)};
  o.integrator.method = IntegrationMethod::kExplicitRungeKutta;
  o.integrator.relative_tolerance = o.integrator.absolute_tolerance = 1e-2;
  SweepStepper stepper(system, observables, o, x0);
  CHECK(stepper.Step() == SweepStepOutcome::kFailed);
  CHECK(stepper.Failed());
  REQUIRE(stepper.points().size() == 1);
  CHECK(stepper.points()[0].status == SweepPointStatus::kIntegrationFailure);
  CHECK_THAT(stepper.points()[0].message, Contains("state bound"));
  CHECK(ClassifySweep(s, stepper.points()).regime[0][0] == RubRegime::kUnknown);
  CHECK(stepper.Step() == SweepStepOutcome::kFailed);
}

TEST_CASE("A soft contact sinks the rotor into the stator: the speed is untrusted, with the depth "
          "in the reason", "[rub_sweep][failure]") {
  // The Mode 1 whirl at 40 rpm of case A(a) (from the rigid-contact closed form, in the fixed
  // frame), swept 40 → 44 rpm at the thesis's contact stiffness (penetration ~3e-9 m) and at
  // k1 = 3e6 N/m, where a normal force of 330–373 N is a penetration of 0.11–0.12 mm (0.29–0.33
  // of the clearance; measured): beyond the small overlap the contact law stands for.
  auto sweep = [](double contact_stiffness) {
    TwoPointParams params = ThesisCaseAa();
    params.contact_stiffness = contact_stiffness;
    const RubStructure s = TwoPointStructure(params);
    const double omega = RpmToRadPerSecond(40.0);
    const Vector x0 = WhirlState(40.0);
    RubFixedFrame system(s, omega);
    RubSweepObservables observables(system);
    SweepOptions o;
    o.parameters = {omega, RpmToRadPerSecond(44.0)};
    o.dwell = 0.75;
    o.integrator.max_order = 2;
    SweepStepper stepper(system, observables, o, x0);
    while (!stepper.Done() && !stepper.Failed()) stepper.Step();
    return std::make_pair(s, stepper.points());
  };
  const auto [stiff_structure, stiff] = sweep(ThesisCaseAa().contact_stiffness);
  const auto [soft_structure, soft] = sweep(3e6);
  REQUIRE(stiff.size() == 2);
  REQUIRE(soft.size() == 2);
  const double clearance = stiff_structure.contacts[0].geometry.clearance;
  for (std::size_t i = 0; i < 2; ++i) {
    const double stiff_depth = stiff[i].channels[0].measures[kPenetrationMeasure].max;
    const double soft_depth = soft[i].channels[0].measures[kPenetrationMeasure].max;
    INFO("speed " << i << ": " << stiff_depth << " m at k1 = 1.75e11, " << soft_depth << " m at 3e6 N/m, N "
                  << soft[i].channels[0].measures[kNormalForceMeasure].max << " N");
    CHECK(stiff_depth < 1e-3 * clearance);
    CHECK(soft_depth > 0.1 * clearance);
  }
  const RubSweepRegimes good = ClassifySweep(stiff_structure, stiff), bad = ClassifySweep(soft_structure, soft);
  CHECK(good.untrusted == std::vector<std::string>{"", ""});
  CHECK_THAT(bad.untrusted[0], Contains("contact penetrates") && Contains("× its clearance (limit 0.1)"));
  CHECK_THAT(bad.untrusted[1], Contains("contact penetrates"));
  // The rule is the option's: a limit above the depth trusts the same points.
  RubRegimeOptions lenient;
  lenient.max_penetration = 1e6;
  CHECK(ClassifySweep(soft_structure, soft, lenient).untrusted == std::vector<std::string>{"", ""});
  lenient.max_penetration = 0.0;
  CHECK_THROWS_WITH(ClassifySweep(soft_structure, soft, lenient), Contains("max_penetration = 0: must be positive"));
}

TEST_CASE("A section whose deepest maximum passes the limit is untrusted, by its deepest contact",
          "[rub_sweep][failure]") {
  // Case A(a): clearance 3.81e-4 m at both contacts; limit 0.1 × it = 3.81e-5 m.
  const RubStructure structure = TwoPointStructure(ThesisCaseAa());
  std::vector<RubSectionPoint> points = {{0, 0.1, 2e-5, 3000.0}, {1, 0.2, 3e-5, 3100.0}};
  CHECK(UntrustedSection(structure, points, 0.1).empty());
  CHECK(UntrustedSection(structure, {}, 0.1).empty());
  points.push_back({0, 0.3, 5e-5, 3300.0});
  points.push_back({1, 0.4, 6e-5, 3400.0});
  const std::string why = UntrustedSection(structure, points, 0.1);
  CHECK_THAT(why, Contains("the right contact penetrates 6e-05 m") &&
                      Contains("0.157 × its clearance (limit 0.1)"));
  CHECK(UntrustedSection(structure, points, 0.2).empty());
}

TEST_CASE("an untrusted speed marks the jumps from and to it, and only those", "[rub_sweep]") {
  const RubStructure s = TwoPointStructure(ThesisCaseAa());
  const double clearance = s.contacts[0].geometry.clearance;
  // Three speeds: whirl, whip, whip (both contacts); the middle one sinks 0.2 C deep.
  auto point = [&](double rpm, double bp_hz, double slip, double depth) {
    SweepPoint p;
    p.parameter = RpmToRadPerSecond(rpm);
    for (int k = 0; k < 2; ++k) {
      ChannelSummary c;
      c.peak.found = true;
      c.peak.frequency = -bp_hz;
      c.active_fraction = 1.0;
      c.measures = {{slip, slip, slip}, {3000.0, 3000.0, 3000.0}, {depth, depth, depth}};
      p.channels.push_back(c);
    }
    return p;
  };
  const std::vector<SweepPoint> points = {point(40.0, 100.0 * RpmToHz(40.0), 0.0, 1e-8),
                                          point(60.0, 84.0, 0.1, 0.2 * clearance),
                                          point(64.0, 84.0, 0.1, 1e-8), point(68.0, 84.0, 0.1, 1e-8)};
  const RubSweepRegimes r = ClassifySweep(s, points);
  CHECK(r.untrusted[0].empty());
  CHECK_THAT(r.untrusted[1], Contains("the left contact penetrates") && Contains("0.2 × its clearance"));
  CHECK(r.untrusted[2].empty());
  REQUIRE(r.jumps.size() == 2);  // whirl → whip on each contact, 40 → 60 rpm
  for (const RubSweepJump& j : r.jumps) {
    CHECK(j.speed_from_rpm == Approx(40.0));
    CHECK_FALSE(j.trusted);
  }
  // The same speeds with a shallow middle one: trusted.
  std::vector<SweepPoint> shallow = points;
  for (ChannelSummary& c : shallow[1].channels) c.measures[kPenetrationMeasure].max = 0.05 * clearance;
  const RubSweepRegimes t = ClassifySweep(s, shallow);
  CHECK(t.untrusted == std::vector<std::string>(4, ""));
  for (const RubSweepJump& j : t.jumps) CHECK(j.trusted);
}

TEST_CASE("rub motion: named by the exponents and the section's period", "[rub_sweep]") {
  const RubStructure s = TwoPointStructure(ThesisCaseAa());
  auto result = [](int positive, int zero, int negative) {
    AttractorResult r;
    r.exponents = Vector::Zero(positive + zero + negative);
    r.positive = positive;
    r.zero = zero;
    r.negative = negative;
    return r;
  };
  // Normal forces at successive maxima: each contact alike, period 1, period 2 or none.
  auto section = [](int period) {
    std::vector<RubSectionPoint> points;
    for (int j = 0; j < 40; ++j) {
      const double force = period == 0 ? 3000.0 + 300.0 * std::sin(2.4 * j)
                                       : 3000.0 + (period == 2 && j % 2 ? 300.0 : 0.0);
      for (int k = 0; k < 2; ++k) points.push_back({k, 0.005 * j, 1e-8, force});
    }
    return points;
  };
  CHECK(RubSectionPeriod(s, section(1)) == 1);
  CHECK(RubSectionPeriod(s, section(2)) == 2);
  CHECK(RubSectionPeriod(s, section(0)) == 0);
  CHECK(RubSectionPeriod(s, {}) == 0);
  CHECK(RubMotion(s, result(0, 1, 3), {}) == "rotating wave");
  CHECK(RubMotion(s, result(0, 0, 4), {}) == "equilibrium");
  CHECK(RubMotion(s, result(0, 2, 2), section(1)) == "relative periodic orbit");
  CHECK(RubMotion(s, result(0, 2, 2), section(2)) == "relative periodic orbit, period 2 in the section");
  CHECK(RubMotion(s, result(0, 2, 2), section(0)) == "relative periodic orbit");  // the exponents decide
  CHECK_THAT(RubMotion(s, result(0, 3, 1), section(1)), Contains("near a bifurcation"));
  CHECK(RubMotion(s, result(0, 3, 1), section(0)) == "relative 2-torus");
  CHECK(RubMotion(s, result(1, 2, 1), section(0)) == "chaotic");
  CHECK_THAT(RubMotion(s, result(1, 2, 1), section(1)), Contains("unsettled"));
  CHECK_THAT(RubMotion(s, result(0, 4, 0), section(0)), Contains("at least 4 frequencies"));
  AttractorResult failed = result(0, 2, 2);
  failed.status = AttractorStatus::kIntegrationFailure;
  CHECK_THAT(RubMotion(s, failed, section(1)), Contains("integration failure"));
}

}  // namespace
}  // namespace rubcont
