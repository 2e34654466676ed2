// The whip of case C(a) modulated at two frequencies: the relative tori born at the Neimark–Sacker
// point of its modulated whip (level L2).
#include "shooting/rub_tori.h"

#include <cmath>
#include <vector>

#include <catch2/catch.hpp>

#include "models/two_point_params.h"
#include "models/units.h"

namespace rubcont {
namespace {

TwoPointParams CaseCaTanh() {
  TwoPointParams params = ThesisCaseCa();
  params.friction_law.kind = FrictionLawKind::kTanh;
  return params;
}

TEST_CASE("a failed torus family whose last torus has a contact lifting off ends at a grazing",
          "[torus][rub]") {
  // C(c)'s torus at 71.1142 rpm (results/thesis_C_c_tori): the left contact's least normal force
  // 0.6 N of 495.6 N, the right's 4846 N of more; the corrector failed beyond it.
  const RubStructure structure = TwoPointStructure(ThesisCaseCc());
  TorusBranch tori;
  tori.end = TorusEnd::kFailed;
  tori.end_note = "the corrector failed";
  BranchPoint last;
  last.lambda = RpmToRadPerSecond(71.1142);
  tori.branch.points.push_back(last);
  RubTorusLines lines;
  lines.valid = true;
  lines.contacts.resize(2);
  lines.contacts[0].min_normal_force = 0.6;
  lines.contacts[0].max_normal_force = 495.6;
  lines.contacts[1].min_normal_force = 4845.8;
  lines.contacts[1].max_normal_force = 6300.0;
  const std::vector<RubTorusLines> all{lines};
  TorusBranch failed = tori;
  ReadLiftOff(structure, all, failed);
  CHECK(failed.end == TorusEnd::kGrazing);
  CHECK_THAT(failed.end_note, Catch::Contains("the left contact lifts off at 71.1142 rpm"));
  CHECK_THAT(failed.end_note, Catch::Contains("the corrector failed"));
  // Pressed by more than 1 % of its largest force: still a failure; and no other end is re-read.
  lines.contacts[0].min_normal_force = 5.0;
  TorusBranch pressed = tori;
  ReadLiftOff(structure, {lines}, pressed);
  CHECK(pressed.end == TorusEnd::kFailed);
  lines.contacts[0].min_normal_force = 0.6;
  TorusBranch bound = tori;
  bound.end = TorusEnd::kBound;
  ReadLiftOff(structure, {lines}, bound);
  CHECK(bound.end == TorusEnd::kBound);
  // A located grazing (RubTorusGrazing's test, the engine's status) is named in rpm.
  TorusBranch located = tori;
  located.end = TorusEnd::kGrazing;
  located.branch.status = BranchStatus::kGrazing;
  located.branch.measure_names = {"rotation_number"};
  SpecialPoint grazing;
  grazing.type = SpecialPointType::kGrazing;
  grazing.label = "lift_off_left";
  grazing.lambda = RpmToRadPerSecond(70.9107);
  grazing.measures = Vector::Constant(1, 0.310995);
  located.branch.special_points.push_back(grazing);
  ReadLiftOff(structure, {lines}, located);
  CHECK(located.end == TorusEnd::kGrazing);
  CHECK_THAT(located.end_note, Catch::Contains("lift_off_left at 70.9107 rpm (ρ = 0.310995)"));
}

// Measured on this case with these numerics (the committed scene runs the same): the modulated whip
// born at 48.486 rpm loses stability at a Neimark–Sacker point at 48.667 rpm (angle 2π·0.4431); the
// tori born there have ρ falling from 0.443 towards 2/5 while the circle's fifth harmonic grows to
// half its first (at 48.867 rpm, 31 tori without the tail event): the 2:5 resonance, whose locked
// 5-lap orbits exist between folds at 48.851 and 48.876 rpm.
TEST_CASE("case C(a): the torus born at the modulated whip's Neimark-Sacker point locks at 2/5, "
          "between the folds of its 5-lap orbits",
          "[torus][rub]") {
  const RubStructure structure = TwoPointStructure(CaseCaTanh());
  RotatingWaveBranchOptions waves;
  waves.search.speed_min = RpmToRadPerSecond(20);
  waves.search.speed_max = RpmToRadPerSecond(70);
  waves.search.precession_max = HzToRadPerSecond(200);
  const auto branches = ComputeRotatingWaveBranches(structure, FrictionLawKind::kTanh, waves);
  const auto starts = StableBoundaryHopfPoints(branches, structure.Coordinates());
  REQUIRE_FALSE(starts.empty());
  HopfOrbitOptions hopf;
  hopf.amplitude = 1e-3;
  hopf.orbits.lambda_min = RpmToRadPerSecond(20);
  hopf.orbits.lambda_max = RpmToRadPerSecond(48.8);
  hopf.orbits.shooting.segments = 4;
  hopf.orbits.shooting.integrator.method = IntegrationMethod::kGaussCollocation;
  hopf.orbits.shooting.integrator.collocation_steps = 100;
  hopf.orbits.shooting.integrator.relative_tolerance = 1e-7;
  hopf.orbits.shooting.integrator.absolute_tolerance = 1e-7;
  hopf.orbits.shooting.sensitivities_in_residual = true;
  hopf.orbits.continuation.bounds.max_steps = 40;
  hopf.orbits.continuation.step.target_iterations = 5;
  RubTorusOptions options;
  options.tori.lambda_min = RpmToRadPerSecond(20);
  options.tori.lambda_max = RpmToRadPerSecond(52.0);
  options.tori.harmonics = 8;
  options.tori.max_fourier_tail = 1e-2;
  options.tori.continuation.bounds.max_steps = 20;
  options.tori.continuation.step.target_iterations = 5;
  options.tori.continuation.corrector.residual_tolerance = 1e-8;
  const RubModulatedTori tori = ContinueModulatedTori(structure, branches, starts.front(), hopf, options);
  const Branch& orbits = tori.orbits.orbits.branch;
  INFO(orbits.BriefReport());
  REQUIRE(tori.tori.size() == 1);
  const TorusBranch& t = tori.tori[0];
  INFO(t.message << " / " << t.branch.BriefReport() << " / " << t.end_note);
  REQUIRE(t.ok);
  const SpecialPoint& ns = orbits.special_points[t.special_point];
  CHECK(ns.type == SpecialPointType::kNeimarkSacker);
  CHECK(RadPerSecondToRpm(t.birth_lambda) == Approx(48.667).epsilon(0).margin(0.01));
  // The start's ρ₀ is the located multiplier's angle, recomputed from the segment STMs.
  CHECK(t.birth_rotation_number == Approx(ns.frequency / kTwoPi).epsilon(0).margin(1e-4));
  CHECK(t.birth_modulus == Approx(1.0).epsilon(0).margin(1e-4));

  // Supercritical: the tori lie above the point, and the first is the orbit's modulation plus a
  // second frequency ρ₀/T.
  const std::vector<BranchPoint>& points = t.branch.points;
  REQUIRE(points.size() >= 4);
  const double orbit_modulation = ns.measures(orbits.MeasureIndex("modulation_hz"));
  const RubTorusLines& first = tori.lines[0].front();
  REQUIRE(first.valid);
  CHECK(first.first_hz == Approx(orbit_modulation).epsilon(1e-2));
  CHECK(first.second_hz == Approx(t.birth_rotation_number * orbit_modulation).epsilon(2e-2));
  CHECK(first.carrier_hz ==
        Approx(ns.measures(orbits.MeasureIndex("precession_hz"))).epsilon(1e-5));
  for (std::size_t i = 0; i < points.size(); ++i) CHECK(points[i].lambda > t.birth_lambda);

  // Where it ends: the circle folds towards 5 points as ρ nears 2/5.
  CHECK(t.end == TorusEnd::kLocking);
  CHECK_THAT(t.end_note, Catch::Contains("2:5 resonance"));
  InvariantCircleProblem circle(std::make_shared<RubRotatingFrame>(structure, starts.front().precession,
                                                                   starts.front().speed),
                                8, OrbitKind::kRelative);
  const double rho_end = circle.RotationNumber(points.back().u);
  CHECK(rho_end < t.birth_rotation_number);
  CHECK(std::abs(rho_end - 0.4) < 0.005);
  CHECK(t.locking_p == 2);
  CHECK(t.locking_q == 5);

  // The locked motion: 5-lap relative periodic orbits, a saddle and a stable one joined at two
  // folds, the edges of the 2:5 tongue; the torus family ends just below the lower one.
  REQUIRE(tori.locked.size() == 1);
  const LockedOrbits& locked = tori.locked[0];
  INFO(locked.message << " / " << locked.orbits.branch.BriefReport());
  REQUIRE(locked.ok);
  CHECK(locked.orbits.segments == 20);
  REQUIRE(locked.folds.size() == 2);
  CHECK(RadPerSecondToRpm(locked.folds[0]) == Approx(48.851).epsilon(0).margin(0.002));
  CHECK(RadPerSecondToRpm(locked.folds[1]) == Approx(48.876).epsilon(0).margin(0.002));
  CHECK(points.back().lambda < locked.folds[0]);
  CHECK(locked.tori_inside == 0);
  CHECK(locked.folds[0] - points.back().lambda < RpmToRadPerSecond(0.02));  // measured 0.015 rpm
  bool stable = false;
  for (const BranchPoint& p : locked.orbits.branch.points) {
    stable = stable || p.num_unstable == 0;
    CHECK(p.lambda >= locked.folds[0] - 1e-9);
    CHECK(p.lambda <= locked.folds[1] + 1e-9);
  }
  CHECK(stable);

  // Independent check of the Gauss map: the second torus under CVODES BDF at 1e-10 (state only) is
  // invariant to the same order as the collocation's own defect.
  IntegratorOptions bdf;
  bdf.relative_tolerance = bdf.absolute_tolerance = 1e-10;
  bdf.max_order = 2;
  bdf.max_steps = 2000000;
  InvariantCircleProblem check(std::make_shared<RubRotatingFrame>(structure, starts.front().precession,
                                                                  starts.front().speed),
                               8, OrbitKind::kRelative, bdf);
  const double defect = check.InvarianceError(points[1].u, points[1].lambda);
  INFO("defect under BDF " << defect);
  CHECK(defect < 1e-5);
}

}  // namespace
}  // namespace rubcont
